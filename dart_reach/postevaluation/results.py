"""The post-evaluation's tables as results anyone can check: how they are stored, where they
come from, and whether a run's are complete.

A run's post-evaluation lives in three tables in its directory, committed with its compact
state for the runs the docs cite (docs/guides/runs.md, "Results"):

    evaluation.parquet   the trained robots' trials (``systematic``), one row per trial
    baseline.parquet     the random genomes' trials (``evaluate --baseline``), one row per trial
    development.parquet  the snapshots' robots' trials (``snapshots``), one row per trial

Storage: zstd parquet, in one file, or where that file would be over ``PART_BYTES`` (a tracked
file may have at most 5 MB) in parts, ``<name>/part-000.parquet``, ``part-001`` ...
(consecutive rows), which ``read_table`` reads as the one table they are. A part is written
once and kept as it is while its rows stay the table's: rows added go into new parts (the last
part joins them while it is small), so a table that grows snapshot by snapshot adds little more
than its new rows to a repository's history, and rows already saved in a full part are never
rewritten to add others. The last part holds the provenance of every session; an earlier part,
that of the sessions up to its own. Every floating-point measure is stored as float32 (7
significant digits: far finer than any measure's meaning; it halves the files) and read back as
float64, so a table evaluated anywhere and a committed one hold the same numbers to the last
bit. A table written before this format (float64; the baseline inside evaluation.parquet; no
provenance) is not read: ``read_table`` names the command that rewrites it once, ``dart-reach
evaluate RUN_DIR --migrate`` (``migrate``: the same rows, in the current format).

Provenance: the parquet file's key-value metadata ``dart_reach`` holds a JSON object
``{"format": FORMAT, "sessions": [...]}``: one entry per session that added rows (``Session``:
git revision and whether the tree was dirty, package version, command, start time, machine,
rows added), and every row's ``session`` column is the index of the entry that added it.
"""

from __future__ import annotations

import io
import json
import math
import os
import platform
import sys
import time
import uuid
from pathlib import Path
from typing import Sequence

import polars as pl

from .. import __version__
from ..evolution.provenance import git_state, simd
from .. import integrity
from ..evolution.rundir import RunError, described_run
from ..files import write_parquet

#: Version of the storage format (1: float32 measures, the baseline in its own table, sessions).
FORMAT = 1
EVALUATION = "evaluation.parquet"
BASELINE = "baseline.parquet"
DEVELOPMENT = "development.parquet"
_META = "dart_reach"
#: The largest file a table is written in; a larger table is written in parts.
PART_BYTES = 4_000_000


def parts_folder(path: str | os.PathLike) -> Path:
    """Where the parts of the table at ``path`` are (``development.parquet``:
    ``development/``)."""
    return Path(path).with_suffix("")


def stored_files(path: str | os.PathLike) -> list[Path]:
    """The files the table at ``path`` is stored in: the file itself, else its parts in order
    (empty: no table), each checked against the ledger of the run it lies in
    (``integrity.verified``: ``integrity.DamagedFile`` for a damaged file, or one the run did
    not write)."""
    path = Path(path)
    if path.is_file():
        return [integrity.verified(path)]
    return [integrity.verified(p) for p in sorted(parts_folder(path).glob("part-*.parquet"),
                                                  key=lambda p: int(p.stem[5:]))]


def exists(path: str | os.PathLike) -> bool:
    """Whether a table is stored at ``path``, in one file or in parts."""
    return bool(stored_files(path))


def rows(path: str | os.PathLike) -> int:
    """How many rows the table at ``path`` holds, over its parts (0: no table); read from the
    files' metadata, not their data."""
    return sum(pl.scan_parquet(f).select(pl.len()).collect().item() for f in stored_files(path))


def session(command: str | None = None) -> dict:
    """This process's provenance entry: ``revision`` (git commit of the package's source, or
    None outside a git tree), ``dirty``, ``version``, ``command`` (default: the command line),
    ``started`` (UTC, ISO 8601, to the second), ``machine``, ``simd`` (numpy's dispatch
    level, ``provenance.simd``), ``pid`` and ``id`` (this call's own: two sessions of one
    process in the same second are two entries); ``rows`` is filled in on saving."""
    git = git_state()
    return {"revision": git["git_revision"], "dirty": git["git_dirty"],
            "version": __version__,
            "command": command if command is not None else " ".join(
                [Path(sys.argv[0]).name, *sys.argv[1:]]),
            "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "machine": f"{platform.machine()} {platform.processor() or ''}".strip(),
            "simd": simd(), "pid": os.getpid(), "id": uuid.uuid4().hex, "rows": 0}


