"""No damaged file of a run's state accepted: every checkpoint, final and snapshot is checked
against the SHA-256 its manifest recorded, and every command refuses a damaged one with one
line, exit code 2, changing nothing on disk."""

from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from dart_reach.evolution import integrity
from dart_reach.evolution.integrity import DamagedFile
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.files import atomic_write

TRAIN = ["train", "standard", "--generations", "3", "--replications", "2", "--trials", "1",
         "--steps", "6", "--seed", "5", "--workers", "1", "--snapshot-every", "1",
         "--record-every", "0"]


def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=600, cwd=cwd)


@pytest.fixture(scope="module")
def evaluated(tmp_path_factory, in_process) -> Path:
    """A tiny trained and post-evaluated run (a few seconds)."""
    out = tmp_path_factory.mktemp("integrity") / "run"
    assert in_process(*TRAIN, "--out", out).returncode == 0
    result = in_process("evaluate", out, "--robots", "1", "--record", "none", "--workers", "1")
    assert result.returncode == 0, result.stderr
    return out


@pytest.fixture
def run(evaluated, tmp_path) -> Path:
    copy = tmp_path / "run"
    shutil.copytree(evaluated, copy)
    return copy


def _hashes(out: Path) -> dict[Path, str]:
    """Every file under ``out`` (the lock file included) and its SHA-256."""
    return {p: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(out.rglob("*")) if p.is_file()}


def _commands(out: Path, tmp_path: Path) -> dict[str, list]:
    return {"train --resume": [*TRAIN, "--out", out, "--resume"],
            "status": ["status", out],
            "evaluate": ["evaluate", out, "--robots", "1", "--record", "none", "--workers", "1"],
            "report": ["report", out, "--out", tmp_path / "report.html"]}


def _refused_by_every_command(out: Path, damaged: Path, tmp_path: Path, in_process) -> None:
    """Each command refuses ``damaged``: status in a process of its own, the others in this
    one (the same code, without a process's imports)."""
    before = _hashes(out)
    for name, args in _commands(out, tmp_path).items():
        result = _cli(*args) if name == "status" else in_process(*args)
        assert result.returncode == 2, (name, result.stdout, result.stderr)
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1, (name, result.stderr)
        assert f"{damaged}: damaged" in lines[0] and "restore it" in lines[0], (name, lines)
        assert "Traceback" not in result.stderr
        assert _hashes(out) == before, f"{name} changed the run"
        assert not (tmp_path / "report.html").exists()


def test_a_new_run_records_the_hash_of_every_state_file(run):
    files = json.loads((run / "manifest.json").read_text())[integrity.LEDGER]
    state = RunDirectory.open(run).state_files()
    assert len(state) == 3 * (2 + 3)  # per phase: checkpoint, final, 3 snapshots
    assert {(run / name) for name in files} == set(state)
    for name, digests in files.items():
        assert digests == [hashlib.sha256((run / name).read_bytes()).hexdigest()], name


def test_a_truncated_final_is_refused_by_every_command(run, tmp_path, in_process):
    final = next(run.glob("phases/fine-*/final.npz"))
    final.write_bytes(final.read_bytes()[:200])
    _refused_by_every_command(run, final, tmp_path, in_process)
    with pytest.raises(DamagedFile, match="final.npz: damaged"):
        RunDirectory.open(run).load_final(RunDirectory.open(run).conditions[0].phases[-1])


def test_a_truncated_checkpoint_is_refused_by_every_command(run, tmp_path, in_process):
    checkpoint = next(run.glob("phases/gross-*/checkpoint.npz"))
    checkpoint.write_bytes(checkpoint.read_bytes()[:-10])
    _refused_by_every_command(run, checkpoint, tmp_path, in_process)
    with pytest.raises(DamagedFile, match="checkpoint.npz: damaged"):
        RunDirectory.open(run)


def test_a_changed_snapshot_is_refused(run, tmp_path, in_process):
    snapshot = next(run.glob("phases/pre-*/snapshots/gen0002.npz"))
    data = bytearray(snapshot.read_bytes())
    data[-30] ^= 1  # one bit, in the zip's directory: still a file of the same size
    snapshot.write_bytes(bytes(data))
    result = in_process("status", run)
    assert result.returncode == 2 and f"{snapshot}: damaged" in result.stderr


def test_a_deleted_final_is_written_again_by_resuming(run, in_process):
    final = next(run.glob("phases/fine-*/final.npz"))
    with np.load(final) as d:
        population = d["population"].copy()
    final.unlink()
    result = in_process(*TRAIN, "--out", run, "--resume")
    assert result.returncode == 0, result.stderr
    with np.load(final) as d:
        assert np.array_equal(d["population"], population)
    assert in_process("status", run).returncode == 0


def test_a_run_without_recorded_hashes_is_read_as_before(run, tmp_path, in_process):
    """Runs written before the ledger (the committed ones): read as they are; a file that
    cannot be read whole is still refused."""
    manifest = json.loads((run / "manifest.json").read_text())
    del manifest[integrity.LEDGER]
    (run / "manifest.json").write_text(json.dumps(manifest, indent=2))
    result = in_process("status", run)
    assert result.returncode == 0, result.stderr
    final = next(run.glob("phases/fine-*/final.npz"))
    final.write_bytes(final.read_bytes()[:200])
    before = _hashes(run)
    result = in_process("status", run)
    assert result.returncode == 2 and f"{final}: damaged, cannot be read" in result.stderr
    assert _hashes(run) == before


def test_the_ledger_accepts_the_file_on_disk_whenever_a_write_stops(run):
    """The commit of a file's digest around its rename: stopped before the rename (the old
    file stays, the ledger accepts both digests) or after it, before the ledger keeps the new
    digest alone, the file on disk is accepted."""
    path = next(run.glob("phases/pre-*/snapshots/gen0001.npz"))
    old = path.read_bytes()
    name = path.relative_to(run).as_posix()

    class Stop(Exception):
        pass

    def stop_before_rename(tmp):
        manifest = json.loads((run / "manifest.json").read_text())
        accept = manifest["files"][name] + [integrity.sha256(tmp)]
        manifest["files"][name] = accept
        (run / "manifest.json").write_text(json.dumps(manifest))
        raise Stop

    with pytest.raises(Stop):
        atomic_write(path, lambda p: p.write_bytes(b"new content"),
                     before_replace=stop_before_rename)
    assert path.read_bytes() == old and integrity.check(run, path)
    path.write_bytes(b"new content")  # the rename done, the ledger's last step not
    assert integrity.check(run, path)
    integrity.recorded_write(run, path, lambda p: p.write_bytes(b"newer"))
    assert json.loads((run / "manifest.json").read_text())["files"][name] == [
        hashlib.sha256(b"newer").hexdigest()]
    path.write_bytes(b"new content")  # an old version is no longer accepted
    with pytest.raises(DamagedFile):
        integrity.check(run, path)
