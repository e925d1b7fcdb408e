"""Every file of a run, checked when it is read: no damaged file is accepted, and no file the
run did not write.

A run's ledger, ``ledger.json`` beside its manifest, maps every file the run holds, by its
path relative to the run (``manifest.json``, ``phases/pre-1a2b3c4d/final.npz``,
``development/part-000.parquet``, ``evaluation/pre/rep00-rank0-normal-t07.rrd``), to the
SHA-256 digests it may have: one, normally. Hidden files (the lock, ``.lock``, and the
temporaries of a write in progress) are not run files. The ledger carries the SHA-256 of its
own content and is written in one canonical form, so one flipped bit in it is found too.

A file is written (``recorded_write``; ``write`` finds the run a path lies in) through a
temporary file renamed over the old one, and its digest is committed around that rename:

1. the temporary file is complete and on disk; the ledger is rewritten (atomically) to accept
   the old digest and the new one;
2. the temporary file is renamed over the old file;
3. the ledger is rewritten to accept the new digest alone.

However a process stops, the file on disk is one the ledger accepts: the old one before step
2, the new one after it. A reader (``check``, ``verified``) hashes the file and compares, before
it uses anything of it: a digest the ledger does not hold means the file changed after it was
written (truncated, overwritten, one bit flipped, a bad copy), a file the ledger does not name
was not written by the run (put there by hand, or a run written before the ledger), and both
raise ``DamagedFile`` naming the file and what to do. ``verify_run`` checks every file of a
run at once (the commands that write into a run do so before anything else).

A run written before the ledger has no ``ledger.json`` and is refused until ``migrate``
(``dart-reach migrate RUN``) has checked what can be checked of its files (each ``.npz``
read whole against its zip entries' CRCs, each parquet table read whole, the manifest read,
the digests an older ledger in the manifest recorded, and, in a git work tree, each tracked
file against its committed content) and recorded them.
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import UsageError
from .files import atomic_write

#: The ledger's file, in the run directory.
LEDGER_FILE = "ledger.json"
MANIFEST = "manifest.json"
#: The manifest's key of the ledger before it had a file of its own (read by ``migrate``).
LEDGER = "files"
FORMAT = 1


class DamagedFile(UsageError):
    """A file of a run is not the file that was written (its digest differs from the one its
    ledger recorded, or it cannot be read), or not one the run wrote."""


def sha256(path: Path) -> str:
    """The SHA-256 digest of a file, as hex."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


_hashed: dict[tuple, str] = {}


def _digest(path: Path) -> str:
    """``sha256``, remembered for a file whose inode, size and modification time are those
    it had when it was hashed (a file read several times by one command is hashed once)."""
    st = os.stat(path)
    key = (str(Path(path).resolve()), st.st_ino, st.st_size, st.st_mtime_ns)
    if key not in _hashed:
        if len(_hashed) > 100_000:
            _hashed.clear()
        _hashed[key] = sha256(path)
    return _hashed[key]


# ------------------------------------------------------------------------------ the ledger
def _render(files: dict[str, list[str]]) -> bytes:
    body = json.dumps({"format": FORMAT, "files": dict(sorted(files.items()))},
                      sort_keys=True, indent=1)
    own = hashlib.sha256(body.encode()).hexdigest()
    # the body with its digest, the last key in sorted order, before its closing "\n}": the
    # bytes json.dumps(dict(body, sha256=own), sort_keys=True, indent=1) gives, encoded once
    return (body[:-2] + f',\n "sha256": "{own}"\n}}\n').encode()


#: The ledgers found whole, by the SHA-256 of their bytes: a ledger read again unchanged (a
#: run's every file checked, each against it) is parsed and rendered once, not once a file.
_ledgers: dict[bytes, dict[str, list[str]]] = {}


def has_ledger(out: Path) -> bool:
    return (Path(out) / LEDGER_FILE).is_file()


