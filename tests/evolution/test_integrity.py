"""No damaged file of a run accepted, nor one the run did not write: every file a run holds
(the manifest, the tables, the checkpoints, finals, snapshots and recordings) is in its
ledger, and every command and loader that reads one refuses it, damaged, with one line and
exit code 2, changing nothing on disk; a run written before the ledger is refused until
``dart-reach migrate`` has checked and recorded it; a finished run is not written to."""

from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from dart_reach.postevaluation.results import stored_table
from dart_reach import integrity
from dart_reach.integrity import DamagedFile
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.files import LOCK_NAME, atomic_write
from dart_reach.postevaluation import results
from dart_reach.postevaluation.snapshots import load_development
from dart_reach.postevaluation.systematic import BLUEPRINT, load_evaluation
from dart_reach.recording.rrd import read_rrd

TRAIN = ["train", "standard", "--generations", "2", "--replications", "2", "--trials", "2",
         "--steps", "20", "--seed", "5", "--workers", "1", "--snapshot-every", "1",
         "--record-every", "2"]
EVALUATE = ["--robots", "1", "--record", "none", "--workers", "1"]


def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=600, cwd=cwd)


@pytest.fixture(scope="module")
def evaluated(built_once, in_process) -> Path:
    """A tiny trained and post-evaluated run (under a minute): one robot per replication
    recorded, a random baseline, and the development over generations stored in parts. Made
    once for the session (read only: ``run`` copies it)."""
    def build(root):
        out = root / "run"
        assert in_process(*TRAIN, "--out", out).returncode == 0
        result = in_process("evaluate", out, "--robots", "1", "--record", "best", "--baseline",
                            "1", "--workers", "1")
        assert result.returncode == 0, result.stderr
        with pytest.MonkeyPatch.context() as patch:  # small parts, to have a table in parts
            patch.setattr(results, "PART_BYTES", 30_000)
            result = in_process("evaluate", out, *EVALUATE, "--development", "1")
        assert result.returncode == 0, result.stderr
        (out / LOCK_NAME).unlink()

    return built_once("integrity", build) / "run"


@pytest.fixture
def run(evaluated, tmp_path) -> Path:
    copy = tmp_path / "run"
    shutil.copytree(evaluated, copy)
    return copy


def _hashes(out: Path) -> dict[Path, str]:
    """Every file under ``out`` (the lock file included) and its SHA-256."""
    return {p: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(out.rglob("*")) if p.is_file()}


def _flip(path: Path) -> None:
    """One bit flipped in the middle of ``path``: a file of the same size."""
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0x04
    path.write_bytes(bytes(data))


def _phase(run: Path, path: Path):
    opened = RunDirectory.open(run)
    return next(p for _, p in opened.unique_phases() if opened.phase_dir(p) in path.parents)


#: Every kind of file a run holds: (where it is, the Python loader that reads it).
KINDS = {
    "manifest": ("manifest.json", lambda run, path: RunDirectory.open(run)),
    "ledger": ("ledger.json", lambda run, path: RunDirectory.open(run)),
    "generations": ("generations.parquet", lambda run, path: stored_table(path)),
    "training recording": ("training.rrd", lambda run, path: read_rrd(path)),
    "checkpoint": ("phases/gross-*/checkpoint.npz", lambda run, path: RunDirectory.open(run)),
    "final": ("phases/fine-*/final.npz",
              lambda run, path: RunDirectory.open(run).load_final(_phase(run, path))),
    "snapshot": ("phases/pre-*/snapshots/gen0002.npz",
                 lambda run, path: RunDirectory.open(run).snapshots(_phase(run, path))),
    "best table": ("phases/pre-*/best.parquet", lambda run, path: stored_table(path)),
    "best recording": ("phases/pre-*/best/gen0002-rep01.rrd", lambda run, path: read_rrd(path)),
    "evaluation": ("evaluation.parquet", lambda run, path: load_evaluation(run)),
    "baseline": ("baseline.parquet", lambda run, path: load_evaluation(run, baseline=True)),
    "development part": ("development/part-001.parquet",
                         lambda run, path: load_development(run)),
    "trial recording": ("evaluation/pre-*/normal/rep*-rank0/trial07-*.rrd",
                        lambda run, path: read_rrd(path)),
    "blueprint": ("evaluation/trial.rbl", None),
}
#: The files ``export`` reads (it refuses those alone); every other command reads them all.
EXPORTED = {"manifest", "ledger", "generations", "evaluation", "baseline", "development part"}


def _commands(run: Path, damaged: Path, tmp_path: Path) -> dict[str, tuple[list, bool]]:
    """Each command on ``run`` and whether it reads ``damaged``."""
    kind = damaged.suffix
    read = ([damaged, "--csv", tmp_path / "read.csv"] if kind == ".parquet" else
            [damaged] if kind == ".rrd" else [run / "training.rrd"])
    name = damaged.name
    return {"train --resume": ([*TRAIN, "--out", run, "--resume"], True),
            "status": (["status", run], True),
            "evaluate": (["evaluate", run, *EVALUATE, "--baseline", "2"], True),
            "report": (["report", run, "--out", tmp_path / "report.html"], True),
            "export": (["export", run, "--csv", tmp_path / "csv"],
                       name in ("manifest.json", "ledger.json") or kind == ".parquet"
                       and "phases" not in damaged.parts),
            "read": (["read", *read], kind in (".parquet", ".rrd") or name == "ledger.json")}


