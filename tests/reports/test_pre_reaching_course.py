"""The pre-reaching course page (``reports.pre_reaching_course``): which strategy has taken
over, when the strategies last changed, when the question is next answered, the growth of
fitness, what the snapshots cost, and the full-budget run's judged generations."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import polars as pl
import pytest

from dart_reach.analysis import strategy_course as sc
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.evolution.settings import snapshot_due
from dart_reach.postevaluation import results
from dart_reach.postevaluation.snapshots import load_development
from reports import pre_reaching_course as course_page
from reports.runs import FULL, JUDGED, TEN

ROOT = Path(__file__).resolve().parents[2]


def test_the_course_page_says_which_strategy_has_taken_over():
    assert course_page.outcome(10, 0) == "babbling has taken over (all 10 populations babble)"
    assert course_page.outcome(0, 10) == ("stillness has taken over (all 10 populations are "
                                            "still)")
    assert course_page.outcome(4, 6) == "both persist (4 populations babble, 6 are still)"
    values = course_page.values(ROOT / "recordings")
    rows = [r for r in values["matrix"].splitlines()[2:]]
    last = rows[-1].split(" | ")
    assert last[0].strip("| ") == values["last"]
    babbling = sum(c.strip(" |").startswith("B") for c in last[1:])
    still = sum(c.strip(" |").startswith("S") for c in last[1:])
    assert values["outcome"] == course_page.outcome(babbling, still)


def test_the_course_page_says_when_the_strategies_last_changed():
    turns = pl.DataFrame({"replication": [0, 1, 2], "last_change": [20, None, 20]},
                         schema={"replication": pl.Int64, "last_change": pl.Int64})
    assert course_page.settled(turns, [1, 10, 20, 30, 40]) == (
        "The last change came at generation 20 (replications 0, 2); at the 2 snapshots since "
        "(30-40) every population kept its strategy.")
    assert course_page.settled(turns.head(2), [1, 10, 20]) == (
        "The last change came at generation 20 (replication 0), the last snapshot.")
    assert course_page.settled(turns.filter(pl.col("replication") == 1), [1, 10]) == (
        "No population changed strategy between snapshots.")


def test_the_course_page_says_when_the_question_is_next_answered():
    assert course_page.still_to_know(240, 500) == (
        "Whether this holds is known at generation 250 (this round's end) and at 500.")
    assert course_page.still_to_know(250, 500) == (
        "Whether it holds to generation 500 is known when pre-reaching ends there.")
    values = course_page.values(ROOT / "recordings")
    last = int(load_development(ROOT / "recordings" / FULL)
               .filter(pl.col("phase") == "pre")["generation"].max())
    assert values["last"] == str(last)
    assert values["still_to_know"] == (
        "Whether this holds is known at generation 250 (this round's end) and at 500."
        if last < 250 else
        "Whether it holds to generation 500 is known when pre-reaching ends there.")


def test_the_course_page_gives_the_growth_over_a_longer_window_once_it_is_trained():
    directory = ROOT / "recordings" / course_page.FULL
    stats = RunDirectory.open(directory).stats
    course = sc.course(load_development(directory))
    long_ = course_page.LONG_WINDOW
    rows = course_page.fitness_values(course, stats)["growth_table"].splitlines()[2:]
    raw = pl.read_parquet(directory / "generations.parquet").filter(pl.col("phase") == "pre")
    ratios = []
    for replication in sorted(raw["replication"].unique().to_list()):
        means = (raw.filter(pl.col("replication") == replication).sort("generation")
                 ["mean"].to_numpy())
        ratios.append(means[-long_:].mean() / means[-2 * long_:-long_].mean())
    assert [float(r.strip("| ").split(" | ")[-1]) for r in rows] == pytest.approx(ratios,
                                                                                 rel=5e-3)
    early = course_page.fitness_values(course, stats.filter(pl.col("generation") < 2 * long_))
    assert f"{2 * long_} generations are not yet trained" in early["growth_summary"]
    assert all(r.strip("| ").split(" | ")[-1] == "–"
               for r in early["growth_table"].splitlines()[2:])


def _trial_core_s_from_the_raw_records(directory: Path, upto: int) -> float:
    """The median core-seconds of a pre-reaching trial, recomputed here with plain polars and
    json from the run's raw records (not through ``cost``): a generation's wall time, on the
    workers of the last session started before it, over 10 replications x 40 lifetimes x
    18 trials."""
    manifest = json.loads((directory / "manifest.json").read_text())
    starts = [(s["generations_done"]["standard/pre"], s["workers"]) for s in manifest["sessions"]]
    walls = (pl.read_parquet(directory / "generations.parquet")
             .filter((pl.col("phase") == "pre") & (pl.col("generation") <= upto))
             .group_by("generation").agg(pl.col("wall_s").first()).sort("generation"))
    per = [wall * [w for done, w in starts if done < g][-1] / (10 * 40 * 18)
           for g, wall in walls.iter_rows()]
    return float(np.median(per))


def test_the_course_page_costs_the_snapshots_from_the_runs_own_records():
    """The snapshot rule the cost counts is the one the run followed (its committed snapshots
    are those ``snapshot_due`` names: to generation 250, 1, 2, 5 and every 10th), and the cost
    of a trial is the run's own, recomputed here from its raw records; the core-hours follow
    from the counts of the committed snapshots, positions and conditions."""
    directory = ROOT / "recordings" / "standard-500x10"
    kept = sorted(int(p.stem.removeprefix("gen"))
                  for p in directory.glob("phases/pre-*/snapshots/gen*.npz"))
    assert kept == [g for g in range(1, kept[-1] + 1)
                    if snapshot_due(g, 500, course_page.SNAPSHOT_EVERY)]
    values = course_page.cost_values(RunDirectory.open(directory), 500)
    upto = [g for g in kept if g <= 250]
    assert values["snapshots"] == str(len(upto)) == "28"
    trial = _trial_core_s_from_the_raw_records(directory, 250)
    assert float(values["trial_core_s"]) == pytest.approx(trial, abs=5e-4)
    assert float(values["trial_q1"]) < trial < float(values["trial_q3"])
    robots, positions = 5 * 10, 45  # the snapshot robots of 10 replications, 45 positions
    assert float(values["snapshots_core_h"]) == pytest.approx(
        len(upto) * robots * positions * trial / 3600, abs=0.1)
    assert float(values["judged_core_h"]) == pytest.approx(  # 4 other conditions
        len(JUDGED) * 4 * robots * positions * trial / 3600, abs=0.1)
    assert float(values["terms_core_h"]) == pytest.approx(
        len(JUDGED) * robots * positions * trial / 3600, abs=0.1)


def test_the_makefile_evaluates_the_generations_judged():
    makefile = (ROOT / "Makefile").read_text()
    line = next(x for x in makefile.splitlines() if x.startswith("JUDGED :="))
    assert line.split(":=")[1].strip() == ",".join(map(str, JUDGED))


def test_the_committed_runs_scale_ends_hold_no_rate():
    """On the full-budget run's committed snapshots no listed claim is of a rate."""
    dev = load_development(ROOT / "recordings" / FULL, senses=None)
    ends = sc.scale_ends(dev, JUDGED)
    assert not any("babbling" in c or "reach" in c for c in ends["claim"])


