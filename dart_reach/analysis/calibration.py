"""Calibration of the verdict rules by simulation of nested data like the runs'.

A run's units are nested: ``replications`` independent populations per group, the best
``robots`` robots of each, a robot's value the mean over its post-evaluation trials. Data sets
are drawn with a between-replication and a within-replication spread (``Nesting``), under each
rule's null (where a decided verdict is an error) and under effects (where it is power), and
each rule of ``verdicts`` is applied to them exactly as ``findings`` applies it. For every rule
and nesting, ``calibrate`` measures:

- the rate of a decided verdict (reproduced or contradicted) where the truth is the rule's
  null, which must be at most ``ALPHA`` within Monte-Carlo error, also when one replication is
  an outlier (``OUTLIER`` between-replication s.d.) and, for the directional rules, when the
  groups' shapes differ at theta = 0.5 (``shaped``: bimodal against unimodal, zero-inflated
  against continuous, unequal spreads), with the rule before (Mann-Whitney) reported beside;
- the coverage of the rule's interval (it must hold the true effect at least as often as its
  level says, within Monte-Carlo error);
- the power: how often it reproduces a true effect of 1 and 2 s.d. of a replication mean.

Beside the headline rules, ``robot_level_null`` measures what treating the robots as
independent units would decide under the null (the pseudo-replication the headline avoids).
Every number is a pure function of the seed.
"""

from __future__ import annotations

import math

import numpy as np
import polars as pl
from scipy import optimize
from scipy import stats as sps

from . import verdicts as v
from .calibration_core import (  # noqa: F401  (re-exported: the calibration's shared names)
    DATASETS, NESTINGS, OUTLIER, RUN_RATIOS, Z_MC, Nesting, rate as _rate, repeat as _repeat,
    robots, row as _row)
from .paired_calibration import (  # noqa: F401  (re-exported: the paired rules' blocks)
    PAIRED_BEFORE, PAIRED_UNGATED, RATE_BEFORE, RATE_SHAPES, RATE_UNGATED, SENSES_UNGATED,
    paired, paired_rates, rate_pairs, senses, t_tost)
from .run_shaped_calibration import band_shapes, paired_shapes


def _pair(rng, nest, shift_b=0.0, outlier=False):
    a, b = robots(rng, nest), robots(rng, nest, shift_b)
    if outlier:  # one replication of the pooled 2r moved: the groups stay exchangeable
        k = rng.integers(2 * nest.replications)
        (a if k < nest.replications else b)[k % nest.replications] += OUTLIER * nest.between_sd
    return a, b



def _theta_shift(theta: float, sd: float) -> float:
    """The shift of b over a (both normal with s.d. ``sd``) that gives P(B > A) = theta."""
    return math.sqrt(2) * sd * sps.norm.ppf(theta)



# ------------------------------------------------------------------- groups of unequal shapes
#: Where the groups' shapes differ under theta = P(B > A) + P(B = A) / 2 = 0.5 (the null of a
#: directional claim), in between-replication s.d.: a bimodal group (replications at +-1, s.d.
#: 0.25 about each: babbling or still) against a narrow unimodal one (s.d. 0.3); a
#: zero-inflated group (half its replications exactly 0 on every robot, as a still population's
#: babbling; the others N(3, 1)) against a continuous one (s.d. 0.3, its centre solved for
#: theta = 0.5); unequal spreads (s.d. 1 against 4).
BIMODAL = (1.0, 0.25, 0.3)
ZERO_INFLATED = (0.5, 3.0, 0.3)
SPREADS = (1.0, 4.0)


def _noisy(rng, nest, rep):
    return rep[:, None] + rng.normal(0.0, nest.within_sd, (len(rep), nest.robots))


def _zero_inflated_centre(nest: Nesting, target: float = 0.5) -> float:
    """The centre of the continuous group that gives theta = ``target`` against the
    zero-inflated one (replication means: the still ones exactly 0, the others N(3, s_a), the
    continuous N(centre, s_b), s from between and within s.d.)."""
    share, centre_a, sd_b = ZERO_INFLATED
    s_a = math.sqrt(nest.between_sd ** 2 + nest.within_sd ** 2 / nest.robots)
    s_b = math.sqrt((sd_b * nest.between_sd) ** 2 + nest.within_sd ** 2 / nest.robots)
    theta = lambda c: (share * sps.norm.cdf(c / s_b) + (1 - share) * sps.norm.cdf(  # noqa: E731
        (c - centre_a * nest.between_sd) / math.hypot(s_a, s_b)) - target)
    return float(optimize.brentq(theta, -10 * centre_a, 10 * centre_a))


