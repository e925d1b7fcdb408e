"""Training runs: determinism across back-ends, resume after SIGKILL, bad input (III-C/D)."""

from __future__ import annotations

import dataclasses
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import polars as pl
import pytest

from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.provenance import cpu
from dart_reach.evolution.rundir import RunError
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import Trainer, train

TINY = Settings(replications=2, trials=1, steps=4, seed=3)


def _cli(*args, timeout=600):
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *args], capture_output=True,
                          text=True, timeout=timeout)


def _result(out: Path) -> tuple[pl.DataFrame, dict]:
    stats = pl.read_parquet(out / "generations.parquet").drop("wall_s")
    finals = {}
    for d in sorted((out / "phases").iterdir()):
        with np.load(d / "final.npz") as f:
            finals[d.name] = (f["population"].copy(), f["fitness"].copy())
    return stats, finals


def _same(a, b) -> bool:
    (sa, fa), (sb, fb) = a, b
    return sa.equals(sb) and fa.keys() == fb.keys() and all(
        np.array_equal(fa[k][0], fb[k][0]) and np.array_equal(fa[k][1], fb[k][1]) for k in fa)


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    """The standard condition, 2 generations per phase, trained on one process (read only)."""
    return train([scaled(load_condition("standard"), 2)], TINY,
                 tmp_path_factory.mktemp("serial") / "run", workers=1)


def test_same_seed_same_result_whatever_the_backend(serial, tmp_path):
    cond = [scaled(load_condition("standard"), 2)]
    pool = train(cond, TINY, tmp_path / "pool", workers=2)
    a, b = _result(serial.out), _result(pool.out)
    assert _same(a, b)
    # the manifest says on how many workers each session trained (its cost in core-seconds)
    assert [[s["workers"] for s in json.loads((r.out / "manifest.json").read_text())
             ["sessions"]] for r in (serial, pool)] == [[1], [2]]
    stats = a[0]
    assert stats.height == 3 * 2 * 2  # phases x replications x generations
    assert set(stats.columns) >= {"condition", "phase", "replication", "generation", "best",
                                  "mean", "min"}
    other = train(cond, Settings(replications=2, trials=1, steps=4, seed=4), tmp_path / "s4",
                  workers=1)
    assert not _same(a, _result(other.out))


def test_a_private_ray_instance_trains_the_serial_bits(serial, tmp_path, monkeypatch):
    """``ray_address="local"`` (``--ray local``): a Ray instance of this process's own. Its
    workers at the driver's priority (Ray's default puts them 15 steps nicer: beside the
    suite's other process they would wait for minutes), as ``LocalRayCluster``'s."""
    pytest.importorskip("ray")
    monkeypatch.setenv("RAY_AUTH_MODE", os.environ.get("RAY_AUTH_MODE", "disabled"))
    monkeypatch.setenv("RAY_worker_niceness", "0")
    import ray
    try:
        ray_run = train([scaled(load_condition("standard"), 2)], TINY, tmp_path / "ray",
                        workers=2, ray_address="local")
    finally:
        ray.shutdown()
    assert _same(_result(serial.out), _result(ray_run.out))


def test_model_version_2_trains_the_same_whatever_the_workers(tmp_path):
    """Under version 2 the shipped robots' lifetimes (robots that touch: the fitness is not
    0) are the same on one process and on a pool of two, and a tiny run records the version."""
    from dart_reach.evolution.backends import Job, PoolBackend, SerialBackend
    from dart_reach.evolution.genome import as_groups
    from dart_reach.evolution.settings import trial_config
    from dart_reach.model.world import WorldConfig
    from dart_reach.robots import robots

    pre = load_condition("standard").phases[0]
    trial = trial_config(pre, Settings(trials=3, model_version=2))
    jobs = [Job(r.genome, as_groups(pre.free_groups), trial, WorldConfig(), (7, i))
            for i, r in enumerate(robots("pre", run="replication-50x10")[:4])]
    serial = np.array(SerialBackend().map(jobs))
    pool = PoolBackend(2)
    try:
        pooled = np.array(pool.map(jobs))
    finally:
        pool.close()
    assert (serial > 0).sum() >= 2 and np.array_equal(serial, pooled)
    run = train([scaled(load_condition("standard"), 1)],
                dataclasses.replace(TINY, model_version=2), tmp_path / "v2", workers=1)
    manifest = json.loads((run.out / "manifest.json").read_text())
    assert manifest["settings"]["model_version"] == 2


