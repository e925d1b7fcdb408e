"""Babbling before the first touch measured for a run's trials after their post-evaluation
(section IV-A-1; ``measures.kinematics.babbling_before_touch``, the measure of babbling
validated with the ball and without it: docs/model/measures.md, "The second validation
sample").

The post-evaluation table keeps a trial's measures, not its hand path, so the measure is
computed by running the trials again (the trial is deterministic) and stored beside the run as
``TABLE``: one row per trial (``KEYS``, ``generation`` null for the run's final robots) with
``COLUMN``. ``attach`` adds the column to a run's post-evaluation table where the file exists;
without it the column is absent and a claim on it is not run.
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
    """``table`` (a run's post-evaluation trials of its final robots: ``KEYS``) with
    ``COLUMN`` from the run's ``TABLE`` (null for a trial it does not hold); ``table``
    unchanged when the run has none."""
    stored = load(run_dir)
    if stored is None or not set(KEYS) <= set(table.columns):
        return table
    final = stored.filter(pl.col("generation").is_null()).select(*KEYS, COLUMN)
    if final.height == 0:
        return table
    return table.drop(COLUMN, strict=False).join(final, on=list(KEYS), how="left",
                                                 maintain_order="left")
