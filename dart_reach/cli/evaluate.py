"""``evaluate``: post-evaluate a trained run on the 45 systematic positions (section IV), and
optionally its snapshots (the development over generations)."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path

from ..progress import evaluation_bar
from .arguments import (add_workers, command, generations, non_negative, path_arg,
                        positive)
from .stopping import checked, interrupted


def register_evaluate(subparsers) -> None:
    p = command(subparsers, "evaluate", "post-evaluate a trained run on the 45 systematic "
                                        "positions (section IV)")
    p.add_argument("run_dir", type=path_arg, metavar="RUN_DIR", help="a run directory of 'train'")
    p.add_argument("--sensors", default="normal",
                   help="sensory condition(s) of Fig. 9 (normal, no-touch, no-sight, "
                        "nothing) or no-ball, the ball-absent test of section IV-A-1; several "
                        "separated by commas; all = the five (default normal)")
    p.add_argument("--robots", type=positive, default=5,
                   help="best robots of each replication to test (default 5)")
    p.add_argument("--record", default="best",
                   choices=("best", "replications", "all", "none"),
                   help="which robots' trials to record as .rrd: the best robot of the best "
                        "replication (default), the best of each replication, all, none")
    p.add_argument("--baseline", type=non_negative, default=0, metavar="N",
                   help="also post-evaluate N random genomes per phase, the chance level of "
                        "every measure (in baseline.parquet; default 0)")
    p.add_argument("--development", type=non_negative, default=0, metavar="N",
                   help="also post-evaluate the best N robots of each replication of every "
                        "snapshot (train --snapshot-every): the measures' course over "
                        "generations, in development.parquet (default 0: not)")
    p.add_argument("--development-sensors", default="normal", metavar="SENSES",
                   help="the conditions the snapshots are evaluated under, as --sensors "
                        "(default normal)")
    p.add_argument("--snapshots", type=generations, metavar="G,G,...",
                   help="with --development: only the snapshots of these generations "
                        "(default: all)")
    p.add_argument("--finished-only", action="store_true",
                   help="evaluate what a run still training has finished (on a copy of its "
                        "directory: the training holds the lock): its finished phases, the "
                        "random genomes of --baseline, and with --development the snapshots "
                        "saved so far")
    p.add_argument("--migrate", action="store_true",
                   help="only rewrite the run's post-evaluation tables stored in an older "
                        "format in the current one (the same rows), once; nothing is evaluated")
    add_workers(p)
    p.set_defaults(func=cmd_evaluate)


def cmd_evaluate(args) -> int:
    import polars as pl

    from ..evolution.rundir import RunDirectory
    from ..postevaluation.results import BASELINE, migrate, rows
    from ..postevaluation.snapshots import check_snapshots
    from ..postevaluation.systematic import (BLUEPRINT, RECORDINGS, TABLE, evaluate_run,
                                             finished_phases, parse_senses)

    def senses_of(option: str, text: str) -> tuple[str, ...]:
        try:
            return parse_senses(text)
        except ValueError as exc:
            raise ValueError(f"{option}: {exc}") from None

    if args.migrate:
        written = migrate(args.run_dir)
        print("\n".join(f"rewrote {path} in the current format" for path in written)
              or f"{args.run_dir}: every table is in the current format", file=sys.stderr)
        return 0
    senses = senses_of("--sensors", args.sensors)
    development_senses = senses_of("--development-sensors", args.development_sensors)
    if args.snapshots and not args.development:
        raise ValueError("--snapshots chooses the snapshots of --development: give "
                         "--development N too")
    if args.snapshots:  # before the post-evaluation, which may take hours
        check_snapshots(RunDirectory.open(args.run_dir), args.snapshots)
    try:
        with evaluation_bar() as bar:
            table = (pl.DataFrame() if args.development and args.finished_only
                     and not args.baseline and not finished_phases(args.run_dir) else
                     evaluate_run(args.run_dir, senses=senses, robots=args.robots,
                                  record=args.record, workers=args.workers,
                                  ray_address=args.ray, progress=checked(bar),
                                  baseline=args.baseline, finished_only=args.finished_only))
    except KeyboardInterrupt as exc:
        # every robot whose trials were collected is saved, reported or not: a stop signal can
        # land between a robot's trials and its progress line
        path = Path(args.run_dir) / TABLE
        saved = rows(path)
        print(f"\ninterrupted: {saved} trials are saved in {path}; run the same command "
              f"again to evaluate the rest", file=sys.stderr)
        return interrupted(exc)
    out = Path(args.run_dir)
    if table.height:
        trained = table.filter(~pl.col("baseline")).height
        saved = [f"{n} trials in {out / name}" for n, name in
                 ((trained, TABLE), (table.height - trained, BASELINE)) if n]
        print("\n" + ", ".join(saved), file=sys.stderr)
    if args.development:
        from ..postevaluation.snapshots import TABLE as DEVELOPMENT, measure_snapshots

        with evaluation_bar() as bar:
            dev = measure_snapshots(args.run_dir, robots=args.development,
                                    workers=args.workers, ray_address=args.ray,
                                    progress=checked(bar), senses=development_senses,
                                    generations=args.snapshots,
                                    finished_only=args.finished_only)
        print(f"{dev.height} trials of the snapshots' best robots in {out / DEVELOPMENT}",
              file=sys.stderr)
    recorded = table.filter(table["recording"].is_not_null())["recording"] if table.height else []
    if len(recorded):
        print(f"{len(recorded)} recordings under {out / RECORDINGS}; open one with its layout:"
              f"\n  {shlex.join(['rerun', str(out / recorded[0]), str(out / BLUEPRINT)])}",
              file=sys.stderr)
    return 0
