"""Decision rules that keep evidence apart from its absence (section IV's claims; DESIGN.md,
"Findings as data"; docs/analysis.md, "Verdicts").

One rule per kind of claim, each a pure function of the samples that returns the verdict and
the numbers behind it:

- ``directional``: "b is higher (lower) than a" by a two-tailed Mann-Whitney U test; the
  direction is the rank statistic's (U - n_a n_b / 2), the effect size the Hodges-Lehmann shift
  (median of the pairwise differences b - a) with its distribution-free 95 % interval.
- ``equivalent``: "a and b do not differ" by two one-sided tests (Lakens 2017) on the
  probabilistic index theta = P(B > A) + P(B = A) / 2, margin 0.5 +- ``EQUIVALENCE_MARGIN``,
  with the Brunner-Munzel estimate of its standard error (Brunner & Munzel 2000; the rank
  analogue of Wellek's Mann-Whitney equivalence test).
- ``in_band``: "about half": a percentile bootstrap interval over replications inside the band.
- ``at_least``: "in every sector": every sector's lower bound above a floor.
- ``at_most``: "never": the upper bound of a share below a small epsilon.
- ``paired``: "the senses matter": Friedman's test with the robot as block.

Verdicts (``VERDICTS``): *reproduced* (the data show what the paper says), *contradicted* (they
show the opposite, or a difference where the paper says none), *inconclusive* (the data cannot
decide at this n), *underpowered* (even the most favourable data could not reach the level at
this n: decided from the sample sizes before any test), *not run*. One level ``ALPHA`` for both
directions; whether the paper's own level is met is a separate column.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from scipy import stats as sps

REPRODUCED, CONTRADICTED, INCONCLUSIVE, UNDERPOWERED, NOT_RUN = (
    "reproduced", "contradicted", "inconclusive", "underpowered", "not run")
VERDICTS = (REPRODUCED, CONTRADICTED, INCONCLUSIVE, UNDERPOWERED, NOT_RUN)

#: Significance level of every verdict, whatever the direction.
ALPHA = 0.05
#: Equivalence margin on theta = P(B > A) + P(B = A) / 2: "no difference" means theta within
#: 0.5 +- 0.15, i.e. a random robot of one group beats one of the other at most 65 % of the
#: time (a "small" effect; Vargha & Delaney 2000 put small at 0.56, medium at 0.64).
EQUIVALENCE_MARGIN = 0.15
#: Bootstrap resamples of the interval rules, and the fewest units they accept: a percentile
#: interval of fewer than 4 units is about their range, which holds the mean less than 9 times
#: in 10 (1 - 2^(1 - n)), not 19 in 20.
RESAMPLES = 10_000
MIN_BOOTSTRAP_UNITS = 4
#: "Succeed in all 9 sectors": each sector's reach and grasp rate at least this (lower bound).
SECTOR_FLOOR = 0.10
#: "Never": a share of trials at most this (upper bound).
NEVER_EPSILON = 0.05


@dataclass(frozen=True)
class Outcome:
    """A verdict and what it rests on. ``effect`` and its interval are in the units the rule
    names (a shift, a probability, a rate); ``p`` is NaN where the rule has none;
    ``paper_level_met`` is None where the paper gives no level."""

    verdict: str
    p: float = math.nan
    effect: float = math.nan
    low: float = math.nan
    high: float = math.nan
    paper_level_met: bool | None = None
    note: str = ""


def _finite(x) -> np.ndarray:
    x = np.asarray(x, float)
    return x[np.isfinite(x)]


# --------------------------------------------------------------------------------- two groups
def smallest_mann_whitney_p(n_a: int, n_b: int) -> float:
    """The smallest two-tailed p a Mann-Whitney U test can give for sizes n_a, n_b: complete
    separation, exact distribution, 2 / C(n_a + n_b, n_a)."""
    return min(1.0, 2.0 / math.comb(n_a + n_b, n_a))


def hodges_lehmann(a, b, confidence: float = 0.95) -> tuple[float, float, float]:
    """Hodges-Lehmann shift of b over a (median of the n_a n_b differences b_j - a_i) and its
    distribution-free interval: the K-th smallest and K-th largest difference, K from the
    normal approximation of U's distribution (Hollander & Wolfe, ch. 4); infinite when the
    samples are too small for that confidence."""
    a, b = _finite(a), _finite(b)
    d = np.sort((b[None, :] - a[:, None]).ravel())
    n, m = len(a), len(b)
    z = sps.norm.ppf(0.5 + confidence / 2)
    k = int(math.floor(n * m / 2 - z * math.sqrt(n * m * (n + m + 1) / 12)))
    if k < 1:
        return float(np.median(d)), -math.inf, math.inf
    return float(np.median(d)), float(d[k - 1]), float(d[len(d) - k])


def directional(a, b, sign: int, level: float) -> Outcome:
    """Claim: b is higher (``sign`` +1) or lower (-1) than a; the paper's level ``level``.
    Underpowered when even complete separation cannot reach ``ALPHA``."""
    a, b = _finite(a), _finite(b)
    if smallest_mann_whitney_p(len(a), len(b)) >= ALPHA:
        return Outcome(UNDERPOWERED, note=f"smallest possible p at {len(b)} vs {len(a)} is "
                                          f"{smallest_mann_whitney_p(len(a), len(b)):.2g}")
    shift, low, high = hodges_lehmann(a, b)
    if np.ptp(np.concatenate([a, b])) == 0:
        return Outcome(INCONCLUSIVE, 1.0, shift, low, high, False, "every value equal")
    res = sps.mannwhitneyu(b, a, alternative="two-sided")
    p = float(res.pvalue)
    observed = int(np.sign(res.statistic - len(a) * len(b) / 2))
    if p < ALPHA and observed == sign:
        verdict = REPRODUCED
    elif p < ALPHA and observed == -sign:
        verdict = CONTRADICTED
    else:
        verdict = INCONCLUSIVE
    return Outcome(verdict, p, shift, low, high, bool(p < level and observed == sign))


def probabilistic_index(a, b) -> tuple[float, float, float]:
    """theta = P(B > A) + P(B = A) / 2 from mid-ranks, its Brunner-Munzel standard error and
    degrees of freedom (Brunner & Munzel 2000). Needs at least 2 values per group."""
    a, b = _finite(a), _finite(b)
    n, m = len(a), len(b)
    ranks = sps.rankdata(np.concatenate([a, b]))
    ra, rb = ranks[:n], ranks[n:]
    theta = (rb.mean() - ra.mean()) / (n + m) + 0.5
    sa = ((ra - sps.rankdata(a) - ra.mean() + (n + 1) / 2) ** 2).sum() / (n - 1)
    sb = ((rb - sps.rankdata(b) - rb.mean() + (m + 1) / 2) ** 2).sum() / (m - 1)
    se = math.sqrt(n * sa + m * sb) / (n * m)
    if n * sa + m * sb == 0:
        return float(theta), 0.0, math.inf
    df = (n * sa + m * sb) ** 2 / ((n * sa) ** 2 / (n - 1) + (m * sb) ** 2 / (m - 1))
    return float(theta), se, float(df)


def equivalence_reachable(n_a: int, n_b: int, margin: float = EQUIVALENCE_MARGIN) -> bool:
    """Whether the most favourable continuous samples (theta = 0.5, theta's null standard error
    sqrt((n_a + n_b + 1) / (12 n_a n_b))) could show equivalence at ``ALPHA``."""
    if min(n_a, n_b) < 2:
        return False
    se = math.sqrt((n_a + n_b + 1) / (12 * n_a * n_b))
    return margin / se > sps.norm.ppf(1 - ALPHA)


def equivalent(a, b, margin: float = EQUIVALENCE_MARGIN) -> Outcome:
    """Claim: a and b do not differ. Reproduced when both one-sided tests reject theta outside
    0.5 +- ``margin`` (p = the larger of the two); contradicted when the two-tailed
    Mann-Whitney test shows a difference; otherwise inconclusive, or underpowered where the
    sizes could not show equivalence (``equivalence_reachable``). Equal values everywhere are
    no evidence of equivalence (no variance to estimate: inconclusive)."""
    a, b = _finite(a), _finite(b)
    if min(len(a), len(b)) < 2:
        return Outcome(UNDERPOWERED, note=f"{len(b)} vs {len(a)}: no variance to estimate")
    theta, se, df = probabilistic_index(a, b)
    if np.ptp(np.concatenate([a, b])) == 0:
        return Outcome(INCONCLUSIVE, math.nan, theta, note="every value equal: no evidence")
    p_diff = float(sps.mannwhitneyu(b, a, alternative="two-sided").pvalue)
    if not equivalence_reachable(len(a), len(b), margin):  # a difference can still be shown
        return Outcome(CONTRADICTED if p_diff < ALPHA else UNDERPOWERED,
                       p_diff if p_diff < ALPHA else math.nan, theta,
                       note=f"{len(b)} vs {len(a)} cannot show theta within 0.5 +- {margin:g} "
                            f"at p < {ALPHA:g}; difference p = {p_diff:.2g}")
    if se == 0:  # complete separation without spread: a difference, never equivalence
        p_eq = 1.0
        low = high = theta
    else:
        t = sps.t(df)
        p_eq = max(float(t.sf((theta - 0.5 + margin) / se)),
                   float(t.cdf((theta - 0.5 - margin) / se)))
        low, high = theta - t.ppf(1 - ALPHA) * se, theta + t.ppf(1 - ALPHA) * se
    if p_eq < ALPHA:
        verdict, p = REPRODUCED, p_eq
    elif p_diff < ALPHA:
        verdict, p = CONTRADICTED, p_diff
    else:
        verdict, p = INCONCLUSIVE, p_eq
    return Outcome(verdict, p, theta, low, high,
                   note=f"theta {theta:.2f}, 90% CI {low:.2f}-{high:.2f}; "
                        f"difference p = {p_diff:.2g}")


# ----------------------------------------------------------------------- intervals over units
def bootstrap_mean_interval(units, rng: np.random.Generator, confidence: float = 0.95
                            ) -> tuple[float, float, float]:
    """Mean of ``units`` and its percentile bootstrap interval (``RESAMPLES`` resamples)."""
    x = _finite(units)
    means = x[rng.integers(0, len(x), (RESAMPLES, len(x)))].mean(axis=1)
    tail = (1 - confidence) / 2
    return float(x.mean()), float(np.quantile(means, tail)), float(np.quantile(means, 1 - tail))


def _too_few(units) -> Outcome | None:
    x = _finite(units)
    if len(x) < MIN_BOOTSTRAP_UNITS:
        return Outcome(UNDERPOWERED, effect=float(x.mean()) if len(x) else math.nan,
                       note=f"{len(x)} replications; an interval needs at least "
                            f"{MIN_BOOTSTRAP_UNITS}")
    return None


def in_band(units, band: tuple[float, float], rng: np.random.Generator) -> Outcome:
    """Claim: the mean of ``units`` (one value per replication, a rate) lies in ``band``.
    Reproduced when the 95 % interval, kept in [0, 1], lies inside; contradicted when it lies
    wholly outside; otherwise inconclusive."""
    if (few := _too_few(units)) is not None:
        return few
    mean, low, high = bootstrap_mean_interval(units, rng)
    low, high = max(low, 0.0), min(high, 1.0)
    if band[0] <= low and high <= band[1]:
        verdict = REPRODUCED
    elif high < band[0] or low > band[1]:
        verdict = CONTRADICTED
    else:
        verdict = INCONCLUSIVE
    return Outcome(verdict, effect=mean, low=low, high=high)


def at_least(units_by_cell: dict, floor: float, rng: np.random.Generator) -> Outcome:
    """Claim: in every cell (a sector's reach or grasp), the mean over replications is at least
    ``floor``. Reproduced when every cell's lower 95 % bound is above it; contradicted when some
    cell's upper bound is below it; otherwise inconclusive. ``effect``: the lowest cell mean."""
    cells = list(units_by_cell.values())
    if (few := _too_few(cells[0] if cells else [])) is not None:
        means = [float(np.mean(_finite(c))) for c in cells if len(_finite(c))]
        return replace(few, effect=min(means) if means else math.nan)
    bounds = {k: bootstrap_mean_interval(v, rng) for k, v in units_by_cell.items()}
    worst = min(bounds, key=lambda k: bounds[k][1])
    below = [k for k, (_, _, high) in bounds.items() if high < floor]
    if below:
        verdict = CONTRADICTED
    elif all(low > floor for _, low, _ in bounds.values()):
        verdict = REPRODUCED
    else:
        verdict = INCONCLUSIVE
    mean, low, high = bounds[worst]
    note = f"weakest: {worst}" + (f"; below the floor: {', '.join(map(str, below))}"
                                  if below else "")
    return Outcome(verdict, effect=mean, low=low, high=high, note=note)


def at_most(units, epsilon: float, rng: np.random.Generator) -> Outcome:
    """Claim: a share (one value per replication) is at most ``epsilon`` ("never"). Reproduced
    when the upper 95 % bound is at most epsilon; contradicted when the lower bound is above it;
    otherwise inconclusive."""
    if (few := _too_few(units)) is not None:
        return few
    mean, low, high = bootstrap_mean_interval(units, rng, confidence=0.90)  # one-sided 95 %
    verdict = (REPRODUCED if high <= epsilon else CONTRADICTED if low > epsilon
               else INCONCLUSIVE)
    return Outcome(verdict, effect=mean, low=low, high=high)


# ------------------------------------------------------------------------------ paired samples
#: Equivalence margin of a paired claim of no change ("the behavior remains substantially the
#: same", IV-A-1): the mean change within +-20 % of the median of the reference condition.
PAIRED_MARGIN = 0.20


def smallest_signed_rank_p(n: int) -> float:
    """The smallest two-tailed p of the Wilcoxon signed-rank test of n non-zero differences
    (all of one sign, exact distribution): 2 / 2^n."""
    return min(1.0, 2.0 / 2 ** n)


def paired_directional(reference, changed, sign: int, level: float) -> Outcome:
    """Claim: ``changed`` is higher (``sign`` +1) or lower (-1) than ``reference`` in the same
    units (a robot under two conditions, a replication at two moments). Two-tailed Wilcoxon
    signed-rank test of the changes; direction from the sum of signed ranks; effect: the
    median change (Hodges-Lehmann: the median of the Walsh averages) with the bootstrap-free
    interval left out. Underpowered when the changes, all of one sign, cannot reach ``ALPHA``."""
    ref, new = np.asarray(reference, float), np.asarray(changed, float)
    keep = np.isfinite(ref) & np.isfinite(new)
    d = new[keep] - ref[keep]
    if smallest_signed_rank_p(int(np.count_nonzero(d))) >= ALPHA:
        return Outcome(UNDERPOWERED, note=f"{np.count_nonzero(d)} non-zero changes: smallest "
                                          f"possible p {smallest_signed_rank_p(int(np.count_nonzero(d))):.2g}")
    walsh = (d[:, None] + d[None, :])[np.triu_indices(len(d))]
    res = sps.wilcoxon(d, alternative="two-sided")
    p = float(res.pvalue)
    ranks = sps.rankdata(np.abs(d[d != 0]))
    observed = int(np.sign((ranks * np.sign(d[d != 0])).sum()))
    verdict = (REPRODUCED if p < ALPHA and observed == sign else
               CONTRADICTED if p < ALPHA and observed == -sign else INCONCLUSIVE)
    return Outcome(verdict, p, float(np.median(walsh)), paper_level_met=bool(
        p < level and observed == sign), note=f"{len(d)} pairs")


def paired_equivalent(reference, changed, margin: float = PAIRED_MARGIN) -> Outcome:
    """Claim: ``changed`` is substantially the same as ``reference`` (paired). Two one-sided
    paired t-tests (Lakens 2017) of the mean change against +-``margin`` x |median of the
    reference|. Reproduced when both reject; contradicted when the change differs from 0 (paired
    t, two-tailed); otherwise inconclusive. Every unit unchanged is evidence of sameness unless
    every value is the same (a floor: inconclusive). Underpowered below 3 pairs."""
    ref, new = np.asarray(reference, float), np.asarray(changed, float)
    keep = np.isfinite(ref) & np.isfinite(new)
    ref, new = ref[keep], new[keep]
    n = len(ref)
    if n < 3:
        return Outcome(UNDERPOWERED, note=f"{n} pairs")
    d = new - ref
    bound = margin * abs(float(np.median(ref)))
    mean, sd = float(d.mean()), float(d.std(ddof=1))
    if np.ptp(np.concatenate([ref, new])) == 0:
        return Outcome(INCONCLUSIVE, effect=mean, note="every value equal: no evidence")
    if sd == 0:
        same = abs(mean) < bound or mean == 0
        return Outcome(REPRODUCED if same else CONTRADICTED, 0.0, mean, mean, mean,
                       note=f"every unit changed by {mean:.3g} (margin +-{bound:.3g})")
    se, t = sd / math.sqrt(n), sps.t(n - 1)
    p_eq = max(float(t.sf((mean + bound) / se)), float(t.cdf((mean - bound) / se)))
    p_diff = float(2 * t.sf(abs(mean) / se))
    low, high = mean - t.ppf(1 - ALPHA) * se, mean + t.ppf(1 - ALPHA) * se
    verdict = (REPRODUCED if p_eq < ALPHA else CONTRADICTED if p_diff < ALPHA
               else INCONCLUSIVE)
    return Outcome(verdict, p_eq if verdict != CONTRADICTED else p_diff, mean, low, high,
                   note=f"mean change {mean:.3g}, 90% CI {low:.3g} to {high:.3g}, margin "
                        f"+-{bound:.3g}; difference p = {p_diff:.2g}")


# ------------------------------------------------------------------------------ paired blocks
def smallest_friedman_p(blocks: int, treatments: int) -> float:
    """The smallest p of Friedman's chi-square for ``blocks`` with every block ranking the
    treatments the same way (chi2 = blocks (treatments - 1))."""
    return float(sps.chi2.sf(blocks * (treatments - 1), treatments - 1))


def paired(matrix, level: float) -> Outcome:
    """Claim: the treatments (columns) differ, each row a block (a robot under every sensory
    condition). Friedman's test; effect: Kendall's W (0 = no agreement, 1 = every block ranks
    the treatments alike). A difference is what the paper claims, so there is no
    "contradicted": no difference is inconclusive."""
    x = np.asarray(matrix, float)
    x = x[np.isfinite(x).all(axis=1)]
    n, k = x.shape
    if smallest_friedman_p(n, k) >= ALPHA:
        return Outcome(UNDERPOWERED, note=f"{n} blocks: smallest possible p "
                                          f"{smallest_friedman_p(n, k):.2g}")
    if np.ptp(x) == 0:
        return Outcome(INCONCLUSIVE, 1.0, 0.0, paper_level_met=False, note="every value equal")
    chi2, p = sps.friedmanchisquare(*x.T)
    w = float(chi2) / (n * (k - 1))
    return Outcome(REPRODUCED if p < ALPHA else INCONCLUSIVE, float(p), w,
                   paper_level_met=bool(p < level))


# --------------------------------------------------------------------------------- the table
def holm(p: Sequence[float]) -> np.ndarray:
    """Holm's step-down adjusted p-values (NaN stays NaN, not counted)."""
    p = np.asarray(p, float)
    out = np.full(len(p), math.nan)
    idx = np.flatnonzero(np.isfinite(p))
    order = idx[np.argsort(p[idx])]
    m, running = len(order), 0.0
    for i, j in enumerate(order):
        running = max(running, min(1.0, (m - i) * p[j]))
        out[j] = running
    return out
