"""The band, every sector, the paired change and "senses differ" calibrated under nulls shaped
like the runs' rates (``run_shaped_calibration``): the draws are what they claim (rates on the
trial grid, the mean exactly at the edge), each kind of row can fail, the committed rows are
the simulation's, every row not met is named on the page, and the pages' labels of the band's
and the paired change's intervals read the table."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import polars as pl
import pytest

from dart_reach.analysis import calibration as cal
from dart_reach.analysis import coverage
from dart_reach.analysis import run_shaped_calibration as rs
from dart_reach.analysis import verdicts as v
from dart_reach.analysis.claims import ABOUT_HALF
from dart_reach.analysis.verdict_core import Outcome
from reports import calibration as calibration_page

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "results" / "calibration.md"
RULES = (rs.BAND, rs.SECTORS, rs.CHANGE, rs.SENSES)


@pytest.fixture(scope="module")
def table() -> pl.DataFrame:
    return calibration_page.committed()


@pytest.mark.parametrize("shape", rs.BAND_SHAPES)
def test_the_rates_are_on_the_trial_grid_with_their_mean_at_the_edge(shape):
    rng = np.random.default_rng(3)
    nest = cal.NESTINGS[1]  # within s.d. 3: the widest robots
    rates = np.concatenate([rs.replication_rates(rng, nest, shape, 10, ABOUT_HALF[0], -1)
                            for _ in range(4000)])
    grid = rates * rs.ROBOTS * rs.TRIALS
    assert np.allclose(grid, np.round(grid)) and rates.min() >= 0 and rates.max() <= 1
    se = rates.std() / np.sqrt(len(rates))
    assert abs(rates.mean() - ABOUT_HALF[0]) < 4 * se, (rates.mean(), se)
    if "still" in shape:
        assert 0.25 < np.mean(rates == 0) < 0.35


def _liberal_band(units, band):
    """A band rule deliberately too liberal: its interval at 60 % called 95 %."""
    mean, low, high = v.mean_interval(units, 0.60)
    inside = band[0] <= low and high <= band[1]
    return Outcome(v.REPRODUCED if inside else v.INCONCLUSIVE, effect=mean, low=low, high=high,
                   confidence=0.95)


def test_a_too_liberal_band_rule_fails_both_rows():
    """The rows can fail: a band rule with a 60 % interval decides too often at the edge and
    its interval covers too rarely, on the same draws as the rule's rows."""
    rng = np.random.default_rng(5)
    nest, n = cal.NESTINGS[2], 300
    data = [rs.replication_rates(rng, nest, rs.BAND_SHAPES[0], 10, ABOUT_HALF[0], -1)
            for _ in range(n)]
    for judge, fails in ((_liberal_band, True), (v.in_band, False)):
        out = [judge(x, ABOUT_HALF) for x in data]
        rows = rs._level_and_coverage("band", nest, "edge", out, v.DECIDED, ABOUT_HALF[0],
                                      1 - 2 * v.BAND_LEVEL, n)
        assert [r["ok"] for r in rows] == [not fails] * 2, rows


def test_a_too_liberal_paired_rule_and_senses_rule_fail_their_rows():
    """A paired change judged at p < 0.3 and senses judged at p < 0.3 decide above the bound
    under the run-shaped nulls at 10 pairs; the rules themselves do not."""
    rng = np.random.default_rng(7)
    nest, n, shape = cal.NESTINGS[2], 300, "rates in fifths"
    pairs = [cal.rate_pairs(rng, shape, 10, 0.0) for _ in range(n)]
    blocks = [np.column_stack(cal.rate_pairs(rng, shape, 10, 0.0, conditions=4))
              for _ in range(n)]
    liberal = rs.row("x", nest, "null", "decided", rs.rate(
        [v.wilcoxon(b - a)[0] < 0.3 for a, b in pairs]), v.ALPHA, "at most", n)
    rule = rs.row("x", nest, "null", "decided", rs.rate(
        [v.paired_directional(a, b, +1).verdict in v.DECIDED for a, b in pairs]), v.ALPHA,
        "at most", n)
    senses = rs.row("x", nest, "null", "reproduced", rs.rate(
        [v.friedman(x)[1] < 0.3 for x in blocks]), v.ALPHA, "at most", n)
    assert liberal["ok"] is False and senses["ok"] is False and rule["ok"] is True


def test_four_conditions_begin_with_the_pair_drawn_alone():
    """``rate_pairs`` with four conditions draws its first two as the pair alone (the same
    stream: the paired blocks' committed rows keep their data sets)."""
    for shape in cal.RATE_SHAPES:
        pair = cal.rate_pairs(np.random.default_rng(1), shape, 6, 0.1)
        four = cal.rate_pairs(np.random.default_rng(1), shape, 6, 0.1, conditions=4)
        assert len(four) == 4 and all(np.array_equal(a, b) for a, b in zip(pair, four[:2]))


