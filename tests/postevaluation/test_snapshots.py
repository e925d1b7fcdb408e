"""Development over generations (``postevaluation/snapshots.py``, the snapshots of
``RunDirectory``): the measures' course per replication through a condition's phases (sections
IV-A, IV-C, V; Table I). That snapshots change nothing trained and survive a resume:
tests/evolution/test_trainer.py."""

from __future__ import annotations

import math

import polars as pl
import pytest

from dart_reach import integrity
from dart_reach.postevaluation import snapshots as dev
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.postevaluation.systematic import evaluate_run, load_evaluation
from dart_reach.evolution.settings import Settings, snapshot_due
from dart_reach.evolution.trainer import train
from dart_reach.measures.metrics import trial_metrics
from dart_reach.recording.rrd import read_rrd

TINY = Settings(replications=2, trials=1, steps=4, seed=3)


def test_snapshot_generations():
    due = [g for g in range(1, 501) if snapshot_due(g, 500, 50)]
    assert due == [1, 2, 5, 10, 50, 100, 150, 200, 250, 300, 350, 400, 450, 500]
    assert [g for g in range(1, 8) if snapshot_due(g, 7, 50)] == [1, 2, 5, 7]
    assert not any(snapshot_due(g, 500, 0) for g in range(1, 501))


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The standard condition, 2 generations per phase, with snapshots and recordings after
    every generation (that they change nothing trained: tests/evolution/test_trainer.py)."""
    cond = [scaled(load_condition("standard"), 2)]
    snap = train(cond, TINY, tmp_path_factory.mktemp("dev") / "snap", workers=1,
                 progress=False, snapshot_every=1, record_every=1)
    return cond, None, snap


def test_development_course_from_snapshots(runs):
    _, _, snap = runs
    told = []
    table = dev.measure_snapshots(snap.out, robots=1, workers=1, progress=told.append)
    assert table.height == 3 * 2 * 2 * 45  # phases x snapshots x replications x positions
    assert [p.robots_done for p in told] == list(range(1, 13))
    assert {p.robots_total for p in told} == {12} and told[-1].eta_s == 0.0
    assert all(p.eta_s > 0 for p in told[:-1]) and told[0].phase.startswith("pre @")
    assert (snap.out / dev.TABLE).is_file()
    again = dev.measure_snapshots(snap.out, robots=1, workers=1)
    assert again.equals(table)  # nothing evaluated twice
    more = dev.measure_snapshots(snap.out, robots=2, workers=1)
    assert more.height == 2 * table.height
    c = dev.course(more)
    assert c.height == 3 * 2 * 2 and set(c["robots"].to_list()) == {2}
    assert c.filter(pl.col("notation") == "gross")["x"].unique().sort().to_list() == [3, 4]
    assert c.filter(pl.col("notation") == "fine")["x"].unique().sort().to_list() == [5, 6]
    # a replication's course value is its robots' mean of their trials' means
    one = more.filter((pl.col("notation") == "pre") & (pl.col("replication") == 1)
                      & (pl.col("generation") == 2))
    expected = one.group_by("rank").agg(pl.col("hand_path").mean())["hand_path"].mean()
    got = c.filter((pl.col("notation") == "pre") & (pl.col("replication") == 1)
                   & (pl.col("generation") == 2))["hand_path"].item()
    assert got == pytest.approx(expected)
    w = dev.window(c, "hand_path", "gross", first=1, last=1)
    assert w["replication"].to_list() == [0, 1] and w["points"].to_list() == [1, 1]


def test_a_recording_reads_back_into_the_same_measures(runs):
    """The course from best-of-generation recordings (all a run made before snapshots has)
    measures what the trial measured: every measure that does not need the any-face touches
    or the palm's normal, which recordings do not hold."""
    _, _, snap = runs
    table = evaluate_run(snap.out, robots=1, record="best", workers=1, progress=False)
    row = table.filter(pl.col("recording").is_not_null()).row(3, named=True)
    data = dev.trial_from_recording(read_rrd(snap.out / row["recording"]), row["sector"])
    m = trial_metrics(data, 0.1)
    for name in ("fitness", "reached_inner", "grasped", "hand_path", "var_elbow",
                 "var_shoulder", "hand_shoulder_cv", "babbling_share", "hand_amplitude"):
        a, b = m[name], row[name]
        assert (math.isnan(a) and math.isnan(b)) if isinstance(a, float) and math.isnan(a) \
            else a == pytest.approx(b), name
    recorded = dev.recorded_development(snap.out)
    assert recorded.height == 3 * 2 * 2  # phases x replications x generations (every 1)
    assert set(recorded["generation"].to_list()) == {1, 2}
    assert dev.course(recorded)["x"].max() == 6


