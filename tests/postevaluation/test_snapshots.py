"""Development over generations (``postevaluation/snapshots.py``, the snapshots of
``RunDirectory``): the measures' course per replication through a condition's phases (sections
IV-A, IV-C, V; Table I). That snapshots change nothing trained and survive a resume:
tests/evolution/test_trainer.py."""

from __future__ import annotations

import math

import polars as pl
import pytest

from dart_reach.postevaluation import snapshots as dev
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.postevaluation.systematic import evaluate_run
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
