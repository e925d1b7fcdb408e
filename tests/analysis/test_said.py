"""The words of a two-group comparison come from the gated rules (``said.two_groups``), never
from a raw test, and theta's interval carries the coverage measured for it
(``coverage.label``)."""

from __future__ import annotations

import numpy as np
import polars as pl
import pytest
from scipy import stats as sps

from dart_reach.analysis import coverage, said


def _table(values: dict[int, tuple[float, ...]]) -> pl.DataFrame:
    """A calibration table holding only the directional rule's coverage rows: per number of
    replications, the coverages measured (one row each), plus a row of another rule that
    must be ignored."""
    rows = [{"rule": "directional", "replications": r, "measure": coverage.MEASURE
             + (" (reported)" if i else ""), "value": x}
            for r, xs in values.items() for i, x in enumerate(xs)]
    rows.append({"rule": "band", "replications": 10, "measure": coverage.MEASURE, "value": 0.5})
    return pl.DataFrame(rows)


TABLE = _table({10: (0.961, 0.920, 0.944)})


def test_3_against_7_separated_is_underpowered_where_mann_whitney_says_differs():
    """Complete separation of 3 against 7: Mann-Whitney's two-sided p is 2 / C(10, 3) =
    1/60, below 0.05, which the page once wrote as "differs"; below the gate of 6 a group it
    is underpowered, with the smallest p of the rule's test there (4 / 120 = 0.0333)."""
    a, b = np.array([0.1, 0.2, 0.3]), np.arange(7.0) + 1
    assert sps.mannwhitneyu(a, b).pvalue == pytest.approx(1 / 60)
    text = said.two_groups(a, b, "still", "babbling", TABLE)
    assert text.startswith("underpowered (n = 7 babbling vs 3 still; the smallest p possible "
                           "is 0.0333")
    assert "differs" not in text and "higher" not in text and "[" not in text


@pytest.mark.parametrize("shift, word", [(10.0, "higher"), (-10.0, "lower")])
def test_6_against_6_separated_is_a_difference_with_its_direction(shift, word):
    """6 against 6 apart: the rule decides at its smallest p, 4 / C(12, 6) = 0.00433, and
    the interval is labelled with the coverage measured at 10 vs 10, not called 95 %."""
    text = said.two_groups(np.arange(6.0), np.arange(6.0) + shift, "still", "babbling", TABLE)
    assert text.startswith(f"babbling {word} (Brunner-Munzel permutation p = 0.00433, "
                           "n = 6 babbling vs 6 still, the smallest p possible 0.00433")
    assert ("nominally 95 %, covering 0.92-0.96 in simulation; not simulated at 6 vs 6, "
            "measured at 10 vs 10") in text


def test_the_same_only_when_equivalence_is_shown():
    """30 against 30 interleaved (theta 0.5): the same within the margin; 12 against 12
    interleaved: no difference, and said to be no evidence of the same."""
    x = np.linspace(0, 1, 30)
    assert said.two_groups(x, x + 0.001, "a", "b", TABLE).startswith(
        "the same within θ = 0.5 ± 0.15 (equivalence p = ")
    x = x[:12]
    text = said.two_groups(x, x + 0.001, "a", "b", TABLE)
    assert text.startswith("no difference detected (") and "no evidence that they are the same" \
        in text


def test_equal_values_are_no_evidence():
    assert said.two_groups(np.ones(6), np.ones(6), "a", "b", TABLE) == (
        "every value equal (n = 6 b vs 6 a): no evidence of a difference or of the same")
    assert said.two_groups([1.0], [2.0, 3.0], "a", "b", TABLE) == "not tested (n = 2 b vs 1 a)"


def test_the_interval_is_called_95_percent_only_where_that_was_measured():
    """The label takes the lowest and highest coverage of the directional rule's rows at the
    size nearest the smaller group (other rules ignored), "95 %" only when the lowest
    reaches it at that very size."""
    assert coverage.label(TABLE, 10, 10) == "nominally 95 %, covering 0.92-0.96 in simulation"
    held = _table({4: (0.90,), 10: (0.951, 0.97)})
    assert coverage.label(held, 10, 10) == "95 %"
    assert coverage.label(held, 8, 9) == ("nominally 95 %, covering 0.95-0.97 in simulation; "
                                          "not simulated at 9 vs 8, measured at 10 vs 10")
    assert coverage.label(held, 6, 9).startswith("nominally 95 %, covering 0.90-0.90")  # 4
    assert coverage.label(_table({}), 10, 10) == "nominally 95 %; its coverage not measured"
    measured = coverage.theta_coverage(held)
    assert measured.rows() == [(4, 0.90, 0.90, 1), (10, 0.951, 0.97, 2)]


def test_the_committed_calibration_says_theta_s_interval_falls_short_at_10():
    """In the committed calibration table theta's interval covers less than 95 % in some
    shape at 10 replications (0.92-0.93 at theta = 0.75): no page may call it 95 % there."""
    from reports.calibration import TABLE as COMMITTED
    table = pl.read_parquet(COMMITTED)
    rows = table.filter((pl.col("rule") == "directional") & (pl.col("replications") == 10)
                        & pl.col("measure").str.contains("coverage"))
    assert rows["value"].min() < 0.95
    assert coverage.label(table, 10, 10).startswith("nominally 95 %, covering 0.92-")
