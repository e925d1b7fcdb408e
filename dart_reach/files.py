"""Writing result files so that nothing already saved is ever half-overwritten, and one
process at a time in a run directory."""

from __future__ import annotations

import contextlib
import errno
import fcntl
import os
import re
import tempfile
from pathlib import Path
from typing import Callable

TEMP_SUFFIX = ".tmp"
LOCK_NAME = ".lock"


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write(path: Path, write: Callable[[Path], None],
                 before_replace: Callable[[Path], None] | None = None) -> Path:
    """Write through a temporary file in the same directory, then rename: a reader (or a
    resumed run) sees the old file or the new one, never half of one. The file gets the
    permissions of a plainly created one (0666 less the umask). ``before_replace`` is called
    with the temporary file once it is complete and on disk, before the rename (to record
    its hash: ``integrity``); if it raises, the old file stays."""
    path = Path(path)
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=TEMP_SUFFIX)
        os.close(fd)
        tmp = Path(name)
        write(tmp)
        with open(tmp, "rb") as f:
            os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        if before_replace is not None:
            before_replace(tmp)
        os.replace(tmp, path)
    except OSError as exc:
        raise _naming(exc, path) from None
    except Exception as exc:  # libraries (polars) wrap the OS's error in their own
        found = re.search(r"os error (\d+)", str(exc))
        if not found:
            raise
        raise _naming(OSError(int(found[1]), os.strerror(int(found[1]))), path) from None
    finally:
        if tmp is not None:
            tmp.unlink(missing_ok=True)
    return path


def write_parquet(frame, path: Path, metadata: dict[str, str] | None = None,
                  compression: str = "zstd") -> None:
    """Write a polars frame to the parquet file ``path`` (plainly: through ``atomic_write``'s
    temporary file) with a CRC-32 in every page's header (pyarrow's ``write_page_checksum``),
    which readers that check them (``pyarrow.parquet.read_table(...,
    page_checksum_verification=True)``) use to refuse a damaged page; ``metadata``: the file's
    key-value metadata."""
    import pyarrow.parquet as pq

    table = frame.to_arrow()
    if metadata:
        table = table.replace_schema_metadata(
            {**(table.schema.metadata or {}), **{k.encode(): v.encode()
                                                  for k, v in metadata.items()}})
    where = os.fspath(path) if isinstance(path, (str, os.PathLike)) else path  # or a buffer
    pq.write_table(table, where, compression=compression, write_page_checksum=True)


def _naming(exc: OSError, path: Path) -> OSError:
    """The same error, naming the file being written (a full disk's error names none)."""
    code = exc.errno if exc.errno is not None else errno.EIO
    return OSError(code, f"cannot write: {exc.strerror or exc}", str(path))


def check_new_file(path, suffix: str, what: str, option: str = "out") -> Path:
    """Refuse, before any work, a path where a new file of ``what`` (``"a CSV table"``) could
    not be written: a name not ending in ``suffix``, an existing file (nothing is ever
    overwritten), a missing or read-only directory. The errors name the argument ``option``
    (a library argument, or a command line option beginning with ``--``)."""
    path = Path(path)
    name = f"{option} {path}" if option.startswith("--") else f"{option}={str(path)!r}"
    if path.suffix.lower() != suffix:
        raise ValueError(f"{name}: {what} is a {suffix} file; give a name ending in {suffix}")
    if path.exists() or path.is_symlink():
        raise FileExistsError(f"{name}: the file exists; choose another (nothing is "
                              f"overwritten)")
    if not path.parent.is_dir():
        raise FileNotFoundError(f"{name}: no such directory {path.parent}; create it first")
    if not os.access(path.parent, os.W_OK | os.X_OK):
        raise PermissionError(f"{name}: the directory {path.parent} is not writable")
    return path


def remove_temporaries(directory: Path) -> list[Path]:
    """Delete the temporary files ``atomic_write`` leaves when its process is killed
    mid-write (``.<name>.<random>.tmp``), anywhere under ``directory``. Call it only while
    holding the directory's ``DirectoryLock``."""
    removed = []
    for p in Path(directory).rglob(f".*{TEMP_SUFFIX}"):
        if p.is_file():
            p.unlink(missing_ok=True)
            removed.append(p)
    return removed


class DirectoryBusy(RuntimeError):
    """Another live process holds the directory's lock."""


class DirectoryLock:
    """An exclusive lock on a directory (``fcntl.flock`` on ``<directory>/.lock``), held by
    one process at a time and released by the OS when that process ends, however it ends: a
    lock left by a killed process never blocks. The lock file holds the holder's PID.

    Used as a context manager, a block refused (left by a ``ValueError``: bad input, a
    damaged file, another run there) leaves no trace: the lock file is deleted, and the
    directory too when the lock made it and it is empty."""

    def __init__(self, directory: Path, what: str = "run"):
        self.directory, self.what = Path(directory), what
        self._file = None
        self._made: list[Path] = []

    def acquire(self) -> "DirectoryLock":
        if not self.directory.is_dir():
            self._made.append(self.directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        if not (self.directory / LOCK_NAME).exists():
            self._made.append(self.directory / LOCK_NAME)
        f = open(self.directory / LOCK_NAME, "a+")
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            f.seek(0)
            holder = f.read().strip() or "?"
            f.close()
            raise DirectoryBusy(f"{self.directory}: in use by another process (PID {holder}); "
                                f"wait for it to finish or stop it") from None
        f.seek(0)
        f.truncate()
        f.write(f"{os.getpid()}\n")
        f.flush()
        self._file = f
        return self

    def release(self) -> None:
        if self._file is not None:
            self._file.close()  # closing the descriptor releases the flock
            self._file = None

    def __enter__(self) -> "DirectoryLock":
        return self.acquire()

    def __exit__(self, kind, *exc) -> None:
        if kind is not None and issubclass(kind, ValueError) and self._file is not None:
            for made in reversed(self._made):  # the lock file while it is held, then the folder
                with contextlib.suppress(OSError):
                    made.rmdir() if made == self.directory else made.unlink()
        self.release()
