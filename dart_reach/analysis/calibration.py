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
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import polars as pl
from scipy import optimize
from scipy import stats as sps

from . import verdicts as v

#: Data sets per rule, nesting and scenario; the Monte-Carlo standard error of a rate near
#: ALPHA is then sqrt(0.05 x 0.95 / 2000) = 0.0049.
DATASETS = 2000
#: The outlying replication of the robustness null, in between-replication s.d.
OUTLIER = 4.0
#: One-sided z of the Monte-Carlo tolerance (99 %): a rule fails when its rate exceeds
#: ALPHA + Z_MC x its standard error, or its coverage falls below the level - Z_MC x s.e.
Z_MC = 2.33


@dataclass(frozen=True)
class Nesting:
    """Replications per group, robots per replication, and the s.d. of replication effects
    and of robots within a replication, in the measure's units."""

    replications: int
    robots: int = 5
    between_sd: float = 1.0
    within_sd: float = 0.2

    @property
    def label(self) -> str:
        return (f"{self.replications} x {self.robots} (s.d. {self.between_sd:g} between, "
                f"{self.within_sd:g} within)")

    @property
    def mean_sd(self) -> float:
        """s.d. of a replication's mean over its robots."""
        return math.sqrt(self.between_sd ** 2 + self.within_sd ** 2 / self.robots)


#: The runs' ratio of within- to between-replication s.d. (``spreads``, over phases and
#: measures; docs/results/replication.md): the lowest lower quartile (0.62) and the highest
#: upper quartile (2.97) over the project's committed replication runs, rounded.
RUN_RATIOS = (0.6, 3.0)
#: The nestings of the runs: 4 replications (the 10- and 50-generation runs), 10 (the
#: paper's), each at the two ends of the runs' quartile ratios.
NESTINGS = tuple(Nesting(r, 5, 1.0, w) for r in (4, 10) for w in RUN_RATIOS)


def robots(rng: np.random.Generator, nest: Nesting, shift: float = 0.0,
           outlier: bool = False) -> np.ndarray:
    """One group's robot values, shape (replications, robots): replication effects
    N(shift, between_sd), robots N(replication, within_sd); with ``outlier`` one replication
    moved by ``OUTLIER`` between-replication s.d."""
    rep = rng.normal(shift, nest.between_sd, nest.replications)
    if outlier:
        rep[rng.integers(nest.replications)] += OUTLIER * nest.between_sd
    return rep[:, None] + rng.normal(0.0, nest.within_sd, (nest.replications, nest.robots))


def _pair(rng, nest, shift_b=0.0, outlier=False):
    a, b = robots(rng, nest), robots(rng, nest, shift_b)
    if outlier:  # one replication of the pooled 2r moved: the groups stay exchangeable
        k = rng.integers(2 * nest.replications)
        (a if k < nest.replications else b)[k % nest.replications] += OUTLIER * nest.between_sd
    return a, b


def _theta_shift(theta: float, sd: float) -> float:
    """The shift of b over a (both normal with s.d. ``sd``) that gives P(B > A) = theta."""
    return math.sqrt(2) * sd * sps.norm.ppf(theta)


def _rate(flags) -> float:
    return float(np.mean(flags))


def _row(rule: str, nest: Nesting, scenario: str, measure: str, value: float, bound: float,
         kind: str) -> dict:
    """``kind``: "at most" (an error rate against ``bound``), "at least" (a coverage),
    "power" or "reported" (a rule not used, for comparison; neither has a bound)."""
    if kind not in ("at most", "at least", "power", "reported"):
        raise ValueError(f"unknown kind {kind!r}")
    free = kind in ("power", "reported")
    se = math.sqrt(max(bound * (1 - bound), 1e-12) / DATASETS) if not free else math.nan
    ok = (value <= bound + Z_MC * se if kind == "at most" else
          value >= bound - Z_MC * se if kind == "at least" else None)
    return {"rule": rule, "replications": nest.replications, "robots": nest.robots,
            "between_sd": nest.between_sd, "within_sd": nest.within_sd, "scenario": scenario,
            "measure": measure, "value": value, "bound": bound if not free else math.nan,
            "kind": kind, "ok": ok}


