"""``read`` (what a .rrd recording holds, its properties and series, optionally saved as a
table, CSV or parquet; a results table given instead is exported as CSV) and ``export`` (every
results table of a run as CSV)."""

from __future__ import annotations

from pathlib import Path

from .arguments import command, path_arg


def register_read(subparsers) -> None:
    p = command(subparsers, "read", "show a .rrd recording's properties and series; --csv "
                                    "and --parquet save its series as a table")
    p.add_argument("rrd", type=path_arg, metavar="FILE.rrd",
                   help="a trial or training recording (or a results table, FILE.parquet, "
                        "with --csv: exported as CSV, as 'export' does)")
    p.add_argument("--csv", type=path_arg, default=None, metavar="OUT.csv",
                   help="also save its series as CSV, a new file: a header of named columns "
                        "with their units (a trial's properties and ball position, step, "
                        "sim_time [s], <entity>/<series> [unit]), then one row per time step "
                        "(default: none)")
    p.add_argument("--parquet", type=path_arg, default=None, metavar="OUT.parquet",
                   help="also save its series as a parquet table, a new file (default: none)")
    p.set_defaults(func=cmd_read)


def _is_table(path: Path) -> bool:
    from ..postevaluation.results import stored_files

    return path.suffix.lower() == ".parquet" or bool(stored_files(path.with_suffix(".parquet"))
                                                     and path.is_dir())


def cmd_read(args) -> int:
    """Print what a .rrd file holds; optionally save its time series as CSV and/or parquet.
    The output files are checked before the recording is read."""
    if _is_table(args.rrd):
        if args.csv is None or args.parquet is not None:
            raise ValueError(f"{args.rrd}: a results table, not a recording: export it with "
                             f"--csv OUT.csv, or every table of its run with 'dart-reach "
                             f"export RUN --csv DIR'")
        from ..analysis.export import export_table

        print(f"wrote {export_table(args.rrd, args.csv, '--csv')}")
        return 0
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


def register_export(subparsers) -> None:
    p = command(subparsers, "export", "write a run's results tables (evaluation, baseline, "
                                      "development, generations, findings: those it has) as "
                                      "CSV, columns named with their units")
    p.add_argument("run_dir", type=path_arg, metavar="RUN_DIR", help="a run directory of 'train'")
    p.add_argument("--csv", type=path_arg, required=True, metavar="DIR",
                   help="the directory to write <table>.csv into (created if missing; no "
                        "file is overwritten; required, no default)")
    p.set_defaults(func=cmd_export)


def cmd_export(args) -> int:
    from ..analysis.export import export_run

    for path in export_run(args.run_dir, args.csv):
        print(f"wrote {path}")
    return 0
