"""A recording's time series saved as a table that pandas, R, MATLAB or a spreadsheet opens:
CSV (a header of named columns, then one row per time step) or parquet.

The columns are ``read_rrd``'s: the timelines first (``step`` and ``sim_time`` in s for a
trial, ``generation`` for ``training.rrd``), then one column per series named
``<entity>/<series>`` (``robot/positions/hand/x``, ``network/hidden/h3``; the entities are
listed in ``rrd``). A series without a value at a time point is an empty CSV cell (null).
"""

from __future__ import annotations

from pathlib import Path

from ..files import atomic_write, check_new_file
from .rrd import read_rrd

#: The table formats by file suffix: (what the file is, how a table is written to it).
FORMATS = {".csv": ("a CSV table", lambda table, path: table.write_csv(path)),
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


def save_series(rrd, out) -> Path:
    """Save the time series of the recording ``rrd`` (a trial's or ``training.rrd``) to
    ``out``, a new file: CSV when its name ends in .csv, parquet when in .parquet. Returns
    ``out``. An existing ``out`` is refused, never overwritten."""
    out = check_table_out(out)
    table = read_rrd(rrd)
    check_table_out(out)  # still new after the reading
    return atomic_write(out, lambda path: FORMATS[out.suffix.lower()][1](table, path))