def test_every_rule_is_calibrated_at_the_runs_sizes(table):
    for rule in RULES:
        rows = table.filter(pl.col("rule") == rule)
        sizes = set(rows["scenario"].str.extract(r", (\d+) \w+$").cast(int))
        assert sizes == {3, 4, 6, 10}, (rule, sizes)
        assert set(rows["kind"]) >= {"at most"}
    for rule in (rs.BAND, rs.SECTORS, rs.CHANGE):
        assert table.filter((pl.col("rule") == rule) & (pl.col("kind") == "at least")).height


def test_the_committed_paired_block_is_the_simulation(table):
    """The first nesting's paired block recomputed alone (its own seed) is the committed one:
    about 20 s of CPU."""
    nest = cal.NESTINGS[0]
    block = cal.calibrate((nest,), rules=(cal.paired_shapes,))
    committed = table.filter((pl.col("replications") == nest.replications)
                             & (pl.col("within_sd") == nest.within_sd)
                             & pl.col("rule").is_in(list(block["rule"].unique())))
    assert block.equals(committed)


def test_every_row_not_met_is_named_on_the_page(table):
    page = " ".join(DOC.read_text().split())
    bad = calibration_page.failing(table)
    assert set(bad["rule"]) <= set(RULES), "a rule before these rows fails"
    for r in bad.iter_rows(named=True):
        assert (f"{r['scenario']} ({r['measure']}): {r['value']:.3f} at within s.d. "
                f"{r['within_sd']:g}") in page, r


@pytest.mark.parametrize("which", ["band", "change"])
def test_the_labels_read_the_table(table, which):
    label = coverage.shaped_label(table, which)
    measured = coverage.shaped_coverage(table, coverage.SHAPED_RULES[which])
    assert measured.height and f"{measured['low'].min():.3f}" in label
    moved = table.with_columns(pl.when(pl.col("rule") == coverage.SHAPED_RULES[which])
                               .then(0.5).otherwise(pl.col("value")).alias("value"))
    assert "0.500 at" in coverage.shaped_label(moved, which)
    assert "not measured" in coverage.shaped_label(
        table.filter(pl.col("rule") != coverage.SHAPED_RULES[which]), which)
    assert " ".join(label.split()) in " ".join(DOC.read_text().split())


def _pilot_table(errors: dict[str, dict[int, dict[float, float]]]) -> pl.DataFrame:
    """A pilot table with every rule's sizes and levels at error 0, except ``errors``
    (rule -> size -> level -> error)."""
    return pl.DataFrame([
        {"rule": rule, "size": k, "level": level, "error": errors.get(rule, {}).get(k, {}).get(
            level, 0.0), "worst": "x"}
        for rule, sizes in rs.PILOT_SIZES.items() for k in sizes
        for level in rs.PILOT_LEVELS[rule]])


def test_the_choice_takes_the_smallest_gate_then_the_largest_level():
    """``choose``: the gate is the smallest size from which some level holds at every larger
    size, the level the largest that holds there; a rule that holds nowhere at its largest
    size decides at none of the pilot's sizes."""
    levels = rs.PILOT_LEVELS[rs.BAND]
    fails = {k: {lv: 0.2 for lv in levels} for k in (3, 4, 6, 8)}  # every level fails
    fails[10] = {lv: 0.06 if lv > 0.01 else 0.04 for lv in levels}  # holds from 0.01 down
    sectors = {4: {lv: 0.06 for lv in rs.PILOT_LEVELS[rs.SECTORS][:3]}}  # 0.03 holds
    nowhere = {10: {lv: 0.1 for lv in rs.PILOT_LEVELS[rs.CHANGE]}}
    chosen = rs.choose(_pilot_table({rs.BAND: fails, rs.SECTORS: sectors, rs.CHANGE: nowhere}))
    assert chosen[rs.BAND] == (10, 0.01)
    assert chosen[rs.SECTORS] == (3, rs.PILOT_LEVELS[rs.SECTORS][3])
    assert chosen[rs.CHANGE] == (11, 0.05)
    assert chosen[rs.SENSES] == (6, 0.05)


def test_the_rules_run_at_the_committed_pilots_choice():
    """The gates and levels of ``verdict_core`` are the committed pilot's choice (a changed
    constant, or a pilot recomputed to another choice, fails), and the page shows the pilot."""
    chosen = rs.choose(pl.read_parquet(calibration_page.PILOT))
    assert chosen == {rs.BAND: (v.BAND_MIN_UNITS, v.BAND_LEVEL),
                      rs.SECTORS: (v.SECTOR_MIN_UNITS, v.SECTOR_LEVEL),
                      rs.CHANGE: (6, v.PAIRED_CHANGE_LEVEL),  # its test decides from 7 pairs
                      rs.SENSES: (6, v.FRIEDMAN_LEVEL)}
    page = " ".join(DOC.read_text().split())
    shown = calibration_page.pilot_values(pl.read_parquet(calibration_page.PILOT))
    assert " ".join(shown["pilot_choice"].split()) in page
    assert all(line in DOC.read_text() for line in shown["pilot_table"].splitlines())