@pytest.mark.parametrize("kind", KINDS)
def test_one_flipped_bit_in_any_file_is_refused_by_every_command_that_reads_it(
        run, kind, tmp_path, in_process):
    pattern, loader = KINDS[kind]
    found = sorted(run.glob(pattern))
    assert found, pattern
    damaged = found[0]
    assert (kind in EXPORTED) == (damaged.suffix == ".parquet" and "phases" not in damaged.parts
                                  or damaged.name in ("manifest.json", "ledger.json"))
    _flip(damaged)
    before = _hashes(run)
    for name, (args, reads) in _commands(run, damaged, tmp_path).items():
        result = _cli(*args) if name == "status" else in_process(*args)
        if reads:
            assert result.returncode == 2, (name, result.stdout, result.stderr)
            lines = result.stderr.strip().splitlines()
            assert len(lines) == 1, (name, result.stderr)
            assert f"{damaged}: damaged" in lines[0] and "restore it" in lines[0], (name, lines)
        else:  # export and read verify what they read, and nothing else
            assert result.returncode == 0, (name, result.stderr)
        assert "Traceback" not in result.stderr
        assert _hashes(run) == before, f"{name} changed the run"
        assert not (tmp_path / "report.html").exists()
        shutil.rmtree(tmp_path / "csv", ignore_errors=True)
        (tmp_path / "read.csv").unlink(missing_ok=True)
    if loader is not None:
        with pytest.raises(DamagedFile, match=f"{damaged.name}: damaged"):
            loader(run, damaged)


def test_every_file_of_a_run_is_in_its_ledger_and_written_with_page_checksums(run):
    import pyarrow.parquet as pq

    files = integrity.ledger(run)
    on_disk = integrity.run_files(run)
    assert {run / name for name in files} == set(on_disk)
    kinds = {p.suffix for p in on_disk}
    assert kinds == {".json", ".parquet", ".rrd", ".npz", ".rbl"}, kinds
    for name, digests in files.items():
        assert digests == [hashlib.sha256((run / name).read_bytes()).hexdigest()], name
    assert integrity.verify_run(run) == len(on_disk)
    for table in run.rglob("*.parquet"):  # a page's CRC is checked by readers that check it
        data = bytearray(table.read_bytes())
        column = pq.ParquetFile(table).metadata.row_group(0).column(0)
        start = (column.dictionary_page_offset if column.has_dictionary_page
                 else column.data_page_offset)
        data[start + column.total_compressed_size - 2] ^= 1  # in its last page's data
        damaged = table.with_name("damaged.parquet")
        damaged.write_bytes(bytes(data))
        with pytest.raises(OSError, match="CRC checksum verification failed"):
            pq.read_table(damaged, page_checksum_verification=True)
        damaged.unlink()


def test_a_file_the_ledger_does_not_name_is_refused(run, in_process):
    stray = run / "phases" / "extra.npz"
    shutil.copy(next(run.glob("phases/pre-*/final.npz")), stray)
    before = _hashes(run)
    result = in_process("status", run)
    assert result.returncode == 2 and f"{stray}: not a file of the run" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and _hashes(run) == before
    part = run / "development" / "part-099.parquet"  # a table's part put there by hand
    stray.rename(part)
    part.write_bytes((run / "development" / "part-000.parquet").read_bytes())
    with pytest.raises(DamagedFile, match="part-099.parquet: not a file of the run"):
        load_development(run)


def test_a_run_written_before_the_ledger_is_refused_until_migrate_checks_it(
        run, tmp_path, in_process):
    (run / integrity.LEDGER_FILE).unlink()
    before = _hashes(run)
    for args in (["status", run], ["evaluate", run, *EVALUATE],
                 ["export", run, "--csv", tmp_path / "csv"], [*TRAIN, "--out", run, "--resume"]):
        result = in_process(*args)
        assert result.returncode == 2 and f"dart-reach migrate {run}" in result.stderr, (
            args, result.stderr)
        assert _hashes(run) == before
    final = next(run.glob("phases/fine-*/final.npz"))
    good = final.read_bytes()
    final.write_bytes(good[:200])  # a pre-ledger run's damage: found by reading it whole
    result = in_process("migrate", run)
    assert result.returncode == 2 and f"{final}: damaged, cannot be read" in result.stderr
    assert not (run / integrity.LEDGER_FILE).exists() and not (run / LOCK_NAME).exists()
    final.write_bytes(good)
    result = in_process("migrate", run)
    assert result.returncode == 0, result.stderr
    assert "files recorded" in result.stdout and "read whole" in result.stdout
    assert integrity.verify_run(run) == len(integrity.ledger(run))
    assert in_process("status", run).returncode == 0
    again = in_process("migrate", run)
    assert again.returncode == 0 and "recorded already" in again.stdout


