"""Sentences generated from the project's gated rules: what a comparison of two groups' units
may say, and no more (DESIGN.md, "Prose says no more than its row's verdict"; section IV's
comparisons of populations, the replication as the unit).

``two_groups`` words the comparison of two groups of units (replications) from the rules of
``verdicts`` alone, never from a raw test:

- a difference ("higher", "lower") only when ``verdicts.directional`` decides (the
  studentized permutation Brunner-Munzel test, gated below 6 units a group: a two-mode
  group of fewer falls in one mode more often than ``ALPHA`` under no difference);
- "the same" only when ``verdicts.equivalent`` is reproduced (theta within 0.5 +-
  ``EQUIVALENCE_MARGIN``, the same gate);
- "underpowered" when the gate holds: neither a difference nor the same can be shown,
  whatever the data;
- otherwise "no difference detected", with why that is no evidence of the same.

Every sentence carries n, the p of the rule's test, the smallest p those sizes allow
(``verdicts.smallest_directional_p``) and theta = P(B > A) + P(B = A) / 2, with its interval
where the rule is not gated, labelled with the coverage the calibration measured for it
(``coverage.label``: the interval is nominally 95 %, less away from theta = 0.5 between
groups of unequal shapes).
"""

from __future__ import annotations

import polars as pl

from . import coverage, formatting, verdicts
from .brunner_munzel import probabilistic_index


def _theta(outcome: verdicts.Outcome, a_name: str, b_name: str, interval: str | None) -> str:
    text = f"θ = P({b_name} > {a_name}) = {formatting.significant(outcome.effect)}"
    if interval is None:
        return text
    return (f"{text} [{formatting.significant(outcome.low)}, "
            f"{formatting.significant(outcome.high)}], {interval}")


def two_groups(a, b, a_name: str, b_name: str, calibration: pl.DataFrame) -> str:
    """What may be said of ``b`` (named ``b_name``) against ``a``, the unit a replication:
    "{b_name} higher" or "lower" when ``verdicts.directional`` decides, "the same within ..."
    when ``verdicts.equivalent`` is reproduced, "underpowered" below the rules' gate, else
    "no difference detected"; each with n, the rule's p, the smallest p possible and theta
    (an interval only where the rule is not gated, labelled by ``coverage.label`` from the
    ``calibration`` table, ``reports.calibration.TABLE``)."""
    a, b = verdicts.finite(a), verdicts.finite(b)
    n = f"n = {len(b)} {b_name} vs {len(a)} {a_name}"
    if min(len(a), len(b)) < 2:
        return f"not tested ({n})"
    smallest = formatting.significant(verdicts.smallest_directional_p(len(a), len(b)))
    d = verdicts.directional(a, b, +1)
    if d.verdict == verdicts.UNDERPOWERED:
        theta = probabilistic_index(a, b)[0]
        return (f"underpowered ({n}; the smallest p possible is {smallest}; "
                f"θ = P({b_name} > {a_name}) = {formatting.significant(theta)}): below 6 "
                "replications a group the project's rules can show neither a difference nor "
                "the same")
    if verdicts.no_spread(a, b):
        return f"every value equal ({n}): no evidence of a difference or of the same"
    interval = coverage.label(calibration, len(a), len(b))
    p = min(d.p, d.p_against)
    tested = (f"Brunner-Munzel permutation p = {formatting.significant(p)}, {n}, the smallest p "
              f"possible {smallest}; {_theta(d, a_name, b_name, interval)}")
    if d.verdict in verdicts.DECIDED:
        word = "higher" if d.verdict == verdicts.REPRODUCED else "lower"
        return f"{b_name} {word} ({tested})"
    same = verdicts.equivalent(a, b)
    if same.verdict == verdicts.REPRODUCED:
        return (f"the same within θ = 0.5 ± {verdicts.EQUIVALENCE_MARGIN:g} (equivalence p = "
                f"{formatting.significant(same.p)}; {tested})")
    return (f"no difference detected ({tested}): the interval reaches beyond 0.5 ± "
            f"{verdicts.EQUIVALENCE_MARGIN:g}, so this is no evidence that they are the same")
