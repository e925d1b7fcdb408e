"""Sentences generated from their tests: what a comparison of two groups' units may say, and no
more (DESIGN.md, "Prose says no more than its row's verdict").

``two_groups`` words the comparison of two groups of units (replications) from three numbers
computed here: the two-sided Mann-Whitney p the results pages report
(``scipy.stats.mannwhitneyu``, exact without ties, ``stats.mann_whitney``'s), the smallest p
those sizes allow (``verdicts.smallest_mann_whitney_p``: whether the test could find a
difference at all), and theta = P(B > A) + P(B = A) / 2 with its 95 % interval (the
studentized permutation Brunner-Munzel test inverted, ``brunner_munzel.test``), beside the
project's rule of a no-difference claim (``verdicts.equivalent``, gated below 6 units a
group). A difference is said only when the test finds one; "the same" only when the rule
shows equivalence; otherwise "no difference detected", with why that is no evidence of the
same.
"""

from __future__ import annotations

import numpy as np
from scipy import stats as sps

from . import brunner_munzel, formatting, verdicts


def mann_whitney_p(a, b) -> float:
    """Two-sided Mann-Whitney p of ``b`` against ``a`` (scipy's default method, as
    ``stats.mann_whitney``); 1 when every value is equal."""
    a, b = verdicts.finite(a), verdicts.finite(b)
    if np.ptp(np.concatenate([a, b])) == 0:
        return 1.0
    return float(sps.mannwhitneyu(a, b, alternative="two-sided").pvalue)


def two_groups(a, b, a_name: str, b_name: str) -> str:
    """What may be said of ``b`` (named ``b_name``) against ``a``: "differs (...)" when the
    Mann-Whitney p is below ``verdicts.ALPHA``, "the same within ..." when
    ``verdicts.equivalent`` is reproduced, else "no difference detected (...)" with n, the
    smallest p possible, theta with its interval and the reason it is not a finding of the
    same (the gate, or an interval reaching beyond the margin)."""
    a, b = verdicts.finite(a), verdicts.finite(b)
    n = f"n = {len(b)} {b_name} vs {len(a)} {a_name}"
    if min(len(a), len(b)) < 2:
        return f"not tested ({n})"
    p = mann_whitney_p(a, b)
    smallest = verdicts.smallest_mann_whitney_p(len(a), len(b))
    bm = brunner_munzel.test(a, b)
    theta = (f"θ = P({b_name} > {a_name}) = {formatting.significant(bm.theta)} [{formatting.significant(bm.low)}, {formatting.significant(bm.high)}], "
             "95 %")
    rule = verdicts.equivalent(a, b)
    if p < verdicts.ALPHA:
        return f"differs (Mann-Whitney p = {formatting.significant(p)}, {n}; {theta})"
    if rule.verdict == verdicts.REPRODUCED:
        return (f"the same within θ = 0.5 ± {verdicts.EQUIVALENCE_MARGIN:g} (equivalence p = "
                f"{formatting.significant(rule.p)}, {n}; {theta})")
    why = ("below 6 units a group the project's rule can show neither a difference nor the "
           "same" if rule.verdict == verdicts.UNDERPOWERED else
           f"the interval reaches beyond 0.5 ± {verdicts.EQUIVALENCE_MARGIN:g}, so this is no "
           "evidence that they are the same")
    return (f"no difference detected (Mann-Whitney p = {formatting.significant(p)}, {n}; the smallest p possible "
            f"is {formatting.significant(smallest)}; {theta}): {why}")