def ledger(out: Path) -> dict[str, list[str]]:
    """The digests the run in ``out`` accepts, by path relative to the run. ``DamagedFile``
    when the run has no ledger (written before it: ``migrate``) or the ledger is damaged."""
    out = Path(out)
    path = out / LEDGER_FILE
    if not path.is_file():
        raise DamagedFile(
            f"{out}: no {LEDGER_FILE} (a run written before its files were recorded, or not "
            f"a run); check its files once and record them with: dart-reach migrate {out}")
    data = path.read_bytes()
    files = _ledgers.get(hashlib.sha256(data).digest())
    if files is None:
        try:
            files = json.loads(data)["files"]
            if _render(files) != data:
                raise ValueError("its content is not the content it recorded")
        except (ValueError, KeyError, TypeError, AttributeError) as exc:
            raise DamagedFile(f"{path}: damaged ({type(exc).__name__}: {exc}); restore it from "
                              f"a copy of the run (a committed run: git checkout -- {path})"
                              ) from None
        _remember(data, files)
    return {name: list(digests) for name, digests in files.items()}  # the caller's own copy


def _save(out: Path, files: dict[str, list[str]]) -> None:
    data = _render(files)
    atomic_write(Path(out) / LEDGER_FILE, lambda p: p.write_bytes(data))
    _remember(data, files)


def _remember(data: bytes, files: dict[str, list[str]]) -> None:
    """Put the ledger ``data`` (whole: ``files`` rendered) among ``_ledgers``, in the order
    its file holds (by name)."""
    if len(_ledgers) > 64:
        _ledgers.clear()
    _ledgers[hashlib.sha256(data).digest()] = {name: list(d) for name, d in sorted(files.items())}


def _name(out: Path, path: Path) -> str:
    return Path(path).resolve().relative_to(Path(out).resolve()).as_posix()


def run_of(path: Path) -> Path | None:
    """The run directory a file lies in, or None: the nearest directory above it that holds
    a run's manifest and ledger, a run's manifest alone (a run written before the ledger),
    or a ledger naming the file. A ``manifest.json`` that is not a run's (a web app's, say)
    or a lone copy of a ledger in a folder above a user's output captures nothing."""
    path = Path(path).resolve()
    for parent in path.parents:
        if _is_run_of(parent, path):
            return parent
    return None


#: The keys every run's manifest holds (``evolution.rundir`` writes and checks them).
RUN_MANIFEST_KEYS = frozenset({"format", "conditions", "settings"})


def _is_run_of(parent: Path, path: Path) -> bool:
    manifest, ledger_file = parent / MANIFEST, parent / LEDGER_FILE
    has_manifest, has_ledger_file = manifest.is_file(), ledger_file.is_file()
    if has_manifest and has_ledger_file:
        return True
    if has_manifest:
        content = _json_or_none(manifest)
        return isinstance(content, dict) and RUN_MANIFEST_KEYS <= content.keys()
    if has_ledger_file:
        content = _json_or_none(ledger_file)
        files = content.get("files") if isinstance(content, dict) else None
        return isinstance(files, dict) and path.relative_to(parent).as_posix() in files
    return False


def _json_or_none(path: Path):
    try:
        return json.loads(path.read_bytes())
    except (OSError, ValueError):
        return None


def run_files(out: Path) -> list[Path]:
    """Every file of the run in ``out`` on disk: all files under it but the ledger and hidden
    ones (the lock, temporaries of a write in progress)."""
    out = Path(out)
    return sorted(p for p in out.rglob("*") if p.is_file() and p.name != LEDGER_FILE
                  and not any(part.startswith(".") for part in p.relative_to(out).parts))


# ------------------------------------------------------------------------------ writing
def recorded_write(out: Path, path: Path, write) -> Path:
    """Write ``path`` (a file of the run in ``out``) through ``write(temporary path)``
    atomically, its digest committed in the run's ledger around the rename (see the
    module's text). The ledger of a new run begins with its manifest. Call it while holding
    the run's lock."""
    out, path = Path(out), Path(path)
    name = _name(out, path)
    if not has_ledger(out) and name == MANIFEST and not path.exists():
        _save(out, {})
    ledger(out)  # refused before anything is written when there is none
    new: list[str] = []

    def accept_both(tmp: Path) -> None:
        new.append(sha256(tmp))
        files = ledger(out)
        files[name] = [d for d in files.get(name, []) if d != new[0]] + new
        _save(out, files)

    atomic_write(path, write, before_replace=accept_both)
    files = ledger(out)
    files[name] = new
    _save(out, files)
    return path