def read_table(path: str | os.PathLike) -> pl.DataFrame | None:
    """The table at ``path`` (one file or its parts, read as one) with its float32 columns as
    float64, or None when there is none; ``RunError`` when it cannot be read, or when it is
    stored in an older format (one line naming the command that migrates it)."""
    files = stored_files(path)
    if not files:
        return None
    for file in files:  # a damaged file is unreadable, not old
        try:
            pl.read_parquet_metadata(file)
        except Exception as exc:  # polars raises several kinds for a damaged file
            raise RunError(f"{file}: unreadable ({exc})") from None
    if not is_current(path):
        raise RunError(f"{path}: stored in a format older than the current one ({FORMAT}); "
                       f"rewrite it once with 'dart-reach evaluate {Path(path).parent} "
                       f"--migrate' (the same rows)")
    return _read(files)


def _read(files: list[Path]) -> pl.DataFrame:
    """The table in ``files``, whatever its format, float32 columns as float64."""
    return _concat(files).with_columns(pl.col(pl.Float32).cast(pl.Float64))


def _concat(files: list[Path]) -> pl.DataFrame:
    """The parquet ``files`` read as one table, values as stored; ``RunError`` naming a file
    that cannot be read."""
    frames = []
    for file in files:
        try:
            frames.append(pl.read_parquet(file))
        except Exception as exc:  # polars raises several kinds for a damaged file
            raise RunError(f"{file}: unreadable ({exc})") from None
    return pl.concat(frames, how="diagonal_relaxed") if len(frames) > 1 else frames[0]


def stored_table(path: str | os.PathLike) -> pl.DataFrame:
    """The table at ``path`` (one parquet file or its parts, read as one) with its values as
    stored (float32 kept float32), whatever its format; ``RunError`` when there is none or a
    file cannot be read."""
    files = stored_files(path)
    if not files:
        raise RunError(f"{path}: no such table")
    return _concat(files)


def sessions(path: str | os.PathLike) -> list[dict]:
    """The provenance entries of the table at ``path`` (empty for a table written before
    provenance was recorded, or none): those of its file, or of its last part."""
    files = stored_files(path)
    if not files:
        return []
    try:
        meta = pl.read_parquet_metadata(files[-1])
    except Exception as exc:
        raise RunError(f"{files[-1]}: unreadable ({exc})") from None
    return json.loads(meta[_META])["sessions"] if _META in meta else []


def is_current(path: str | os.PathLike) -> bool:
    """True when the table at ``path`` is stored in the current ``FORMAT`` (every part)."""
    files = stored_files(path)
    try:
        metas = [pl.read_parquet_metadata(f) for f in files]
    except Exception:
        return False
    return bool(metas) and all(_META in m and json.loads(m[_META]).get("format") == FORMAT
                               for m in metas)


def _stored(frame: pl.DataFrame) -> pl.DataFrame:
    return frame.with_columns(pl.col(pl.Float64).cast(pl.Float32))


def quantised(frame: pl.DataFrame) -> pl.DataFrame:
    """``frame`` with every float64 column rounded to float32 and back: the values a table
    holds once saved (what the reproduction check compares)."""
    return frame.with_columns(pl.col(pl.Float64).cast(pl.Float32).cast(pl.Float64))


def _kept_parts(parts: list[Path], stored: pl.DataFrame) -> tuple[list[Path], int]:
    """The leading ``parts`` whose rows are the first rows of ``stored`` as they are, and how
    many rows they hold; the last is left out, to be written again with the rows after it,
    when they hold every row (the new provenance) or when it is under a quarter of
    ``PART_BYTES`` (so that a table growing a little at a time is not split into as many
    small parts)."""
    kept, heights = [], []
    for part in parts:
        rows = pl.read_parquet(part)
        start = sum(heights)
        if start + rows.height > stored.height or not rows.equals(
                stored.slice(start, rows.height)):
            break
        kept.append(part)
        heights.append(rows.height)
    if kept and (sum(heights) == stored.height or kept[-1].stat().st_size < PART_BYTES / 4):
        kept.pop()
        heights.pop()
    return kept, sum(heights)


