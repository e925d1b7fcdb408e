"""The committed tables of Eq. 5's factors (``studies.fitness_terms``, written by
``reports.stillness``) are the post-evaluated robots' trials: their fitness is the committed
post-evaluation's, and a robot's trials run again give its rows."""

from __future__ import annotations

import shutil
from pathlib import Path

import polars as pl
import pytest

from dart_reach import robots
from dart_reach.analysis import strategies
from dart_reach.evolution.provenance import simd
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.measures.fitness import TERMS
from dart_reach.postevaluation import results
from dart_reach.postevaluation.snapshots import load_development
from dart_reach.postevaluation.systematic import load_evaluation
from dart_reach.studies import fitness_terms
from reports import pre_reaching_course, stillness
from reports.runs import FULL, JUDGED

ROOT = Path(__file__).resolve().parents[2]
RUN_DIR = ROOT / "recordings" / stillness.RUN


def committed() -> pl.DataFrame:
    return results.read_table(RUN_DIR / fitness_terms.TABLE)


def test_the_table_holds_every_post_evaluated_pre_reacher_on_every_position():
    table = committed()
    evaluated = fitness_terms.evaluated_pre(RUN_DIR)
    assert len(evaluated) == 50  # the best 5 of each of 10 replications
    assert sorted(table.select("replication", "rank").unique().iter_rows()) == evaluated
    assert table.height == 45 * len(evaluated)
    assert set(TERMS) <= set(table.columns)
    shipped = {(r.replication, r.rank) for r in robots.robots("pre", run=stillness.RUN)}
    assert shipped <= set(evaluated)  # the shipped robots are among them


def test_its_fitness_is_the_committed_post_evaluation():
    evaluation = results.read_table(RUN_DIR / results.EVALUATION).filter(
        (pl.col("phase") == "pre") & (pl.col("senses") == "normal") & ~pl.col("baseline"))
    joined = committed().join(evaluation.select("replication", "rank", "trial", "sector",
                                                pl.col("fitness").alias("evaluated")),
                              on=["replication", "rank", "trial", "sector"])
    assert joined.height == committed().height
    assert (joined["fitness"] == joined["evaluated"]).all()


def test_a_robot_run_again_gives_its_rows():
    """The still robot of replication 9 (rank 1) on its first sector's 5 positions. Bit for
    bit only at the numpy dispatch level the table was written at (docs/guides/runs.md,
    "Results"): elsewhere the trials may part, and the check is skipped."""
    written = {s.get("simd") for s in results.sessions(RUN_DIR / fitness_terms.TABLE)}
    if written != {simd()}:
        pytest.skip(f"table written at numpy's {written}, this process runs at {simd()}")
    run = RunDirectory.open(RUN_DIR)
    again = results.quantised(pl.DataFrame(fitness_terms.robot_trials(run, 9, 1, positions=5)))
    stored = committed().filter((pl.col("replication") == 9) & (pl.col("rank") == 1)
                                & (pl.col("trial") < 5)).sort("trial")
    for term in TERMS:
        assert again[term].to_list() == pytest.approx(stored[term].to_list(), nan_ok=True), term
    assert again["touches"].sum() > 0  # the check is on trials that touch the ball


def test_the_still_replications_are_those_in_which_no_robot_babbles():
    """The rule's split is replication.md's: no trial babbles in a still replication."""
    evaluation = results.read_table(RUN_DIR / results.EVALUATION).filter(
        (pl.col("phase") == "pre") & (pl.col("senses") == "normal") & ~pl.col("baseline"))
    never = sorted(evaluation.group_by("replication").agg(pl.col("babbling").any())
                   .filter(~pl.col("babbling"))["replication"])
    values = stillness.values(ROOT / "recordings", lambda table: table.write_csv())
    assert values["still.replications"] == ", ".join(map(str, never))
    assert int(values["still.count"]) + int(values["babbling.count"]) == 10


def test_the_plain_words_say_which_strategy_is_higher_only_by_the_gated_rule():
    """"In plain words" carries the gated rule's words recomputed from the committed table
    (the replications' means, ``compare``, ``decided``) and ratios of the pooled trials' means
    recomputed the same way, and none of the comparison words the means once decided."""
    t = stillness.tables(ROOT / "recordings")
    page = (ROOT / "docs/results/stillness.md").read_text()
    plain = page[page.index("## In plain words"):page.index("## Per strategy")]
    assert strategies.decided(strategies.compare(t["by_replication"])) in plain
    per = {r["strategy"]: r for r in t["by_strategy"].iter_rows(named=True)}
    bout = per[strategies.STILL]["contact_bout_s"] / per[strategies.BABBLING]["contact_bout_s"]
    assert f"still / babbling, a ratio of the means, {bout:.1f})" in plain
    for word in ("more of its hand", "for longer", "out-earns", "not what separates"):
        assert word not in plain


