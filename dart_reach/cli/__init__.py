"""``dart-reach``: the command line, a thin layer over the library.

Any error in the user's input (a ValueError or a missing file) becomes one line on stderr and
exit code 2, without a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shlex
import signal
import sys
from pathlib import Path

import numpy as np

from ..progress import ProgressBar, evaluation_bar, training_bar


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


def cores() -> int:
    """The cores this process may run on (its CPU affinity where the system tells it)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # macOS, Windows
        return os.cpu_count() or 1


def _workers(text: str) -> int:
    """An argparse type: local worker processes, 1 to the machine's cores. More are refused
    rather than capped: the work is CPU-bound, so they would not finish sooner (results are
    identical for any number of workers), and each process holds ~115 MB."""
    n, available = _positive(text), cores()
    if n > available:
        raise argparse.ArgumentTypeError(
            f"{n} is more than the {available} cores of this machine: extra processes would not "
            f"finish sooner (the work is CPU-bound) and each takes ~115 MB; use {available} or "
            f"fewer, or --ray for a cluster")
    return n


def _physics_dt(text: str) -> float:
    """An argparse type: a physics step in s, positive, finite, dividing the control step."""
    from ..model.world import WorldConfig

    control = WorldConfig().control_dt
    try:
        dt = float(text)
    except ValueError:
        dt = math.nan
    if not (math.isfinite(dt) and dt > 0):
        raise argparse.ArgumentTypeError(f"expected a positive number of seconds, got {text!r}")
    substeps = control / dt
    if substeps < 1 or abs(substeps - round(substeps)) > 1e-9:
        raise argparse.ArgumentTypeError(
            f"{text} s does not divide the control step ({control:g} s) a whole number of "
            f"times: use {control:g}/n, e.g. 0.02 or 0.01")
    return dt


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
    from ..model.icub import HAND_SEGMENTS
    from ..model.scripted import ScriptedReach
    from ..model.world import World, WorldConfig

    if not (np.isfinite(args.seconds) and 0 < args.seconds <= 3600):
        raise ValueError(f"--seconds must be a number of simulated seconds in (0, 3600], got "
                         f"{args.seconds:g}")
    world = World(_world_config(args, WorldConfig(skeleton=args.skeleton)))
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


def _world_config(args, base=None):
    """``base`` (default ``WorldConfig()``) with the sectors of ``--scene`` if given."""
    from ..model.scenes import load_scene
    from ..model.world import WorldConfig

    base = base or WorldConfig()
    return base if args.scene is None else load_scene(args.scene).world(base)


def cmd_scenes(args) -> int:
    """The shipped scenes and where their ball positions lie relative to the right arm."""
    from ..model.scenes import DEFAULT_SCENE, load_scene, scene_names
    from ..studies.validate import scene_geometry
    from ..model.world import World

    print(f"{'scene':<22}{'radius':>7}  {'ball centre / arm length':<26}"
          f"{'elevation from shoulder':<25}{'lateral from midline':<22}description")
    for name in scene_names():
        scene = load_scene(name)
        g = scene_geometry(World(scene.world()))
        mark = " *" if name == DEFAULT_SCENE else ""
        print(f"{name + mark:<22}{scene.sectors.radius:>6.3f}m  "
              f"{g['arm_fraction_min']:.2f} / {g['arm_fraction_median']:.2f} / "
              f"{g['arm_fraction_max']:.2f}{'':<8}"
              f"{g['elevation_min_deg']:+.0f} / {g['elevation_median_deg']:+.0f} / "
              f"{g['elevation_max_deg']:+.0f} deg{'':<7}"
              f"{g['lateral_min_m'] * 100:.0f} to {g['lateral_max_m'] * 100:.0f} cm{'':<10}"
              f"{scene.description}")
    print(f"(min / median / max over a 7 x 7 grid of every sector; arm length "
          f"{g['arm_length_m']:.3f} m, shoulder to palm centre, elbow straight; * the default)")
    return 0


def cmd_bench(args) -> int:
    from ..studies import bench

    if args.json is not None and args.json.exists():
        raise FileExistsError(f"--json {args.json} exists; choose another file")
    if args.physics:
        from ..studies import physics_step as physics_study

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
    from ..studies import validate
    from ..model.world import World

    if args.json is not None and args.json.exists():
        raise FileExistsError(f"--json {args.json} exists; choose another file")
    results = validate.run(World(_world_config(args)), grid=args.grid, networks=args.networks,
                           chance_networks=args.chance_networks, scene_only=args.scene_only)
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