def _spreads_centre(nest: Nesting, target: float = 0.5) -> float:
    """The centre of the wide group (s.d. ``SPREADS[1]``) that gives theta = ``target``
    against the narrow one centred at 0 (replication means normal, within s.d. included)."""
    var = sum((k * nest.between_sd) ** 2 + nest.within_sd ** 2 / nest.robots for k in SPREADS)
    return float(math.sqrt(var) * sps.norm.ppf(target))


def shaped(rng: np.random.Generator, nest: Nesting, shape: str,
           replications: int | None = None, theta: float = 0.5
           ) -> tuple[np.ndarray, np.ndarray]:
    """Replication means (a, b) of two groups of different ``shape`` (``SHAPES``) with
    theta = 0.5; ``replications`` of b (default ``nest.replications``; a's too). ``theta``
    other than 0.5 moves b (zero-inflated and unequal spreads only: the coverage of an
    interval away from the null)."""
    n = nest.replications
    m = replications or n
    sd = nest.between_sd
    if theta != 0.5 and shape == SHAPES[0]:
        raise ValueError("the bimodal shape is drawn at theta = 0.5 only")
    if shape == "bimodal against unimodal":
        centre, spread, narrow = BIMODAL
        a = rng.choice((-centre, centre), n) * sd + rng.normal(0.0, spread * sd, n)
        b = rng.normal(0.0, narrow * sd, m)
        return _noisy(rng, nest, a).mean(axis=1), _noisy(rng, nest, b).mean(axis=1)
    if shape == "zero-inflated against continuous":
        share, centre_a, sd_b = ZERO_INFLATED
        still = rng.random(n) < share
        a = np.where(still, 0.0, _noisy(rng, nest, rng.normal(centre_a * sd, sd, n))
                     .mean(axis=1))
        b = rng.normal(_zero_inflated_centre(nest, theta), sd_b * sd, m)
        return a, _noisy(rng, nest, b).mean(axis=1)
    if shape == "unequal spreads (1 : 4)":
        a, b = (rng.normal(centre, k * sd, size) for centre, k, size
                in zip((0.0, _spreads_centre(nest, theta)), SPREADS, (n, m)))
        return _noisy(rng, nest, a).mean(axis=1), _noisy(rng, nest, b).mean(axis=1)
    raise ValueError(f"unknown shape {shape!r}; known: {SHAPES}")


SHAPES = ("bimodal against unimodal", "zero-inflated against continuous",
          "unequal spreads (1 : 4)")


def mann_whitney_decides(a, b, sign: int = 0) -> bool:
    """The directional rule before Brunner-Munzel (kept to measure what the change costs and
    gains): two-tailed Mann-Whitney U (``scipy.stats.mannwhitneyu``, exact without ties) at
    ``ALPHA``, in direction ``sign`` (0: either)."""
    ties = len(np.unique(np.concatenate([a, b]))) < len(a) + len(b)
    res = sps.mannwhitneyu(b, a, method="asymptotic" if ties else "exact")
    return bool(res.pvalue < v.ALPHA
                and (sign == 0 or np.sign(res.statistic - len(a) * len(b) / 2) == sign))


def _has_intervals(out) -> bool:
    """Whether the rule gave intervals (none where it is underpowered at these sizes)."""
    return any(o.verdict != v.UNDERPOWERED for o in out)


