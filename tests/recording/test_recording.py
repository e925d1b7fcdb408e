"""Recordings: a real trial in the real world, written to .rrd, verified by rerun's own
verifier, and read back equal to what was logged."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import numpy as np
import polars as pl
import pytest
from rerun.chunk import RrdReader
from scipy.spatial.transform import Rotation

from dart_reach import save_series
from dart_reach.measures.units import with_unit
from dart_reach.measures import metrics
from dart_reach.recording import rrd as rec
from dart_reach.recording.quaternion import quaternions
from dart_reach.model.ctrnn import random_params
from dart_reach.model.task import Trial, TrialConfig, network_for
from dart_reach.model.world import World


@pytest.fixture(scope="module")
def world():
    return World()


@pytest.fixture(scope="module")
def trial(world):
    config = TrialConfig(steps=40, acuity=3.0, reflexes=False)
    runner = Trial(world, config)
    network = network_for(random_params(np.random.default_rng(5)), config)
    return runner.run(network, 4, world.sector_point(4, 0.3, 0.6))


INFO = rec.TrialInfo("standard", "pre", 1, 2, 4, 7, "SeedSequence(3, (1, 2))", "no-touch")


def _write(tmp_path, world, data, name="t.rrd"):
    return rec.write_rrd(tmp_path / name, rec.trial_rrd(data, INFO, rec.RobotModel(world)))


def test_what_is_read_equals_what_was_logged(tmp_path, world, trial):
    path = _write(tmp_path, world, trial)
    rec.verify(path)
    table = rec.read_rrd(path)
    assert table.height == trial.steps_run == 40
    assert table["step"].to_list() == list(range(40))
    assert np.allclose(table["sim_time"].to_numpy(), np.arange(40) * 0.1)
    n_series = 0
    for entity, names, get in rec.SIGNALS:
        logged = np.asarray(get(trial), float)
        columns = [f"{entity}/{n}" for n in names]
        read = table.select(columns).to_numpy()
        assert np.array_equal(read, logged), columns[0]  # bit for bit
        n_series += len(names)
    assert table.width == 2 + n_series
    props = rec.read_properties(path)
    info = {"layout": rec.LAYOUT, "condition": "standard", "phase": "pre", "replication": 1,
            "individual": 2, "sector": 4, "trial": 7, "trial_seed": "SeedSequence(3, (1, 2))",
            "senses": "no-touch", "generation": -1}
    measures = metrics.trial_metrics(trial)
    assert props.keys() == info.keys() | set(rec.MEASURES)
    assert {k: props[k] for k in info} == info
    for m in rec.MEASURES:
        assert props[m] == measures[m] or (np.isnan(props[m]) and np.isnan(measures[m])), m


def test_movement_variability_per_step_ends_at_the_trials_measures(tmp_path, world, trial):
    """Fig. 6's variability and the hand distances, per step in the recording: the cumulative
    values at the last step and the distances' statistics are the trial's measures, as
    post-evaluation computes them for evaluation.parquet."""
    table = rec.read_rrd(_write(tmp_path, world, trial))
    measures = metrics.trial_metrics(trial)
    for group in ("elbow", "shoulder", "trunk"):
        cumulative = table[f"variability/joints/cumulative/{group}"].to_numpy()
        assert cumulative[-1] == pytest.approx(measures[f"var_{group}"], rel=1e-9, abs=1e-12)
        assert cumulative[0] == 0.0 and (cumulative >= 0).all()
        window = table[f"variability/joints/window/{group}"].to_numpy()
        q = trial.joints[:40][:, list(metrics.JOINT_GROUPS[group])]
        assert window[30] == pytest.approx(q[11:31].std(axis=0).mean(), rel=1e-9, abs=1e-12)
    d = table["variability/distance/hand_shoulder"].to_numpy()
    assert d.mean() == pytest.approx(measures["hand_shoulder_mean"], rel=1e-12)
    assert d.std() == pytest.approx(measures["elbow_freezing"], rel=1e-9)
    assert table["variability/distance/hand_ball"].min() == pytest.approx(
        measures["hand_ball_min"], rel=1e-12)


def _chunks(data: bytes, tmp_path) -> dict:
    """entity -> [its chunks' columns (row ids left out): name -> (Arrow type, metadata,
    values as Python's)]."""
    path = tmp_path / "c.rrd"
    path.write_bytes(data)
    out = {}
    for c in RrdReader(path).stream().to_chunks():
        batch = c.to_record_batch()
        out.setdefault(c.entity_path, []).append({
            f.name: (str(f.type), f.metadata, batch.column(f.name).to_pylist())
            for f in batch.schema if "RowId" not in f.name})
    return out


def _same(a, b) -> bool:
    """Equal, NaN equal to NaN, to the last bit."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) and isinstance(b, float) and a != a and b != b:
        return True
    return type(a) is type(b) and a == b


def test_the_rows_and_property_are_what_rerun_s_own_builders_make(tmp_path, world, trial):
    """``trial_rrd`` builds its rows as one Arrow record batch and its property from typed
    Arrow values, not through rerun's archetypes: every entity's rows and the property
    ``trial`` hold what ``send_columns`` of rerun's archetypes and ``AnyValues`` hold."""
    import dataclasses
    import rerun as rr
    model, dt = rec.RobotModel(world), 0.1
    info = dataclasses.replace(INFO, senses="normal")
    data = dataclasses.replace(trial, contacts=trial.contacts.copy())
    data.contacts[::3, :4] = True  # touching segments are drawn in another colour
    measures = metrics.trial_metrics(data)
    T = data.steps_run

    def reference(stream):
        steps = np.arange(T)
        index = [rr.TimeColumn("step", sequence=steps),
                 rr.TimeColumn("sim_time", duration=steps * dt)]
        for entity, _, get in rec.SIGNALS:
            stream.send_columns(entity, indexes=index,
                                columns=rr.Scalars.columns(scalars=np.asarray(get(data), float)))
        centres, quats, spheres = model.shape_poses(data.dofs[:T])
        n = centres.shape[1]
        touching = np.zeros((T, n), bool)
        on_hand = model.box_segment >= 0
        touching[:, on_hand] = data.contacts[:T][:, model.box_segment[on_hand]]
        colours = np.where(touching[..., None], rec._TOUCH, rec._GREY).astype(np.uint8)
        stream.send_columns("world/robot", indexes=index, columns=rr.Boxes3D.columns(
            centers=centres.reshape(-1, 3), quaternions=quats.reshape(-1, 4),
            colors=colours.reshape(-1, 4)).partition([n] * T))
        rounds = np.concatenate([spheres, data.ball[:T, None], data.hand[:T, None]], axis=1)
        stream.send_columns("world/spheres", indexes=index, columns=rr.Ellipsoids3D.columns(
            centers=rounds.reshape(-1, 3)).partition([rounds.shape[1]] * T))
        pivot = np.asarray(data.ball_start) + [0, 0, model.string_length]
        stream.send_columns("world/pendulum/string", indexes=index, columns=rr.LineStrips3D.columns(
            strips=np.stack([np.broadcast_to(pivot, (T, 3)), data.ball[:T]], axis=1)))
        stream.send_property("trial", rr.AnyValues(layout=rec.LAYOUT, **dataclasses.asdict(info),
                                                   **{m: measures[m] for m in rec.MEASURES}))

    expected = _chunks(rec.encoded("reference", reference), tmp_path)
    written = _chunks(rec.trial_rrd(data, info, model, dt, blueprint=False), tmp_path)
    assert len(expected) == len(rec.SIGNALS) + 4
    for entity, chunks in expected.items():
        (mine,) = [c for c in written[entity] if "step" in c or entity == "/__properties/trial"]
        assert _same(chunks[0], mine), entity
    (rows,) = [c for c in written["/world/robot"] if "step" in c]
    assert any(rec._rgba32(np.array(rec._TOUCH, np.uint8)) in row
               for row in rows["Boxes3D:colors"][2])


def test_a_diverged_trial_records_only_the_steps_it_ran(tmp_path, world, trial):
    import dataclasses
    short = dataclasses.replace(trial, steps_run=13, diverged=True)
    table = rec.read_rrd(_write(tmp_path, world, short))
    assert table.height == 13


def test_scene_follows_the_skeleton(world, trial):
    """The vectorised forward kinematics equals DART's body transforms."""
    model = rec.RobotModel(world)
    transforms = model.body_transforms(trial.dofs[[0, 20, 39]])
    for k, t in enumerate((0, 20, 39)):
        world.robot.setPositions(trial.dofs[t])
        for i, body in enumerate(world.robot.getBodyNodes()):
            assert np.allclose(transforms[k, i], body.getWorldTransform().matrix(), atol=1e-12)
    world.reset(world.sector_point(4, 0.5, 0.5))


def test_quaternions_match_scipy():
    rotations = Rotation.random(2000, random_state=3)
    axes = Rotation.random(200, random_state=4).as_rotvec()
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    # half-turns (w = 0), where the signs must come from the largest component
    special = Rotation.from_rotvec(np.concatenate([
        np.eye(3) * np.pi, np.eye(3) * np.pi / 2, np.zeros((1, 3)), axes * np.pi,
        axes * (np.pi - 1e-9), [[np.pi / np.sqrt(2), -np.pi / np.sqrt(2), 0]]]))
    for r in (rotations, special):
        q = quaternions(r.as_matrix())
        assert np.allclose(np.abs(np.sum(q * r.as_quat(), axis=-1)), 1.0, atol=1e-12)


def test_training_recording_round_trip(tmp_path):
    stats = pl.DataFrame({
        "condition": ["c"] * 6, "phase": ["pre"] * 4 + ["gross"] * 2,
        "replication": [0, 0, 1, 1, 0, 0], "generation": [1, 2, 1, 2, 1, 2],
        "best": [.1, .2, .3, .4, .5, .6], "mean": [.01, .02, .03, .04, .05, .06],
        "min": [0.0] * 6})
    path = rec.write_rrd(tmp_path / "training.rrd", rec.training_rrd(stats, "run"))
    rec.verify(path)
    table = rec.read_rrd(path)
    assert table["generation"].to_list() == [1, 2, 3, 4]  # gross follows pre
    assert table["c/pre/best rep1"].to_list()[:2] == [.3, .4]
    assert table["c/pre/mean rep0"].to_list()[:2] == [.01, .02]
    assert table["c/gross/mean rep0"].to_list()[2:] == [.05, .06]


def _threads() -> int:
    return len(os.listdir(f"/proc/{os.getpid()}/task"))


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="counts threads in /proc")
def test_recordings_written_leave_no_threads_behind(world, trial):
    """rerun keeps a recording stream's batcher and sink threads until it is disconnected or
    cleaned up as an orphan: without ``rrd.encoded`` and ``rrd._send_blueprint`` each of
    these 20 recordings (and the blueprint of each) left two threads behind."""
    model = rec.RobotModel(world)
    stats = pl.DataFrame({"condition": ["c"], "phase": ["pre"], "replication": [0],
                          "generation": [1], "best": [.1], "mean": [.01], "min": [0.0]})
    rec.trial_rrd(trial, INFO, model)  # rerun's and polars' own pools start once
    rec.training_rrd(stats, "run")
    before = _threads()
    for _ in range(10):
        rec.trial_rrd(trial, INFO, model)
        rec.training_rrd(stats, "run")
    assert _threads() - before < 4