def _repeat(rng, n, draw: Callable):
    return [draw(rng) for _ in range(n)]


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
    rows.append(_row("band", nest, "mean 0.5", "coverage of the 95 % interval",
                     _rate([o.low <= 0.5 <= o.high for o in out]), 0.95, "at least"))
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


def _paired(nest, rng, n):
    """One group's replications under two conditions (or in two generation windows): each
    replication changes by N(shift, between_sd) on the replication-mean scale."""
    rows = []

    def pairs(r, shift, outlier=False):
        ref = robots(r, nest).mean(axis=1)
        change = r.normal(shift, nest.mean_sd, nest.replications)
        if outlier:
            change[r.integers(nest.replications)] += OUTLIER * nest.mean_sd * r.choice((-1, 1))
        return ref, ref + change
    for outlier in (False, True):
        out = _repeat(rng, n, lambda r: v.paired_directional(*pairs(r, 0.0, outlier), +1))
        rows.append(_row("paired change", nest, "null" + (", one outlying replication"
                                                          if outlier else ""),
                         "decided", _rate([o.verdict in v.DECIDED for o in out]), v.ALPHA,
                         "at most"))
    shift = nest.mean_sd
    out = _repeat(rng, n, lambda r: v.paired_directional(*pairs(r, shift), +1))
    rows.append(_row("paired change", nest, "change 1 s.d.", "coverage of the 95 % interval",
                     _rate([o.low <= shift <= o.high for o in out]), 0.95, "at least"))
    rows.append(_row("paired change", nest, "change 1 s.d.", "reproduced",
                     _rate([o.verdict == v.REPRODUCED for o in out]), math.nan, "power"))

    def same(r, change_by, k, modes=0.0):
        """``k`` positive references (each replication's change is relative to its own
        level), each changed by a relative change N(change_by x margin, margin), or with
        ``modes`` at change_by x margin +- modes x margin (two modes, s.d. margin / 10)."""
        ref = robots(r, nest).mean(axis=1)[:k] + 10.0  # k <= the nesting's replications
        spread = PAIRED_SD if not modes else 0.1
        c = r.normal(change_by * v.PAIRED_MARGIN, spread * v.PAIRED_MARGIN, k)
        if modes:
            c += r.choice((-modes, modes), k) * v.PAIRED_MARGIN
        c = np.clip(c, -1.9, 1.9)
        return ref, ref * (2 + c) / (2 - c)  # (new - ref) / mean(new, ref) = c
    judge = lambda ref, new: v.paired_equivalent(ref, new, relative=True)  # noqa: E731
    for k in _pair_sizes(nest):
        at = "" if k == nest.replications else f", {k} pairs"
        for modes, shape in ((0.0, ""), (TWO_MODES, ", two-mode changes")):
            for change_by, scenario, error in ((1.0, "change at the margin", v.REPRODUCED),
                                               (0.0, "no change", v.CONTRADICTED)):
                data = _repeat(rng, n, lambda r: same(r, change_by, k, modes))
                out = [judge(a, b) for a, b in data]
                rows.append(_row("paired no change", nest, scenario + shape + at, error,
                                 _rate([o.verdict == error for o in out]), v.ALPHA,
                                 "at most"))
                rows.append(_row(PAIRED_BEFORE, nest, scenario + shape + at, error, _rate(
                    [_t_tost(v.relative_changes(a, b), v.PAIRED_MARGIN) == error
                     for a, b in data]), math.nan, "reported"))
                if change_by == 0.0 and not modes:
                    rows.append(_row("paired no change", nest, scenario + at, "reproduced",
                                     _rate([o.verdict == v.REPRODUCED for o in out]),
                                     math.nan, "power"))
    return rows


