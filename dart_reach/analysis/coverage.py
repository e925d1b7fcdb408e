"""How often theta's interval holds theta, as measured: the label an interval of the
directional rule carries wherever it is shown (DESIGN.md, "Findings as data": "its intervals
cover what they claim"; docs/results/calibration.md).

theta = P(B > A) + P(B = A) / 2 of two groups of replications has the interval of the
studentized permutation Brunner-Munzel test inverted (``brunner_munzel``, ``verdicts.directional``),
nominally 95 %. It is exact at theta = 0.5; away from it, between groups of unequal shapes, the
calibration (``calibration._shapes``, ``calibration._directional``) measured less
(docs/results/calibration.md gives how much, per size and shape). A page may call the
interval 95 % only where that is what was measured; everywhere else it says the coverage
measured for the nearest size the calibration simulated, or that none was. The numbers come
from the committed calibration table (``reports.calibration.TABLE``), never from here.

A paired claim of no change's interval (``paired_label``) is labelled the same way: nominally
99 %, exact for changes symmetric about their centre, with the coverage the calibration
measured per number of pairs and shape of the changes (``paired_calibration.coverage_row``).
The band's interval (Student's t) and the paired change's (the Hodges-Lehmann change's, exact
for symmetric changes) are labelled with the coverage measured under rates shaped like the
runs' (``shaped_label``; ``run_shaped_calibration``), per number of replications.
"""

from __future__ import annotations

import polars as pl

from . import paired_calibration, run_shaped_calibration
from .verdict_core import (BAND_LEVEL, PAIRED_CHANGE_LEVEL, PAIRED_EQUIVALENCE_LEVEL,
                           SECTOR_LEVEL, smallest_signed_rank_p)

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


# ------------------------------------------------------------- a paired claim of no change
#: The calibration table's rows of a paired claim of no change's interval (the mean change's,
#: the centres the sign-flip test's one-sided tests at ``PAIRED_EQUIVALENCE_LEVEL`` do not
#: reject; ``paired_calibration.coverage_row``): only reported, the interval being exact for
#: changes symmetric about their centre alone.
PAIRED_RULES = ("paired no change", "paired rate no change")
PAIRED_MEASURE = paired_calibration.COVERAGE
#: The level the paired interval is built for.
PAIRED_NOMINAL = 1 - 2 * PAIRED_EQUIVALENCE_LEVEL


def paired_shape(scenario: str) -> str:
    """"symmetric" or "asymmetric": whether the changes of a paired calibration row's
    ``scenario`` are symmetric about their mean (``paired_calibration.symmetric_changes``:
    normal, two-mode, rates at no change) or not (skewed, zero-inflated, straddling 0, rates
    in fifths or with replications still at a change)."""
    return "symmetric" if paired_calibration.symmetric_changes(scenario) else "asymmetric"


def paired_coverage(table: pl.DataFrame) -> pl.DataFrame:
    """Per number of pairs (``pairs``) and shape of the changes (``shape``: "symmetric" or
    "asymmetric", ``paired_shape``): the lowest and highest coverage of a paired claim of no
    change's interval over the scenarios and nestings of the calibration (``low``, ``high``:
    shares of the data sets with an interval whose interval held the true mean change), how
    many rows (``rows``) and the scenario of the lowest (``lowest_at``). Empty when the table
    has none (below 6 pairs the rule shows no interval)."""
    rows = table.filter(pl.col("rule").is_in(PAIRED_RULES)
                        & (pl.col("measure") == PAIRED_MEASURE))
    rows = rows.with_columns(
        pl.col("scenario").str.extract(r", (\d+) pairs$").cast(pl.Int64)
        .fill_null(pl.col("replications")).alias("pairs"),
        pl.col("scenario").map_elements(paired_shape, return_dtype=pl.String).alias("shape"))
    return (rows.sort("value").group_by("pairs", "shape", maintain_order=True)
            .agg(pl.col("value").min().alias("low"), pl.col("value").max().alias("high"),
                 pl.len().alias("rows"), pl.col("scenario").first().alias("lowest_at"))
            .sort("pairs", "shape", descending=[False, True]))


#: How a label names each shape of the changes (``paired_shape``).
SHAPE_WORDS = {"symmetric": "where the changes are symmetric about their centre",
               "asymmetric": "where they are not (skewed, zero-inflated, straddling 0, or rates "
                             "at a change with replications still)"}