# ----------------------------------------------------------------------------------- the rules
def _directional(nest, rng, n):
    """The rule under its nulls (also with unequal shapes) and effects; beside it, as
    "reported", the old rule (Mann-Whitney) under the same data."""
    means = lambda x: x.mean(axis=1)  # noqa: E731
    old = "directional: Mann-Whitney (the rule before, reported)"
    nulls = {"null": lambda r: tuple(map(means, _pair(r, nest))),
             "null, one outlying replication": lambda r: tuple(map(means, _pair(r, nest, 0.0,
                                                                                True)))}
    nulls.update({f"null, {shape}": (lambda r, s=shape: shaped(r, nest, s)) for shape in SHAPES})
    rows = []
    for scenario, draw in nulls.items():
        data = _repeat(rng, n, draw)
        out = [v.directional(a, b, +1) for a, b in data]
        rows.append(_row("directional", nest, scenario, "decided",
                         _rate([o.verdict in v.DECIDED for o in out]), v.ALPHA, "at most"))
        if scenario != "null, one outlying replication" and _has_intervals(out):
            rows.append(_row("directional", nest, scenario, "coverage of the 95 % interval",
                             _rate([o.low <= 0.5 <= o.high for o in out]), 0.95, "at least"))
        rows.append(_row(old, nest, scenario, "decided",
                         _rate([mann_whitney_decides(a, b) for a, b in data]), math.nan,
                         "reported"))
    theta = float(sps.norm.cdf(1 / math.sqrt(2)))  # a shift of 1 s.d.
    for d in (1, 2):
        data = _repeat(rng, n, lambda r: tuple(map(means, _pair(r, nest, d * nest.mean_sd))))
        out = [v.directional(a, b, +1) for a, b in data]
        if d == 1 and _has_intervals(out):
            rows.append(_row("directional", nest, "shift 1 s.d.", "coverage of the 95 % "
                             "interval", _rate([o.low <= theta <= o.high for o in out]), 0.95,
                             "at least"))
        rows.append(_row("directional", nest, f"shift {d} s.d.", "reproduced",
                         _rate([o.verdict == v.REPRODUCED for o in out]), math.nan, "power"))
        rows.append(_row(old, nest, f"shift {d} s.d.", "reproduced",
                         _rate([mann_whitney_decides(a, b, +1) for a, b in data]), math.nan,
                         "reported"))
    return rows


def _against_random(nest, rng, n):
    """A phase's replication means against random genomes, which are independent robots (10
    of them): under the null alike, and with the phase's replications bimodal against
    unimodal random genomes or with spreads 1 : 4."""
    sd = math.sqrt(nest.between_sd ** 2 + nest.within_sd ** 2)
    rule = "directional vs 10 random genomes"

    def alike(r, d=0.0):
        return r.normal(0.0, sd, 10), robots(r, nest, d * sd).mean(axis=1)

    def unequal(r, shape):
        phase, random_ = shaped(r, nest, shape, replications=10)
        return random_, phase
    rows = []
    for scenario, draw in (("null", alike),
                           *((f"null, {s}", lambda r, s=s: unequal(r, s))
                             for s in (SHAPES[0], SHAPES[2]))):
        out = _repeat(rng, n, lambda r: v.directional(*draw(r), +1))
        rows.append(_row(rule, nest, scenario, "decided",
                         _rate([o.verdict in v.DECIDED for o in out]), v.ALPHA, "at most"))
    out = _repeat(rng, n, lambda r: v.directional(*alike(r, 1.0), +1))
    rows.append(_row(rule, nest, "shift 1 s.d.", "reproduced",
                     _rate([o.verdict == v.REPRODUCED for o in out]), math.nan, "power"))
    return rows


def _equivalence(nest, rng, n):
    means = lambda x: x.mean(axis=1)  # noqa: E731
    edge = _theta_shift(0.5 + v.EQUIVALENCE_MARGIN, nest.mean_sd)
    rows = []
    for rule, judge in (("no difference", lambda a, b: v.equivalent(a, b)),
                        ("not better", lambda a, b: v.not_better(a, b, +1))):
        out = _repeat(rng, n, lambda r: judge(*map(means, _pair(r, nest, edge))))
        rows.append(_row(rule, nest, "theta at 0.5 + margin", "reproduced",
                         _rate([o.verdict == v.REPRODUCED for o in out]), v.ALPHA, "at most"))
        for outlier in (False, True):
            out = _repeat(rng, n, lambda r: judge(*map(means, _pair(r, nest, 0.0, outlier))))
            rows.append(_row(rule, nest, "no difference" + (", one outlying replication"
                                                            if outlier else ""),
                             "contradicted", _rate([o.verdict == v.CONTRADICTED for o in out]),
                             v.ALPHA, "at most"))
            if not outlier:
                rows.append(_row(rule, nest, "no difference", "reproduced",
                                 _rate([o.verdict == v.REPRODUCED for o in out]), math.nan,
                                 "power"))
    return rows


