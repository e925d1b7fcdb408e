"""The paired rules of ``verdicts`` (the same units under two conditions or at two moments, and
the sensory conditions with the replication as block), kept apart by family; ``verdicts``
re-exports them, so ``verdicts.paired_equivalent`` and the rest are where they always were.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.stats import rankdata

from .verdict_core import (ALPHA, CONTRADICTED, FRIEDMAN_LEVEL, INCONCLUSIVE,
                           PAIRED_CHANGE_LEVEL, PAIRED_EQUIVALENCE_LEVEL, PAIRED_MARGIN,
                           RATE_MARGIN, REPRODUCED, UNDERPOWERED, Outcome, finite, friedman,
                           no_spread, normal_sf, signed_rank_distribution, smallest_friedman_p,
                           smallest_signed_rank_p, t_cdf, t_quantile, t_sf, tie_sum,
                           walsh_median)


# ------------------------------------------------------------------------------ paired units
def wilcoxon(d, alternative: str = "two-sided") -> tuple[float, int]:
    """p of the Wilcoxon signed-rank test of the changes ``d`` (zeros dropped) and their
    observed direction: exact without ties (``signed_rank_distribution``), else the normal
    approximation with the tie correction. Equal to ``scipy.stats.wilcoxon(d, method="exact" /
    "approx")`` (tested)."""
    d = finite(d)
    d = d[d != 0]
    n = len(d)
    if n == 0:
        return 1.0, 0
    ranks = rankdata(np.abs(d))
    t_plus = float(ranks[d > 0].sum())
    mu = n * (n + 1) / 4
    direction = int(np.sign(t_plus - mu))
    ties = tie_sum(np.abs(d))
    if ties == 0:
        cdf = np.cumsum(signed_rank_distribution(n))
        k = int(round(t_plus))
        below, above = cdf[k], 1.0 - (cdf[k - 1] if k else 0.0)
        p = {"two-sided": min(1.0, 2 * min(below, above)), "greater": above,
             "less": below}[alternative]
        return float(min(max(p, 0.0), 1.0)), direction
    sd = math.sqrt(n * (n + 1) * (2 * n + 1) / 24 - ties / 48)
    z = (t_plus - mu) / sd
    p = {"two-sided": min(1.0, 2 * normal_sf(abs(z))), "greater": normal_sf(z),
         "less": normal_sf(-z)}[alternative]
    return float(p), direction


def paired_directional(reference, changed, sign: int, level: float = ALPHA,
                       test_level: float = PAIRED_CHANGE_LEVEL) -> Outcome:
    """Claim: ``changed`` is higher (``sign`` +1) or lower (-1) than ``reference`` in the same
    units (a replication under two conditions or in two generation windows). Two-tailed
    Wilcoxon signed-rank test of the changes at ``test_level``; direction from the signed
    ranks; effect: the Hodges-Lehmann change with its exact interval at 1 - ``test_level``.
    Underpowered when changes all of one sign cannot reach ``test_level``; ``level`` is the
    paper's (``paper_level_met``)."""
    ref, new = np.asarray(reference, float), np.asarray(changed, float)
    keep = np.isfinite(ref) & np.isfinite(new)
    d = new[keep] - ref[keep]
    nonzero = int(np.count_nonzero(d))
    if len(d) == 0:
        return Outcome(UNDERPOWERED, note="no pairs")
    confidence = 1 - test_level
    effect, low, high = walsh_median(d, confidence)
    if smallest_signed_rank_p(len(d)) >= test_level:
        return Outcome(UNDERPOWERED, effect=effect, low=low, high=high, confidence=confidence,
                       note=f"{len(d)} pairs: the smallest possible p is "
                            f"{smallest_signed_rank_p(len(d)):.2g}")
    if nonzero == 0:
        return Outcome(INCONCLUSIVE, 1.0, effect, low, high, confidence, 1.0, False,
                       "no unit changed: no evidence")
    p, observed = wilcoxon(d)
    verdict = (REPRODUCED if p < test_level and observed == sign else
               CONTRADICTED if p < test_level and observed == -sign else INCONCLUSIVE)
    return Outcome(verdict, p if observed == sign else 1.0, effect, low, high, confidence,
                   p if observed == -sign else 1.0, bool(p < level and observed == sign),
                   f"{len(d)} pairs")


