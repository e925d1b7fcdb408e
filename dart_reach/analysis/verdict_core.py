"""What every verdict rule shares (``verdicts``, ``paired_verdicts``): the verdicts, the
level and margins, the ``Outcome`` a rule returns, and the exact null distributions, smallest
attainable p-values and interval helpers the rules are built from."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy import special
from scipy.stats import rankdata

from . import brunner_munzel

REPRODUCED, CONTRADICTED, INCONCLUSIVE, UNDERPOWERED, NOT_RUN = (
    "reproduced", "contradicted", "inconclusive", "underpowered", "not run")
VERDICTS = (REPRODUCED, CONTRADICTED, INCONCLUSIVE, UNDERPOWERED, NOT_RUN)
DECIDED = (REPRODUCED, CONTRADICTED)

#: Significance level of every verdict, whatever the direction.
ALPHA = 0.05
#: Margin on theta = P(B > A) + P(B = A) / 2 of "no (significant) difference" and "not
#: significantly better": a unit of one group beats one of the other at most 65 % of the time
#: (Vargha & Delaney 2000 put small at 0.56, medium at 0.64). Fixed before any data was judged.
EQUIVALENCE_MARGIN = 0.15
#: Margin of a paired claim of no change ("the behavior remains substantially the same",
#: IV-A-1): the mean change within +-20 % of the median of the reference condition.
PAIRED_MARGIN = 0.20
#: Margin of a paired claim of no change in a *rate* (babbling, reach: a share of trials, in
#: [0, 1]), in rate units: the mean change within +-0.10. It is ``PAIRED_MARGIN`` (20 %) of
#: the one rate level the paper gives of pre-reachers, "about half of the trials" (0.5, the
#: centre of ``claims.ABOUT_HALF``, F1, IV-A-1), fixed from the paper before any data was
#: judged on it: 4.5 of a robot's 45 trials. A relative change ((new - ref) / mean) is -2
#: whenever one side is 0, so one babbling trial in 225 would decide a rate near 0.
RATE_MARGIN = 0.10
#: One-sided level of each of the two one-sided tests of a paired claim of no change
#: (``paired_verdicts``: a rate, a relative change, the equivalence side of "senses differ"):
#: the least favourable level over the declared null family of the changes' shapes (the
#: calibration's, and skewed changes straddling 0 by 2-4 margins; pre-registered in
#: docs/model/claims.md, "Skewed changes across 0"): the largest of 0.050, 0.045, ..., 0.005
#: whose largest error over the family was at most ``ALPHA`` on a pilot apart from the
#: calibration (seed 2113, ``paired_calibration.level_pilot``): 0.010 gave 0.0505, 0.050 gave
#: 0.130, under changes straddling 0 by 2 margins. Its interval is the centre's 1 - 2 x this.
#: A difference (the contradiction) stays at ``ALPHA``, two-tailed.
PAIRED_EQUIVALENCE_LEVEL = 0.005
#: "Succeed in all 9 sectors": each sector's reach and grasp rate at least this (lower bound).
SECTOR_FLOOR = 0.10
#: The fewest units of an interval rule: Student's t with at least 2 degrees of freedom.
MIN_UNITS = 3
#: The band's and every sector's gate (the fewest replications they decide at) and the
#: one-sided level of each bound they decide by (the band: each edge; every sector: each
#: cell's lower bound), and the level of the paired change's Wilcoxon test (which decides from
#: 7 pairs at it: 2 / 2^7) and of "senses differ"'s Friedman test: chosen over the declared
#: family of nulls shaped like the runs' rates on a pilot apart from the calibration
#: (docs/model/claims.md, "Rates shaped like the runs'"; ``run_shaped_calibration.pilot`` and
#: ``choose``, its table committed and shown in docs/results/calibration.md). Before it: the
#: band from 3 at 0.025 (a 95 % interval), every sector at 0.05, both tests at ``ALPHA``.
BAND_MIN_UNITS, BAND_LEVEL = 10, 0.005
SECTOR_MIN_UNITS, SECTOR_LEVEL = MIN_UNITS, 0.02
PAIRED_CHANGE_LEVEL = 0.02
FRIEDMAN_LEVEL = 0.025


@dataclass(frozen=True)
class Outcome:
    """A verdict and what it rests on. ``effect`` and its interval [``low``, ``high``] are in
    the units the rule names (a shift, a probability, a rate); ``confidence`` is the interval's
    level; ``p`` is the p of the rule's test of the claim as stated (NaN where the rule has
    none), ``p_against`` the p of its test of the opposite (a contradiction);
    ``paper_level_met`` is None where the paper gives no level."""

    verdict: str
    p: float = math.nan
    effect: float = math.nan
    low: float = math.nan
    high: float = math.nan
    confidence: float = math.nan
    p_against: float = math.nan
    paper_level_met: bool | None = None
    note: str = ""


def finite(x) -> np.ndarray:
    """The finite values of ``x`` as a float array."""
    x = np.asarray(x, float)
    return x[np.isfinite(x)]


def no_spread(*groups) -> bool:
    """Whether the values of ``groups`` together have no spread (or there are none)."""
    values = np.concatenate([np.ravel(g) for g in groups])
    return len(values) == 0 or bool(np.ptp(values) == 0)


def t_cdf(x: float, df: float) -> float:
    """Student's t distribution function (``scipy.special.stdtr``: the scipy.stats object is
    a hundred times slower, which matters for calibration)."""
    return float(special.stdtr(df, x))


def t_sf(x: float, df: float) -> float:
    return float(special.stdtr(df, -x))


def t_quantile(q: float, df: float) -> float:
    return float(special.stdtrit(df, q))


def friedman(x: np.ndarray) -> tuple[float, float]:
    """Friedman's chi-square of ``x`` (rows: blocks, columns: treatments) with the tie
    correction, and its p (chi-square, k - 1 degrees of freedom). Equal to
    ``scipy.stats.friedmanchisquare`` (tested)."""
    n, k = x.shape
    ranks = rankdata(x, axis=1)
    sums = ranks.sum(axis=0)
    ties = sum(tie_sum(row) for row in x)
    chi2 = (12 / (n * k * (k + 1)) * float((sums ** 2).sum()) - 3 * n * (k + 1)) \
        / (1 - ties / (n * k * (k * k - 1)))
    return float(chi2), float(special.chdtrc(k - 1, chi2))


# ------------------------------------------------------------------------ exact rank machinery
@functools.cache
def u_distribution(n: int, m: int) -> np.ndarray:
    """Exact null distribution of the Mann-Whitney U of sizes n, m without ties: P(U = u),
    u = 0 .. n m (the number of ways to place n ranks among n + m, by the usual recursion)."""
    # counts[i][j] over u for i of n, j of m: f(i, j, u) = f(i-1, j, u-j) + f(i, j-1, u)
    f = [[None] * (m + 1) for _ in range(n + 1)]
    for i in range(n + 1):
        for j in range(m + 1):
            if i == 0 or j == 0:
                c = np.zeros(i * j + 1)
                c[0] = 1.0
            else:
                c = np.zeros(i * j + 1)
                prev = f[i - 1][j]
                c[j:j + len(prev)] += prev
                c[:len(f[i][j - 1])] += f[i][j - 1]
            f[i][j] = c
    counts = f[n][m]
    return counts / counts.sum()


@functools.cache
def signed_rank_distribution(n: int) -> np.ndarray:
    """Exact null distribution of the Wilcoxon signed-rank statistic T+ of n non-zero
    differences without ties: P(T+ = t), t = 0 .. n (n + 1) / 2."""
    c = np.zeros(n * (n + 1) // 2 + 1)
    c[0] = 1.0
    for k in range(1, n + 1):
        c[k:] = c[k:] + c[:-k].copy()
    return c / c.sum()


def order_index(distribution: np.ndarray, confidence: float) -> int:
    """The largest k >= 1 with P(S <= k - 1) <= (1 - confidence) / 2 under ``distribution``
    (0 when even the extremes are too likely: the interval is unbounded)."""
    cdf = np.cumsum(distribution)
    return int(np.searchsorted(cdf, (1 - confidence) / 2 + 1e-12, side="right"))


def smallest_mann_whitney_p(n_a: int, n_b: int) -> float:
    """The smallest two-tailed p a Mann-Whitney U test can give for sizes n_a, n_b: complete
    separation, exact distribution, 2 / C(n_a + n_b, n_a)."""
    return min(1.0, 2.0 / math.comb(n_a + n_b, n_a)) if n_a and n_b else 1.0


@functools.cache
def smallest_directional_p(n_a: int, n_b: int) -> float:
    """The smallest two-sided p of ``directional``'s test for sizes n_a, n_b: where the test
    is exact (at most ``brunner_munzel.EXACT_SPLITS`` splits), the p of complete separation
    by the test itself (both complete separations and the splits next to them tie at the top
    of its statistic: 4 / C(n_a + n_b, n_a) at 6 vs 6 and 7 vs 7, 6 / C(16, 6) at 6 vs 10);
    where it is Monte Carlo, 1 / (1 + ``brunner_munzel.PERMUTATIONS``), the p when no random
    split reaches the observed one. 4 / C(n_a + n_b, n_a) below 2 units a group (no test)."""
    if min(n_a, n_b) < 2:
        return min(1.0, 4.0 / math.comb(n_a + n_b, n_a)) if n_a and n_b else 1.0
    if math.comb(n_a + n_b, n_a) > brunner_munzel.EXACT_SPLITS:
        return 1.0 / (1 + brunner_munzel.PERMUTATIONS)
    apart = brunner_munzel.test(np.arange(n_a, dtype=float), np.arange(n_b, dtype=float) + n_a)
    return float(apart.p)


def one_mode(n_a: int, n_b: int) -> float:
    """How often, under theta = 0.5, a group of two equal modes (a population babbling or
    still) has every unit in one mode, against a group between the modes: 2^(1 - n) for the
    smaller group's n. Complete separation then has that chance, so no rank test of fewer
    units than 6 a group can hold ``ALPHA`` when the shapes may differ so (4: 1 / 8)."""
    return 2.0 ** (1 - min(n_a, n_b))


def two_mode_gate(a, b, theta: float) -> Outcome | None:
    """The gate of every two-group rule (``directional``, ``equivalent``, ``not_better``):
    underpowered when, under theta = 0.5, a two-mode group could fall in one mode more often
    than ``ALPHA`` (``one_mode``: fewer than 6 units in the smaller group), whatever the data.
    Below it an equivalence is as unsafe as a difference: a 3-unit two-mode group against 7
    narrow units looks like a difference or like no difference by the luck of its modes."""
    n_a, n_b = len(a), len(b)
    if one_mode(n_a, n_b) <= ALPHA:
        return None
    return Outcome(UNDERPOWERED, effect=theta, note=f"{n_b} vs {n_a}: under the null a two-mode "
                   f"group falls in one mode {one_mode(n_a, n_b):.2g} of the time (the gate: "
                   f"at least 6 units a group); the smallest Mann-Whitney p possible is "
                   f"{smallest_mann_whitney_p(n_a, n_b):.3g}")


def smallest_signed_rank_p(n: int) -> float:
    """The smallest two-tailed p of the Wilcoxon signed-rank test of n non-zero differences
    (all of one sign, exact distribution): 2 / 2^n."""
    return min(1.0, 2.0 / 2 ** n)


def smallest_friedman_p(blocks: int, treatments: int) -> float:
    """The smallest p of Friedman's chi-square with every block ranking the treatments alike
    (chi2 = blocks (treatments - 1))."""
    return float(special.chdtrc(treatments - 1, blocks * (treatments - 1)))


def hodges_lehmann(a, b, confidence: float = 0.95) -> tuple[float, float, float]:
    """Hodges-Lehmann shift of b over a (median of the n_a n_b differences b_j - a_i) and its
    exact distribution-free interval: the k-th smallest and k-th largest difference, k from
    the exact null distribution of U (``u_distribution``); infinite where the samples are too
    small for that confidence."""
    a, b = finite(a), finite(b)
    d = np.sort((b[None, :] - a[:, None]).ravel())
    k = order_index(u_distribution(len(a), len(b)), confidence)
    if k < 1:
        return float(np.median(d)), -math.inf, math.inf
    return float(np.median(d)), float(d[k - 1]), float(d[len(d) - k])


def walsh_median(d, confidence: float = 0.95) -> tuple[float, float, float]:
    """Hodges-Lehmann estimate of a paired change (the median of the Walsh averages of the
    changes ``d``) and its exact interval from the signed-rank distribution."""
    d = finite(d)
    walsh = np.sort((d[:, None] + d[None, :])[np.triu_indices(len(d))] / 2)
    k = order_index(signed_rank_distribution(len(d)), confidence)
    if k < 1:
        return float(np.median(walsh)), -math.inf, math.inf
    return float(np.median(walsh)), float(walsh[k - 1]), float(walsh[len(walsh) - k])


def tie_sum(values: np.ndarray) -> float:
    """Sum of t^3 - t over the groups of tied values (the tie correction's numerator)."""
    _, counts = np.unique(values, return_counts=True)
    return float((counts ** 3 - counts).sum())


def normal_sf(z: float) -> float:
    """The standard normal survival function."""
    return float(special.ndtr(-z))


# --------------------------------------------------------------------------------- two groups
