"""``dart-reach``: the command line, a thin layer over the library.

Any error in the user's input (a ValueError or a missing file), and model version 1 asked to
run where numpy's kernels are not pinned (``pinning.KernelsNotPinned``), becomes one line on
stderr and exit code 2, without a traceback.

One module per group of commands, each registering its commands beside their handlers:
``watch`` (watch, video), ``world`` (reach, scenes, versions), ``shipped`` (robots, conditions),
``train`` (train, status), ``migrate``, ``evaluate``, ``report``, ``read`` (read, export),
``studies`` (validate, bench, screen);
``arguments`` holds the argparse types and shared options, ``stopping`` Ctrl-C and SIGTERM.
The handlers import the library only when they run, so that ``dart-reach --help`` took 0.06 s
of CPU (0.14 s wall; ``python -c pass`` 0.03 s) where the handlers' imports at the top would
take 2.5 s (5 s wall), ``analysis.report`` alone 2.4 s (matplotlib, scipy), ``recording.rrd``
(rerun) 0.8 s, ``model.world`` (dartpy) 0.2 s and numpy 0.13 s (medians of 9 whole processes,
on 2 cores busy with a training run).
"""

from __future__ import annotations

import signal
import sys

from . import evaluate, migrate, read, report, shipped, studies, train, watch, world
from .arguments import Help, Parser
from .stopping import (STOPPED, ignore_stop_signals, interrupted, on_stop_signal, stops,
                       unraisable)

#: Every command's registration, in the order ``dart-reach --help`` lists them.
COMMANDS = (watch.register_watch, watch.register_video, world.register_reach,
            world.register_scenes, world.register_versions, shipped.register_robots,
            shipped.register_conditions,
            train.register_train, evaluate.register_evaluate, report.register_report,
            train.register_status, migrate.register_migrate, read.register_read,
            read.register_export,
            studies.register_validate, studies.register_bench, studies.register_screen)


def build_parser() -> Parser:
    from .. import __version__

    parser = Parser(
        prog="dart-reach", formatter_class=Help,
        description="Reaching and grasping development of a simulated iCub "
                    "(Savastano & Nolfi 2013) on DART.",
        epilog="'dart-reach COMMAND --help' lists a command's options. First contact: "
               "'dart-reach watch' shows an evolved robot in the Rerun viewer.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", title="commands")
    for register in COMMANDS:
        register(subparsers)
    return parser


def _message(exc: BaseException) -> str:
    """One line for an error: an OS error names its file and the problem."""
    if isinstance(exc, OSError) and exc.filename and exc.strerror:
        return f"{exc.filename}: {exc.strerror}"
    return " ".join(str(getattr(exc, "cli", exc)).split())


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:  # a bare dart-reach: what it can do
        parser.print_help()
        return 2
    stops.clear()
    signal.signal(signal.SIGTERM, on_stop_signal)
    signal.signal(signal.SIGINT, on_stop_signal)
    sys.unraisablehook = unraisable(sys.__unraisablehook__)
    from ..files import DirectoryBusy
    from ..pinning import KernelsNotPinned

    try:
        code = args.func(args)
    except (ValueError, OSError, DirectoryBusy, KernelsNotPinned) as exc:
        print(f"dart-reach: error: {_message(exc)}", file=sys.stderr)
        code = 2
    except KeyboardInterrupt as exc:
        print("dart-reach: interrupted", file=sys.stderr)
        code = interrupted(exc)
    if stops or code in STOPPED:
        ignore_stop_signals()
    return code
