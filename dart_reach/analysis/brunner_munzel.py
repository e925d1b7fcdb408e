"""The studentized permutation test of the Brunner-Munzel statistic (Neubert & Brunner 2007),
on the logit scale (Pauly, Asendorf & Konietschke 2016): the two-group rule whose null is
what a directional claim means, and which holds its level when the groups' shapes differ.

The effect is the probabilistic index theta = P(B > A) + P(B = A) / 2 of the two groups' units;
the null is theta = 0.5, whatever the groups' shapes or spreads (Mann-Whitney's exact null is
that the two groups have the *same distribution*: under theta = 0.5 with a bimodal group
against a unimodal one it decides more often than its level; docs/results/calibration.md).
theta's standard error se is Brunner & Munzel's (2000), from the variances of the placements
(``scipy.stats.brunnermunzel``'s, tested equal), never below ``smallest_se``; the statistic is
T = logit(theta) theta (1 - theta) / se, the logit of theta over its delta-method standard
error (theta clipped 1 / (n_a n_b) inside (0, 1)), so that the interval stays in (0, 1) and
covers a theta near 0 or 1 (on theta's own scale it does not: se is small there). The t
approximation is liberal at a few units a group, so p comes from the distribution of T over
the splits of the pooled units into groups of the same sizes: every split when there are at
most ``EXACT_SPLITS`` (exact; 924 at 6 vs 6), else ``PERMUTATIONS`` random ones (Monte
Carlo) drawn by a generator seeded with ``SEED`` (the same data, the same p), p then
(1 + count) / (1 + PERMUTATIONS). Studentizing makes the permutation test asymptotically
exact for theta = 0.5 even when the shapes differ, and exact when they are the same.

The interval of theta is the test inverted with the same permutation distribution:
expit(logit(theta) +- q se / (theta (1 - theta))), q the permutation critical value of |T|:
0.5 lies outside it exactly when the two-sided p is below 1 - confidence, so a verdict and
its interval always agree (ties included). Complete separation (se 0) has a finite T, equal
to that of the splits one pair short of it, and an interval.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy import special

#: At most this many distinct splits: every one is used (an exact test).
EXACT_SPLITS = 10_000
#: Random splits beyond ``EXACT_SPLITS``: the Monte Carlo s.e. of a p near 0.05 is 0.005
#: (the level holds at any number: the observed split is one of them).
PERMUTATIONS = 1_999
#: Seed of the random splits.
SEED = 2000


@dataclass(frozen=True)
class Result:
    """theta, its interval [low, high] at ``confidence``, the p of ``alternative``, the
    statistic T and the number of splits the p is over (``exact``: every split)."""

    theta: float
    low: float
    high: float
    confidence: float
    p: float
    statistic: float
    splits: int
    exact: bool
    p_greater: float = math.nan
    p_less: float = math.nan


@functools.cache
def _splits(n_a: int, n_b: int) -> tuple[np.ndarray, bool]:
    """Boolean membership of group b (rows: splits; columns: the pooled units, a's first);
    the observed split is row 0."""
    total = math.comb(n_a + n_b, n_b)
    if total <= EXACT_SPLITS:
        rows = np.zeros((total, n_a + n_b), bool)
        for i, chosen in enumerate(itertools.combinations(range(n_a + n_b), n_b)):
            rows[i, list(chosen)] = True
        observed = np.zeros(n_a + n_b, bool)
        observed[n_a:] = True
        rows = rows[np.argsort(~(rows == observed).all(axis=1), kind="stable")]
        return rows, True
    rng = np.random.default_rng(SEED)
    rows = np.zeros((PERMUTATIONS + 1, n_a + n_b), bool)
    rows[0, n_a:] = True
    for i in range(1, PERMUTATIONS + 1):
        rows[i, rng.permutation(n_a + n_b)[:n_b]] = True
    return rows, False


#: Relative tolerance under which two values of T are the same (splits that are mirror images
#: give the same |T| up to rounding).
TOLERANCE = 1e-9


def _placements(pooled, in_b: np.ndarray):
    """theta and the variances of the placements of a's and b's units of every split, and
    the group sizes: ``pooled`` the N values, ``in_b`` the (splits, N) membership of group b.
    A unit's placement: its count of the other group's units below it, ties 1/2."""
    x = np.asarray(pooled, float)
    compare = (x[:, None] > x[None, :]) + 0.5 * (x[:, None] == x[None, :])
    below = compare.sum(axis=1) - 0.5  # every other unit below it, ties 1/2
    b = in_b.astype(float)
    a = 1.0 - b
    n_a, n_b = a[0].sum(), b[0].sum()
    among_a = np.einsum("pj,ij->pi", a, compare)  # placements among the split's a (einsum:
    # no threaded BLAS, which is slower for these small products on a busy machine)
    among_b = below - among_a        # ... and among its b (itself left out)
    mean_b = (b * among_a).sum(axis=1) / n_b
    mean_a = (a * among_b).sum(axis=1) / n_a
    with np.errstate(divide="ignore", invalid="ignore"):  # a group of 1: no variance
        var_b = (b * (among_a - mean_b[:, None]) ** 2).sum(axis=1) / (n_b - 1)
        var_a = (a * (among_b - mean_a[:, None]) ** 2).sum(axis=1) / (n_a - 1)
    return mean_b / n_a, var_a, var_b, n_a, n_b


def statistics(pooled, in_b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """theta, its standard error (never below ``smallest_se``) and T of every split:
    ``pooled`` the N values, ``in_b`` the (splits, N) membership of group b."""
    theta, var_a, var_b, n_a, n_b = _placements(pooled, in_b)
    se = np.maximum(np.sqrt(var_a / (n_a * n_b ** 2) + var_b / (n_b * n_a ** 2)),
                    smallest_se(int(n_a), int(n_b)))
    return theta, se, _logit(theta, int(n_a), int(n_b)) / se


def probabilistic_index(a, b) -> tuple[float, float, float]:
    """theta = P(B > A) + P(B = A) / 2 of b against a (the finite values), its Brunner-Munzel
    standard error and Satterthwaite degrees of freedom (Brunner & Munzel 2000;
    ``scipy.stats.brunnermunzel``'s, tested equal): the observed split of ``statistics``,
    without its floor, for the rules that use theta on its own scale (``verdicts``). The
    standard error is 0 under complete separation (degrees of freedom infinite), NaN with
    fewer than 2 values in a group (theta is defined from 1)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    a, b = a[np.isfinite(a)], b[np.isfinite(b)]
    observed = np.zeros((1, len(a) + len(b)), bool)
    observed[0, len(a):] = True
    theta, var_a, var_b, n_a, n_b = _placements(np.concatenate([a, b]), observed)
    theta, var_a, var_b = float(theta[0]), float(var_a[0]), float(var_b[0])
    if min(n_a, n_b) < 2:
        return theta, math.nan, math.nan
    if var_a == 0 and var_b == 0:
        return theta, 0.0, math.inf
    se = math.sqrt(var_a / (n_a * n_b ** 2) + var_b / (n_b * n_a ** 2))
    df = (n_a * var_a + n_b * var_b) ** 2 / ((n_a * var_a) ** 2 / (n_a - 1)
                                             + (n_b * var_b) ** 2 / (n_b - 1))
    return theta, se, float(df)


def _clip(theta, n_a: int, n_b: int):
    """theta kept 1 / (n_a n_b) inside (0, 1), where its logit is finite: complete
    separation counts as one pair short of it, and with ``smallest_se`` ties the split of one
    pair swapped (any closer edge would rank it below that split)."""
    edge = 1 / (n_a * n_b)
    return np.clip(theta, edge, 1 - edge)


def _logit(theta, n_a: int, n_b: int):
    """logit(theta) x theta (1 - theta), theta clipped (``_clip``): theta - 0.5 to first
    order, on the logit scale (the delta method's: T is then logit(theta) over its s.e.)."""
    c = _clip(theta, n_a, n_b)
    return np.where(np.abs(theta - 0.5) < 1e-12, 0.0, special.logit(c)) * c * (1 - c)


def smallest_se(n_a: int, n_b: int) -> float:
    """The floor of the standard error: sqrt(2) / (n_a n_b), Brunner-Munzel's for the samples
    nearest complete separation (one unit of each group one place over). Without it complete
    separation (se 0) would give T infinite and theta an interval of one point."""
    return math.sqrt(2) / (n_a * n_b)


def test(a, b, alternative: str = "two-sided", confidence: float = 0.95) -> Result:
    """Studentized permutation Brunner-Munzel test of b against a: ``alternative``
    "two-sided", "greater" (b higher: theta > 0.5) or "less"; the interval is the two-sided
    one at ``confidence`` whatever the alternative. ValueError with fewer than 2 finite values
    a group, an unknown alternative or a confidence outside (0, 1)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    a, b = a[np.isfinite(a)], b[np.isfinite(b)]
    if min(len(a), len(b)) < 2:
        raise ValueError(f"Brunner-Munzel needs at least 2 finite values a group, got "
                         f"{len(a)} and {len(b)}")
    if alternative not in ("two-sided", "greater", "less"):
        raise ValueError(f"unknown alternative {alternative!r}")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence!r}")
    in_b, exact = _splits(len(a), len(b))
    theta, se, t = statistics(np.concatenate([a, b]), in_b)
    observed, permuted = t[0], (t if exact else t[1:])
    extra = 0 if exact else 1  # Monte Carlo: the observed split counts once more
    total = len(permuted) + extra
    at_least = {"two-sided": (np.abs(permuted), abs(observed)),
                "greater": (permuted, observed), "less": (-permuted, -observed)}
    ps = {side: min(1.0, (extra + int(np.count_nonzero(values >= at - TOLERANCE * abs(at))))
                    / total) for side, (values, at) in at_least.items()}
    p = ps[alternative]
    # q: |T| > q exactly when the two-sided p < 1 - confidence (the k-th largest |T|)
    k = math.ceil((1 - confidence) * total - extra)
    q = float(np.sort(np.abs(permuted))[::-1][k - 1]) / (1 - TOLERANCE) if k >= 1 else math.inf
    clipped = float(_clip(theta[0], len(a), len(b)))
    half = q * se[0] / (clipped * (1 - clipped))
    low, high = special.expit(special.logit(clipped) + np.array([-half, half]))
    return Result(float(theta[0]), float(low), float(high), confidence, float(p),
                  float(observed), total, exact, ps["greater"], ps["less"])