def test_the_50_generation_comparison_takes_contact_after_first_from_the_table(tmp_path):
    """replication-50x10's evaluation predates ``contact_after_first``: the course page's
    comparison at 50 generations gives its pre-reachers' trials the table's values, and a
    table missing a robot is an error, not a silent NaN."""
    evaluation = load_evaluation(RUN_DIR)
    assert "contact_after_first" not in evaluation.columns
    measured = pre_reaching_course.with_terms(RUN_DIR, evaluation)
    keys = ["replication", "rank", "trial"]
    joined = measured.join(committed().select(*keys, pl.col("contact_after_first").alias("t")),
                           on=keys)
    assert measured.height == joined.height == 45 * 50
    assert joined["contact_after_first"].equals(joined["t"], null_equal=True)
    assert measured["contact_after_first"].is_nan().sum() < measured.height  # touches exist
    short = tmp_path / "run"
    short.mkdir()
    results.write_table(short / fitness_terms.TABLE,
                        committed().filter(pl.col("replication") != 3), [{}])
    with pytest.raises(ValueError, match="not every pre-reacher's trial"):
        pre_reaching_course.with_terms(short, evaluation)


FULL_DIR = ROOT / "recordings" / FULL


def test_the_full_runs_table_holds_its_snapshots_robots_with_their_development_fitness():
    """Each snapshot generation in standard-500x10's table: every robot its development.parquet
    post-evaluated there, on every position, with the fitness it stored, to the last bit."""
    table = results.read_table(FULL_DIR / fitness_terms.TABLE)
    generations = table["generation"].unique().sort().to_list()
    assert generations and set(generations) <= set(JUDGED)
    development = load_development(FULL_DIR)
    keys = ["generation", "replication", "rank", "trial", "sector"]
    for generation in generations:
        rows = table.filter(pl.col("generation") == generation)
        assert (sorted(rows.select("replication", "rank").unique().iter_rows())
                == fitness_terms.snapshot_pre(FULL_DIR, generation))
        assert rows.height == 45 * 50
    joined = table.join(development.select(*keys, pl.col("fitness").alias("evaluated")),
                        on=keys)
    assert joined.height == table.height
    assert (joined["fitness"] == joined["evaluated"]).all()
    assert set(TERMS) <= set(table.columns)


def test_every_judged_snapshot_post_evaluated_is_taken_apart(tmp_path):
    """The committed table holds every judged generation the development table has; without
    the table, those are the generations ``--judged`` would run."""
    assert fitness_terms.missing(FULL_DIR, JUDGED) == []
    judged = sorted(set(results.read_table(FULL_DIR / fitness_terms.TABLE)["generation"]))
    for name in results.stored_files(FULL_DIR / results.DEVELOPMENT):
        (tmp_path / name.relative_to(FULL_DIR)).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(name, tmp_path / name.relative_to(FULL_DIR))
    assert fitness_terms.missing(tmp_path, JUDGED) == judged


def test_a_snapshot_not_post_evaluated_is_one_line_and_exit_2(capsys):
    assert stillness.main([str(ROOT), "--generation", "7"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "no pre-reaching snapshot of generation 7" in err


def test_a_snapshot_of_one_strategy_is_said_not_compared(tmp_path):
    """Generation 100 as committed compares the two strategies; with every population made to
    babble there is nothing to compare, and the page says so instead of failing."""
    def md(table):
        return table.write_csv()

    committed_values = stillness.budget_values(ROOT / "recordings", md)
    assert "at 100, 3 still against 7 babbling replications, the gated rule: " in \
        committed_values["budget.body"]
    run = tmp_path / FULL
    run.mkdir()
    development = load_development(FULL_DIR).filter(pl.col("generation") == 100)
    results.write_table(run / results.DEVELOPMENT,
                        development.with_columns(pl.lit(True).alias("babbling")), [{}])
    terms = results.read_table(FULL_DIR / fitness_terms.TABLE).filter(pl.col("generation") == 100)
    results.write_table(run / fitness_terms.TABLE, terms, [{}])
    values = stillness.budget_values(tmp_path, md)
    assert values["budget.generations"] == "100"
    assert "at 100 all the populations are babbling: nothing to compare" in values["budget.body"]
    assert "(none)" in values["budget.body"]