def cmd_robots(args) -> int:
    """The shipped robots files (``data.index()``)."""
    from ..robots import index

    rows = [("run", "condition/phase", "robots", "generations", "replications", "scene", "file")]
    for r in index():
        b = r["budget"] or {}
        rows.append((str(r["run"] or "?"), f"{r['condition']}/{r['phase']}", str(r["robots"]),
                     *(str(b.get(k) or "?") for k in ("generations", "replications", "scene")),
                     r["file"]))
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    for row in rows:
        print("  ".join(x.ljust(w) for x, w in zip(row, widths)) + "  " + row[-1])
    return 0


def cmd_conditions(args) -> int:
    from ..evolution.conditions import list_conditions

    print(f"{'name':<16}{'paper':<22}{'phases':<26}{'generations':<17}description")
    for c in list_conditions():
        phases = " -> ".join(p.name for p in c.phases)
        budgets = " + ".join(str(p.generations) for p in c.phases)
        print(f"{c.name:<16}{c.notation:<22}{phases:<26}{budgets:<17}{c.description}")
    return 0


def cmd_train(args) -> int:
    from ..evolution.conditions import load_condition, scaled
    from ..evolution.run import Settings, train
    from ..model.world import WorldConfig

    conditions = [load_condition(c) for c in args.conditions]
    if args.generations is not None:
        conditions = [scaled(c, args.generations) for c in conditions]
    world = _world_config(args, None if args.physics_dt is None
                          else WorldConfig(physics_dt=args.physics_dt))
    settings = Settings(replications=args.replications, trials=args.trials, steps=args.steps,
                        seed=args.seed, world=world)
    out = args.out or Path("recordings") / f"{'+'.join(c.name for c in conditions)}-s{args.seed}"
    if not args.resume:
        _announce_cost(conditions, settings, None if args.ray else args.workers or cores())
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


#: Core-hours from which ``train`` announces the size of a run before starting it.
LONG_RUN_CORE_HOURS = 1.0


def _announce_cost(conditions, settings, workers: int | None) -> None:
    """Before a long run: its size, the core-hours it will take and how to make it smaller
    (stderr); the progress bar's ETA takes over once generations finish."""
    from ..evolution.run import GENERATION_CORE_S, cost_estimate

    est = cost_estimate(conditions, settings)
    low, high = est.core_hours
    if high < LONG_RUN_CORE_HOURS:
        return
    wall = (f", {low / workers:,.0f}-{high / workers:,.0f} h on {workers} worker"
            f"{'s' if workers > 1 else ''}") if workers else ""
    lo_s, hi_s = GENERATION_CORE_S
    print(f"dart-reach: this run is {est.replication_generations:,} replication-generations, "
          f"about {low:,.0f}-{high:,.0f} core-hours{wall} (from {lo_s:g}-{hi_s:g} core-s per "
          f"replication-generation of 20 genotypes (40 evaluations) x 18 trials x 200 "
          f"steps measured by "
          f"'dart-reach bench', scaled to {settings.trials} trials x {settings.steps} steps).\n"
          f"  The cost is proportional to --generations (per phase) x --replications x --trials "
          f"x --steps: make them smaller for a quicker run (make demo: --generations 3 "
          f"--replications 2 --trials 6, a few minutes on 2 cores). The progress bar's ETA "
          f"follows.",
          file=sys.stderr)


def cmd_evaluate(args) -> int:
    from ..postevaluation.systematic import BLUEPRINT, RECORDINGS, TABLE, evaluate_run, parse_senses

    senses = parse_senses(args.sensors)
    if args.finished_only and args.development:
        raise ValueError("--development needs the whole run trained: not with --finished-only")
    try:
        with evaluation_bar() as bar:
            table = evaluate_run(args.run_dir, senses=senses, robots=args.robots,
                                 record=args.record, workers=args.workers, ray_address=args.ray,
                                 progress=_checked(bar), baseline=args.baseline,
                                 finished_only=args.finished_only)
    except KeyboardInterrupt as exc:
        print(f"\ninterrupted: the robots finished so far are saved in {args.run_dir}/{TABLE}; "
              f"run the same command again to evaluate the rest", file=sys.stderr)
        return _interrupted(exc)
    out = Path(args.run_dir)
    print(f"\n{table.height} trials in {out / TABLE}", file=sys.stderr)
    if args.development:
        from ..postevaluation.snapshots import TABLE as DEVELOPMENT, evaluate_snapshots

        with evaluation_bar() as bar:
            dev = evaluate_snapshots(args.run_dir, robots=args.development,
                                     workers=args.workers, ray_address=args.ray,
                                     progress=_checked(bar))
        print(f"{dev.height} trials of the snapshots' best robots in {out / DEVELOPMENT}",
              file=sys.stderr)
    recorded = table.filter(table["recording"].is_not_null())["recording"] if table.height else []
    if len(recorded):
        print(f"{len(recorded)} recordings under {out / RECORDINGS}; open one with its layout:"
              f"\n  {shlex.join(['rerun', str(out / recorded[0]), str(out / BLUEPRINT)])}",
              file=sys.stderr)
    return 0