def write(path: Path, write_file) -> Path:
    """``recorded_write`` into the run ``path`` lies in; a plain atomic write for a file in
    no run."""
    out = run_of(path)
    if out is None:
        return atomic_write(Path(path), write_file)
    return recorded_write(out, path, write_file)


def remove(path: Path) -> None:
    """Delete a file of a run and its ledger entry (the entry of a file no longer there is
    dropped by ``settle`` if a process stops between the two)."""
    path = Path(path)
    path.unlink(missing_ok=True)
    out = run_of(path)
    if out is not None and has_ledger(out):
        files = ledger(out)
        if files.pop(_name(out, path), None) is not None:
            _save(out, files)


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
            digest = _digest(out / name) if len(digests) > 1 else None
            settled[name] = [digest] if digest in digests else digests
    if settled != files:
        _save(out, settled)


# ------------------------------------------------------------------------------ reading
def advice(out: Path, path: Path) -> str:
    """What to do with a damaged file of a run, by kind."""
    path = Path(path)
    restore = f"restore it from a copy of the run (a committed run: git checkout -- {path})"
    if path.name == "final.npz":
        return (f"{restore}, or delete it and resume the training (dart-reach train ... "
                f"--resume --out {out}): the phase's checkpoint writes it again")
    if path.parent.name == "snapshots":
        return (f"{restore}, or delete it: the development over generations then lacks that "
                f"generation")
    if path.name in ("generations.parquet", "training.rrd", "best.parquet") or (
            path.suffix == ".rrd" and path.parent.name == "best"):
        return f"{restore}, or delete it: 'dart-reach train ... --resume' writes it again"
    if path.suffix == ".parquet" or path.parent.name.endswith(("evaluation", "development")):
        return (f"{restore}, or delete it and post-evaluate again (dart-reach evaluate "
                f"{out} ...)")
    return f"{restore}, or start a new run"


def check(out: Path, path: Path) -> bool:
    """Verify a file of the run in ``out`` against its ledger before it is read: True when
    its digest is one the ledger accepts. Raises ``DamagedFile`` naming the file and what to
    do when the digest differs, when the ledger does not name the file, and when the run has
    no ledger. (A digest that differs is checked once more against a ledger read again: a
    training process may have committed the file meanwhile.)"""
    out, path = Path(out), Path(path)
    name = _name(out, path)
    for _ in range(2):
        accepted = ledger(out).get(name)
        if not accepted:
            raise DamagedFile(
                f"{path}: not a file of the run (its {LEDGER_FILE} does not name it: put "
                f"there by hand or by a copy); move it out of {out}, or, for a run written "
                f"before the ledger, record its files with: dart-reach migrate {out}")
        if _digest(path) in accepted:
            return True
    raise DamagedFile(f"{path}: damaged (its SHA-256 is not the one {LEDGER_FILE} recorded "
                      f"when it was written); {advice(out, path)}")


def verified(path: Path) -> Path:
    """``path``, once checked against the ledger of the run it lies in (``check``); a file
    in no run is not checked."""
    out = run_of(path)
    if out is not None:
        check(out, path)
    return Path(path)


def verify_run(out: Path) -> int:
    """``check`` every file of the run in ``out`` (``run_files``); returns how many. Raises
    ``DamagedFile`` for the first damaged or unknown one; changes nothing on disk."""
    files = run_files(out)
    for path in files:
        check(out, path)
    return len(files)


