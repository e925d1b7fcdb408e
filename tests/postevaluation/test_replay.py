"""Recordings made again on demand (replay.py): the trial of a committed row, run again in the
real DART world, is recorded where the post-evaluation would have put it, its measures are the
row's, and Fig. 8 draws from committed results alone."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import polars as pl

from dart_reach.analysis import figures, tables
from dart_reach.postevaluation import replay
from dart_reach.postevaluation.systematic import load_evaluation
from dart_reach.recording.rrd import MEASURES, read_properties, read_rrd

ROOT = Path(__file__).resolve().parents[2]


def test_a_committed_trial_is_recorded_again_with_the_rows_measures(tmp_path):
    run = tmp_path / "near"
    shutil.copytree(ROOT / "recordings/scene-study/near", run)
    table = load_evaluation(run, None)
    assert table["recording"].is_null().all()  # the committed results hold no recording
    robot = tables.recorded_robot(table.filter(~pl.col("baseline")), "pre")
    assert robot.height == 45 and robot["rank"].unique().to_list() == [0]
    row = robot.filter(pl.col("trial") == 20).row(0, named=True)
    path = replay.recording(run, row)
    assert path.is_file() and path.is_relative_to(run / "evaluation")
    assert (run / "evaluation" / "trial.rbl").is_file()
    props = read_properties(path)
    assert (props["replication"], props["trial"], props["sector"]) == (
        row["replication"], 20, 4)
    for m in MEASURES:  # the table stores float32
        value = np.float32(props[m]) if isinstance(props[m], float) else props[m]
        assert value == row[m] or (np.isnan(props[m]) and np.isnan(row[m])), m
    stamp = path.stat().st_mtime_ns
    assert replay.recording(run, row) == path and path.stat().st_mtime_ns == stamp  # kept
    chance = table.filter(pl.col("baseline") & (pl.col("trial") == 3)).row(0, named=True)
    assert read_rrd(replay.recording(run, chance)).height > 0


def test_fig8_draws_from_committed_results_alone(tmp_path):
    run = tmp_path / "near"
    shutil.copytree(ROOT / "recordings/scene-study/near", run)
    table = load_evaluation(run)
    fig = figures.fig8_trajectories(table, run, ["pre"], senses=["normal", "no-ball"])
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert "no recording" not in texts
    assert len(list((run / "evaluation").rglob("*.rrd"))) == 2
