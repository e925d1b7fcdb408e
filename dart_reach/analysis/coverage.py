"""How often theta's interval holds theta, as measured: the label an interval of the
directional rule carries wherever it is shown (DESIGN.md, "Findings as data": "its intervals
cover what they claim"; docs/results/calibration.md).

theta = P(B > A) + P(B = A) / 2 of two groups of replications has the interval of the
studentized permutation Brunner-Munzel test inverted (``brunner_munzel``, ``verdicts.directional``),
nominally 95 %. It is exact at theta = 0.5; away from it, between groups of unequal shapes, the
calibration (``calibration._shapes``, ``calibration._directional``) measured less: 0.92-0.93 at
theta = 0.75 and 10 replications a group. A page may call the interval 95 % only where that is
what was measured; everywhere else it says the coverage measured for the nearest size the
calibration simulated, or that none was. The numbers come from the committed calibration table
(``reports.calibration.TABLE``), never from here.
"""

from __future__ import annotations

import polars as pl

#: The calibration table's rows of theta's interval: the directional rule's coverage rows,
#: those held to the level and those only reported.
RULE, MEASURE = "directional", "coverage of the 95 % interval"
#: The level the interval is built for.
NOMINAL = 0.95


def theta_coverage(table: pl.DataFrame) -> pl.DataFrame:
    """Per number of replications a group the calibration simulated (``replications``): the
    lowest and highest coverage of theta's nominal 95 % interval over its scenarios and
    nestings (``low``, ``high``: shares of data sets whose interval held the true theta) and
    how many rows they are over (``rows``). Empty when the table has none (the rule is gated
    at that size)."""
    rows = table.filter((pl.col("rule") == RULE)
                        & pl.col("measure").str.starts_with(MEASURE))
    return (rows.group_by("replications")
            .agg(pl.col("value").min().alias("low"), pl.col("value").max().alias("high"),
                 pl.len().alias("rows"))
            .sort("replications"))


def label(table: pl.DataFrame, n_a: int, n_b: int) -> str:
    """What to call theta's interval between groups of ``n_a`` and ``n_b`` replications:
    "95 %" only when every coverage measured at that size (equal groups of the calibration)
    reaches ``NOMINAL``; else "nominally 95 %, covering LOW-HIGH in simulation at R vs R
    replications" with the calibration's range at the size nearest to the smaller group, or
    "coverage not measured" when the table has no row of theta's interval at all."""
    measured = theta_coverage(table)
    if not measured.height:
        return "nominally 95 %; its coverage not measured"
    nearest = min(measured.iter_rows(named=True),
                  key=lambda r: (abs(r["replications"] - min(n_a, n_b)), -r["replications"]))
    r, low, high = nearest["replications"], nearest["low"], nearest["high"]
    same = {n_a, n_b} == {r}
    if same and low >= NOMINAL:
        return "95 %"
    size = "" if same else f"; not simulated at {n_b} vs {n_a}, measured at {r} vs {r}"
    return f"nominally 95 %, covering {low:.2f}-{high:.2f} in simulation{size}"