def paired_tost(reference, changed, bound: float) -> tuple[float, float, float, float, float]:
    """Two one-sided paired t-tests of the mean change against +-``bound``: (p of
    equivalence, p of a difference (two-tailed), mean change, its 90 % interval). The rule
    before ``sign_flip_tost`` (its calibration rows are reported beside the rule's)."""
    d = np.asarray(changed, float) - np.asarray(reference, float)
    d = d[np.isfinite(d)]
    n, mean, sd = len(d), float(d.mean()), float(d.std(ddof=1))
    if sd == 0:
        return (0.0 if abs(mean) < bound else 1.0), (0.0 if mean else 1.0), mean, mean, mean
    se = sd / math.sqrt(n)
    p_eq = max(t_sf((mean + bound) / se, n - 1), t_cdf((mean - bound) / se, n - 1))
    p_diff = 2 * t_sf(abs(mean) / se, n - 1)
    half = t_quantile(1 - ALPHA, n - 1) * se
    return p_eq, p_diff, mean, mean - half, mean + half


#: Units up to which ``sign_flip_tost`` enumerates every sign vector (2^16); beyond (the
#: robot-level analyses beside the headline), ``FLIPS`` random ones drawn from ``FLIP_SEED``.
EXACT_FLIP_UNITS = 16
FLIPS = 9_999
FLIP_SEED = 2013