#: s.d. of the relative changes of "paired no change" (in margins): wide enough that the
#: rule, shown no equivalence, can be wrong the other way (a row that can fail).
PAIRED_SD = 1.0
#: Two-mode changes: each replication changes by the null's change +- this many margins.
TWO_MODES = 1.5
#: The paired rules' rule before the sign-flip test (reported beside it).
PAIRED_BEFORE = "paired no change: paired t TOST (the rule before, reported)"
RATE_BEFORE = "paired rate no change: paired t TOST (the rule before, reported)"


def _pair_sizes(nest: Nesting) -> tuple[int, ...]:
    """The pairs a paired rule is calibrated at: the nesting's replications, and 3 beside 4
    (the smallest run and the old gate)."""
    return (3, 4) if nest.replications == 4 else (nest.replications,)


def _t_tost(d, bound) -> str:
    """The verdict of the paired rules before the sign-flip test: two one-sided paired
    t-tests of the changes ``d`` (``verdicts.paired_tost``) from 3 pairs."""
    d = np.asarray(d, float)
    if len(d) < v.MIN_UNITS or np.ptp(d) == 0:
        return v.UNDERPOWERED if len(d) < v.MIN_UNITS else v.INCONCLUSIVE
    p_eq, p_diff, *_ = v.paired_tost(np.zeros_like(d), d, bound)
    return v.REPRODUCED if p_eq < v.ALPHA else v.CONTRADICTED if p_diff < v.ALPHA \
        else v.INCONCLUSIVE


def _fifths(r, p):
    """Replication rates over 5 robots each babbling or not (a no-ball robot's 45 trials are
    one trial): Binomial(5, p) / 5."""
    return r.binomial(5, np.clip(p, 0.0, 1.0)) / 5


#: The shapes of a rate's paired changes (``rate_pairs``), and whether the changes are
#: symmetric about their centre (where the sign-flip test is exact).
RATE_SHAPES = {"rates in fifths": True, "30 % of replications still": True,
               "50 % of replications still": True, "two-mode changes": True,
               "zero-inflated changes (70 % unchanged)": False,
               "skewed changes (exponential)": False}


def rate_pairs(r: np.random.Generator, shape: str, k: int, change: float
               ) -> tuple[np.ndarray, np.ndarray]:
    """``k`` replications' rates under two conditions whose mean change is ``change``, in
    ``shape`` (``RATE_SHAPES``): rates in fifths (each replication's chance uniform in
    [0.2, 0.8], moved by ``change``); a share of replications still (0 under both, the others
    in fifths, moved by change / (1 - share)); two-mode changes (+-0.15 about ``change``);
    zero-inflated (70 % of replications unchanged, the others by change / 0.3); skewed (the
    change plus an exponential of mean 0.1, less its mean, away from 0)."""
    if shape == "rates in fifths":
        p = r.uniform(0.2, 0.8, k)
        return _fifths(r, p), _fifths(r, p + change)
    if shape.endswith("of replications still"):
        share = int(shape.split(" ")[0]) / 100
        still = r.random(k) < share
        p = r.uniform(0.2, 0.7, k)
        return (np.where(still, 0.0, _fifths(r, p)),
                np.where(still, 0.0, _fifths(r, p + change / (1 - share))))
    p = r.uniform(0.3, 0.6, k)
    if shape == "two-mode changes":
        return p, p + change + r.choice((-0.15, 0.15), k) + r.normal(0.0, 0.01, k)
    if shape.startswith("zero-inflated"):
        moved = r.random(k) < 0.3
        return p, p + moved * (change / 0.3 + r.normal(0.0, 0.02, k))
    if shape.startswith("skewed"):
        tail = (r.exponential(0.1, k) - 0.1) * (1 if change >= 0 else -1)
        return p, p + change + tail
    raise ValueError(f"unknown shape {shape!r}; known: {tuple(RATE_SHAPES)}")