def test_the_course_page_says_the_strategies_fitness_only_through_the_gated_rule():
    """The committed snapshots of the full-budget run never have 6 populations of each
    strategy (counted here from the page's own matrix of strategies), so the page may say of
    their fitness neither a difference nor the same: every verdict cell is underpowered and
    the words say so."""
    values = course_page.values(ROOT / "recordings")
    rows = values["matrix"].splitlines()[2:]
    counts = [[sum(c.strip(" |").startswith(k) for c in r.split(" | ")[1:]) for k in "BS"]
              for r in rows]
    smaller = [min(c) for c in counts if min(c)]
    assert smaller and max(smaller) < 6
    assert "differs" not in values["fitness_summary"]
    assert "can show neither a difference nor the same" in values["fitness_summary"]
    cells = [c.strip(" |") for r in values["fitness_table"].splitlines()[2:]
             for c in r.split(" | ")[7:11]]
    assert cells and set(cells) == {"underpowered"}


def test_the_pages_words_on_babbling_are_counted_from_the_committed_trials():
    """"Some random networks babble" and "alike without the ball" are counts: recomputed here
    from the committed baseline and development tables with plain polars (a robot's share
    over its trials), and a robot made to babble in one no-ball trial only changes them."""
    baseline = results.read_table(ROOT / "recordings" / TEN / results.BASELINE)
    genomes = (baseline.filter((pl.col("phase") == "pre") & (pl.col("senses") == "normal"))
               .group_by("replication", "rank").agg(pl.col("babbling").any()))
    dev = load_development(ROOT / "recordings" / FULL, senses=None)
    robots = (dev.filter(pl.col("generation").is_in(JUDGED) & (pl.col("phase") == "pre")
                         & (pl.col("senses") == "no-ball"))
              .group_by("generation", "replication", "rank")
              .agg(pl.col("babbling").all().alias("all"), pl.col("babbling").any().alias("any")))
    alike = robots.filter(pl.col("all") | ~pl.col("any")).height
    words = course_page.babbling_words(dev, ROOT / "recordings")
    assert words["random_babbling"].startswith(
        f"{int(genomes['babbling'].sum())} of the {genomes.height} random pre-reaching genomes")
    assert words["no_ball_alike"].startswith(f"{alike} of the {robots.height} robots")
    page = (ROOT / "docs" / "results" / "pre-reaching-course.md").read_text()
    assert words["random_babbling"] in page and words["no_ball_alike"] in page
    one = robots.filter(~pl.col("any")).row(0, named=True)
    first = (pl.col("generation") == one["generation"]) & (pl.col("replication") == one[
        "replication"]) & (pl.col("rank") == one["rank"]) & (pl.col("senses") == "no-ball") & (
        pl.col("phase") == "pre") & (pl.col("trial") == 0)
    changed = dev.with_columns(pl.when(first).then(True).otherwise(pl.col("babbling"))
                               .alias("babbling"))
    assert course_page.babbling_words(changed, ROOT / "recordings")["no_ball_alike"].startswith(
        f"{alike - 1} of the {robots.height} robots")
