"""Every results table of a run out as CSV (``dart-reach export RUN --csv DIR``), for pandas,
R, MATLAB or a spreadsheet.

The tables (those the run has): ``evaluation`` and ``baseline`` (the post-evaluation, one row
per trial), ``development`` (the snapshots' trials), ``generations`` (the training's statistics,
one row per phase, replication and generation) and ``findings`` (every claim judged, ``make
results``). Each is written to ``DIR/<table>.csv``, one file however many parts it is stored
in (``postevaluation.results``), its columns named with their units (``first_touch_s [s]``,
``hand_path [m]``; ``measures.units``). Values are written as stored: a measure stored as
float32 is written with the digits a float32 holds (``0.6``), not widened to float64
(``0.6000000238``). A list column (none in these tables today) is written as its items
separated by spaces. Nothing is overwritten and nothing is written into the run.
"""

from __future__ import annotations

import os
from pathlib import Path

import polars as pl

from ..evolution.rundir import RunError, described_run
from ..files import atomic_write, check_new_file
from ..measures.units import with_unit
from ..postevaluation import results

#: The tables ``export_run`` writes, in this order: name -> the file in the run.
TABLES = {"evaluation": results.EVALUATION, "baseline": results.BASELINE,
          "development": results.DEVELOPMENT, "generations": "generations.parquet",
          "findings": "findings.parquet"}


def _csv(table: pl.DataFrame, path: Path) -> None:
    lists = [c for c, t in table.schema.items() if isinstance(t, pl.List)]
    table = table.with_columns(pl.col(c).list.eval(pl.element().cast(pl.Utf8)).list.join(" ")
                               for c in lists)
    table.rename({c: with_unit(c) for c in table.columns}).write_csv(path)


def _outside(run: Path, path: Path) -> None:
    """Refuse ``path`` at or inside the run ``run``: a file there the run does not know would
    make it refuse to open."""
    if run.resolve() == path.resolve() or run.resolve() in path.resolve().parents:
        raise ValueError(f"{path}: inside the run {run}; export it elsewhere")


def export_table(path: str | os.PathLike, out: str | os.PathLike,
                 option: str = "out") -> Path:
    """Write the parquet table at ``path`` (a file or a table in parts) to ``out``, a new CSV
    file outside the table's run (a file there would make the run refuse to open), its columns
    named with their units. Returns ``out``."""
    out = check_new_file(out, ".csv", "a CSV table", option)
    run = Path(path).parent
    if (run / "manifest.json").is_file():
        _outside(run, out)
    table = results.stored_table(path)
    return atomic_write(out, lambda p: _csv(table, p))


def export_run(run_dir, out_dir) -> list[Path]:
    """Write every results table the run in ``run_dir`` has (``TABLES``) to
    ``out_dir/<table>.csv`` (``out_dir`` created if missing, its parent must exist); returns
    the files written. Refuses, before writing any, a run without a table and an existing
    file. Reads the run's manifest and the tables alone, each checked against the run's
    ledger (``integrity``) before it is read."""
    out, _, _ = described_run(run_dir)
    out_dir = Path(out_dir)
    found = {name: out / file for name, file in TABLES.items() if results.exists(out / file)}
    if not found:
        raise RunError(f"{out}: no results table to export (train writes "
                       f"generations.parquet, evaluate evaluation.parquet)")
    if not out_dir.is_dir() and not out_dir.parent.is_dir():
        raise FileNotFoundError(f"out_dir {out_dir}: no such directory {out_dir.parent}; "
                                f"create it first")
    _outside(out, out_dir)
    for name in found:
        if (out_dir / f"{name}.csv").exists():
            raise FileExistsError(f"{out_dir / f'{name}.csv'}: the file exists; choose another "
                                  f"directory (nothing is overwritten)")
    out_dir.mkdir(exist_ok=True)
    return [export_table(path, out_dir / f"{name}.csv") for name, path in found.items()]