def _flipped_sets(d: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The sums and sizes of the units whose sign a sign vector flips, over every sign
    vector but the identity (exact up to ``EXACT_FLIP_UNITS`` units), or over ``FLIPS``
    random ones (the empty set included, as drawn), and the count of vectors a p is over."""
    n = len(d)
    if n <= EXACT_FLIP_UNITS:
        sums, sizes = np.zeros(1), np.zeros(1)
        for x in d:
            sums, sizes = np.concatenate([sums, sums + x]), np.concatenate([sizes, sizes + 1])
        return sums[1:], sizes[1:], 2 ** n
    flips = np.random.default_rng(FLIP_SEED).random((FLIPS, n)) < 0.5
    return flips @ d, flips.sum(axis=1).astype(float), FLIPS + 1


def sign_flip_tost(d, bound: float, confidence: float = 1 - 2 * ALPHA
                   ) -> tuple[float, float, float, float]:
    """The exact sign-flip test of paired changes ``d`` (Fisher's, on their sum; exact for
    changes symmetric about their centre, whatever their shape, ties and zeros included) as
    two one-sided tests against +-``bound`` and as a test of no change: (p of equivalence,
    p of a difference (two-tailed), and the interval of the centre at ``confidence`` that
    inverts the one-sided tests). A sign vector flips a set F of units; the sum of the
    flipped changes less the bound is below the observed one exactly when the mean of d over
    F is at least the bound, so each p counts the sets F whose mean lies beyond (ties count
    against the claim) and the interval's ends are order statistics of those means."""
    d = finite(d)
    sums, sizes, total = _flipped_sets(d)
    tol = 1e-9 * max(1.0, float(np.abs(d).sum()))
    means = sums / np.where(sizes > 0, sizes, 1)
    empty = sizes == 0  # an empty flipped set (random draws only): in every tail
    p_upper = (1 + np.count_nonzero((sums >= bound * sizes - tol) | empty)) / total
    p_lower = (1 + np.count_nonzero((sums <= -bound * sizes + tol) | empty)) / total
    p_more = (1 + np.count_nonzero(sums <= tol)) / total
    p_less = (1 + np.count_nonzero(sums >= -tol)) / total
    # the one-sided tests at (1 - confidence) / 2 reject a centre beyond the k-th most
    # extreme mean, k the most sets whose count still gives p below that level
    k = math.ceil((1 - confidence) / 2 * total - 1) - 1
    ordered = np.sort(means[~empty])
    low = float(ordered[k]) if 0 <= k < len(ordered) else -math.inf
    high = float(ordered[len(ordered) - 1 - k]) if 0 <= k < len(ordered) else math.inf
    return (float(max(p_upper, p_lower)), float(min(1.0, 2 * min(p_more, p_less))), low,
            high)


#: The changes are *lopsided* (``lopsided``) when at most this many of the units that changed
#: at all moved against the rest: the changes lie (almost) wholly on one side of 0.
LOPSIDED_MINORITY = 1


def lopsided(d) -> str:
    """Why the paired changes ``d`` (one per unit, in the measure's units: a rate change, a
    relative change; section IV-A's claims of no change) are too lopsided for the exact
    sign-flip test of their mean, or "" when they are not. The test is exact for changes
    symmetric about their centre; no test of a mean change is exact whatever its shape, and
    where the changes lie (almost) wholly on one side of 0 (at most ``LOPSIDED_MINORITY`` of
    the units that changed at all moved against the rest: the unchanged ones at 0 and a few
    moved far, as replications still under both conditions beside a few that changed, or every
    unit moved one way by a skewed amount, as a rate held up by its floor at 0) a mean at the
    margin looks like a smaller one more often than the test allows (docs/results/
    calibration.md, the rows of zero-inflated and skewed changes). The criterion is fixed from
    the changes' form alone (their signs), before any test; skewed changes that straddle 0
    are beyond it (no criterion on the form of 10 changes tells them from symmetric ones
    without refusing a large share of those: the calibration reports them)."""
    d = finite(d)
    moved = d[d != 0]
    up, down = int((moved > 0).sum()), int((moved < 0).sum())
    if len(moved) == 0 or min(up, down) > LOPSIDED_MINORITY:
        return ""
    return f"of {len(d)} pairs {up} moved up, {down} down, {len(d) - len(moved)} not at all"


def _equivalence(d: np.ndarray, bound: float, what: str) -> Outcome:
    """The verdict of a claim of no change on the changes ``d`` within +-``bound``
    (``sign_flip_tost``, its one-sided tests at ``PAIRED_EQUIVALENCE_LEVEL``): underpowered
    where a difference could not be shown even with every change of one sign
    (``smallest_signed_rank_p``: 2 / 2^n, fewer than 6 pairs); inconclusive without spread (no
    evidence); reproduced when both one-sided tests reject and the changes are not lopsided
    (``lopsided``: the gate; there the test of the mean is not exact, and no change cannot be
    decided), contradicted when the test of no change rejects at ``ALPHA`` (a change shown),
    else underpowered where no change could not be shown whatever the data (1 / 2^n, the
    smallest one-sided p, not below the level: fewer than 8 pairs), else inconclusive. ``p``
    stays the sign-flip test's, gated or not."""
    n, smallest = len(d), smallest_signed_rank_p(len(d))
    level = PAIRED_EQUIVALENCE_LEVEL
    if smallest >= ALPHA:
        return Outcome(UNDERPOWERED, effect=float(d.mean()) if n else math.nan,
                       note=f"{n} pairs: the smallest possible p of the sign-flip test is "
                            f"{smallest:.2g} (two-tailed), {smallest / 2:.2g} (one-sided)")
    if no_spread(d):
        return Outcome(INCONCLUSIVE, effect=float(d.mean()),
                       note="every unit changed alike: no evidence")
    p_eq, p_diff, low, high = sign_flip_tost(d, bound, confidence=1 - 2 * level)
    why = lopsided(d)
    verdict = (REPRODUCED if p_eq < level and not why else CONTRADICTED if p_diff < ALPHA
               else UNDERPOWERED if smallest / 2 >= level else INCONCLUSIVE)
    note = (f"{what} within +-{bound:.3g} (exact sign-flip test, {n} pairs, each one-sided "
            f"test at {level:g}); difference p = {p_diff:.2g}")
    if verdict == UNDERPOWERED:
        note = (f"{n} pairs: no change cannot be shown, the smallest one-sided p being "
                f"{smallest / 2:.2g}, not below {level:g}; " + note)
    if why:
        note = (f"cannot decide no change: the changes are lopsided ({why}), where the "
                f"sign-flip test of their mean is not exact ({n} pairs: its smallest possible "
                f"p is {smallest / 2:.2g} one-sided; equivalence p = {p_eq:.2g}); " + note)
    return Outcome(verdict, p_eq, float(d.mean()), low, high, 1 - 2 * level, p_diff, note=note)


def relative_changes(reference, changed) -> np.ndarray:
    """Each unit's change relative to its own level: (changed - reference) over their mean
    magnitude, 0 where both are 0 (in [-2, 2]; +-0.2 is a change of about 20 %)."""
    ref, new = np.asarray(reference, float), np.asarray(changed, float)
    scale = (np.abs(ref) + np.abs(new)) / 2
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(scale > 0, (new - ref) / np.where(scale > 0, scale, 1.0), 0.0)


def paired_equivalent(reference, changed, margin: float = PAIRED_MARGIN,
                      relative: bool = False) -> Outcome:
    """Claim: ``changed`` is substantially the same as ``reference`` (paired). The exact
    sign-flip test (``sign_flip_tost``) of the mean change against +-``margin`` x |median of
    the reference|, or with ``relative`` of the mean of each unit's change relative to its
    own level (``relative_changes``) against +-``margin`` (a still replication and a babbling
    one each keep their own scale): reproduced when both one-sided tests reject at
    ``PAIRED_EQUIVALENCE_LEVEL``; contradicted when the change differs from 0 (two-tailed,
    ``ALPHA``); otherwise inconclusive; the interval is the centre's 1 - 2 x that level.
    Underpowered below 6 pairs (``_equivalence``: the smallest one-sided p of 4 pairs is
    1/16), whatever the data, and below 8 unless a change is shown; changes without spread
    are no evidence."""
    ref, new = np.asarray(reference, float), np.asarray(changed, float)
    keep = np.isfinite(ref) & np.isfinite(new)
    ref, new = ref[keep], new[keep]
    d = relative_changes(ref, new) if relative else new - ref
    bound = margin if relative else margin * abs(float(np.median(ref))) if len(ref) else margin
    return _equivalence(d, bound, "relative change" if relative else "change")


def paired_rate_equivalent(reference, changed, margin: float = RATE_MARGIN) -> Outcome:
    """Claim: a *rate* (a share of trials in [0, 1]: babbling, reach) is substantially the
    same under ``changed`` as under ``reference``, in the same units (replications; a robot's
    rate is its mean over its trials, and a condition whose trials repeat one another, as the
    ball-absent ones do (the scene is the same in every trial and the controller is
    deterministic, so a robot's 45 no-ball trials are one trial 45 times), adds nothing to n:
    n is the units, never the trials). Judged on the rate's own scale: the exact sign-flip
    test (``sign_flip_tost``) of the mean absolute change against +-``margin``
    (``RATE_MARGIN``, rate units, fixed from the paper): reproduced when both one-sided tests
    reject at ``PAIRED_EQUIVALENCE_LEVEL``; contradicted when the change differs from 0
    (two-tailed, ``ALPHA``); otherwise inconclusive. A unit at 0 is a level like any other
    (the relative change of ``paired_equivalent(relative=True)`` is -2 there). Underpowered
    below 6 pairs, whatever the data, and below 8 unless a change is shown; changes without
    spread are no evidence (inconclusive). The test is exact for changes symmetric about their
    centre (rates in fifths, still replications, two-mode changes); lopsided changes are gated
    (``lopsided``) and skewed ones that straddle 0 are held by the level
    (docs/results/calibration.md)."""
    ref, new = np.asarray(reference, float), np.asarray(changed, float)
    keep = np.isfinite(ref) & np.isfinite(new)
    return _equivalence(new[keep] - ref[keep], margin, "rate change")


# ------------------------------------------------------------------------------ paired blocks
def senses_differ(matrix, level: float = ALPHA, margin: float = PAIRED_MARGIN,
                  test_level: float = FRIEDMAN_LEVEL) -> Outcome:
    """Claim: the treatments (columns, e.g. the four sensory conditions) differ, each row a
    block (a replication under every condition). Friedman's test at ``test_level`` (``level``:
    the paper's, ``paper_level_met``); effect: Kendall's W (0: no
    agreement, 1: every block ranks the treatments alike). Contradicted when every pair of
    treatments is equivalent (the exact sign-flip test of each pair's changes within
    ``margin`` x |median of the pair's first|, ``sign_flip_tost``; the largest p of the pairs
    below ``PAIRED_EQUIVALENCE_LEVEL``, an intersection-union test; never below 8 blocks, where
    no such test can decide, nor through a lopsided pair); otherwise inconclusive."""
    x = np.asarray(matrix, float)
    x = x[np.isfinite(x).all(axis=1)]
    n, k = x.shape
    if n < 2 or smallest_friedman_p(n, k) >= test_level:
        return Outcome(UNDERPOWERED, note=f"{n} blocks: the smallest possible p is "
                                          f"{smallest_friedman_p(max(n, 1), k):.2g}")
    if no_spread(x) or all(no_spread(block) for block in x):  # no ranks to compare
        return Outcome(INCONCLUSIVE, 1.0, 0.0, paper_level_met=False,
                       note="every value equal" + ("" if no_spread(x) else " within each "
                                                   "block") + ": no evidence")
    chi2, p = friedman(x)
    w = chi2 / (n * (k - 1))
    decidable = smallest_signed_rank_p(n) / 2 < PAIRED_EQUIVALENCE_LEVEL
    pairs = {(i, j): x[:, j] - x[:, i] for i in range(k) for j in range(i + 1, k)}
    uneven = sum(bool(lopsided(d)) for d in pairs.values()) if decidable else 0
    p_same = max(sign_flip_tost(d, margin * abs(float(np.median(x[:, i]))))[0]
                 for (i, _), d in pairs.items()) if decidable and not uneven else 1.0
    verdict = (REPRODUCED if p < test_level else CONTRADICTED if p_same < PAIRED_EQUIVALENCE_LEVEL
               else INCONCLUSIVE)
    return Outcome(verdict, float(p), w, p_against=p_same, paper_level_met=bool(p < level),
                   note=f"{n} blocks x {k} conditions; all pairs equivalent p = {p_same:.2g} "
                        f"(each one-sided test at {PAIRED_EQUIVALENCE_LEVEL:g})"
                        + (f" (cannot be shown: {uneven} of the {len(pairs)} pairs' changes are "
                           "lopsided)" if uneven else ""))

