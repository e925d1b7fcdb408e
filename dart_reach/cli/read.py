"""``read``: what a .rrd recording holds (its properties and series), optionally saved as a
table (CSV or parquet)."""

from __future__ import annotations

from pathlib import Path

from .arguments import command


def register_read(subparsers) -> None:
    p = command(subparsers, "read", "show a .rrd recording's properties and series; --csv "
                                    "and --parquet save its series as a table")
    p.add_argument("rrd", type=Path, metavar="FILE.rrd", help="a trial or training recording")
    p.add_argument("--csv", type=Path, default=None, metavar="OUT.csv",
                   help="also save its series as CSV, a new file: a header of named columns "
                        "(step, sim_time, <entity>/<series>), then one row per time step "
                        "(default: none)")
    p.add_argument("--parquet", type=Path, default=None, metavar="OUT.parquet",
                   help="also save its series as a parquet table, a new file (default: none)")
    p.set_defaults(func=cmd_read)


def cmd_read(args) -> int:
    """Print what a .rrd file holds; optionally save its time series as CSV and/or parquet.
    The output files are checked before the recording is read."""
    from ..recording.export import check_table_out, save_series
    from ..recording.rrd import read_properties, read_rrd

    outs = [check_table_out(path, suffix, option) for path, suffix, option in
            ((args.csv, ".csv", "--csv"), (args.parquet, ".parquet", "--parquet")) if path]
    props, table = read_properties(args.rrd), read_rrd(args.rrd)
    for k, v in props.items():
        print(f"{k:>12}: {v}")
    print(f"{table.height} rows x {table.width} columns: {', '.join(table.columns[:6])}, ...")
    for out in outs:
        print(f"wrote {save_series(args.rrd, out)}")
    return 0