def cmd_report(args) -> int:
    from ..analysis import report
    from ..postevaluation.systematic import TABLE
    from ..evolution.run import Run

    for run_dir in args.run_dirs:
        Run.open(run_dir)  # one clear line for a path that is not a run
        if not (run_dir / TABLE).is_file():
            raise ValueError(
                f"{run_dir}: not post-evaluated yet (no {TABLE}), and the report's findings and "
                f"figures come from the post-evaluation; run first: "
                + shlex.join(["dart-reach", "evaluate", str(run_dir), "--sensors", "all",
                              "--baseline", "20"]))
    path = report.build(args.run_dirs, args.out, findings_out=args.findings)
    print(f"report: {path}\nopen it in a browser (it is self-contained, works offline)")
    if args.findings:
        print(f"findings: {args.findings} (every claim at every budget, as in the report)")
    return 0


def cmd_status(args) -> int:
    """Where a run's training stands: generations, fitness and wall time per phase and
    replication, and the sessions that trained it."""
    from ..evolution.run import Run

    run = Run.open(args.run_dir)
    table = run.status()
    head = ("condition", "phase", "replication", "generations", "best", "mean", "wall (h)")
    rows = [(r["condition"], r["phase"], str(r["replication"]),
             f"{r['generations']} / {r['of']}", f"{r['best']:.4f}", f"{r['mean']:.4f}",
             f"{r['wall_h']:.2f}") for r in table.iter_rows(named=True)]
    if args.markdown:
        print("| " + " | ".join(head) + " |\n|" + "---|" * len(head))
        print("\n".join("| " + " | ".join(r) + " |" for r in rows))
    else:
        widths = [max(len(x) for x in col) for col in zip(head, *rows)]
        for r in (head, *rows):
            print("  ".join(x.ljust(w) for x, w in zip(r, widths)))
    done, total = int(table["generations"].sum()), int(table["of"].sum())
    wall = table.unique(["condition", "phase"])["wall_h"].sum()
    sessions = json.loads((run.out / "manifest.json").read_text()).get("sessions", [])
    print(f"{done} of {total} replication-generations ({done / total:.0%}), {wall:.1f} h of "
          f"wall time, {len(sessions)} session(s) recorded; unfinished: "
          f"{', '.join(run.unfinished()) or 'none'}")
    return 0


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


def cmd_watch(args) -> int:
    """One trial of an evolved robot in the Rerun viewer (or saved for it)."""
    from ..viewing.watch import watch

    watched = watch(args.phase, args.condition, args.replication, args.rank, args.sector,
                    args.senses, args.run, args.out, viewer=False if args.no_viewer else None,
                    shipped=args.shipped)
    m = watched.measures
    print(f"{watched.robot}\nsector {args.sector}, {args.senses} senses: "
          f"{'reached' if m['reached'] else 'no reach'}, "
          f"{'grasped' if m['grasped'] else 'no grasp'}, fitness {m['fitness']:.4f}")
    if watched.viewer_pid is not None:
        print(f"the Rerun viewer is opening {watched.recording} (PID {watched.viewer_pid})")
    else:
        print(f"wrote {watched.recording} and its layout {watched.layout}; open them where "
              f"there is a display with:\n  {shlex.join(watched.open_command)}")
    return 0


def cmd_video(args) -> int:
    """A trial recording rendered frame by frame by the headless viewer into a video."""
    from ..viewing.video import render_video, video_missing

    reason = video_missing()
    if reason:  # this machine, not the input: still one line, before any work
        raise ValueError(f"cannot render a video here: {reason}")
    result = render_video(args.rrd, args.out, layout=args.layout, fps=args.fps,
                          size=args.size, progress=True)
    print(f"wrote {result.path}: {result.frames} frames, {result.sim_seconds:g} simulated s, "
          f"rendered in {result.wall_seconds:.0f} s")
    return 0