def test_transition_takes_the_best_of_each_replication(tmp_path):
    cond = scaled(load_condition("standard"), 1)
    run = train([cond], TINY, tmp_path / "r", workers=1)
    pre = cond.phases[0]
    finals, _ = run.load_final(pre)
    init = run._initial_states(cond, 1)
    expected = np.concatenate([f[:10] for f in finals])  # population 20 / 2 replications
    assert len(init) == TINY.replications
    for state in init:
        # only genes of the newly freed groups may differ (released near their fixed value)
        from dart_reach.evolution.genome import free_mask
        mask = free_mask(pre.free_groups)
        assert np.array_equal(state.genomes[:, mask], expected[:, mask])


def test_shared_phases_are_trained_once(tmp_path):
    conds = [scaled(load_condition(n), 1) for n in ("pre-h", "gross-h")]
    run = train(conds, TINY, tmp_path / "r", workers=1)
    stats = pl.read_parquet(run.out / "generations.parquet")
    assert stats.filter(pl.col("phase") == "pre-h").height == 2  # 2 replications x 1 generation
    assert len(list((run.out / "phases").iterdir())) == 2


def _train_cmd(out, *extra):
    return ["train", "standard", "--generations", "3", "--replications", "2", "--trials", "1",
            "--steps", "6", "--seed", "5", "--workers", "1", "--out", str(out), *extra]


@pytest.fixture(scope="module")
def whole(built_once, in_process) -> Path:
    """``_train_cmd``'s run, uninterrupted, made once for the session (read only: copy it to
    write)."""
    def build(root):
        result = in_process(*_train_cmd(root / "run"))
        assert result.returncode == 0, result.stderr

    return built_once("trainer-whole", build) / "run"


