"""The files a run's state is built from, checked when they are read: no damaged file is
accepted.

The state of a run is its manifest and the files of its phases: the checkpoints (the GA
states and statistics of the last committed generation), the finals (the end of a phase) and
the snapshots (the best genomes over generations). Everything else in a run directory is
derived from them (``generations.parquet``, ``training.rrd``, ``best.parquet``) or is a result
checked by its own reader (the post-evaluation's tables).

The manifest's ``files`` ledger maps each of those files, by its path relative to the run
(``phases/pre-1a2b3c4d/final.npz``), to the SHA-256 digests it may have: one, normally. A file
is written (``recorded_write``) as every result file is, through a temporary file renamed over
the old one, and its digest is committed around that rename:

1. the temporary file is complete and on disk; the ledger is rewritten (atomically) to accept
   the old digest and the new one;
2. the temporary file is renamed over the old file;
3. the ledger is rewritten to accept the new digest alone.

However a process stops, the file on disk is one the ledger accepts: the old one before step
2, the new one after it. A reader (``check``) hashes the file and compares: a digest the
ledger does not hold means the file changed after it was written (truncated, overwritten, a
bad copy) and the reader raises ``DamagedFile``, naming the file and what to do, before it
uses anything of it.

A file the ledger does not name is read as before, unverified: runs written before the
ledger existed (the committed runs under ``recordings/`` among them) keep working unchanged;
their files are only checked for being readable (``readable``).
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

from ..errors import UsageError
from ..files import atomic_write

#: The manifest's key of the ledger.
LEDGER = "files"
MANIFEST = "manifest.json"


class DamagedFile(UsageError):
    """A file of a run's state is not the file that was written (its digest differs from the
    one the manifest recorded, or it cannot be read)."""


def sha256(path: Path) -> str:
    """The SHA-256 digest of a file, as hex."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _manifest(out: Path) -> dict:
    return json.loads((out / MANIFEST).read_text())


def _save_manifest(out: Path, manifest: dict) -> None:
    atomic_write(out / MANIFEST, lambda p: p.write_text(json.dumps(manifest, indent=2)))


def ledger(out: Path) -> dict[str, list[str]]:
    """The digests the manifest of the run in ``out`` accepts, by path relative to the run
    ({} for a run written before the ledger, or without a readable manifest)."""
    try:
        files = _manifest(Path(out)).get(LEDGER, {})
    except (OSError, ValueError):
        return {}
    return files if isinstance(files, dict) else {}


def _name(out: Path, path: Path) -> str:
    return Path(path).resolve().relative_to(Path(out).resolve()).as_posix()


def recorded_write(out: Path, path: Path, write) -> Path:
    """Write ``path`` (a file of the run in ``out``) through ``write(temporary path)``
    atomically, its digest committed in the manifest's ledger around the rename (see the
    module's text). Call it while holding the run's lock."""
    out, path = Path(out), Path(path)
    name = _name(out, path)
    new: list[str] = []

    def accept_both(tmp: Path) -> None:
        new.append(sha256(tmp))
        manifest = _manifest(out)
        files = manifest.setdefault(LEDGER, {})
        files[name] = [d for d in files.get(name, []) if d != new[0]] + new
        _save_manifest(out, manifest)

    atomic_write(path, write, before_replace=accept_both)
    manifest = _manifest(out)
    manifest[LEDGER][name] = new
    _save_manifest(out, manifest)
    return path


def settle(out: Path) -> None:
    """After a write that stopped between the rename and the ledger's last step: keep, for
    each file, the one digest of the file on disk, and drop the entries of files no longer
    there (a write stopped before its first rename, a damaged file deleted to be written
    again). Call it while holding the run's lock, once its files are verified."""
    out = Path(out)
    files = ledger(out)
    settled = {}
    for name, digests in files.items():
        if (out / name).is_file():
            digest = sha256(out / name) if len(digests) > 1 else None
            settled[name] = [digest] if digest in digests else digests
    if settled != files:
        manifest = _manifest(out)
        manifest[LEDGER] = settled
        _save_manifest(out, manifest)


def advice(out: Path, path: Path) -> str:
    """What to do with a damaged file of a run's state, by kind."""
    name = Path(path).name
    restore = f"restore it from a copy of the run (a committed run: git checkout -- {path})"
    if name == "final.npz":
        return (f"{restore}, or delete it and resume the training (dart-reach train ... "
                f"--resume --out {out}): the phase's checkpoint writes it again")
    if Path(path).parent.name == "snapshots":
        return (f"{restore}, or delete it: the development over generations then lacks that "
                f"generation")
    return f"{restore}, or start a new run"


def check(out: Path, path: Path) -> bool:
    """Verify a file of the run in ``out`` against the manifest's ledger before it is read:
    True when its digest is one the ledger accepts, False when the ledger does not name it
    (a run written before the ledger: read as before). Raises ``DamagedFile`` naming the file
    and what to do when the digest differs. (A digest that differs is checked once more
    against a ledger read again: a training process may have committed the file meanwhile.)"""
    out, path = Path(out), Path(path)
    name = _name(out, path)
    for _ in range(2):
        accepted = ledger(out).get(name)
        if not accepted:
            return False
        if sha256(path) in accepted:
            return True
    raise DamagedFile(f"{path}: damaged (its SHA-256 is not the one manifest.json recorded "
                      f"when it was written); {advice(out, path)}")


def readable(out: Path, path: Path) -> None:
    """Check that a ``.npz`` file the ledger does not name can be read whole (every array,
    each against the checksum its zip entry carries); ``DamagedFile`` when it cannot."""
    try:
        with np.load(path, allow_pickle=False) as d:
            for key in d.files:
                d[key]
    except Exception as exc:  # zipfile, numpy and OS errors of a damaged file
        raise DamagedFile(f"{path}: damaged, cannot be read ({type(exc).__name__}: {exc}); "
                          f"{advice(out, path)}") from None


def verify(out: Path, path: Path) -> None:
    """``check`` a file of a run's state; one the ledger does not name is checked for being
    ``readable``."""
    if not check(out, path):
        readable(out, path)