def _band(nest, rng, n):
    """Replication rates: replication mean N(centre, between), robots N(rep, within), both on
    the rate scale (s.d. 0.1 and 0.1 x within/between)."""
    scale = 0.1
    rates = lambda r, centre: (robots(r, nest) * scale + centre).mean(axis=1)  # noqa: E731
    band = (1 / 3, 2 / 3)
    rows = []
    for centre, scenario in ((band[0], "mean at the band's edge"),):
        out = _repeat(rng, n, lambda r: v.in_band(rates(r, centre), band))
        rows.append(_row("band", nest, scenario, "decided",
                         _rate([o.verdict in v.DECIDED for o in out]), v.ALPHA, "at most"))
    out = _repeat(rng, n, lambda r: v.in_band(rates(r, 0.5), band))
    shown = [o for o in out if math.isfinite(o.low)]  # none below the gate
    if shown:
        level = 1 - 2 * v.BAND_LEVEL
        rows.append(_row("band", nest, "mean 0.5", f"coverage of the {100 * level:g} % interval",
                         _rate([o.low <= 0.5 <= o.high for o in shown]), level, "at least"))
    rows.append(_row("band", nest, "mean 0.5", "reproduced",
                     _rate([o.verdict == v.REPRODUCED for o in out]), math.nan, "power"))
    return rows


def _sectors(nest, rng, n):
    scale, floor, cells = 0.1, v.SECTOR_FLOOR, 18

    def table(r, weakest):
        return {k: (robots(r, nest) * scale + (weakest if k == 0 else 0.6)).mean(axis=1)
                for k in range(cells)}
    out = _repeat(rng, n, lambda r: v.at_least(table(r, floor), floor))
    rows = [_row("every sector", nest, "one cell at the floor", "reproduced",
                 _rate([o.verdict == v.REPRODUCED for o in out]), v.ALPHA, "at most")]
    out = _repeat(rng, n, lambda r: v.at_least(
        {k: (robots(r, nest) * scale + floor).mean(axis=1) for k in range(cells)}, floor))
    rows.append(_row("every sector", nest, "every cell at the floor", "contradicted",
                     _rate([o.verdict == v.CONTRADICTED for o in out]), v.ALPHA, "at most"))
    out = _repeat(rng, n, lambda r: v.at_least(table(r, floor + 2 * scale), floor))
    rows.append(_row("every sector", nest, "weakest cell 2 s.d. above the floor", "reproduced",
                     _rate([o.verdict == v.REPRODUCED for o in out]), math.nan, "power"))
    return rows


#: The paired rules' blocks (``paired_calibration``), under the names ``RULES`` and the
#: tests use.
_paired, _senses, _paired_rates, _t_tost = paired, senses, paired_rates, t_tost


#: Sizes of the groups where the strategies split a run's replications (7 babbling, 3 still):
#: a two-mode group of the smaller size against a narrow one of the larger.
SPLIT = (3, 7)
#: theta of the coverage rows away from the null, with the groups' shapes unequal.
COVERAGE_THETA = 0.75


def _shapes(nest, rng, n):
    """Every two-group rule under the shape nulls (theta = 0.5, groups of unequal shapes): at
    the nesting's size, and at ``SPLIT`` (3 two-mode units against 7 narrow ones: every rule
    is gated there, ``verdicts.one_mode``); and the directional rule's coverage at theta =
    ``COVERAGE_THETA`` with unequal spreads and zero-inflation, reported beside its level: the
    interval is the permutation test inverted, exact at theta = 0.5, and may fall short away
    from it when the shapes differ (docs/results/calibration.md says where)."""
    judges = {"directional": (lambda a, b: v.directional(a, b, +1), v.DECIDED, "decided"),
              "no difference": (v.equivalent, (v.CONTRADICTED,), "contradicted"),
              "not better": (lambda a, b: v.not_better(a, b, +1), (v.CONTRADICTED,),
                             "contradicted")}
    rows = []
    small = Nesting(SPLIT[0], nest.robots, nest.between_sd, nest.within_sd)
    split = f"null, {SHAPES[0]}, {SPLIT[0]} vs {SPLIT[1]}"
    draws = {split: lambda r: shaped(r, small, SHAPES[0], replications=SPLIT[1])}
    draws.update({f"null, {shape}": (lambda r, s=shape: shaped(r, nest, s)) for shape in SHAPES})
    for scenario, draw in draws.items():
        data = _repeat(rng, n, draw)
        for rule, (judge, errors, measure) in judges.items():
            if rule == "directional" and scenario != split:
                continue  # the directional rule's shape nulls are in its own block
            rows.append(_row(rule, nest, scenario, measure,
                             _rate([judge(a, b).verdict in errors for a, b in data]), v.ALPHA,
                             "at most"))
    for shape in SHAPES[1:]:
        out = _repeat(rng, n, lambda r, s=shape: v.directional(
            *shaped(r, nest, s, theta=COVERAGE_THETA), +1))
        if _has_intervals(out):
            rows.append(_row("directional", nest, f"theta {COVERAGE_THETA:g}, {shape}",
                             "coverage of the 95 % interval (reported)",
                             _rate([o.low <= COVERAGE_THETA <= o.high for o in out]), math.nan,
                             "reported"))
    return rows