class _Help(argparse.HelpFormatter):
    """Every option's default in its help (unless the help already says it)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if (action.option_strings and action.nargs != 0 and "default" not in text
                and default is not None and default is not argparse.SUPPRESS
                and default != []):
            text += " (default: %(default)s)"
        return text


class _Parser(argparse.ArgumentParser):
    """Usage errors as one line and exit code 2, like every other bad input."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def _add_workers(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=_workers, default=None,
                   help="local processes, at most the machine's cores (default: every core; "
                        "1 = serial)")
    p.add_argument("--ray", default=None, metavar="ADDRESS",
                   help="evaluate on a Ray cluster ('auto', 'local' or an address; default: "
                        "none, local processes)")


def _add_scene(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scene", default=None, metavar="SCENE",
                   help="where the ball hangs: a shipped scene (see 'scenes') or a scene file "
                        "(default: the default scene)")


def build_parser() -> argparse.ArgumentParser:
    from .. import __version__

    parser = _Parser(
        prog="dart-reach", formatter_class=_Help,
        description="Reaching and grasping development of a simulated iCub "
                    "(Savastano & Nolfi 2013) on DART.",
        epilog="'dart-reach COMMAND --help' lists a command's options. First contact: "
               "'dart-reach watch' shows an evolved robot in the Rerun viewer.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", title="commands")

    def command(name: str, text: str) -> argparse.ArgumentParser:
        return sub.add_parser(name, help=text, description=text, formatter_class=_Help)

    p = command("watch", "run one trial of an evolved robot (a shipped one, or a trained "
                         "run's best with --run) and show it in the Rerun viewer")
    p.add_argument("phase", nargs="?", default=None, metavar="PHASE",
                   help="pre, gross or fine (default: the most developed phase available)")
    p.add_argument("--condition", default="standard",
                   help="the condition the robot was trained in")
    p.add_argument("--run", type=Path, default=None, metavar="RUN_DIR",
                   help="watch this trained run's robot (default: a shipped robot)")
    p.add_argument("--shipped", default=None, metavar="NAME",
                   help="a shipped robot of the shipped run NAME (see 'robots'; default: "
                        "the run that trained the phase longest)")
    p.add_argument("--replication", type=_non_negative, default=None, metavar="R",
                   help="the robot's replication (default: the best replication)")
    p.add_argument("--rank", type=_non_negative, default=0,
                   help="the robot's rank in its replication's final population (0 = best)")
    p.add_argument("--sector", type=int, default=4, choices=range(9), metavar="K",
                   help="the ball at the centre of sector K, 0..8")
    p.add_argument("--senses", default="normal",
                   choices=("normal", "no-touch", "no-sight", "nothing"),
                   help="sensory condition (Fig. 9)")
    p.add_argument("--out", type=Path, default=None, metavar="FILE.rrd",
                   help="the recording (default: recordings/watch/<condition>-<phase>-"
                        "sector<K>.rrd); its layout is written beside it (.rbl)")
    p.add_argument("--no-viewer", action="store_true",
                   help="only write the files, even where there is a display")
    p.set_defaults(func=cmd_watch)

    p = command("video", "render a trial recording frame by frame with the Rerun viewer, "
                         "headless, into a video (MP4)")
    p.add_argument("rrd", type=Path, metavar="TRIAL.rrd",
                   help="a trial recording (watch, evaluate or train --record-every)")
    p.add_argument("out", type=Path, metavar="OUT.mp4", help="the video, a new file")
    p.add_argument("--layout", type=Path, default=None, metavar="FILE.rbl",
                   help="a viewer layout (default: the trial layout of 'dart-reach watch' "
                        "and the post-evaluation)")
    p.add_argument("--fps", type=_positive, default=10,
                   help="frames per simulated second (10 = one per control step, real time)")
    p.add_argument("--size", default="1280x720", metavar="WxH", help="frame size in pixels")
    p.set_defaults(func=cmd_video)

    p = command("reach", "run a scripted reach-and-grasp and print what happened")
    p.add_argument("--sector", type=int, default=4, help="ball sector 0..8 (default 4)")
    p.add_argument("--seconds", type=float, default=5.0, help="simulated seconds (default 5)")
    p.add_argument("--skeleton", type=Path, default=None,
                   help="robot model (URDF; default: the shipped skeleton)")
    _add_scene(p)
    p.set_defaults(func=cmd_reach)

    p = command("scenes", "list the shipped scenes (where the ball hangs) and their geometry "
                          "relative to the arm")
    p.set_defaults(func=cmd_scenes)

    p = command("robots", "list the shipped evolved robots (their run, phase and budget; "
                          "'watch --shipped RUN' shows one)")
    p.set_defaults(func=cmd_robots)

    p = command("conditions", "list the shipped conditions")
    p.set_defaults(func=cmd_conditions)

    p = command("train", "train conditions (shipped names or condition files)")
    p.add_argument("conditions", nargs="+", metavar="CONDITION",
                   help="a shipped condition name (see 'conditions') or a condition file")
    p.add_argument("--out", type=Path, default=None,
                   help="run directory (default recordings/<conditions>-s<seed>)")
    p.add_argument("--generations", type=_positive, default=None,
                   help="generations per standard phase (default: the condition's, 500)")
    p.add_argument("--replications", type=_positive, default=10,
                   help="independent runs of the GA per phase")
    p.add_argument("--trials", type=_positive, default=18, help="trials per evaluation")
    p.add_argument("--steps", type=_positive, default=200, help="0.1 s steps per trial")
    p.add_argument("--seed", type=_non_negative, default=0,
                   help="root of the run's seed tree (same seed, same result)")
    p.add_argument("--physics-dt", type=_physics_dt, default=None, metavar="DT",
                   help="physics step in s, a divisor of 0.1 (default 0.02, the step chosen "
                        "in docs/world.md)")
    _add_scene(p)
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

    p = command("evaluate", "post-evaluate a trained run on the 45 systematic "
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
    p.add_argument("--finished-only", action="store_true",
                   help="evaluate the phases that have finished training in a run that has "
                        "not (on a copy of a run still training: it holds the lock); "
                        "not with --development")
    _add_workers(p)
    p.set_defaults(func=cmd_evaluate)

    p = command("report", "one self-contained HTML file: the paper's findings "
                                      "tested against runs, provenance, training, Figs. 5-10")
    p.add_argument("run_dirs", type=Path, nargs="+", metavar="RUN_DIR",
                   help="post-evaluated run directories (dart-reach evaluate)")
    p.add_argument("--out", type=Path, default=None, metavar="FILE.html",
                   help="where to write it, in an existing directory (default "
                        "RUN_DIR/report.html of the first run)")
    p.add_argument("--findings", type=Path, default=None, metavar="FILE.parquet",
                   help="also write the findings, every claim at every budget, to this new "
                        "parquet file (default: none)")
    p.set_defaults(func=cmd_report)

    p = command("status", "where a run's training stands: generations, fitness and wall "
                          "time per phase and replication")
    p.add_argument("run_dir", type=Path, metavar="RUN_DIR", help="a run directory of 'train'")
    p.add_argument("--markdown", action="store_true",
                   help="print the table as markdown, e.g. for docs/replication.md "
                        "(default: a plain table)")
    p.set_defaults(func=cmd_status)

    p = command("read", "show a .rrd recording's properties and series; "
                                    "--parquet saves them as a table")
    p.add_argument("rrd", type=Path, metavar="FILE.rrd", help="a trial or training recording")
    p.add_argument("--parquet", type=Path, default=None, metavar="OUT.parquet",
                   help="also save its series as a table, a new file (default: none)")
    p.set_defaults(func=cmd_read)

    p = command("validate", "check the model: scene, scripted grasps, reflexes, "
                                        "chance level (exit 0 when every check passes)")
    p.add_argument("--json", type=Path, default=None,
                   help="also write the figures to FILE, a new file (default: none)")
    p.add_argument("--grid", type=_int_at_least(2), default=7,
                   help="start positions per sector side checked (default 7: 49 per sector)")
    # validate.REFLEX_NETWORKS and CHANCE_NETWORKS (not imported here: it loads dartpy)
    p.add_argument("--networks", type=_positive, default=200,
                   help="random networks of the reflex checks (default 200)")
    p.add_argument("--chance-networks", type=_positive, default=30,
                   help="random networks post-evaluated for the chance level (default 30)")
    p.add_argument("--scene-only", action="store_true",
                   help="only the scene checks and the scripted grasps (seconds, not minutes)")
    _add_scene(p)
    p.set_defaults(func=cmd_validate)

    p = command("bench", "measure simulation speed (see README)")
    p.add_argument("--json", type=Path, default=None,
                   help="also write the figures to FILE, a new file (default: none)")
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
                   help="finished runs whose best robots join the panel (default: none)")
    p.add_argument("--workers", type=_workers, default=None,
                   help="local processes for the study (default: every core)")
    p.set_defaults(func=cmd_bench)
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
    _stops.clear()
    signal.signal(signal.SIGTERM, _on_stop_signal)
    signal.signal(signal.SIGINT, _on_stop_signal)
    sys.unraisablehook = _unraisable(sys.__unraisablehook__)
    from ..files import DirectoryBusy

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
