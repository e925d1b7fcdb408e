"""Calibration of the rules on rates and of the paired rules under nulls shaped like the runs'
data (``calibration`` runs these blocks among the others, ``calibration.RULES``): the band
(``verdicts.in_band``, claim F1's "reach about half", section IV-B) and every sector
(``verdicts.at_least``, section IV-B's sectors) on replication rates that are means over 5
robots x 45 trials (so on a grid of 1/225), with a share of still replications at 0, two
modes, or skewed; the paired change (``verdicts.paired_directional``) and "senses differ"
(``verdicts.senses_differ``, Fig. 9) under the shapes the paired blocks already draw
(``paired_calibration.rate_pairs``). Each at the replications the runs have (3 and 4 in the
4-replication columns, 6 and 10 in the 10-replication ones: ``sizes``), with the true mean
exactly at the band's edge or the floor (the level) and the coverage of the interval each
rule shows (``coverage`` labels the pages' intervals with it). At most ``DATASETS`` data
sets a row (the machine is shared; each row's Monte-Carlo error is its own)."""

from __future__ import annotations

import math

import numpy as np
import polars as pl

from . import verdicts as v
from .calibration_core import RUN_RATIOS, Nesting, rate, repeat, row
from .claims import ABOUT_HALF
from .paired_calibration import RATE_SHAPES, rate_mean, rate_pairs

#: Data sets a row of these blocks is over, at most: the Monte-Carlo standard error of a rate
#: near ALPHA is then sqrt(0.05 x 0.95 / 1000) = 0.0069 (a row fails above 0.066).
DATASETS = 1000
#: Robots a replication's rate is the mean of, and trials per robot (the post-evaluation's 45
#: targets: ``eval.protocol``).
ROBOTS, TRIALS = 5, 45
#: The largest half-spread of replication chances about their mean (rate units), shrunk near
#: 0 and 1 (``_half_width``).
SPREAD = 0.15
#: s.d. of the robots' chances about their replication's at a chance of 0.5 (rate units), per
#: unit of the nesting's ratio of within- to between-replication s.d.
ROBOT_SD = 0.1
#: The share of still replications (their rate 0 on every robot), and of replications in the
#: skewed shape's tail.
STILL, TAIL = 0.3, 0.2
#: The shapes of replication rates (``replication_rates``).
BAND_SHAPES = ("rates on the trial grid", f"{100 * STILL:g} % of replications still",
               "two modes", "skewed (a 20 % tail away from the band)")
#: Sectors of the sector claims (``findings``: 9 reach and 9 grasp cells), and the others'
#: mean chance.
CELLS, OTHER_CELLS = 18, 0.6


def scenario_size() -> pl.Expr:
    """The number of replications, pairs or blocks a row of these blocks was drawn at, read
    from the end of its scenario (", N replications" / ", N pairs" / ", N blocks"); null for a
    scenario that does not end so."""
    return (pl.col("scenario").str.extract(r", (\d+) (?:replications|pairs|blocks)$")
            .cast(pl.Int64))


def sizes(nest: Nesting) -> tuple[int, int]:
    """The replications a block draws at: 3 and 4 in the 4-replication nesting, 6 and 10 in
    the 10-replication one (the runs' sizes: 4-replication runs, a smallest of 3, 6, and the
    paper's 10)."""
    return (3, 4) if nest.replications == 4 else (6, 10)


def _half_width(mean: float) -> float:
    return min(SPREAD, 0.7 * mean, 0.7 * (1 - mean))