def write_table(path: Path, table: pl.DataFrame, entries: Sequence[dict]) -> None:
    """Write ``table`` (float64 columns stored as float32) with its provenance ``entries``,
    each file atomically: in one file, or in parts of consecutive rows when one file would be
    over ``PART_BYTES``, keeping the parts already stored whose rows are the table's first
    rows unchanged and writing the rest in new ones (the other form, and parts no longer
    the table's, removed after)."""
    meta = {_META: json.dumps({"format": FORMAT, "sessions": list(entries)})}
    stored = _stored(table)
    buffer = io.BytesIO()
    write_parquet(stored, buffer, metadata=meta)
    path, folder = Path(path), parts_folder(path)
    old = stored_files(path)
    if buffer.tell() <= PART_BYTES:
        integrity.write(path, lambda p: p.write_bytes(buffer.getvalue()))
        written = [path]
    else:
        written, start = _kept_parts([] if path.is_file() else old, stored)
        rest = stored.slice(start)
        rest_buffer = io.BytesIO()
        write_parquet(rest, rest_buffer)
        count = math.ceil(rest_buffer.tell() / (0.8 * PART_BYTES))
        size = math.ceil(rest.height / count)
        folder.mkdir(parents=True, exist_ok=True)
        first = int(written[-1].stem[5:]) + 1 if written else 0
        for i in range(count):
            part = folder / f"part-{first + i:03d}.parquet"
            integrity.write(part, lambda p, i=i: write_parquet(rest.slice(i * size, size), p,
                                                               metadata=meta))
            written.append(part)
    for stale in set(old) - set(written):
        integrity.remove(stale)
    if folder.is_dir() and not any(folder.iterdir()):
        folder.rmdir()


def save_table(path: Path, table: pl.DataFrame | None, rows: list[dict], key: Sequence[str],
               entry: dict) -> pl.DataFrame:
    """``rows`` (added by the session ``entry``) added to ``table`` (the table at ``path`` as
    read or as last returned), replacing its rows of the same ``key`` (robots measured by an
    older version of the measures), written atomically; returns the new table as it now reads
    back."""
    entries = sessions(path)
    same = [i for i, e in enumerate(entries) if all(
        e.get(k) == entry.get(k) for k in ("pid", "started", "id"))]
    index = same[0] if same else len(entries)
    if not same:
        entries.append(dict(entry))
    if rows:
        new = quantised(pl.DataFrame(rows, schema_overrides={"recording": pl.Utf8},
                                     infer_schema_length=None)
                        ).with_columns(pl.lit(index, pl.Int16).alias("session"))
        entries[index]["rows"] = entries[index].get("rows", 0) + new.height
        if table is not None:
            table = table.with_row_index("_row").join(  # in order: its parts stay
                new.select(key).unique(), on=list(key), how="anti").sort("_row").drop("_row")
        table = new if table is None else pl.concat([table, new], how="diagonal_relaxed")
    write_table(path, table, entries)
    return table


def migrate(run_dir, entry: dict | None = None) -> list[Path]:
    """Rewrite a run's post-evaluation tables written before the current ``FORMAT`` in it
    (the baseline's rows of an old evaluation.parquet into baseline.parquet), giving their rows
    without a session the provenance ``entry`` (default: one saying it is unknown). Returns the
    tables rewritten; tables already current are left as they are."""
    run_dir, _, _ = described_run(run_dir)  # a run, or refused
    entry = entry or {"revision": None, "dirty": None, "version": None, "command": None,
                      "started": None, "machine": None, "pid": None,
                      "note": "written before provenance was recorded"}
    written = []
    legacy = (_read(stored_files(run_dir / EVALUATION))
              if exists(run_dir / EVALUATION) and not is_current(run_dir / EVALUATION) else None)
    parts = {}
    if legacy is not None:
        if "baseline" not in legacy.columns:  # written before the baseline existed
            legacy = legacy.with_columns(pl.lit(False).alias("baseline"))
        if "measures_version" not in legacy.columns:  # measured before version 2
            legacy = legacy.with_columns(pl.lit(1).alias("measures_version"))
        parts[EVALUATION] = legacy.filter(~pl.col("baseline"))
        if legacy["baseline"].any():  # the new code writes both tables in the new format
            parts[BASELINE] = legacy.filter(pl.col("baseline"))
    if not is_current(run_dir / DEVELOPMENT) and exists(run_dir / DEVELOPMENT):
        parts[DEVELOPMENT] = _read(stored_files(run_dir / DEVELOPMENT))
    for name, table in parts.items():
        write_table(run_dir / name, quantised(table).with_columns(
            pl.lit(0, pl.Int16).alias("session")), [dict(entry, rows=table.height)])
        written.append(run_dir / name)
    return written
