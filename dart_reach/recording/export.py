"""A recording's time series saved as a table that pandas, R, MATLAB or a spreadsheet opens:
CSV (a header of named columns, then one row per time step) or parquet.

The columns are ``read_rrd``'s: the timelines first (``step`` and ``sim_time`` in s for a
trial, ``generation`` for ``training.rrd``), then one column per series named
``<entity>/<series>`` (``robot/positions/hand/x``, ``network/hidden/h3``; the entities are
listed in ``rrd``). A series without a value at a time point is an empty CSV cell (null).

A CSV names its columns with their units (``sim_time [s]``, ``robot/positions/hand/x [m]``;
``measures.units``) and, for a trial, begins with the trial's properties as columns of the
same value on every row, so that the file says alone which trial it is: ``PROPERTIES`` (those
the recording holds) and the ball's position at the start, ``ball_x``/``ball_y``/``ball_z``
(m, the iCub root frame). The parquet holds ``read_rrd``'s table as it is.
"""

from __future__ import annotations

from pathlib import Path

import polars as pl

from ..files import atomic_write, check_new_file
from ..measures.units import with_unit
from .rrd import read_properties, read_rrd

#: A trial's properties that its CSV carries, in this order (those the recording holds).
PROPERTIES = ("condition", "phase", "replication", "individual", "generation", "senses",
              "sector", "trial", "trial_seed")


def _write_csv(table: pl.DataFrame, path: Path) -> None:
    table.rename({c: with_unit(c) for c in table.columns}).write_csv(path)


#: The table formats by file suffix: (what the file is, how a table is written to it).
FORMATS = {".csv": ("a CSV table", _write_csv),
           ".parquet": ("a parquet table", lambda table, path: table.write_parquet(path))}


def check_table_out(out, suffix: str | None = None, option: str = "out") -> Path:
    """``out`` if a table can be saved there as a new file, else a clear error, before any
    work: its suffix (``suffix``, or any of ``FORMATS`` when None) chooses the format."""
    out = Path(out)
    if suffix is None and out.suffix.lower() not in FORMATS:
        raise ValueError(f"{option}={str(out)!r}: give a name ending in "
                         f"{' or '.join(FORMATS)}, the table's format")
    suffix = suffix or out.suffix.lower()
    return check_new_file(out, suffix, FORMATS[suffix][0], option)


def with_properties(rrd, table: pl.DataFrame) -> pl.DataFrame:
    """``table`` (``read_rrd(rrd)``) with the trial's properties and the ball's starting
    position as leading columns (none for ``training.rrd``)."""
    props = read_properties(rrd)
    ball = [f"robot/positions/ball/{a}" for a in "xyz"]
    constant = {k: props[k] for k in PROPERTIES if k in props}
    if table.height and all(c in table.columns for c in ball):
        constant.update({f"ball_{a}": table[c][0] for a, c in zip("xyz", ball)})
    return table.select([pl.lit(v).alias(k) for k, v in constant.items()]
                        + [pl.col(c) for c in table.columns])


def save_series(rrd, out) -> Path:
    """Save the time series of the recording ``rrd`` (a trial's or ``training.rrd``) to
    ``out``, a new file: CSV when its name ends in .csv (with units and the trial's
    properties), parquet when in .parquet. Returns ``out``. An existing ``out`` is refused,
    never overwritten."""
    out = check_table_out(out)
    table = read_rrd(rrd)
    if out.suffix.lower() == ".csv":
        table = with_properties(rrd, table)
    check_table_out(out)  # still new after the reading
    return atomic_write(out, lambda path: FORMATS[out.suffix.lower()][1](table, path))