def _blueprint_chunks(data: bytes, tmp_path) -> list:
    path = tmp_path / "b.rrd"
    path.write_bytes(data)
    reader = RrdReader(path)
    (store,) = reader.blueprints()
    # a visualizer override's id is drawn anew each time a blueprint is built
    return sorted((re.sub(r"visualizers/[0-9a-f-]{36}", "visualizers/*", str(c.entity_path)),
                   c.num_rows) for c in reader.stream(store=store).to_chunks())


def test_the_blueprint_sent_is_rerun_s_own(tmp_path):
    """The layout embedded by ``_send_blueprint`` is what rerun's ``send_blueprint`` sends."""
    def send(mine: bool):
        def write(stream):
            if mine:
                rec._send_blueprint(stream, rec.trial_blueprint())
            else:
                stream.send_blueprint(rec.trial_blueprint())
        return _blueprint_chunks(rec.encoded("r", write), tmp_path)
    theirs = send(False)
    assert len(theirs) > 50 and send(True) == theirs


def test_damaged_files_are_named_with_their_problem(tmp_path, world, trial):
    path = _write(tmp_path, world, trial)
    content = path.read_bytes()
    for name, data in (("half.rrd", content[: len(content) // 2]),
                       ("tail.rrd", content[:-10]), ("text.rrd", b"hello")):
        bad = tmp_path / name
        bad.write_bytes(data)
        with pytest.raises(rec.RecordingError, match=name):
            rec.read_rrd(bad)
        if name != "tail.rrd":  # rerun's verifier lets a file missing its last bytes pass
            with pytest.raises(rec.RecordingError, match="verify"):
                rec.verify(bad)
    with pytest.raises(rec.RecordingError, match="no such recording"):
        rec.read_rrd(tmp_path / "missing.rrd")
    cli = subprocess.run([sys.executable, "-m", "dart_reach.cli", "read",
                          str(tmp_path / "half.rrd")], capture_output=True, text=True)
    assert cli.returncode == 2
    assert cli.stderr.count("\n") == 1 and "half.rrd: truncated" in cli.stderr


def _read_cli(*args):
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", "read", *map(str, args)],
                          capture_output=True, text=True)


def test_cli_read_saves_the_series_as_csv_and_parquet_without_overwriting(tmp_path, world,
                                                                          trial, in_process):
    path = _write(tmp_path, world, trial)
    csv, parquet = tmp_path / "t.csv", tmp_path / "t.parquet"
    result = _read_cli(path, "--csv", csv, "--parquet", parquet)
    assert result.returncode == 0, result.stderr
    assert "senses: no-touch" in result.stdout and "40 rows" in result.stdout
    table = rec.read_rrd(path)
    assert pl.read_parquet(parquet).equals(table)
    from_csv = pl.read_csv(csv)
    # the trial's properties and ball position first, then the series, named with units
    properties = ["condition", "phase", "replication", "individual", "generation", "senses",
                  "sector", "trial", "trial_seed", "ball_x [m]", "ball_y [m]", "ball_z [m]"]
    assert from_csv.columns == properties + [with_unit(c) for c in table.columns]
    assert from_csv.height == 40  # one row per step
    assert from_csv.columns[12:14] == ["step", "sim_time [s]"]
    assert "robot/positions/hand/x [m]" in from_csv.columns
    assert "robot/joints/arm_hand/r_elbow [rad]" in from_csv.columns
    assert "network/hidden/h3" in from_csv.columns  # no unit: a neuron's state
    first = from_csv.row(0, named=True)
    assert (first["condition"], first["phase"], first["replication"], first["sector"],
            first["senses"]) == ("standard", "pre", 1, 4, "no-touch")
    assert from_csv["sector"].n_unique() == 1  # the same on every row
    assert np.allclose([first[f"ball_{a} [m]"] for a in "xyz"],
                       table.select(f"robot/positions/ball/{a}" for a in "xyz").row(0))
    series = from_csv.select(from_csv.columns[13:]).to_numpy()
    assert np.allclose(series, table.drop("step").to_numpy(), rtol=1e-6, equal_nan=True)
    saved = csv.read_bytes()
    again = in_process("read", path, "--csv", csv)
    assert again.returncode == 2 and again.stderr.count("\n") == 1
    assert "t.csv: the file exists" in again.stderr
    assert again.stdout == ""  # refused before the recording is read
    assert csv.read_bytes() == saved


def test_cli_read_refuses_a_table_it_could_not_write_before_any_work(tmp_path, world, trial,
                                                                     in_process):
    path = _write(tmp_path, world, trial)
    for i, (args, message) in enumerate((
            (["--parquet", tmp_path / "x.csv"], "--parquet " + str(tmp_path / "x.csv") + ": a "
                                                "parquet table is a .parquet file"),
            (["--csv", tmp_path / "x.parquet"], "give a name ending in .csv"),
            (["--csv", tmp_path / "x"], "give a name ending in .csv"),
            (["--csv", tmp_path / "nowhere" / "x.csv"], "no such directory"),
            (["--csv", path.with_suffix(".rrd") / "x.csv"], "no such directory"))):
        # the first in a process of its own, the others in this one (the same code)
        result = _read_cli(path, *args) if i == 0 else in_process("read", path, *args)
        assert result.returncode == 2 and result.stderr.count("\n") == 1, result.stderr
        assert message in result.stderr and result.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.rrd"]  # nothing written


def test_save_series_from_python_chooses_the_format_by_suffix(tmp_path, world, trial):
    path = _write(tmp_path, world, trial)
    out = save_series(path, tmp_path / "t.csv")
    assert out == tmp_path / "t.csv" and pl.read_csv(out).height == 40
    assert save_series(path, tmp_path / "t.parquet").suffix == ".parquet"
    assert pl.read_parquet(tmp_path / "t.parquet").equals(rec.read_rrd(path))
    with pytest.raises(FileExistsError, match="t.csv"):
        save_series(path, out)
    with pytest.raises(ValueError, match=r"out='.*t\.txt': give a name ending in \.csv or "
                                         r"\.parquet"):
        save_series(path, tmp_path / "t.txt")
    with pytest.raises(rec.RecordingError, match="no such recording"):
        save_series(tmp_path / "missing.rrd", tmp_path / "m.csv")
    assert not (tmp_path / "m.csv").exists()