# ------------------------------------------------------------------------------ migrate
@dataclass
class Migration:
    """What ``migrate`` checked, by how: each a list of run-relative names."""

    out: Path
    already: bool = False
    ledger: list[str] = field(default_factory=list)
    git: list[str] = field(default_factory=list)
    read_whole: list[str] = field(default_factory=list)
    present: list[str] = field(default_factory=list)

    def lines(self) -> list[str]:
        n = len(self.ledger) + len(self.git) + len(self.read_whole) + len(self.present)
        if self.already:
            return [f"{self.out}: recorded already ({LEDGER_FILE}); its {n} files match it"]
        said = [f"{self.out}: {n} files recorded in {self.out / LEDGER_FILE}"]
        for what, names in (
                ("the same as committed in git (HEAD)", self.git),
                ("matching the digests the manifest recorded", self.ledger),
                ("read whole (zip CRCs of .npz, every page of .parquet, the JSON of the "
                 "manifest, the chunks of .rrd)", self.read_whole),
                ("recorded as found, nothing checkable in them", self.present)):
            if names:
                said.append(f"  {len(names)} {what}: {', '.join(names[:4])}"
                            + (", ..." if len(names) > 4 else ""))
        return said


def _committed(out: Path) -> dict[str, str]:
    """The git blob ids of the run's files as committed at HEAD, by run-relative name ({}
    outside a git work tree)."""
    try:
        top = subprocess.run(["git", "-C", str(out), "rev-parse", "--show-toplevel"],
                             capture_output=True, text=True, timeout=30)
        if top.returncode:
            return {}
        listed = subprocess.run(["git", "-C", str(out), "ls-tree", "-r", "--full-name", "HEAD",
                                 "--", "."], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.SubprocessError):
        return {}
    root = Path(top.stdout.strip()).resolve()
    blobs = {}
    for line in listed.stdout.splitlines():
        meta, _, name = line.partition("\t")
        parts = meta.split()
        if len(parts) == 3 and parts[1] == "blob":
            try:
                blobs[_name(out, root / name)] = parts[2]
            except ValueError:
                continue
    return blobs


def _blob(path: Path) -> str:
    data = path.read_bytes()
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


def _read_whole(out: Path, path: Path) -> bool:
    """Read a file as its kind is read, whole; True when its kind can be checked so,
    ``DamagedFile`` when it cannot be read."""
    try:
        if path.suffix == ".npz":
            with np.load(path, allow_pickle=False) as d:
                for key in d.files:
                    d[key]
        elif path.suffix == ".parquet":
            import pyarrow.parquet as pq

            pq.read_table(path, page_checksum_verification=True)
        elif path.suffix == ".json":
            json.loads(path.read_text())
        elif path.suffix == ".rrd":
            from rerun.chunk import RrdReader

            list(RrdReader(str(path)).stream().to_chunks())
        else:
            return False
    except DamagedFile:
        raise
    except Exception as exc:  # numpy, zip, arrow, JSON and OS errors of a damaged file
        raise DamagedFile(f"{path}: damaged, cannot be read ({type(exc).__name__}: {exc}); "
                          f"{advice(out, path)}") from None
    return True


def migrate(out: Path) -> Migration:
    """Give a run written before the ledger its ``ledger.json``: check each of its files as
    far as it can be (against the digests the manifest's older ledger recorded; in a git work
    tree, a tracked file against its committed content; else read whole) and record them.
    Changes nothing but writing ``ledger.json``; raises ``DamagedFile`` (nothing written) for
    a file that fails. A run that has a ledger is verified against it and left as it is.
    Call it while holding the run's lock."""
    out = Path(out)
    found = Migration(out)
    if has_ledger(out):
        found.already = True
        found.present = [_name(out, p) for p in run_files(out)]
        verify_run(out)
        return found
    try:
        old = json.loads((out / MANIFEST).read_text()).get(LEDGER, {})
    except (OSError, ValueError, AttributeError):
        old = {}
    old = old if isinstance(old, dict) else {}
    committed = _committed(out)
    files = {}
    for path in run_files(out):
        name = _name(out, path)
        digest = sha256(path)
        if old.get(name):
            if digest not in old[name]:
                raise DamagedFile(f"{path}: damaged (its SHA-256 is not the one the manifest "
                                  f"recorded when it was written); {advice(out, path)}")
            found.ledger.append(name)
        elif committed.get(name) == _blob(path):
            found.git.append(name)
        elif _read_whole(out, path):
            found.read_whole.append(name)
        else:
            found.present.append(name)
        files[name] = [digest]
    if MANIFEST not in files:
        raise DamagedFile(f"{out}: not a run directory (no {MANIFEST})")
    _save(out, files)
    return found