def chances(r: np.random.Generator, shape: str, k: int, mean: float, away: int) -> np.ndarray:
    """``k`` replications' chances of a reach, their mean exactly ``mean``, in ``shape``
    (``BAND_SHAPES``), half-spread w = ``_half_width``: uniform in mean +- w; ``STILL`` of
    them 0 (still), the others uniform about mean / (1 - STILL); two modes at mean +- w (each
    jittered by +-w/8); skewed: ``TAIL`` of them w from the mean in direction ``away``, the
    others w / 4 the other way (jittered alike)."""
    w = _half_width(mean)
    jitter = r.uniform(-w / 8, w / 8, k)
    if shape == BAND_SHAPES[0]:
        return mean + r.uniform(-w, w, k)
    if shape == BAND_SHAPES[1]:
        active = mean / (1 - STILL)
        still = r.random(k) < STILL
        return np.where(still, 0.0, active + r.uniform(-1, 1, k) * _half_width(active))
    if shape == BAND_SHAPES[2]:
        return mean + r.choice((-w, w), k) + jitter
    if shape == BAND_SHAPES[3]:
        tail = r.random(k) < TAIL
        return mean + away * np.where(tail, w, -w * TAIL / (1 - TAIL)) + jitter
    raise ValueError(f"unknown shape {shape!r}; known: {BAND_SHAPES}")


def replication_rates(r: np.random.Generator, nest: Nesting, shape: str, k: int, mean: float,
                      away: int) -> np.ndarray:
    """``k`` replications' rates: each the mean over ``ROBOTS`` robots of its reaches in
    ``TRIALS`` trials (Binomial), a robot's chance Beta about its replication's (``chances``;
    s.d. ``ROBOT_SD`` x within / between s.d. at 0.5, 0 where the replication is still). The
    expected rate is ``mean`` exactly."""
    c = chances(r, shape, k, mean, away)[:, None]
    sd = ROBOT_SD * nest.within_sd / nest.between_sd
    kappa = max(0.25 / sd ** 2 - 1, 0.5)
    moving = (c > 0) & (c < 1)
    a, b = np.where(moving, c * kappa, 1.0), np.where(moving, (1 - c) * kappa, 1.0)
    p = np.where(moving, r.beta(a, b, (k, ROBOTS)), c)
    return (r.binomial(TRIALS, p) / TRIALS).mean(axis=1)


def _level_and_coverage(rule, nest, scenario, out, error, truth, level, n) -> list[dict]:
    """A rule's error rate (``error``: the verdicts that are wrong) bounded at ``ALPHA``, and
    its interval's coverage of ``truth`` (one number, or one per outcome) over the outcomes
    with an interval, bounded at ``level``."""
    rows = [row(rule, nest, scenario, "decided" if error == v.DECIDED else error[0],
                rate([o.verdict in error for o in out]), v.ALPHA, "at most", n)]
    truth = truth if isinstance(truth, list) else [truth] * len(out)
    shown = [(o, t) for o, t in zip(out, truth)  # an interval: none where every unit is equal
             if math.isfinite(o.low) and math.isfinite(o.high)]
    if shown:
        rows.append(row(rule, nest, scenario, f"coverage of the {100 * level:g} % interval",
                        rate([o.low <= t <= o.high for o, t in shown]), level, "at least",
                        len(shown)))
    return rows


#: The rules' names in the table (beside the normal-draw rows of "band", "every sector",
#: "paired change", "senses differ").
BAND, SECTORS = "band, run-shaped rates", "every sector, run-shaped rates"
CHANGE, SENSES = "paired change, run-shaped rates", "senses differ, run-shaped rates"


def band_shapes(nest, rng, n):
    """``in_band`` with the true mean at either edge of ``claims.ABOUT_HALF`` (a decided
    verdict is the error), and its interval's coverage of that mean; ``at_least`` over
    ``CELLS`` sectors with the weakest exactly at ``verdicts.SECTOR_FLOOR`` (a reproduction
    is the error), the others at ``OTHER_CELLS`` on the trial grid, and the coverage of the
    interval it shows (the weakest cell's); at ``sizes``, per ``BAND_SHAPES``."""
    n = min(n, DATASETS)
    rows = []
    for k in sizes(nest):
        for shape in BAND_SHAPES:
            for edge, away in zip(ABOUT_HALF, (-1, +1)):
                out = repeat(rng, n, lambda r: v.in_band(
                    replication_rates(r, nest, shape, k, edge, away), ABOUT_HALF))
                rows += _level_and_coverage(BAND, nest, f"{shape}, mean at {edge:.3f}, {k} "
                                            "replications", out, v.DECIDED, edge,
                                            1 - 2 * v.BAND_LEVEL, n)

            def table(r):
                return {c: replication_rates(r, nest, shape if c == 0 else BAND_SHAPES[0], k,
                                             v.SECTOR_FLOOR if c == 0 else OTHER_CELLS, -1)
                        for c in range(CELLS)}
            data = repeat(rng, n, table)
            out = [v.at_least(t, v.SECTOR_FLOOR) for t in data]
            truth = [v.SECTOR_FLOOR if min(t, key=lambda c: t[c].mean()) == 0 else OTHER_CELLS
                     for t in data]
            rows += _level_and_coverage(SECTORS, nest, f"{shape}, weakest of {CELLS} at the "
                                        f"floor, {k} replications", out, (v.REPRODUCED,),
                                        truth, 1 - 2 * v.SECTOR_LEVEL, n)
    return rows