def test_figures_of_the_course_and_of_the_behaviours(runs):
    from dart_reach.analysis import figures

    _, _, snap = runs
    c = dev.course(dev.measure_snapshots(snap.out, robots=1, workers=1))
    fig = figures.development_figure(c, "hand_path", "hand path (m)")
    ax = fig.axes[0]
    assert len(ax.lines) == 2 + 1 + 3  # a line per replication, the median, 3 phase starts
    assert [t.get_text().strip() for t in ax.texts] == ["pre", "gross", "fine"]
    empty = figures.development_figure(c.head(0), "hand_path")
    assert "no development data" in empty.axes[0].texts[0].get_text()
    table = evaluate_run(snap.out, robots=1, record="none", workers=1, progress=False)
    fig = figures.table1_behaviours(table)
    assert len(fig.axes) == len(figures.BEHAVIOUR_MEASURES)
    assert fig.axes[0].get_ylabel().startswith("motor babbling")


def test_the_report_draws_the_course_of_every_measure(runs, tmp_path):
    import re

    from dart_reach.analysis import report

    _, _, snap = runs
    dev.measure_snapshots(snap.out, robots=1, workers=1)
    evaluate_run(snap.out, robots=1, record="none", workers=1, progress=False)
    text = report.build([snap.out], tmp_path / "r.html").read_text()
    assert "Development over generations: post-evaluation of the snapshots" in text
    part = text[text.index("Development over generations"):]
    assert len(re.findall(r'src="data:image/png;base64,', part)) >= len(dev.MEASURES)


def _trained_copy(run, out):
    """A copy of a run's training alone (the manifest, its statistics and phases), without
    what the other tests evaluated in it."""
    import shutil

    out.mkdir()
    for name in ("manifest.json", "generations.parquet", "ledger.json"):
        shutil.copy(run / name, out / name)
    shutil.copytree(run / "phases", out / "phases")
    return out


def _cli(*args):
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=600)


def test_chosen_snapshots_under_chosen_senses(runs, tmp_path):
    """``generations`` picks snapshots, ``senses`` the conditions; the course and the
    developmental claims read the normal trials (``load_development``'s default) whatever
    else the table holds, and a condition added later adds only its rows."""
    _, _, snap = runs
    out = _trained_copy(snap.out, tmp_path / "run")
    table = dev.measure_snapshots(out, robots=1, workers=1, senses=("normal", "no-ball"),
                                  generations=(2,))
    assert set(table["generation"]) == {2} and set(table["senses"]) == {"normal", "no-ball"}
    assert table.height == 2 * 3 * 2 * 45  # senses x phases x replications x positions
    saved = (out / dev.TABLE).read_bytes()
    with pytest.raises(ValueError, match=r"no snapshot of generation 99 \(its snapshots: 1, 2"):
        dev.measure_snapshots(out, robots=1, workers=1, generations=(2, 99))
    assert (out / dev.TABLE).read_bytes() == saved  # refused: nothing evaluated or written
    # the command refuses it before its post-evaluation of the final robots (hours on a run)
    assert not (out / "evaluation.parquet").exists()
    cli = _cli("evaluate", out, "--development", "1", "--snapshots", "2,99", "--record", "none",
               "--workers", "1")
    assert cli.returncode == 2 and cli.stderr.count("\n") == 1, cli.stderr
    assert "no snapshot of generation 99" in cli.stderr
    assert not (out / "evaluation.parquet").exists()
    absent = table.filter(pl.col("senses") == "no-ball")
    assert not absent["reached"].any()  # no ball, nothing reached
    normal = dev.load_development(out)
    assert set(normal["senses"]) == {"normal"} and normal.height == table.height // 2
    assert dev.load_development(out, senses=None).height == table.height
    course = dev.course(normal)
    assert course.height == 3 * 2 and set(course["robots"]) == {1}
    from dart_reach.postevaluation import checks, results

    status = next(s for s in checks.table_status(out) if s.name == dev.TABLE)
    assert status.complete and "in 3 of the run's 6 snapshots (no-ball, normal)" in status.summary
    part = table.filter(~((pl.col("phase") == "pre") & (pl.col("replication") == 1)
                          & (pl.col("senses") == "no-ball")))
    results.write_table(out / dev.TABLE, part, results.sessions(out / dev.TABLE))
    status = next(s for s in checks.table_status(out) if s.name == dev.TABLE)
    assert not status.complete and status.missing == ("pre @2 (no-ball): 1 snapshot robots "
                                                      "missing",)
    results.write_table(out / dev.TABLE, table, results.sessions(out / dev.TABLE))
    whole = dev.measure_snapshots(out, robots=1, workers=1)  # the other snapshots, normal
    assert whole.height == table.height + 3 * 2 * 45
    assert whole.filter(pl.col("generation") == 2).drop("session").sort(
        "senses", "phase", "replication", "trial").equals(
        table.drop("session").sort("senses", "phase", "replication", "trial"))


