"""``read``: what a .rrd recording holds (its properties and series), optionally saved as a
parquet table."""

from __future__ import annotations

from pathlib import Path

from .arguments import command


def register_read(subparsers) -> None:
    p = command(subparsers, "read", "show a .rrd recording's properties and series; "
                                    "--parquet saves them as a table")
    p.add_argument("rrd", type=Path, metavar="FILE.rrd", help="a trial or training recording")
    p.add_argument("--parquet", type=Path, default=None, metavar="OUT.parquet",
                   help="also save its series as a table, a new file (default: none)")
    p.set_defaults(func=cmd_read)


def cmd_read(args) -> int:
    """Print what a .rrd file holds; optionally save its time series as parquet."""
    from ..files import atomic_write
    from ..recording.rrd import read_properties, read_rrd

    props, table = read_properties(args.rrd), read_rrd(args.rrd)
    for k, v in props.items():
        print(f"{k:>12}: {v}")
    print(f"{table.height} rows x {table.width} columns: {', '.join(table.columns[:6])}, ...")
    if args.parquet:
        if args.parquet.exists():
            raise FileExistsError(f"{args.parquet} exists; choose another file")
        atomic_write(args.parquet, lambda p: table.write_parquet(p))
        print(f"wrote {args.parquet}")
    return 0
