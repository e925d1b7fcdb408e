"""``report``: one self-contained HTML file of post-evaluated runs (the paper's findings tested,
provenance, training, Figs. 5-10)."""

from __future__ import annotations

import shlex
from pathlib import Path

from .arguments import command, path_arg


def register_report(subparsers) -> None:
    p = command(subparsers, "report", "one self-contained HTML file: an answer per phenomenon "
                                      "of the paper, its findings tested against runs, "
                                      "provenance, training, Figs. 5-10")
    p.epilog = ("The runs are only read: nothing is written into them. "
                "Trials that Figs. 6 and 8 draw and that have no "
                "recording (committed results hold none) are run again and recorded beside "
                "the report, in NAME-recordings/ for NAME.html (their size per simulated minute: "
                "docs/results/benchmarks.md), and "
                "reused by the next build.")
    p.add_argument("run_dirs", type=path_arg, nargs="+", metavar="RUN_DIR",
                   help="post-evaluated run directories (dart-reach evaluate); an unfinished "
                        "run is judged on its post-evaluated snapshots (evaluate "
                        "--development N --finished-only), where it stands said at the top")
    p.add_argument("--out", type=path_arg, default=None, metavar="FILE.html",
                   help="where to write it, in an existing directory outside the runs "
                        "(default: <first RUN_DIR's name>-report.html in the current "
                        "directory)")
    p.add_argument("--findings", type=path_arg, default=None, metavar="FILE.parquet",
                   help="also write the findings, every claim at every budget, to this new "
                        "parquet file (default: none)")
    p.set_defaults(func=cmd_report)


def cmd_report(args) -> int:
    from ..analysis import report, unfinished
    from ..postevaluation.results import exists
    from ..postevaluation.systematic import TABLE
    from ..evolution.rundir import RunDirectory

    for run_dir in args.run_dirs:
        run = RunDirectory.open(run_dir)
        run.verify()  # one clear line for a path not a run or damaged
        if not exists(run_dir / TABLE) and not unfinished.judged(run_dir):
            # an unfinished run is judged on its post-evaluated snapshots
            first = (["--sensors", "all", "--baseline", "20"] if not run.unfinished() else
                     ["--development", "5", "--development-sensors", "all", "--finished-only"])
            raise ValueError(
                f"{run_dir}: not post-evaluated yet (no {TABLE}"
                + (", no post-evaluated snapshot of the unfinished run" if run.unfinished()
                   else "")
                + "), and the report's findings and figures come from the post-evaluation; "
                  "run first: " + shlex.join(["dart-reach", "evaluate", str(run_dir), *first]))
    out = args.out or Path(report.default_name(args.run_dirs[0]))
    caches = report.recordings_dir(out, args.run_dirs)
    before = _recordings(caches)
    path = report.build(args.run_dirs, args.out, findings_out=args.findings)
    print(f"report: {path} ({_megabytes([path])})\nopen it in a browser (it is "
          f"self-contained, works offline)")
    after = _recordings(caches)
    if after:
        folder = next(iter(caches.values())).parent
        print(f"recordings: {folder}/ holds the {len(after)} trials ({_megabytes(after)}) that "
              f"Figs. 6 and 8 draw and the runs hold no recording of, {len(after - before)} "
              f"recorded now; the next build reuses them (delete the folder to free the space, "
              f"or open one with: dart-reach video TRIAL.rrd OUT.mp4)")
    if args.findings:
        print(f"findings: {args.findings} (every claim at every budget, as in the report)")
    return 0


def _recordings(caches: dict) -> set:
    """The trial recordings in the report's folders (``report.recordings_dir``)."""
    return {p for folder in caches.values() if folder.is_dir() for p in folder.rglob("*.rrd")}


def _megabytes(paths) -> str:
    return f"{sum(p.stat().st_size for p in paths) / 1e6:.1f} MB"