def paired_shapes(nest, rng, n):
    """``paired_directional`` where the mean change is 0 (a decided verdict is the error) and
    its interval's coverage of the true mean change (``paired_calibration.rate_mean``) at 0
    and at ``RATE_MARGIN``; ``senses_differ`` over four conditions with the same mean (a
    reproduction is the error); at ``sizes``, per ``paired_calibration.RATE_SHAPES``."""
    n = min(n, DATASETS)
    rows = []
    for k in sizes(nest):
        for shape in RATE_SHAPES:
            for change in (0.0, v.RATE_MARGIN):
                out = repeat(rng, n, lambda r: v.paired_directional(
                    *rate_pairs(r, shape, k, change), +1))
                scenario = f"{shape}, change {change:g}, {k} pairs"
                level = _level_and_coverage(CHANGE, nest, scenario, out, v.DECIDED,
                                            rate_mean(shape, change),
                                            1 - v.PAIRED_CHANGE_LEVEL, n)
                rows += level if change == 0 else level[1:]
            out = repeat(rng, n, lambda r: v.senses_differ(
                np.column_stack(rate_pairs(r, shape, k, 0.0, conditions=4))))
            rows.append(row(SENSES, nest, f"{shape}, no difference, {k} blocks", v.REPRODUCED,
                            rate([o.verdict == v.REPRODUCED for o in out]), v.ALPHA, "at most",
                            n))
    return rows


# ------------------------------------------------------------------------------------ pilot
#: The pilot that chose the gates and levels of ``verdicts.in_band``, ``at_least``,
#: ``paired_directional`` and ``senses_differ`` (docs/model/claims.md, "Rates shaped like the
#: runs'"): its seed, the sizes it draws at per rule, and the levels it tries (largest first).
PILOT_SEED = 2114
PILOT_SIZES = {BAND: (3, 4, 6, 8, 10), SECTORS: (3, 4, 6, 8, 10), CHANGE: (6, 8, 10),
               SENSES: (6, 8, 10)}
PILOT_LEVELS = {BAND: (0.025, 0.020, 0.015, 0.010, 0.005, 0.0025),
                SECTORS: (0.050, 0.040, 0.030, 0.025, 0.020, 0.015, 0.010, 0.005, 0.0025),
                CHANGE: tuple(round(0.05 - 0.005 * i, 3) for i in range(10)),
                SENSES: tuple(round(0.05 - 0.005 * i, 3) for i in range(10))}


def _pilot_draws() -> list[tuple[str, int, str, object]]:
    """(rule, size, scenario, draw) of the declared family: ``draw(r)`` gives one data set
    and ``_wrong`` judges it."""
    nests = [Nesting(10, ROBOTS, 1.0, w) for w in RUN_RATIOS]
    draws = []
    for nest in nests:
        for k in PILOT_SIZES[BAND]:
            for shape in BAND_SHAPES:
                for edge, away in zip(ABOUT_HALF, (-1, +1)):
                    draws.append((BAND, k, f"{shape}, mean at {edge:.3f}, within s.d. "
                                  f"{nest.within_sd:g}", lambda r, n=nest, s=shape, k=k, e=edge,
                                  a=away: replication_rates(r, n, s, k, e, a)))
                draws.append((SECTORS, k, f"{shape}, weakest at the floor, within s.d. "
                              f"{nest.within_sd:g}", lambda r, n=nest, s=shape, k=k: {
                                  c: replication_rates(r, n, s if c == 0 else BAND_SHAPES[0], k,
                                                       v.SECTOR_FLOOR if c == 0 else OTHER_CELLS,
                                                       -1) for c in range(CELLS)}))
    for k in PILOT_SIZES[CHANGE]:
        for shape in RATE_SHAPES:
            draws.append((CHANGE, k, f"{shape}, change 0",
                          lambda r, s=shape, k=k: rate_pairs(r, s, k, 0.0)))
            draws.append((SENSES, k, f"{shape}, no difference", lambda r, s=shape, k=k:
                          np.column_stack(rate_pairs(r, s, k, 0.0, conditions=4))))
    return draws


