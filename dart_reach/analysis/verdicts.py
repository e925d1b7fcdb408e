"""Decision rules that keep evidence apart from its absence (section IV's claims; DESIGN.md,
"Findings as data"; docs/guides/analysis.md, "Verdicts").

One rule per kind of claim, each a pure function of its units that returns the verdict and the
numbers behind it. The unit of every headline verdict is the *replication* (the mean over its
robots): the robots of a phase are the best few of one population, not independent draws, and
the paper's own Fig. 10 compares replications. Every rule is calibrated by simulation of nested
data like the runs' (``calibration``; the table in docs/results/calibration.md).

- ``directional``: "b is higher (lower) than a": the two-sided studentized permutation
  Brunner-Munzel test on the logit scale (``brunner_munzel``: over every split up to 10,000,
  else 1,999 random ones), whose null, theta = P(B > A) + P(B = A) / 2 = 0.5, is what the
  claim denies, whatever the groups' shapes (a bimodal group of pre-reachers against a
  unimodal later phase: Mann-Whitney, whose exact null is "the same distribution", decides
  more often than its level there; docs/results/calibration.md); underpowered below 6 units
  a group (``one_mode``); direction from theta; effect: theta with the 95 % interval of the
  same test inverted, so that verdict and interval agree.
- ``not_better``: "b is not significantly better than a", as the paper words it (one-sided):
  non-superiority on the probabilistic index theta = P(B > A) + P(B = A) / 2 (Brunner-Munzel
  standard error): reproduced when the upper one-sided 95 % bound of theta (in the direction
  "better") is below 0.5 + ``EQUIVALENCE_MARGIN``; contradicted when b is better (one-sided
  Brunner-Munzel permutation p < ALPHA, both directions from one run of the permutations);
  underpowered below 6 units a group (``one_mode``), as every two-group rule.
- ``equivalent``: "a and b do not differ" (two-sided): two one-sided tests on theta within
  0.5 +- ``EQUIVALENCE_MARGIN`` (Lakens 2017); contradicted by a two-sided Brunner-Munzel
  permutation difference; underpowered below 6 units a group (``one_mode``).
- ``in_band``: "about half": Student's t interval of the mean over units inside the band, each
  edge a one-sided test at ``BAND_LEVEL``; underpowered below ``BAND_MIN_UNITS``.
- ``at_least``: "in every sector": every cell's one-sided lower bound at ``SECTOR_LEVEL`` above
  a floor (an intersection-union test); contradicted when some cell's upper bound,
  Bonferroni-adjusted over the cells, is below it. The gates and levels of these two, of the
  paired change and of "senses differ" are the least favourable over nulls shaped like the
  runs' rates (``verdict_core``; docs/model/claims.md, "Rates shaped like the runs'").
- ``paired_directional`` / ``paired_equivalent`` / ``paired_rate_equivalent``: the same units
  under two conditions or at two moments: Wilcoxon signed-rank (exact without ties) at
  ``PAIRED_CHANGE_LEVEL`` / the
  exact sign-flip test as two one-sided tests (``sign_flip_tost``), of the change relative to
  each unit's level for a measure / of the absolute change against ``RATE_MARGIN`` for a rate
  (a rate at 0 is a level like any other; ``paired_verdicts``); each underpowered where no
  sign-flip or signed-rank test can reach its level (below 7 pairs / 6 pairs); no change is shown by
  one-sided tests at ``PAIRED_EQUIVALENCE_LEVEL`` (the least favourable level over the
  declared shapes of the changes, skewed ones across 0 included: from 8 pairs), and never
  where the changes are lopsided (``lopsided``: the sign-flip test of a mean is exact only
  for changes symmetric about their centre).
- ``senses_differ``: "performance varies across the sensory conditions": Friedman's test at
  ``FRIEDMAN_LEVEL`` with the replication as block; contradicted when every pair of
  conditions is equivalent (the sign-flip TOST within ``PAIRED_MARGIN`` at
  ``PAIRED_EQUIVALENCE_LEVEL``, an intersection-union test; from 8 blocks; never where a
  pair's changes are lopsided).

Verdicts (``VERDICTS``): *reproduced* (the data show what the paper says), *contradicted* (they
show the opposite, or a difference where the paper says none), *inconclusive* (the data cannot
decide at this n), *underpowered* (even the most favourable data could not decide at this n:
known from the sample sizes before any test), *not run*. One level ``ALPHA`` in both
directions; whether the paper's own level is met is a separate column. Zero spread is never
evidence: where every unit has the same value a rule that needs a spread is inconclusive.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

from . import brunner_munzel
from .brunner_munzel import probabilistic_index
from .paired_verdicts import (  # noqa: F401  (re-exported: the paired rules)
    LOPSIDED_MINORITY, lopsided, paired_directional, paired_equivalent, paired_rate_equivalent,
    paired_tost, relative_changes, senses_differ, sign_flip_tost, wilcoxon)
from .verdict_core import (  # noqa: F401  (re-exported: the rules' shared names)
    ALPHA, BAND_LEVEL, BAND_MIN_UNITS, CONTRADICTED, DECIDED, EQUIVALENCE_MARGIN, FRIEDMAN_LEVEL,
    INCONCLUSIVE, MIN_UNITS, NOT_RUN, Outcome, PAIRED_CHANGE_LEVEL, PAIRED_EQUIVALENCE_LEVEL,
    PAIRED_MARGIN, RATE_MARGIN, REPRODUCED, SECTOR_FLOOR, SECTOR_LEVEL, SECTOR_MIN_UNITS,
    UNDERPOWERED, VERDICTS, finite, friedman, hodges_lehmann, no_spread, normal_sf, one_mode,
    order_index, signed_rank_distribution, smallest_directional_p, smallest_friedman_p,
    smallest_mann_whitney_p, smallest_signed_rank_p, t_cdf, t_quantile, t_sf, tie_sum,
    two_mode_gate, u_distribution, walsh_median)


def directional(a, b, sign: int, level: float = ALPHA) -> Outcome:
    """Claim: b is higher (``sign`` +1) or lower (-1) than a; ``level`` the paper's. The
    two-sided studentized permutation Brunner-Munzel test (``brunner_munzel.test``): its null
    is theta = P(B > A) + P(B = A) / 2 = 0.5, whatever the shapes of the two groups; direction
    from theta; effect: theta with the interval of the same test inverted (0.5 outside it
    exactly when p < ``ALPHA``). Underpowered when even complete separation cannot reach
    ``ALPHA``, or when a two-mode group could fall in one mode more often than ``ALPHA``
    under the null (``one_mode``: fewer than 6 units a group)."""
    a, b = finite(a), finite(b)
    if min(len(a), len(b)) == 0:
        return Outcome(UNDERPOWERED, note=f"{len(b)} vs {len(a)} units")
    theta = probabilistic_index(a, b)[0]
    if min(len(a), len(b)) < 2 or smallest_directional_p(len(a), len(b)) >= ALPHA:
        return Outcome(UNDERPOWERED, effect=theta, note=f"{len(b)} vs {len(a)}: the smallest "
                       f"possible p is {smallest_directional_p(len(a), len(b)):.2g}")
    if (gated := two_mode_gate(a, b, theta)) is not None:
        return gated
    if no_spread(a, b):
        return Outcome(INCONCLUSIVE, 1.0, 0.5, 0.5, 0.5, 1 - ALPHA, 1.0, False,
                       "every value equal: no evidence")
    res = brunner_munzel.test(a, b, confidence=1 - ALPHA)
    observed = int(np.sign(res.theta - 0.5))
    decided = res.p < ALPHA
    verdict = (REPRODUCED if decided and observed == sign else
               CONTRADICTED if decided and observed == -sign else INCONCLUSIVE)
    return Outcome(verdict, res.p if observed == sign else 1.0, res.theta, res.low, res.high,
                   res.confidence, res.p if observed == -sign else 1.0,
                   bool(res.p < level and observed == sign),
                   f"{'exact' if res.exact else 'Monte Carlo'} over {res.splits} splits")


def equivalence_reachable(n_a: int, n_b: int, margin: float = EQUIVALENCE_MARGIN) -> bool:
    """Whether the most favourable continuous samples (theta = 0.5, theta's null standard error
    sqrt((n_a + n_b + 1) / (12 n_a n_b))) could show equivalence at ``ALPHA``."""
    if min(n_a, n_b) < 2:
        return False
    se = math.sqrt((n_a + n_b + 1) / (12 * n_a * n_b))
    return margin / se > special.ndtri(1 - ALPHA)


def equivalent(a, b, margin: float = EQUIVALENCE_MARGIN, gated: bool = True) -> Outcome:
    """Claim: a and b do not differ. Reproduced when both one-sided tests reject theta outside
    0.5 +- ``margin`` (p = the larger of the two); contradicted when the two-sided
    Brunner-Munzel permutation test shows a difference; otherwise inconclusive, or
    underpowered where the sizes could never show equivalence (``equivalence_reachable``) and
    no difference shows, or below the two-mode gate (``two_mode_gate``; ``gated`` False: the
    rule without it, which the calibration reports beside)."""
    a, b = finite(a), finite(b)
    if min(len(a), len(b)) < 2:
        return Outcome(UNDERPOWERED, note=f"{len(b)} vs {len(a)}: no spread to estimate")
    theta, se, df = probabilistic_index(a, b)
    if gated and (gate := two_mode_gate(a, b, theta)) is not None:
        return gate
    if no_spread(a, b):
        return Outcome(INCONCLUSIVE, math.nan, theta, note="every value equal: no evidence")
    p_diff = brunner_munzel.test(a, b).p
    if se == 0:  # complete separation: a difference, never equivalence
        p_eq, low, high = 1.0, theta, theta
    else:
        p_eq = max(t_sf((theta - 0.5 + margin) / se, df), t_cdf((theta - 0.5 - margin) / se, df))
        half = t_quantile(1 - ALPHA, df) * se
        low, high = theta - half, theta + half
    if p_eq < ALPHA:
        verdict = REPRODUCED
    elif p_diff < ALPHA:
        verdict = CONTRADICTED
    elif not equivalence_reachable(len(a), len(b), margin):
        verdict = UNDERPOWERED
    else:
        verdict = INCONCLUSIVE
    return Outcome(verdict, p_eq, theta, low, high, 1 - 2 * ALPHA, p_diff,
                   note=f"theta within 0.5 +- {margin:g}; difference p = {p_diff:.2g}")


def not_better(a, b, better: int, margin: float = EQUIVALENCE_MARGIN,
               gated: bool = True) -> Outcome:
    """Claim: b is not significantly better than a, where "better" is higher (``better`` +1)
    or lower (-1): the paper's one-sided "no significant improvement". Non-superiority on
    theta_better (theta, or 1 - theta when lower is better): reproduced when its upper
    one-sided 95 % bound is below 0.5 + ``margin``; contradicted when b is better (one-sided
    Brunner-Munzel permutation p < ``ALPHA``); otherwise inconclusive; underpowered below the
    two-mode gate (``gated`` False: without it, as ``equivalent``)."""
    a, b = finite(a), finite(b)
    if min(len(a), len(b)) < 2:
        return Outcome(UNDERPOWERED, note=f"{len(b)} vs {len(a)}: no spread to estimate")
    theta, se, df = probabilistic_index(a, b)
    theta = theta if better > 0 else 1 - theta
    if gated and (gate := two_mode_gate(a, b, theta)) is not None:
        return gate
    if no_spread(a, b):
        return Outcome(INCONCLUSIVE, math.nan, theta, note="every value equal: no evidence")
    res = brunner_munzel.test(a, b)  # once: both one-sided p from the same splits
    p_better, p_worse = ((res.p_greater, res.p_less) if better > 0 else
                         (res.p_less, res.p_greater))
    if se == 0:  # complete separation: b worse everywhere (or better everywhere)
        p_ns = p_worse
        high = theta
    else:
        p_ns = t_cdf((theta - 0.5 - margin) / se, df)
        high = theta + t_quantile(1 - ALPHA, df) * se
    verdict = (REPRODUCED if p_ns < ALPHA else CONTRADICTED if p_better < ALPHA
               else UNDERPOWERED if smallest_mann_whitney_p(len(a), len(b)) / 2 >= ALPHA
               else INCONCLUSIVE)
    return Outcome(verdict, p_ns, theta, 0.0, float(min(high, 1.0)), 1 - ALPHA, p_better,
                   note=f"theta(better) below 0.5 + {margin:g}; better p = {p_better:.2g}")


# ----------------------------------------------------------------------- intervals over units
def mean_interval(units, confidence: float = 0.95) -> tuple[float, float, float]:
    """Mean of ``units`` and its two-sided Student's t interval (a one-sided bound at level c
    is the two-sided interval at 2c - 1)."""
    x = finite(units)
    mean = float(x.mean())
    half = t_quantile(0.5 + confidence / 2, len(x) - 1) * float(x.std(ddof=1)) / math.sqrt(len(x))
    return mean, mean - half, mean + half


def _too_few(units, gate: int = MIN_UNITS) -> Outcome | None:
    x = finite(units)
    if len(x) < gate:
        return Outcome(UNDERPOWERED, effect=float(x.mean()) if len(x) else math.nan,
                       note=f"{len(x)} units; this rule decides from {gate}")
    if no_spread(x):
        return Outcome(INCONCLUSIVE, effect=float(x[0]), note="every unit equal: no evidence")
    return None


def in_band(units, band: tuple[float, float], level: float = BAND_LEVEL,
            gate: int = BAND_MIN_UNITS) -> Outcome:
    """Claim: the mean of ``units`` (one value per replication, a rate) lies in ``band``.
    Reproduced when the t interval at 1 - 2 ``level`` lies inside (each edge a one-sided test
    at ``level``); contradicted when it lies wholly outside; otherwise inconclusive;
    underpowered below ``gate`` units."""
    if (few := _too_few(units, gate)) is not None:
        return few
    confidence = 1 - 2 * level
    mean, low, high = mean_interval(units, confidence)
    verdict = (REPRODUCED if band[0] <= low and high <= band[1] else
               CONTRADICTED if high < band[0] or low > band[1] else INCONCLUSIVE)
    return Outcome(verdict, effect=mean, low=low, high=high, confidence=confidence)


def at_least(units_by_cell: dict, floor: float, level: float = SECTOR_LEVEL,
             gate: int = SECTOR_MIN_UNITS) -> Outcome:
    """Claim: in every cell (a sector's reach or grasp), the mean over units is at least
    ``floor``. Reproduced when every cell's one-sided lower bound at 1 - ``level`` is above it
    (an intersection-union test: its error is at most ``level`` whatever the number of
    cells); contradicted when some cell's upper bound at 1 - ``ALPHA`` / cells is below it;
    otherwise inconclusive; underpowered below ``gate`` units a cell. ``effect``: the weakest
    cell's mean, with its interval."""
    cells = {k: finite(v) for k, v in units_by_cell.items()}
    for v in cells.values():
        if len(v) < gate:
            return Outcome(UNDERPOWERED, note=f"{len(v)} units; this rule decides from {gate}")
    flat = [k for k, v in cells.items() if no_spread(v)]
    k = len(cells)
    lower = {c: mean_interval(v, 1 - 2 * level) for c, v in cells.items() if c not in flat}
    upper = {c: mean_interval(v, 1 - 2 * ALPHA / k) for c, v in cells.items() if c not in flat}
    worst = min(cells, key=lambda c: cells[c].mean())
    below = [c for c, (_, _, high) in upper.items() if high < floor]
    if below:
        verdict = CONTRADICTED
    elif not flat and all(low > floor for _, low, _ in lower.values()):
        verdict = REPRODUCED
    else:
        verdict = INCONCLUSIVE
    mean, low, high = lower.get(worst, (float(cells[worst].mean()), math.nan, math.nan))
    note = "; ".join(filter(None, [
        f"weakest: {worst}", f"below the floor: {', '.join(map(str, below))}" if below else "",
        f"no spread (no evidence): {', '.join(map(str, flat))}" if flat else ""]))
    return Outcome(verdict, effect=mean, low=low, high=high, confidence=1 - 2 * level,
                   note=note)