def paired_label(table: pl.DataFrame) -> str:
    """What to call a paired claim of no change's interval on a page: its nominal level and
    the coverage measured per number of pairs and shape of the changes ("nominally 99 %,
    covering in simulation at N pairs LOW-HIGH where the changes are symmetric about their
    centre and LOW-HIGH where they are not (...)"; the rule shows no interval below 6 pairs),
    read from ``table``; "its coverage not measured" when the table has no row of it."""
    nominal = f"{100 * PAIRED_NOMINAL:g} %"
    measured = paired_coverage(table)
    if not measured.height:
        return (f"nominally {nominal} (exact where the changes are symmetric about their "
                "centre); its coverage not measured")
    parts = []
    for (pairs,), block in measured.group_by("pairs", maintain_order=True):
        parts.append(f"at {pairs} pairs " + " and ".join(
            f"{_span(r['low'], r['high'])} {SHAPE_WORDS[r['shape']]}"
            for r in block.iter_rows(named=True)))
    return (f"nominally {nominal}, covering in simulation {'; '.join(parts)}; none below 6 "
            "pairs")


def _span(low: float, high: float) -> str:
    a, b = f"{low:.3f}", f"{high:.3f}"
    return a if a == b else f"{a}-{b}"


# ------------------------------------------------ the band's and the paired change's intervals
#: The calibration table's rows of the band's interval (Student's t over replications,
#: ``verdicts.in_band``) and the paired change's (the Hodges-Lehmann change's exact interval,
#: ``verdicts.paired_directional``) under nulls shaped like the runs' rates
#: (``run_shaped_calibration``), bounded at their nominal level.
SHAPED_RULES = {"band": run_shaped_calibration.BAND, "sector": run_shaped_calibration.SECTORS,
                "change": run_shaped_calibration.CHANGE}


def shaped_coverage(table: pl.DataFrame, rule: str) -> pl.DataFrame:
    """Per number of replications (``n``, from a row's scenario: "..., N replications" or
    "..., N pairs"): the lowest and highest coverage of ``rule``'s interval over the shapes,
    means and nestings of the calibration (``low``, ``high``), how many rows (``rows``) and
    the scenario of the lowest (``lowest_at``). Empty when the table has none."""
    rows = table.filter((pl.col("rule") == rule)
                        & pl.col("measure").str.starts_with("coverage"))
    rows = rows.with_columns(run_shaped_calibration.scenario_size().alias("n"))
    return (rows.sort("value").group_by("n", maintain_order=True)
            .agg(pl.col("value").min().alias("low"), pl.col("value").max().alias("high"),
                 pl.len().alias("rows"), pl.col("scenario").first().alias("lowest_at"))
            .sort("n"))


def shaped_nominal(which: str) -> str:
    """The nominal level of the band's (``which`` "band"), every sector's weakest cell's
    ("sector") or the paired change's ("change") interval as the rules show it: "95 %" at a
    one-sided level of 0.025 per edge."""
    level = {"band": 1 - 2 * BAND_LEVEL, "sector": 1 - 2 * SECTOR_LEVEL,
             "change": 1 - PAIRED_CHANGE_LEVEL}[which]
    return f"{100 * level:g} %"


def shaped_label(table: pl.DataFrame, which: str) -> str:
    """What to call the band's (``which`` "band"), every sector's weakest cell's ("sector") or
    the paired change's ("change") interval on a page: "nominally 99 %, covering in
    simulation LOW-HIGH at N replications (pairs), ..." over the run-shaped nulls, read from
    ``table``; the paired change's shows no finite
    interval below the pairs at which its test can decide; "its coverage not measured" when
    the table has no row of it."""
    unit = "pairs" if which == "change" else "replications"
    nominal = shaped_nominal(which)
    measured = shaped_coverage(table, SHAPED_RULES[which])
    if not measured.height:
        return f"nominally {nominal}; its coverage not measured"
    parts = "; ".join(f"{_span(r['low'], r['high'])} at {r['n']} {unit}"
                      for r in measured.iter_rows(named=True))
    fewest = next(n for n in range(1, 64) if smallest_signed_rank_p(n) < PAIRED_CHANGE_LEVEL)
    below = f"; no finite interval below {fewest} pairs" if which == "change" else ""
    shapes = ("in fifths, still, two-mode, zero-inflated, skewed changes" if which == "change"
              else "on the trial grid, still, two-mode, skewed")
    return f"nominally {nominal}, covering in simulation {parts} (rates shaped like the " \
        f"runs': {shapes}){below}"
