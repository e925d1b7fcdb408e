"""Babbling before the first touch measured for a run's trials after their post-evaluation
(section IV-A-1; ``measures.kinematics.babbling_before_touch``, the measure of babbling
validated with the ball and without it: docs/model/measures.md, "The second validation
sample").

The post-evaluation table keeps a trial's measures, not its hand path, so the measure is
computed by running the trials again (the trial is deterministic) and stored beside the run as
``TABLE``: one row per trial (``KEYS``, ``generation`` null for the run's final robots) with
``COLUMN``. ``attach`` adds the column to a run's post-evaluation table, or to its
snapshots' (the development table), where the file exists; without it the column is absent
and a claim on it is not run.
"""

from __future__ import annotations

from pathlib import Path

import polars as pl

from .. import integrity

#: The table beside a run, and its column (bool: babbling before the first touch).
TABLE = "babbling-before-touch.parquet"
COLUMN = "babbling_before_touch"
#: A trial's keys in ``TABLE`` besides ``generation``.
KEYS = ("phase_key", "senses", "replication", "rank", "trial")


def load(run_dir) -> pl.DataFrame | None:
    """``TABLE`` of ``run_dir`` (verified against the run's ledger), or None without it."""
    path = Path(run_dir) / TABLE
    if not path.is_file():
        return None
    return pl.read_parquet(integrity.verified(path))


def attach(table: pl.DataFrame, run_dir) -> pl.DataFrame:
    """``table`` with ``COLUMN`` from the run's ``TABLE`` (null for a trial it does not hold):
    a run's post-evaluation trials of its final robots (``KEYS``) take the stored rows of the
    final robots, a development table (``KEYS`` and ``generation``: the snapshots'
    post-evaluation, ``snapshots.load_development``) those of its snapshots; ``table``
    unchanged when the run has none."""
    stored = load(run_dir)
    if stored is None or not set(KEYS) <= set(table.columns):
        return table
    keys = [*KEYS, "generation"] if "generation" in table.columns else list(KEYS)
    rows = stored.filter(pl.col("generation").is_not_null() if "generation" in keys else
                         pl.col("generation").is_null()).select(*keys, COLUMN)
    if rows.height == 0:
        return table
    if "generation" in keys:
        rows = rows.with_columns(pl.col("generation").cast(table.schema["generation"]))
    return table.drop(COLUMN, strict=False).join(rows, on=keys, how="left",
                                                 maintain_order="left")
