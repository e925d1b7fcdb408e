"""``dart-reach``: the command line, a thin layer over the library.

Any error in the user's input (a ValueError or a missing file) becomes one line on stderr and
exit code 2, without a traceback.
"""

from __future__ import annotations

import argparse
import json
import shlex
import signal
import sys
from pathlib import Path

import numpy as np

from .progress import ProgressBar, evaluation_bar, training_bar


def _int_at_least(minimum: int):
    """An argparse type: an integer >= ``minimum``."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {text!r}")
        return value
    return parse


_positive, _non_negative = _int_at_least(1), _int_at_least(0)


class Terminated(KeyboardInterrupt):
    """SIGTERM, handled like Ctrl-C (work saved, a message) but exit code 143."""


#: The stop signals received. Python only prints an exception raised in a destructor (a
#: signal can land in rerun's flush on garbage collection), so a stop could be lost: every
#: progress report (between generations, between robots) raises it again.
_stops: list[KeyboardInterrupt] = []


def _on_stop_signal(signum, frame):
    exc = Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()
    _stops.append(exc)
    raise exc


def _unraisable(hook):
    """``sys.unraisablehook`` that stays quiet about a stop signal swallowed by a destructor
    (it is raised again at the next progress report)."""
    def quiet(info) -> None:
        if not isinstance(info.exc_value, KeyboardInterrupt):
            hook(info)
    return quiet


def _interrupted(exc: KeyboardInterrupt) -> int:
    return 143 if isinstance(exc, Terminated) else 130


def _write_json(path: Path, results: dict) -> None:
    """Write ``results`` to a new file (never over an existing one)."""
    with open(path, "x") as f:
        f.write(json.dumps(results, indent=2) + "\n")
    print(f"wrote {path}")


def cmd_reach(args) -> int:
    """Build the world, run a short scripted reach-and-grasp and say what happened."""
    from .icub import HAND_SEGMENTS
    from .scripted import ScriptedReach
    from .world import World, WorldConfig

    if not (np.isfinite(args.seconds) and 0 < args.seconds <= 3600):
        raise ValueError(f"--seconds must be a number of simulated seconds in (0, 3600], got "
                         f"{args.seconds:g}")
    world = World(WorldConfig(skeleton=args.skeleton))
    ball = world.sector_point(args.sector, 0.5, 0.5)
    world.reset(ball)
    reach = ScriptedReach(world, ball)
    print(f"world: {world.robot.getNumBodyNodes()} robot bodies, {world.robot.getNumDofs()} "
          f"joints, ball r={world.config.ball.radius} m in sector {args.sector} at "
          f"{np.round(ball, 3).tolist()} m")
    print(f"scripted grasp posture found (palm error {reach.solution.palm_error * 1000:.1f} mm)")
    print(f"{'t [s]':>6} {'hand-ball [m]':>14}  contacts")
    touched = set()
    for k in range(int(round(args.seconds / world.config.control_dt))):
        contacts = world.hand_contacts()
        touched.update(np.array(HAND_SEGMENTS)[contacts])
        world.step(reach.targets(contacts))
        if k % 5 == 4:
            names = [n.removeprefix("r_hand_") for n in np.array(HAND_SEGMENTS)[contacts]]
            d = np.linalg.norm(world.hand_position() - world.ball_position())
            print(f"{world.time:6.1f} {d:14.3f}  {', '.join(names) or '-'}")
    print(f"segments that touched the ball: {', '.join(sorted(touched)) or 'none'}")
    return 0


def cmd_bench(args) -> int:
    from . import bench

    if args.json is not None and args.json.exists():
        raise FileExistsError(f"--json {args.json} exists; choose another file")
    if args.physics:
        from . import physics_study

        with ProgressBar(lambda p: (*p, "controller-step", "physics study")) as bar:
            show = _checked(bar)
            results = physics_study.study(
                candidates=args.physics_steps, random=args.networks, runs=args.run,
                workers=args.workers, progress=lambda n, total: show((n, total)))
        print("\n" + physics_study.format_study(results))
    else:
        if not (np.isfinite(args.seconds) and args.seconds > 0):
            raise ValueError(f"--seconds must be a positive number, got {args.seconds:g}")
        results = bench.run(seconds=args.seconds, pairs=args.repeats)
        print(bench.format_table(results))
    if args.json:
        _write_json(args.json, results)
    return 0


def cmd_validate(args) -> int:
    """The model checks of ``validate.py`` on the shipped world; exit 0 when all pass."""
    from . import validate

    if args.json is not None and args.json.exists():
        raise FileExistsError(f"--json {args.json} exists; choose another file")
    results = validate.run(grid=args.grid, networks=args.networks,
                           chance_networks=args.chance_networks)
    print(validate.format_report(results))
    if args.json:
        _write_json(args.json, results)
    return 0 if results["passed"] else 1


def _checked(callback):
    """A progress callback that first raises a stop signal a destructor swallowed."""
    def report(update) -> None:
        if _stops:
            raise _stops[0]
        callback(update)
    return report


def cmd_conditions(args) -> int:
    from .conditions import list_conditions

    print(f"{'name':<16}{'paper':<22}{'phases':<26}{'generations':<17}description")
    for c in list_conditions():
        phases = " -> ".join(p.name for p in c.phases)
        budgets = " + ".join(str(p.generations) for p in c.phases)
        print(f"{c.name:<16}{c.notation:<22}{phases:<26}{budgets:<17}{c.description}")
    return 0


def cmd_train(args) -> int:
    from .conditions import load_condition, scaled
    from .experiment import Settings, train
    from .world import WorldConfig

    conditions = [load_condition(c) for c in args.conditions]
    if args.generations is not None:
        conditions = [scaled(c, args.generations) for c in conditions]
    world = WorldConfig() if args.physics_dt is None else WorldConfig(physics_dt=args.physics_dt)
    settings = Settings(replications=args.replications, trials=args.trials, steps=args.steps,
                        seed=args.seed, world=world)
    out = args.out or Path("recordings") / f"{'+'.join(c.name for c in conditions)}-s{args.seed}"
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be at least 1, got {args.workers}")
    try:
        with training_bar() as bar:
            run = train(conditions, settings, out, workers=args.workers, ray_address=args.ray,
                        resume=args.resume, progress=_checked(bar),
                        record_every=args.record_every,
                        command=shlex.join(["dart-reach", *sys.argv[1:]]),
                        snapshot_every=args.snapshot_every)
    except KeyboardInterrupt as exc:
        again = ["dart-reach", *sys.argv[1:]]
        if "--resume" not in again:
            again.append("--resume")
        if args.out is None:
            again += ["--out", str(out)]
        print(f"\ninterrupted: every finished generation is saved in {out}; continue with:\n"
              f"  {shlex.join(again)}", file=sys.stderr)
        return _interrupted(exc)
    print(f"\ndone: results in {run.out} (manifest.json, generations.parquet, training.rrd, "
          f"phases/*/); post-evaluate with: {shlex.join(['dart-reach', 'evaluate', str(run.out)])}",
          file=sys.stderr)
    return 0


def cmd_evaluate(args) -> int:
    from .evaluation import BLUEPRINT, RECORDINGS, TABLE, evaluate_run, parse_senses

    senses = parse_senses(args.sensors)
    try:
        with evaluation_bar() as bar:
            table = evaluate_run(args.run_dir, senses=senses, robots=args.robots,
                                 record=args.record, workers=args.workers, ray_address=args.ray,
                                 progress=_checked(bar), baseline=args.baseline)
    except KeyboardInterrupt as exc:
        print(f"\ninterrupted: the robots finished so far are saved in {args.run_dir}/{TABLE}; "
              f"run the same command again to evaluate the rest", file=sys.stderr)
        return _interrupted(exc)
    out = Path(args.run_dir)
    print(f"\n{table.height} trials in {out / TABLE}", file=sys.stderr)
    if args.development:
        from .development import TABLE as DEVELOPMENT, evaluate_snapshots

        with ProgressBar(lambda p: (*p, "robot", "development")) as bar:
            dev = evaluate_snapshots(args.run_dir, robots=args.development,
                                     workers=args.workers, ray_address=args.ray,
                                     progress=lambda n, total: _checked(bar)((n, total)))
        print(f"{dev.height} trials of the snapshots' best robots in {out / DEVELOPMENT}",
              file=sys.stderr)
    recorded = table.filter(table["recording"].is_not_null())["recording"] if table.height else []
    if len(recorded):
        print(f"{len(recorded)} recordings under {out / RECORDINGS}; open one with its layout:"
              f"\n  {shlex.join(['rerun', str(out / recorded[0]), str(out / BLUEPRINT)])}",
              file=sys.stderr)
    return 0


def cmd_report(args) -> int:
    from . import report

    path = report.build(args.run_dirs, args.out)
    print(f"report: {path}\nopen it in a browser (it is self-contained, works offline)")
    return 0


def cmd_read(args) -> int:
    """Print what a .rrd file holds; optionally save its time series as parquet."""
    from .files import atomic_write
    from .recording import read_properties, read_rrd

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


class _Parser(argparse.ArgumentParser):
    """Usage errors as one line and exit code 2, like every other bad input."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def _add_workers(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=_positive, default=None,
                   help="local processes (default: every core; 1 = serial)")
    p.add_argument("--ray", default=None, metavar="ADDRESS",
                   help="evaluate on a Ray cluster ('auto', 'local' or an address)")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="dart-reach",
        description="Reaching and grasping development of a simulated iCub "
                    "(Savastano & Nolfi 2013) on DART.")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("reach", help="run a scripted reach-and-grasp and print what happened")
    p.add_argument("--sector", type=int, default=4, help="ball sector 0..8 (default 4)")
    p.add_argument("--seconds", type=float, default=5.0, help="simulated seconds (default 5)")
    p.add_argument("--skeleton", type=Path, default=None, help="robot model (URDF)")
    p.set_defaults(func=cmd_reach)

    p = sub.add_parser("conditions", help="list the shipped conditions")
    p.set_defaults(func=cmd_conditions)

    p = sub.add_parser("train", help="train conditions (shipped names or condition files)")
    p.add_argument("conditions", nargs="+", metavar="CONDITION",
                   help="a shipped condition name (see 'conditions') or a condition file")
    p.add_argument("--out", type=Path, default=None,
                   help="run directory (default recordings/<conditions>-s<seed>)")
    p.add_argument("--generations", type=_positive, default=None,
                   help="generations per standard phase (default: the condition's, 500)")
    p.add_argument("--replications", type=_positive, default=10)
    p.add_argument("--trials", type=_positive, default=18, help="trials per evaluation")
    p.add_argument("--steps", type=_positive, default=200, help="0.1 s steps per trial")
    p.add_argument("--seed", type=_non_negative, default=0)
    p.add_argument("--physics-dt", type=float, default=None, metavar="DT",
                   help="physics step in s, a divisor of 0.1 (default 0.02, the step chosen "
                        "in docs/world.md)")
    _add_workers(p)
    p.add_argument("--resume", action="store_true", help="continue the run in --out")
    p.add_argument("--record-every", type=_non_negative, default=100, metavar="K",
                   help="record one trial of each replication's best individual every K "
                        "generations and at the end of each phase (default 100; 0 = never)")
    p.add_argument("--snapshot-every", type=_non_negative, default=50, metavar="K",
                   help="keep the best 5 genomes of each replication after generations 1, 2, "
                        "5, 10, every K and the last of each phase, for the development over "
                        "generations (default 50; 0 = never)")
    p.set_defaults(func=cmd_train)

    p = sub.add_parser("evaluate", help="post-evaluate a trained run on the 45 systematic "
                                        "positions (section IV)")
    p.add_argument("run_dir", type=Path, metavar="RUN_DIR", help="a run directory of 'train'")
    p.add_argument("--sensors", default="normal",
                   choices=("normal", "no-touch", "no-sight", "nothing", "no-ball", "all"),
                   help="sensory condition(s) of Fig. 9, or no-ball: the ball-absent test of "
                        "section IV-A-1 (default normal; all = the five)")
    p.add_argument("--robots", type=_positive, default=5,
                   help="best robots of each replication to test (default 5)")
    p.add_argument("--record", default="best",
                   choices=("best", "replications", "all", "none"),
                   help="which robots' trials to record as .rrd: the best robot of the best "
                        "replication (default), the best of each replication, all, none")
    p.add_argument("--baseline", type=_non_negative, default=0, metavar="N",
                   help="also post-evaluate N random genomes per phase, the chance level of "
                        "every measure (rows flagged 'baseline'; default 0)")
    p.add_argument("--development", type=_non_negative, default=0, metavar="N",
                   help="also post-evaluate the best N robots of each replication of every "
                        "snapshot (train --snapshot-every): the measures' course over "
                        "generations, in development.parquet (default 0: not)")
    _add_workers(p)
    p.set_defaults(func=cmd_evaluate)

    p = sub.add_parser("report", help="one self-contained HTML file: the paper's findings "
                                      "tested against runs, provenance, training, Figs. 5-10")
    p.add_argument("run_dirs", type=Path, nargs="+", metavar="RUN_DIR")
    p.add_argument("--out", type=Path, default=None, metavar="FILE.html",
                   help="where to write it (default RUN_DIR/report.html of the first run)")
    p.set_defaults(func=cmd_report)

    p = sub.add_parser("read", help="show a .rrd recording's properties and series; "
                                    "--parquet saves them as a table")
    p.add_argument("rrd", type=Path, metavar="FILE.rrd")
    p.add_argument("--parquet", type=Path, default=None, metavar="OUT.parquet")
    p.set_defaults(func=cmd_read)

    p = sub.add_parser("validate", help="check the model: scene, scripted grasps, reflexes, "
                                        "chance level (exit 0 when every check passes)")
    p.add_argument("--json", type=Path, default=None, help="also write the figures to FILE")
    p.add_argument("--grid", type=_int_at_least(2), default=7,
                   help="start positions per sector side checked (default 7: 49 per sector)")
    p.add_argument("--networks", type=_positive, default=40,
                   help="random networks of the reflex checks (default 40)")
    p.add_argument("--chance-networks", type=_positive, default=6,
                   help="random networks post-evaluated for the chance level (default 6)")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("bench", help="measure simulation speed (see README)")
    p.add_argument("--json", type=Path, default=None, help="also write the figures to FILE")
    p.add_argument("--seconds", type=float, default=2.0,
                   help="simulated s per block of the physics pairs (default 2)")
    p.add_argument("--repeats", type=_positive, default=30,
                   help="pairs of blocks for the physics ratio (default 30)")
    p.add_argument("--physics", action="store_true",
                   help="instead: the physics-step study (docs/world.md): a panel of networks "
                        "post-evaluated at each candidate step and at a quarter of it")
    p.add_argument("--physics-steps", type=float, nargs="+", default=[0.02, 0.01],
                   metavar="DT", help="candidate physics steps in s (default 0.02 0.01)")
    p.add_argument("--networks", type=_positive, default=20,
                   help="random networks in the study's panel (default 20)")
    p.add_argument("--run", type=Path, nargs="*", default=[], metavar="RUN_DIR",
                   help="finished runs whose best robots join the panel")
    p.add_argument("--workers", type=_positive, default=None,
                   help="local processes for the study (default: every core)")
    p.set_defaults(func=cmd_bench)
    return parser


def _message(exc: BaseException) -> str:
    """One line for an error: an OS error names its file and the problem."""
    if isinstance(exc, OSError) and exc.filename and exc.strerror:
        return f"{exc.filename}: {exc.strerror}"
    return " ".join(str(exc).split())


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    _stops.clear()
    signal.signal(signal.SIGTERM, _on_stop_signal)
    signal.signal(signal.SIGINT, _on_stop_signal)
    sys.unraisablehook = _unraisable(sys.__unraisablehook__)
    from .files import DirectoryBusy

    try:
        return args.func(args)
    except (ValueError, OSError, DirectoryBusy) as exc:
        print(f"dart-reach: error: {_message(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        print("dart-reach: interrupted", file=sys.stderr)
        return _interrupted(exc)


if __name__ == "__main__":
    sys.exit(main())
