"""Development over generations (``development.py``, the snapshots of ``experiment.Run``):
snapshots change nothing that is trained, survive a resume, and give the measures' course per
replication through a condition's phases (sections IV-A, IV-C, V; Table I)."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest

from dart_reach import development as dev
from dart_reach.conditions import load_condition, scaled
from dart_reach.evaluation import evaluate_run
from dart_reach.experiment import SNAPSHOT_ROBOTS, Run, Settings, snapshot_due, train
from dart_reach.metrics import trial_metrics
from dart_reach.recording import read_rrd

TINY = Settings(replications=2, trials=1, steps=4, seed=3)


def _final(out):
    stats = pl.read_parquet(out / "generations.parquet").drop("wall_s")
    finals = {}
    for d in sorted((out / "phases").iterdir()):
        with np.load(d / "final.npz") as f:
            finals[d.name] = (f["population"].copy(), f["fitness"].copy())
    return stats, finals


def _same(a, b) -> bool:
    return a[0].equals(b[0]) and a[1].keys() == b[1].keys() and all(
        np.array_equal(a[1][k][0], b[1][k][0]) and np.array_equal(a[1][k][1], b[1][k][1])
        for k in a[1])


def test_snapshot_generations():
    due = [g for g in range(1, 501) if snapshot_due(g, 500, 50)]
    assert due == [1, 2, 5, 10, 50, 100, 150, 200, 250, 300, 350, 400, 450, 500]
    assert [g for g in range(1, 8) if snapshot_due(g, 7, 50)] == [1, 2, 5, 7]
    assert not any(snapshot_due(g, 500, 0) for g in range(1, 501))


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The standard condition, 2 generations per phase, with and without snapshots."""
    root = tmp_path_factory.mktemp("dev")
    cond = [scaled(load_condition("standard"), 2)]
    plain = train(cond, TINY, root / "plain", workers=1, progress=False)
    snap = train(cond, TINY, root / "snap", workers=1, progress=False, snapshot_every=1,
                 record_every=1)
    return cond, plain, snap


def test_snapshots_change_nothing_trained_and_hold_the_best(runs):
    _, plain, snap = runs
    assert _same(_final(plain.out), _final(snap.out))
    assert not list(plain.out.rglob("snapshots"))
    for _, phase in snap.unique_phases():
        shots = snap.snapshots(phase)
        assert [g for g, _, _ in shots] == [1, 2]
        generation, genomes, fitness = shots[-1]
        final, final_fitness = snap.load_final(phase)
        assert genomes.shape == (2, SNAPSHOT_ROBOTS, final.shape[2])
        assert np.array_equal(genomes, final[:, :SNAPSHOT_ROBOTS])  # best first
        assert np.array_equal(fitness, final_fitness[:, :SNAPSHOT_ROBOTS])
        assert genomes.dtype == np.uint8 and (snap.snapshot_path(phase, 2)).stat().st_size < 20e3


def test_a_run_made_without_snapshots_resumes_with_them_to_the_same_result(runs, tmp_path):
    cond, plain, _ = runs

    def stop_after_first(progress):
        if progress.done_generations == 1:
            raise KeyboardInterrupt

    out = tmp_path / "old"
    with pytest.raises(KeyboardInterrupt):
        train(cond, TINY, out, workers=1, progress=stop_after_first)  # no snapshots
    train(cond, TINY, out, workers=1, progress=False, resume=True, snapshot_every=1)
    assert _same(_final(plain.out), _final(out))
    run = Run.open(out)
    pre = run.unique_phases()[0][1]
    assert [g for g, _, _ in run.snapshots(pre)] == [2]  # generation 1 was made before


def test_development_course_from_snapshots(runs):
    _, _, snap = runs
    table = dev.evaluate_snapshots(snap.out, robots=1, workers=1)
    assert table.height == 3 * 2 * 2 * 45  # phases x snapshots x replications x positions
    assert (snap.out / dev.TABLE).is_file()
    again = dev.evaluate_snapshots(snap.out, robots=1, workers=1)
    assert again.equals(table)  # nothing evaluated twice
    more = dev.evaluate_snapshots(snap.out, robots=2, workers=1)
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
    from dart_reach import figures

    _, _, snap = runs
    c = dev.course(dev.evaluate_snapshots(snap.out, robots=1, workers=1))
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