def test_resume_after_sigkill_is_bit_identical(whole, tmp_path):
    cut = tmp_path / "cut"
    proc = subprocess.Popen([sys.executable, "-m", "dart_reach.cli", *_train_cmd(cut)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline:  # kill once the second phase has a checkpoint
        if list(cut.glob("phases/gross-*/checkpoint.npz")):
            break
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert proc.returncode == -signal.SIGKILL
    assert not list(cut.glob("phases/fine-*/final.npz")), "killed before the end"
    result = _cli(*_train_cmd(cut, "--resume"))
    assert result.returncode == 0, result.stderr
    assert _same(_result(whole), _result(cut))
    # the manifest records each invocation's source and where it took over
    sessions = json.loads((cut / "manifest.json").read_text())["sessions"]
    assert len(sessions) == 2 and "--resume" in sessions[1]["command"]
    assert all(s["git_diff_sha256"] for s in sessions)
    assert sum(sessions[0]["generations_done"].values()) == 0
    assert sessions[1]["generations_done"]["standard/pre"] > 0
    assert all(s["cpu"] == cpu() for s in sessions)  # the machine each session ran on


def test_ctrl_c_stops_cleanly_and_says_how_to_resume(tmp_path):
    out = tmp_path / "r"
    proc = subprocess.Popen([sys.executable, "-m", "dart_reach.cli", *_train_cmd(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and not list(out.glob("phases/*/checkpoint.npz")):
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "--resume" in err and "Traceback" not in err
    assert _cli(*_train_cmd(out, "--resume")).returncode == 0
    manifest = json.loads((out / "manifest.json").read_text())  # provenance of the report
    assert manifest["command"].startswith("dart-reach train ") and str(out) in manifest["command"]
    assert manifest["machine"]["cores"] == os.cpu_count()


def test_a_stop_signal_after_the_command_stopped_keeps_its_exit_code(tmp_path):
    """Once a command has stopped and said how to go on, only the interpreter's shutdown is
    left, which takes Python's handlers away: a Ctrl-C or SIGTERM landing then must not end
    the process by the signal instead of with 130 (here both come right after ``main``)."""
    out = tmp_path / "r"
    code = f"""
import os, signal, sys, threading, time
from pathlib import Path
from dart_reach.cli import main
out = Path({str(out)!r})
def stop():
    while not list(out.glob("phases/*/checkpoint.npz")):
        time.sleep(0.05)
    os.kill(os.getpid(), signal.SIGINT)
threading.Thread(target=stop, daemon=True).start()
code = main({_train_cmd(out)!r})
os.kill(os.getpid(), signal.SIGINT)
os.kill(os.getpid(), signal.SIGTERM)
time.sleep(0.2)
sys.exit(code)
"""
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 130, r.stderr
    assert "--resume" in r.stderr and "Traceback" not in r.stderr, r.stderr


def test_a_stop_signal_swallowed_by_a_destructor_is_not_lost():
    """Python only prints an exception raised in a destructor (Ctrl-C can land in rerun's
    flush at garbage collection): the CLI raises it again at the next progress report, and
    prints nothing about it."""
    code = """
import os, signal, sys, time
from dart_reach.cli import stopping
signal.signal(signal.SIGINT, stopping.on_stop_signal)
sys.unraisablehook = stopping.unraisable(sys.__unraisablehook__)
class Flush:
    def __del__(self):
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.2)
Flush()
print("the destructor's exception was swallowed", flush=True)
try:
    stopping.checked(print)("next generation")
except KeyboardInterrupt:
    sys.exit(0)
sys.exit(1)
"""
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and "swallowed" in r.stdout, (r.stdout, r.stderr)
    assert "Traceback" not in r.stderr and "Exception ignored" not in r.stderr, r.stderr


def _one_error_line(result, needle):
    assert result.returncode == 2, (result.stdout, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], result.stderr
    assert "Traceback" not in result.stderr


def _saved(out):
    """Every file of a run directory but its lock, with its content."""
    return {p: p.read_bytes() for p in out.rglob("*") if p.is_file() and p.name != ".lock"}


def test_bad_input_is_refused_and_loses_nothing(whole, tmp_path, in_process):
    _one_error_line(_cli("train", "no-such-condition"), "no-such-condition")
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\nbogus = 1\n')
    _one_error_line(in_process("train", str(bad)), "bad.toml")
    _one_error_line(in_process("train", "standard", "--generations", "0"), ">= 1")
    _one_error_line(in_process("train", "standard", "--replications", "-1"), ">= 1")
    out = tmp_path / "run"
    shutil.copytree(whole, out)
    before = _saved(out)
    _one_error_line(in_process(*_train_cmd(out)), "--resume")
    changed = _train_cmd(out, "--resume")
    changed[changed.index("--seed") + 1] = "6"
    _one_error_line(in_process(*changed), "seed given here differs")
    ckpt = next(out.glob("phases/fine-*/checkpoint.npz"))
    (out / "phases" / ckpt.parent.name / "final.npz").unlink()
    before.pop(out / "phases" / ckpt.parent.name / "final.npz")
    ckpt.write_bytes(b"garbage")
    before[ckpt] = b"garbage"
    _one_error_line(in_process(*_train_cmd(out, "--resume")), "checkpoint")
    assert _saved(out) == before, "nothing saved was touched"
    with pytest.raises(RunError, match="nothing to resume"):
        Trainer(tmp_path / "empty", [load_condition("standard")], TINY, resume=True)


def test_training_recordings(tmp_path):
    """training.rrd mirrors generations.parquet; best-individual recordings every K generations
    and snapshots of the best robots do not change the training's result; a snapshot holds
    the best 5 of every replication, best first; a run made without snapshots resumes with
    them to the same result."""
    from dart_reach.evolution.settings import SNAPSHOT_ROBOTS
    from dart_reach.recording.rrd import read_properties, read_rrd, verify

    cond = [scaled(load_condition("standard"), 3)]
    recorded = train(cond, TINY, tmp_path / "rec", workers=1, record_every=2, snapshot_every=2)
    plain = train(cond, TINY, tmp_path / "plain", workers=1)
    assert _same(_result(recorded.out), _result(plain.out))
    assert not list(plain.out.rglob("snapshots"))
    for _, phase in recorded.unique_phases():
        shots = recorded.snapshots(phase)
        assert [g for g, _, _ in shots] == [1, 2, 3]  # 1, 2 early; 3 the last
        genomes, fitness = shots[-1][1:]
        final, final_fitness = recorded.load_final(phase)
        assert genomes.dtype == np.uint8 and genomes.shape == (2, SNAPSHOT_ROBOTS, final.shape[2])
        assert np.array_equal(genomes, final[:, :SNAPSHOT_ROBOTS])
        assert np.array_equal(fitness, final_fitness[:, :SNAPSHOT_ROBOTS])

    def stop_after_first(progress):
        if progress.done_generations == 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        train(cond, TINY, tmp_path / "old", workers=1, progress=stop_after_first)  # none
    old = train(cond, TINY, tmp_path / "old", workers=1, progress=False, resume=True,
                snapshot_every=2)
    assert _same(_result(old.out), _result(plain.out))
    pre = old.unique_phases()[0][1]
    assert [g for g, _, _ in old.snapshots(pre)] == [2, 3]  # generation 1 came before
    stats = pl.read_parquet(recorded.out / "generations.parquet")
    series = read_rrd(recorded.out / "training.rrd")
    for (phase, rep), rows in stats.group_by("phase", "replication"):
        column = series[f"standard/{phase}/best rep{rep}"].drop_nulls()
        assert column.to_list() == rows.sort("generation")["best"].to_list()
    files = sorted(recorded.out.glob("phases/*/best/*.rrd"))
    # generations 2 (every 2) and 3 (the end of the phase), 2 replications, 3 phases
    assert [f.name for f in files if f.parent.parent.name.startswith("pre-")] == [
        "gen0002-rep00.rrd", "gen0002-rep01.rrd", "gen0003-rep00.rrd", "gen0003-rep01.rrd"]
    assert len(files) == 12
    verify(recorded.out / "training.rrd", *files)
    props = read_properties(files[-1])
    assert props["generation"] == 3 and props["replication"] == 1
    assert read_rrd(files[-1]).height == TINY.steps
    assert not list(plain.out.glob("phases/*/best/*.rrd"))


def test_trial_by_trial_scheduling_equals_whole_evaluations():
    """Backend.map schedules single trials; each job's fitness is exactly task.lifetime's
    (evolved robots, which touch the ball, so that fitness is not all zeros)."""
    from dart_reach.robots import evolved_pre
    from dart_reach.evolution.backends import Job, PoolBackend, SerialBackend
    from dart_reach.evolution.genome import as_groups, decode
    from dart_reach.model.task import TrialConfig, lifetime
    from dart_reach.model.world import World, WorldConfig

    trial = TrialConfig(steps=100, trials=3, acuity=3.0, hidden_frozen=True)
    groups = as_groups({"direct"})
    genomes = evolved_pre()[0][:4]
    jobs = [Job(g, groups, trial, WorldConfig(), (7, 1, i)) for i, g in enumerate(genomes)]
    world = World(WorldConfig())
    expected = [lifetime(decode(j.genome, groups), world, trial,
                         np.random.default_rng(np.random.SeedSequence(7, spawn_key=(1, i))))
                .fitness for i, j in enumerate(jobs)]
    serial = SerialBackend().map(jobs)
    pool = PoolBackend(2)
    try:
        pooled = pool.map(jobs)
    finally:
        pool.close()
    assert serial.tolist() == expected and pooled.tolist() == expected
    assert len(set(expected)) > 1


def test_the_cpu_of_a_session_is_read_from_cpuinfo():
    zen4 = ("processor\t: 0\nmodel name\t: AMD EPYC 9R14\ncpu MHz\t\t: 3700.000\n"
            "flags\t\t: fpu sse4_2 avx avx2 avx512f avx512bw\n\n"
            "processor\t: 1\nmodel name\t: other\ncpu MHz\t\t: 1.0\n")
    assert cpu(zen4) == {"model": "AMD EPYC 9R14", "mhz": 3700.0, "vector": "AVX-512"}
    older = "model name\t: AMD EPYC\ncpu MHz\t: 2445.426\nflags\t: fpu sse4_2 avx avx2\n"
    assert cpu(older) == {"model": "AMD EPYC", "mhz": 2445.426, "vector": "AVX2"}
    assert cpu("cpu MHz\t: unknown\n")["mhz"] is None
    assert cpu("")["vector"] is None


def test_manifest_records_whether_the_tree_was_dirty(tmp_path):
    from dart_reach.evolution.provenance import git_state

    def git(*args):
        subprocess.run(["git", "-c", "user.name=t", "-c", "user.email=t@t", *args],
                       cwd=tmp_path, check=True, capture_output=True)

    assert git_state(tmp_path) == {"git_revision": None, "git_dirty": None,
                                   "git_diff_sha256": None}
    git("init", "-q")
    (tmp_path / "a.py").write_text("x = 1\n")
    git("add", "a.py")
    git("commit", "-qm", "a")
    clean = git_state(tmp_path)
    assert clean["git_dirty"] is False and len(clean["git_revision"]) == 40
    (tmp_path / "a.py").write_text("x = 2\n")
    edited = git_state(tmp_path)
    assert edited["git_dirty"] is True and edited["git_revision"] == clean["git_revision"]
    (tmp_path / "a.py").write_text("x = 3\n")
    assert git_state(tmp_path)["git_diff_sha256"] != edited["git_diff_sha256"]
    (tmp_path / "a.py").write_text("x = 1\n")
    (tmp_path / "new.py").write_text("y = 1\n")  # an untracked file counts too
    untracked = git_state(tmp_path)
    assert untracked["git_dirty"] is True
    assert untracked["git_diff_sha256"] != clean["git_diff_sha256"]
    # a run's manifest carries the state of the package's own tree
    run = train([scaled(load_condition("standard"), 1)],
                Settings(replications=1, trials=1, steps=2, seed=0), tmp_path / "run",
                workers=1, progress=False)
    manifest = json.loads((run.out / "manifest.json").read_text())
    assert {"git_revision", "git_dirty", "git_diff_sha256"} <= manifest.keys()
    assert manifest == {**manifest, **git_state()}
