"""Post-evaluation (section IV) of a tiny real run: the table, the recordings, incremental
evaluation, determinism, and bad input."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import numpy as np
import polars as pl
import pytest

from dart_reach import integrity
from dart_reach.measures import metrics
from dart_reach.postevaluation import results
from dart_reach.postevaluation.systematic import SENSES, evaluate_run, load_evaluation
from dart_reach.recording.rrd import MEASURES, read_properties, read_rrd, verify

TRIALS = 45  # systematic positions, 5 per sector


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="module")
def evaluated(request, built_once):
    """``trained`` post-evaluated by ``dart-reach evaluate`` (a process of its own), made once
    for the session (read only: copy it to write): the run and what the command wrote."""
    def build(root):
        out = root / "run"
        shutil.copytree(request.getfixturevalue("trained"), out)
        result = _cli("evaluate", out, "--sensors", "no-touch", "--robots", "2", "--workers",
                      "1")
        assert result.returncode == 0, result.stderr
        (root / "stderr.txt").write_text(result.stderr)

    root = built_once("systematic-evaluated", build)
    return root / "run", subprocess.CompletedProcess(
        ["dart-reach", "evaluate"], 0, "", (root / "stderr.txt").read_text())


def test_table_and_recordings(evaluated):
    out, result = evaluated
    table = load_evaluation(out)
    assert table.height == 3 * 2 * 2 * TRIALS  # phases x replications x robots x positions
    assert set(table["senses"]) == {"no-touch"}
    assert table.group_by("phase", "replication", "rank").len()["len"].to_list() == [TRIALS] * 12
    assert table["sector"].to_list()[:TRIALS] == [k // 5 for k in range(TRIALS)]
    assert {"reached", "grasped", "speed", "straightness", "var_elbow", "babbling_share",
            "lifetime_fitness", "ball_x"} <= set(table.columns)
    recorded = table.filter(pl.col("recording").is_not_null())
    # the best robot of the best replication of each phase, every position
    assert recorded.height == 3 * TRIALS
    assert (recorded["rank"] == 0).all()
    files = sorted((out / "evaluation").rglob("*.rrd"))
    assert sorted(str(out / r) for r in recorded["recording"]) == [str(f) for f in files]
    verify(*files, out / "evaluation" / "trial.rbl")
    assert f"rerun {out / recorded['recording'][0]} {out / 'evaluation/trial.rbl'}" \
        in result.stderr
    row = recorded.row(7, named=True)
    props = read_properties(out / row["recording"])
    assert (props["phase"], props["replication"], props["individual"], props["trial"],
            props["sector"], props["senses"]) == (row["phase"], row["replication"], 0, 7, 1,
                                                  "no-touch")


def test_table_measures_agree_with_the_recording(evaluated):
    """The measures in the table, recomputed from the recorded signals, are the same."""
    out, _ = evaluated
    table = load_evaluation(out).filter(pl.col("recording").is_not_null())
    for row in table.sample(5, seed=0).iter_rows(named=True):
        rec = read_rrd(out / row["recording"])
        hand = rec.select("^robot/positions/hand/.*$").to_numpy()
        ball = rec.select("^robot/positions/ball/.*$").to_numpy()
        contacts = rec.select("^robot/contacts/.*$").to_numpy() > 0.5
        assert metrics.reached(contacts) == row["reached_inner"]  # recordings: inner faces
        assert metrics.grasped(contacts) == row["grasped"]
        # the table stores float32 (results.py): 24 significant bits
        assert rec["fitness/p_multimodal"].mean() == pytest.approx(row["fitness"], rel=2**-23)
        shoulder = rec.select("^robot/positions/shoulder/.*$").to_numpy()
        assert metrics.elbow_freezing(hand, shoulder) == pytest.approx(row["elbow_freezing"])
        assert np.linalg.norm(hand[0] - ball[0]) == pytest.approx(row["hand_ball_initial"])
        # the per-step movement variability ends at the table's values, and the recording's
        # measures are the table's row
        for group in ("elbow", "shoulder", "trunk"):
            assert rec[f"variability/joints/cumulative/{group}"][-1] == pytest.approx(
                row[f"var_{group}"], rel=2**-23, abs=1e-12)
        props = read_properties(out / row["recording"])
        for m in MEASURES:
            value = np.float32(props[m]) if isinstance(props[m], float) else props[m]
            same = value == row[m] or (np.isnan(props[m]) and np.isnan(row[m]))
            assert same, (m, props[m], row[m])


def test_evaluating_again_adds_only_what_is_missing(evaluated, tmp_path):
    src, _ = evaluated
    out = tmp_path / "run"
    shutil.copytree(src, out)
    before = load_evaluation(out)
    old = {p: p.stat().st_mtime_ns for p in (out / "evaluation").rglob("*.rrd")}
    table = evaluate_run(out, senses=SENSES, robots=2, record="none", workers=1)
    assert table.height == 4 * before.height
    assert not (out / "baseline.parquet").exists()  # no random genome asked for: no table
    assert table.filter(pl.col("senses") == "no-touch").equals(before)
    assert {p: p.stat().st_mtime_ns for p in (out / "evaluation").rglob("*.rrd")} == old
    saved = (out / "evaluation.parquet").read_bytes()
    again = evaluate_run(out, senses=SENSES, robots=2, workers=1)
    assert again.equals(table) and (out / "evaluation.parquet").read_bytes() == saved


def test_baseline_random_genomes_are_flagged_and_kept_apart(evaluated, trained, tmp_path,
                                                           in_process):
    src, _ = evaluated
    out = tmp_path / "run"
    shutil.copytree(src, out)
    before = load_evaluation(out)
    result = in_process("evaluate", out, "--sensors", "no-touch", "--robots", "2",
                        "--baseline", "2", "--workers", "1")
    assert result.returncode == 0, result.stderr
    every = load_evaluation(out, baseline=None)
    chance = load_evaluation(out, baseline=True)
    assert load_evaluation(out).equals(before)  # the trained robots' rows untouched
    assert chance.height == 3 * 2 * TRIALS  # phases x random genomes x positions
    assert every.height == before.height + chance.height
    assert (chance["rank"] == 0).all() and chance["lifetime_fitness"].is_nan().all()
    assert chance["recording"].is_null().all()
    assert sorted(set(chance["replication"])) == [0, 1]
    # the same random genomes as a run with a different budget drawn from the same seed
    # tree: the first k do not depend on N; and they are not the trained genomes
    more = evaluate_run(out, senses=["no-touch"], robots=2, baseline=3, workers=1)
    again = load_evaluation(out, baseline=True).filter(pl.col("replication") < 2)
    assert again.equals(chance)
    assert more.filter(pl.col("baseline")).height == 3 * 3 * TRIALS
    # (by the hand's path: continuous, so two genomes' trials share a value only if they move
    # alike; fitness, in steps of 1/80 on a tiny trial, may coincide by chance)
    trained_path = before.group_by("phase", "replication", "rank").agg(pl.col("hand_path").sum())
    random_path = chance.group_by("phase", "replication").agg(pl.col("hand_path").sum())
    assert not set(trained_path["hand_path"]) & set(random_path["hand_path"])
    with pytest.raises(ValueError, match="baseline must be 0 or more"):
        evaluate_run(out, senses=["no-touch"], baseline=-1)


def test_same_result_whatever_the_number_of_workers(evaluated, trained, tmp_path):
    src, _ = evaluated
    serial = load_evaluation(src).drop("recording")
    out = tmp_path / "pool"
    shutil.copytree(trained, out)
    pool = evaluate_run(out, senses=["no-touch"], robots=2, record="none", workers=2)
    assert pool.drop("recording").equals(serial)


def _one_line_error(result, *fragments):
    assert result.returncode == 2, result.stderr
    assert result.stderr.count("\n") == 1, result.stderr
    for f in fragments:
        assert f in result.stderr, result.stderr


def _snapshot(path):
    return {p: p.read_bytes() for p in sorted(path.rglob("*")) if p.is_file()}


def test_bad_input(trained, tmp_path, in_process):
    _one_line_error(_cli("evaluate", tmp_path / "nowhere"), "nowhere: no such run directory")
    empty = tmp_path / "empty"
    empty.mkdir()
    _one_line_error(in_process("evaluate", empty), "empty: not a run directory (no manifest.json)")

    future = tmp_path / "future"
    shutil.copytree(trained, future)
    manifest = json.loads((future / "manifest.json").read_text())
    integrity.write(future / "manifest.json",  # as a newer dart_reach writes it
                    lambda p: p.write_text(json.dumps(dict(manifest, format=99))))
    _one_line_error(in_process("evaluate", future),
                    "manifest.json: written by an incompatible version")

    unfinished = tmp_path / "unfinished"
    shutil.copytree(trained, unfinished)
    integrity.remove(next((unfinished / "phases").glob("fine-*/final.npz")))
    before = _snapshot(unfinished)
    _one_line_error(in_process("evaluate", unfinished), "unfinished run", "standard/fine")
    assert _snapshot(unfinished) == before  # nothing written

    run = tmp_path / "run"
    shutil.copytree(trained, run)
    _one_line_error(in_process("evaluate", run, "--robots", "21"), "robots must be between 1 and")
    _one_line_error(in_process("evaluate", run, "--sensors", "smell"), "--sensors")
    integrity.write(run / "evaluation.parquet", lambda p: p.write_bytes(b"not parquet"))
    _one_line_error(in_process("evaluate", run), "evaluation.parquet: unreadable")
    assert (run / "evaluation.parquet").read_bytes() == b"not parquet"


def test_the_finished_phases_of_an_unfinished_run_and_later_the_rest(trained, tmp_path,
                                                                     in_process):
    """--finished-only evaluates the phases trained to the end (a look at a long run
    part-way); its table, kept once the run has finished, is completed with only the rest,
    and the rows (baseline and every sensory condition included) are those of a whole
    evaluation."""
    args = ("--sensors", "all", "--robots", "1", "--baseline", "1", "--workers", "1",
            "--record", "none")
    whole = tmp_path / "whole"
    shutil.copytree(trained, whole)
    assert _cli("evaluate", whole, *args).returncode == 0
    part = tmp_path / "part"
    shutil.copytree(trained, part)
    fine = next((part / "phases").glob("fine-*/final.npz"))
    kept = fine.read_bytes()
    integrity.remove(fine)
    _one_line_error(in_process("evaluate", part, *args), "unfinished run", "--finished-only")
    done = in_process("evaluate", part, "--finished-only", *args)
    assert done.returncode == 0, done.stderr
    table = load_evaluation(part, None)
    evolved = table.filter(~pl.col("baseline"))
    assert sorted(set(evolved["phase"])) == ["gross", "pre"]
    assert evolved.height == 2 * (len(SENSES) + 1) * 2 * TRIALS  # phases, senses + no-ball
    chance = table.filter(pl.col("baseline"))  # random genomes need no training: every phase
    assert sorted(set(chance["phase"])) == ["fine", "gross", "pre"]
    assert chance.height == 3 * (len(SENSES) + 1) * TRIALS
    integrity.write(fine, lambda p: p.write_bytes(kept))  # the run finishes
    assert in_process("evaluate", part, *args).returncode == 0
    key = ("phase", "senses", "baseline", "replication", "rank", "trial")
    assert load_evaluation(part, None).drop("session").sort(key).equals(  # written in 2 sessions
        load_evaluation(whole, None).drop("session").sort(key))
    none = tmp_path / "none"
    shutil.copytree(trained, none)
    for f in (none / "phases").glob("*/final.npz"):
        integrity.remove(f)
    _one_line_error(in_process("evaluate", none, "--finished-only"), "no phase has finished yet")


def test_rows_of_an_older_version_of_the_measures_are_measured_again(evaluated, tmp_path):
    """A table written before version 2 of the measures (no measures_version; reach on inner
    faces) opens once migrated (version 1), and evaluating its robots again replaces their rows
    instead of mixing versions."""
    src, _ = evaluated
    out = tmp_path / "run"
    shutil.copytree(src, out)
    current = load_evaluation(out)
    old = current.drop("measures_version", "reached_inner", "session").with_columns(
        pl.lit(False).alias("reached"))  # as an older version measured them
    integrity.write(out / "evaluation.parquet", lambda p: old.write_parquet(p))
    assert results.migrate(out) == [out / "evaluation.parquet"]
    assert (load_evaluation(out)["measures_version"] == 1).all()
    table = evaluate_run(out, senses=["no-touch"], robots=2, record="none", workers=1)
    assert table.height == current.height and (table["measures_version"] == 2).all()
    key = ["phase", "replication", "rank", "trial"]
    assert table.sort(key).select(current.columns).drop("recording", "session").equals(
        current.sort(key).drop("recording", "session"))


def test_the_ball_absent_test_is_a_condition_of_its_own(evaluated, tmp_path, in_process):
    """no-ball (IV-A-1): stored and recorded like the senses; nothing is touched, the table
    holds where the ball would hang; Fig. 8 gets its row."""
    from dart_reach.analysis import figures
    from dart_reach.postevaluation.systematic import BALL_ABSENT, TESTS, parse_senses

    assert parse_senses("all") == TESTS == (*SENSES, BALL_ABSENT) and BALL_ABSENT == "no-ball"
    src, _ = evaluated
    out = tmp_path / "run"
    shutil.copytree(src, out)
    result = in_process("evaluate", out, "--sensors", "no-ball", "--robots", "1",
                        "--workers", "1")
    assert result.returncode == 0, result.stderr
    table = load_evaluation(out)
    absent = table.filter(pl.col("senses") == "no-ball")
    assert absent.height == 3 * 2 * TRIALS
    assert not absent["reached"].any() and (absent["fitness"] == 0).all()
    normal_positions = table.filter(pl.col("senses") == "no-touch").select(
        "trial", "ball_x", "ball_y", "ball_z").unique().sort("trial")
    assert absent.select("trial", "ball_x", "ball_y", "ball_z").unique().sort("trial").equals(
        normal_positions)
    recorded = absent.filter(pl.col("recording").is_not_null())
    assert recorded.height == 3 * TRIALS and "/no-ball/" in recorded["recording"][0]
    row = recorded.row(20, named=True)
    assert read_properties(out / row["recording"])["senses"] == "no-ball"
    rec = read_rrd(out / row["recording"])
    ball = rec.select("^robot/positions/ball/.*$").to_numpy()
    assert np.allclose(ball, [row["ball_x"], row["ball_y"], row["ball_z"]])
    fig = figures.fig8_trajectories(table, out, senses=["no-touch", "no-ball"])
    assert len(fig.axes) == 2 * 3 + 1  # two rows of three phases and the colour bar
    assert "no-ball" in fig.axes[3].get_ylabel()