#: The no-difference and not-better rules without their two-mode gate (reported beside the
#: gated rules' rows at ``SPLIT``: what the gate prevents).
UNGATED = {"no difference": "no difference: without the two-mode gate (reported)",
           "not better": "not better: without the two-mode gate (reported)"}


def _split_ungated(nest, rng, n):
    """The no-difference and not-better rules without their gate (``UNGATED``, reported) under
    the null at ``SPLIT`` (3 two-mode units against 7 narrow ones, theta = 0.5), where the
    gated rules never decide (``_shapes``): how often each would contradict. A block of its
    own, so that the gated rules' blocks keep their data sets."""
    small = Nesting(SPLIT[0], nest.robots, nest.between_sd, nest.within_sd)
    data = _repeat(rng, n, lambda r: shaped(r, small, SHAPES[0], replications=SPLIT[1]))
    judges = {"no difference": lambda a, b: v.equivalent(a, b, gated=False),
              "not better": lambda a, b: v.not_better(a, b, +1, gated=False)}
    return [_row(UNGATED[rule], nest, f"null, {SHAPES[0]}, {SPLIT[0]} vs {SPLIT[1]}",
                 "contradicted", _rate([judge(a, b).verdict == v.CONTRADICTED
                                        for a, b in data]), math.nan, "reported")
            for rule, judge in judges.items()]


#: Every block, in the order of their seeds (a block added goes last: the others keep theirs).
RULES = (_directional, _against_random, _equivalence, _band, _sectors, _paired, _senses,
         _shapes, _paired_rates, _split_ungated, band_shapes, paired_shapes)


def calibrate(nestings=NESTINGS, datasets: int = DATASETS, seed: int = 2013,
              rules=RULES) -> pl.DataFrame:
    """Every rule of ``rules`` under every nesting: one row per (rule, nesting, scenario,
    measure) with the measured ``value``, its ``bound`` and whether it is met (``ok``; None
    for power and reported rows). Each (nesting, rule) block has its own seed, so a block
    computed alone is the block of the whole table."""
    rows = []
    for i, nest in enumerate(nestings):
        for rule in rules:
            j = RULES.index(rule)
            rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(i, j)))
            rows += rule(nest, rng, datasets)
    return pl.DataFrame(rows)


def robot_level_null(nest: Nesting, datasets: int = DATASETS, seed: int = 2013) -> dict:
    """What the headline avoids: under the null, how often the directional rule decides when
    every robot counts as a unit, and Friedman's test with the robot as block when each
    replication orders the conditions its own way."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(99,)))
    decided = _rate([v.directional(*(g.ravel() for g in _pair(rng, nest)), +1).verdict
                     in v.DECIDED for _ in range(datasets)])
    k = 4
    friedman = []
    for _ in range(datasets):
        per_rep = rng.normal(0.0, nest.between_sd, (nest.replications, 1, k))
        rob = per_rep + rng.normal(0.0, nest.within_sd, (nest.replications, nest.robots, k))
        friedman.append(v.senses_differ(rob.reshape(-1, k) + 10.0).verdict == v.REPRODUCED)
    return {"directional, robots as units": decided,
            "senses differ, robots as blocks": _rate(friedman)}


def robot_level(nestings=NESTINGS, datasets: int = DATASETS, seed: int = 2013) -> pl.DataFrame:
    """``robot_level_null`` of every nesting: one row per nesting (its replications, robots
    and spreads, as ``calibrate``'s rows) with both rates."""
    return pl.DataFrame([{"replications": nest.replications, "robots": nest.robots,
                          "between_sd": nest.between_sd, "within_sd": nest.within_sd,
                          **robot_level_null(nest, datasets, seed)} for nest in nestings])