def _wrong(rule: str, data, levels) -> list[bool]:
    """Whether ``rule`` at each of ``levels`` (largest first) errs on ``data`` (the band: a
    decision either way; every sector and "senses differ": a reproduction; the paired change:
    a decision), with its gate at the fewest units so that every size is judged."""
    if rule in (BAND, SECTORS):
        out = []
        for level in levels:  # a smaller level never decides where a larger one did not
            o = (v.in_band(data, ABOUT_HALF, level, v.MIN_UNITS) if rule == BAND else
                 v.at_least(data, v.SECTOR_FLOOR, level, v.MIN_UNITS))
            out.append(o.verdict in (v.DECIDED if rule == BAND else (v.REPRODUCED,)))
            if not out[-1]:
                return out + [False] * (len(levels) - len(out))
        return out
    if rule == CHANGE:
        o = v.paired_directional(*data, +1, test_level=max(levels))
        p, smallest = min(o.p, o.p_against), v.smallest_signed_rank_p(len(data[0]))
    else:
        o = v.senses_differ(data, test_level=max(levels))
        p, smallest = o.p, v.smallest_friedman_p(*data.shape)
    return [bool(smallest < level and p < level) for level in levels]


def pilot(datasets: int = DATASETS, seed: int = PILOT_SEED) -> pl.DataFrame:
    """The error of each rule at each of its ``PILOT_LEVELS`` over the declared family of
    nulls shaped like the runs' rates, per size: one row per (rule, size, level) with the
    largest error over the family's scenarios and that scenario. Each scenario draws
    ``datasets`` data sets from its own child of ``seed``."""
    draws = _pilot_draws()
    rows = []
    for child, (rule, k, scenario, draw) in zip(np.random.SeedSequence(seed).spawn(len(draws)),
                                                 draws):
        r = np.random.default_rng(child)
        levels = PILOT_LEVELS[rule]
        wrong = np.array([_wrong(rule, draw(r), levels) for _ in range(datasets)])
        rows += [{"rule": rule, "size": k, "level": level, "scenario": scenario,
                  "error": float(e)} for level, e in zip(levels, wrong.mean(axis=0))]
    return (pl.DataFrame(rows).sort("error", descending=True)
            .group_by("rule", "size", "level", maintain_order=True)
            .agg(pl.col("error").first(), pl.col("scenario").first().alias("worst"))
            .sort("rule", "size", "level", descending=[False, False, True]))


def choose(table: pl.DataFrame) -> dict[str, tuple[int, float]]:
    """The (gate, level) of each rule from ``pilot``'s table: the gate the smallest size from
    which some level holds (its largest error at most ``ALPHA``) at every larger size, the
    level the largest that holds at every size from the gate. Where no level holds at the
    largest size, the gate is one above it (the rule decides at none of the pilot's sizes) and
    the level the largest tried (every level holds at no size)."""
    chosen = {}
    for rule, sizes_ in PILOT_SIZES.items():
        t = table.filter(pl.col("rule") == rule)
        holds = {k: set(t.filter((pl.col("size") == k) & (pl.col("error") <= v.ALPHA))["level"])
                 for k in sizes_}
        chosen[rule] = (max(sizes_) + 1, max(PILOT_LEVELS[rule]))
        for gate in sizes_:
            if common := set.intersection(*(holds[k] for k in sizes_ if k >= gate)):
                chosen[rule] = (gate, max(common))
                break
    return chosen