def _paired_rates(nest, rng, n):
    """The rate rule (A1, A3: babbling, reach) under nulls shaped like its data
    (``RATE_SHAPES``): at a mean change of +``RATE_MARGIN`` (a reproduction is an error:
    bounded where the changes are symmetric, reported where they are not) and of 0 (a
    contradiction is an error), at ``_pair_sizes``; the rule before (paired t TOST)
    reported beside; the power to show no change in fifths."""
    rule, rows = "paired rate no change", []
    for k in _pair_sizes(nest):
        at = "" if k == nest.replications else f", {k} pairs"
        for shape, symmetric in RATE_SHAPES.items():
            for change, error in ((v.RATE_MARGIN, v.REPRODUCED), (0.0, v.CONTRADICTED)):
                scenario = (f"{shape}, change at the margin" if change else
                            f"{shape}, no change") + at
                data = _repeat(rng, n, lambda r: rate_pairs(r, shape, k, change))
                out = [v.paired_rate_equivalent(a, b) for a, b in data]
                bounded = symmetric or error == v.CONTRADICTED
                rows.append(_row(rule, nest, scenario, error,
                                 _rate([o.verdict == error for o in out]),
                                 v.ALPHA if bounded else math.nan,
                                 "at most" if bounded else "reported"))
                rows.append(_row(RATE_BEFORE, nest, scenario, error, _rate(
                    [_t_tost(b - a, v.RATE_MARGIN) == error for a, b in data]), math.nan,
                    "reported"))
                if change == 0.0 and shape == "rates in fifths":
                    rows.append(_row(rule, nest, scenario, "reproduced",
                                     _rate([o.verdict == v.REPRODUCED for o in out]),
                                     math.nan, "power"))
    return rows


def _senses(nest, rng, n):
    """Four conditions, each replication a block. Under the null of the claim each replication
    orders the conditions its own way (condition effects N(0, between_sd) drawn per
    replication); under the null of a contradiction one pair of conditions differs by the
    margin."""
    k, level = 4, 10.0

    def matrix(r, spread=1.0, apart=0.0):
        per_rep = r.normal(0.0, spread * nest.between_sd, (nest.replications, 1, k)) \
            + apart * np.arange(k) * nest.between_sd
        return (per_rep + r.normal(level, nest.between_sd, (nest.replications, 1, 1))
                + r.normal(0.0, nest.within_sd, (nest.replications, nest.robots, k))).mean(axis=1)
    out = _repeat(rng, n, lambda r: v.senses_differ(matrix(r)))
    rows = [_row("senses differ", nest, "null: each replication its own order", "reproduced",
                 _rate([o.verdict == v.REPRODUCED for o in out]), v.ALPHA, "at most")]

    def at_margin(r):
        x = matrix(r, spread=0.1)
        x[:, 1] = x[:, 0] + v.PAIRED_MARGIN * level  # one pair apart by the margin
        x[:, 1] += r.normal(0.0, nest.mean_sd / 5, nest.replications)
        return x
    out = _repeat(rng, n, lambda r: v.senses_differ(at_margin(r)))
    rows.append(_row("senses differ", nest, "one pair apart by the margin", "contradicted",
                     _rate([o.verdict == v.CONTRADICTED for o in out]), v.ALPHA, "at most"))
    out = _repeat(rng, n, lambda r: v.senses_differ(matrix(r, apart=1.0)))
    rows.append(_row("senses differ", nest, "conditions 1 s.d. apart", "reproduced",
                     _rate([o.verdict == v.REPRODUCED for o in out]), math.nan, "power"))
    out = _repeat(rng, n, lambda r: v.senses_differ(matrix(r, spread=0.05)))
    rows.append(_row("senses differ", nest, "no difference", "contradicted",
                     _rate([o.verdict == v.CONTRADICTED for o in out]), math.nan, "power"))
    return rows


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


RULES = (_directional, _against_random, _equivalence, _band, _sectors, _paired, _senses,
         _shapes, _paired_rates)


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