def test_migrate_checks_the_digests_of_the_ledger_in_the_manifest(run, in_process):
    """Runs written while the ledger lived in the manifest (its ``files``): checked against
    it."""
    files = integrity.ledger(run)
    (run / integrity.LEDGER_FILE).unlink()
    manifest = json.loads((run / "manifest.json").read_text())
    manifest[integrity.LEDGER] = {k: v for k, v in files.items() if k.endswith(".npz")}
    (run / "manifest.json").write_text(json.dumps(manifest, indent=2))
    snapshot = next(run.glob("phases/pre-*/snapshots/gen0001.npz"))
    _flip(snapshot)
    result = in_process("migrate", run)
    assert result.returncode == 2 and f"{snapshot}: damaged" in result.stderr
    assert not (run / integrity.LEDGER_FILE).exists()


def test_a_finished_run_is_not_written_to_and_a_refused_command_leaves_no_lock(
        run, tmp_path, in_process):
    before = _hashes(run)
    result = in_process(*TRAIN, "--out", run, "--resume")
    assert result.returncode == 0 and "done" in result.stderr, result.stderr
    assert _hashes(run) == before  # not a session more in the manifest, nor a file rebuilt
    result = in_process("evaluate", run, "--robots", "999", "--workers", "1")
    assert result.returncode == 2 and "robots must be" in result.stderr, result.stderr
    assert _hashes(run) == before and not (run / LOCK_NAME).exists()
    integrity.remove(run / BLUEPRINT)  # refused once its robots are known: no layout written
    before = _hashes(run)
    result = in_process("evaluate", run, "--robots", "2", "--record", "all",
                        "--ray", "127.0.0.1:1")
    assert result.returncode == 2 and "no Ray cluster answers" in result.stderr, result.stderr
    assert _hashes(run) == before and not (run / LOCK_NAME).exists()
    integrity.remove(next(run.glob("phases/fine-*/final.npz")))  # unfinished: resumable
    before = _hashes(run)
    other = [*TRAIN[:2], "pre-h", *TRAIN[2:]]  # another condition: refused once locked
    result = in_process(*other, "--out", run, "--resume")
    assert result.returncode == 2 and "other conditions" in result.stderr, result.stderr
    assert _hashes(run) == before and not (run / LOCK_NAME).exists()
    fresh = tmp_path / "new"  # a new run refused (an odd population) leaves no directory
    result = in_process(*TRAIN, "--replications", "3", "--out", fresh)
    assert result.returncode == 2 and not fresh.exists(), result.stderr


def test_a_deleted_final_is_written_again_by_resuming(run, in_process):
    final = next(run.glob("phases/fine-*/final.npz"))
    content = final.read_bytes()
    integrity.remove(final)
    result = in_process(*TRAIN, "--out", run, "--resume")
    assert result.returncode == 0, result.stderr
    assert final.read_bytes() == content
    assert in_process("status", run).returncode == 0


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
        files = integrity.ledger(run)
        files[name] = files[name] + [integrity.sha256(tmp)]
        integrity._save(run, files)
        raise Stop

    with pytest.raises(Stop):
        atomic_write(path, lambda p: p.write_bytes(b"new content"),
                     before_replace=stop_before_rename)
    assert path.read_bytes() == old and integrity.check(run, path)
    path.write_bytes(b"new content")  # the rename done, the ledger's last step not
    assert integrity.check(run, path)
    integrity.recorded_write(run, path, lambda p: p.write_bytes(b"newer"))
    assert integrity.ledger(run)[name] == [hashlib.sha256(b"newer").hexdigest()]
    path.write_bytes(b"new content")  # an old version is no longer accepted
    with pytest.raises(DamagedFile):
        integrity.check(run, path)


def test_a_stray_ledger_or_a_foreign_manifest_above_a_file_captures_nothing(tmp_path):
    """Only a run's own directory takes a file into its ledger: a lone copy of a ledger in a
    folder above (not naming the file) and a manifest that is not a run's (a web app's) are
    not runs; the file is written plainly and read unchecked, and neither is touched."""
    stray = tmp_path / integrity.LEDGER_FILE
    stray.write_bytes(integrity._render({"manifest.json": ["0" * 64]}))
    foreign = tmp_path / "site" / integrity.MANIFEST
    foreign.parent.mkdir()
    foreign.write_text(json.dumps({"name": "a web app", "start_url": "/"}))
    before = stray.read_bytes(), foreign.read_bytes()
    out = foreign.parent / "figures" / "hand.png"
    out.parent.mkdir()
    assert integrity.run_of(out) is None
    integrity.write(out, lambda p: p.write_bytes(b"picture"))
    assert integrity.verified(out).read_bytes() == b"picture"
    assert (stray.read_bytes(), foreign.read_bytes()) == before
    # a ledger that names the file is its run's, manifest or not
    named = tmp_path / "site" / "figures"
    (named / integrity.LEDGER_FILE).write_bytes(integrity._render({"hand.png": ["0" * 64]}))
    assert integrity.run_of(out) == named.resolve()
    with pytest.raises(DamagedFile, match="damaged"):
        integrity.verified(out)