def test_the_snapshots_of_a_run_still_training(runs, tmp_path, in_process):
    """--finished-only --development: the snapshots saved so far in a run no phase of which
    has finished (on a copy: the training holds the lock), their rows those of the finished
    run, and --baseline's random genomes; without the option the run is refused in one line;
    bad choices are one line too."""
    import shutil

    _, _, snap = runs
    part = _trained_copy(snap.out, tmp_path / "part")
    for f in (part / "phases").glob("*/final.npz"):
        integrity.remove(f)
    for f in (part / "phases").glob("gross-*/snapshots/gen0002.npz"):
        integrity.remove(f)  # gross is at generation 1, fine not begun
    shutil.rmtree(next((part / "phases").glob("fine-*")))
    args = ("--development", "1", "--workers", "1", "--record", "none")
    refused = _cli("evaluate", part, *args)
    assert refused.returncode == 2 and "unfinished run" in refused.stderr, refused.stderr
    for bad, says in ((("--snapshots", "1"), "give --development"),
                      (("--development", "1", "--snapshots", "0"), "generations"),
                      (("--development", "1", "--development-sensors", "normal,dark"),
                       "unknown sensory condition 'dark'")):
        result = in_process("evaluate", part, "--finished-only", *bad)
        assert result.returncode == 2 and result.stderr.count("\n") == 1, result.stderr
        assert says in result.stderr, result.stderr
    done = in_process("evaluate", part, "--finished-only", *args, "--development-sensors",
                      "normal,no-ball", "--baseline", "1")
    assert done.returncode == 0, done.stderr
    assert not (part / "evaluation.parquet").exists()  # no phase finished: no trained robot
    chance = load_evaluation(part, baseline=True)  # random genomes need no training
    assert sorted(set(chance["phase"])) == ["fine", "gross", "pre"]
    assert chance.height == 3 * 45 and set(chance["senses"]) == {"normal"}
    more = in_process("evaluate", part, "--finished-only", "--baseline", "2", "--workers", "1",
                      "--development", "1", "--snapshots", "1")
    assert more.returncode == 0, more.stderr
    again = load_evaluation(part, baseline=True)
    assert again.height == 2 * chance.height  # the first genome's rows kept, not redone
    assert again.filter(pl.col("replication") == 0).drop("session").sort("phase", "trial").equals(
        chance.drop("session").sort("phase", "trial"))
    table = dev.load_development(part, senses=None)
    seen = set(table.select("phase", "generation", "senses").unique().iter_rows())
    assert seen == {(p, g, s) for p, g in (("pre", 1), ("pre", 2), ("gross", 1))
                    for s in ("normal", "no-ball")}
    full = dev.measure_snapshots(snap.out, robots=1, workers=1).filter(pl.col("rank") == 0)
    key = ("phase", "generation", "replication", "trial")
    mine = table.filter(pl.col("senses") == "normal").drop("session").sort(key)
    assert mine.equals(full.join(mine.select("phase", "generation").unique(),
                                 on=["phase", "generation"]).drop("session").sort(key)
                       .select(mine.columns))
