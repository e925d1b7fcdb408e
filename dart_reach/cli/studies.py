"""The studies of the model itself: ``validate`` (the model checks; exit 0 when every one
passes), ``bench`` (simulation speed, or with ``--physics`` the physics-step study) and
``screen`` (a run's robots again under other levers)."""

from __future__ import annotations

import json
import math
from pathlib import Path

from ..files import check_new_file
from ..progress import ProgressBar
from .arguments import (add_levers, add_scene, command, int_at_least, levers, path_arg,
                        physics_dt, positive, workers, world_config)
from .stopping import checked


def write_json(path: Path, results: dict) -> None:
    """Write ``results`` to a new file (never over an existing one)."""
    with open(path, "x") as f:
        f.write(json.dumps(results, indent=2) + "\n")
    print(f"wrote {path}")


def register_validate(subparsers) -> None:
    p = command(subparsers, "validate", "check the model: scene, scripted grasps, reflexes, "
                                        "chance level (exit 0 when every check passes)")
    p.add_argument("--json", type=path_arg, default=None,
                   help="also write the figures to FILE, a new file (default: none)")
    p.add_argument("--grid", type=int_at_least(2), default=7,
                   help="start positions per sector side checked (default 7: 49 per sector)")
    # validate.REFLEX_NETWORKS and CHANCE_NETWORKS (not imported here: it loads dartpy)
    p.add_argument("--networks", type=positive, default=200,
                   help="random networks of the reflex checks (default 200)")
    p.add_argument("--chance-networks", type=positive, default=30,
                   help="random networks post-evaluated for the chance level (default 30)")
    p.add_argument("--scene-only", action="store_true",
                   help="only the scene checks and the scripted grasps (seconds, not minutes)")
    p.add_argument("--reflex-inputs", choices=["hand-set", "evolved"], default="hand-set",
                   help="the reflex checks with this lever (docs/model/levers.md)")
    add_scene(p)
    p.set_defaults(func=cmd_validate)


def cmd_validate(args) -> int:
    """The model checks of ``validate.py`` on the shipped world; exit 0 when all pass."""
    from ..studies import validate
    from ..model.world import World

    if args.json is not None:  # before the study: a new .json file in a directory that exists
        check_new_file(args.json, ".json", "a JSON file", "--json")
    results = validate.run(World(world_config(args)), grid=args.grid, networks=args.networks,
                           chance_networks=args.chance_networks, scene_only=args.scene_only,
                           reflex_inputs=args.reflex_inputs)
    print(validate.format_report(results))
    if args.json:
        write_json(args.json, results)
    return 0 if results["passed"] else 1


def register_bench(subparsers) -> None:
    p = command(subparsers, "bench", "measure simulation speed (docs/results/benchmarks.md)")
    p.add_argument("--json", type=path_arg, default=None,
                   help="also write the figures to FILE, a new file (default: none)")
    p.add_argument("--seconds", type=float, default=2.0,
                   help="simulated s per block of the physics pairs (default 2)")
    p.add_argument("--repeats", type=positive, default=30,
                   help="pairs of blocks for the physics ratio (default 30)")
    p.add_argument("--model-version", type=int, default=None, metavar="N",
                   help="the model version the trials compute with; with --physics the "
                        "panel's random networks and scripted reach run under its whole model "
                        "(scene, levers), the robots of --run under their run's (default: the "
                        "version new runs use)")
    p.add_argument("--physics", action="store_true",
                   help="instead: the physics-step study (docs/results/physics-step.md): a "
                        "panel of networks post-evaluated at each candidate step and at a "
                        "quarter of it")
    p.add_argument("--scaling", type=positive, nargs="*", default=None, metavar="NODES",
                   help="instead: generations on local Ray clusters of NODES one-CPU nodes "
                        "each (default 2 4), the driver's and the workers' measured costs, "
                        "and a generation projected at 16, 64 and 256 CPUs "
                        "(docs/guides/cluster.md, 'Blocks')")
    p.add_argument("--physics-steps", type=physics_dt, nargs="+", default=[0.02, 0.01],
                   metavar="DT", help="candidate physics steps in s (default 0.02 0.01)")
    p.add_argument("--networks", type=positive, default=20,
                   help="random networks in the study's panel (default 20)")
    p.add_argument("--run", type=path_arg, nargs="*", default=[], metavar="RUN_DIR",
                   help="finished runs whose best robots join the panel (default: none)")
    p.add_argument("--workers", type=workers, default=None,
                   help="local processes for the study (default: every core)")
    p.set_defaults(func=cmd_bench)


def cmd_bench(args) -> int:
    from ..studies import bench, scaling

    if args.json is not None:  # before the study: a new .json file in a directory that exists
        check_new_file(args.json, ".json", "a JSON file", "--json")
    from ..model.versions import CURRENT_MODEL_VERSION, check_model_version

    version = (CURRENT_MODEL_VERSION if args.model_version is None
               else check_model_version(args.model_version))
    if args.physics:
        from ..studies import physics_step as physics_study

        with ProgressBar(lambda p: (*p, "controller-step", "physics study")) as bar:
            show = checked(bar)
            results = physics_study.study(
                candidates=args.physics_steps, random=args.networks, runs=args.run,
                workers=args.workers, model_version=version,
                progress=lambda n, total: show((n, total)))
        print("\n" + physics_study.format_study(results))
    elif args.scaling is not None:
        measured = scaling.ray_scaling(nodes=args.scaling or (2, 4))
        projected = scaling.scaling_projection(measured)
        print(measured)
        print(projected)
        results = {"machine": bench.machine(), "measured": measured.to_dicts(),
                   "projected": projected.to_dicts()}
    else:
        if not (math.isfinite(args.seconds) and args.seconds > 0):
            raise ValueError(f"--seconds must be a positive number, got {args.seconds:g}")
        results = bench.run(seconds=args.seconds, pairs=args.repeats, model_version=version)
        results.update(scaling.late_population())
        print(bench.format_table(results))
    if args.json:
        write_json(args.json, results)
    return 0


def register_screen(subparsers) -> None:
    p = command(subparsers, "screen", "run a run's snapshot robots again under other levers "
                                      "(scene, self-collision, network start, reflex inputs), "
                                      "without training: docs/model/levers.md")
    p.add_argument("run_dir", type=path_arg, metavar="RUN_DIR", help="a run with snapshots")
    p.add_argument("--generation", type=positive, required=True,
                   help="the snapshot's generation (required: no default)")
    p.add_argument("--phase", default="pre", help="the phase (default: pre)")
    p.add_argument("--robots", type=positive, default=2,
                   help="the best robots of each replication (default 2)")
    p.add_argument("--arm", required=True, metavar="NAME",
                   help="the name of this lever setting in the table (letters, digits, '-'; "
                        "required: no default)")
    p.add_argument("--out", type=path_arg, required=True,
                   help="the screen table (parquet): this arm's rows are added or replaced "
                        "(required: no default)")
    p.add_argument("--workers", type=workers, default=None,
                   help="local processes (default: every core)")
    add_scene(p)
    add_levers(p)
    p.set_defaults(func=cmd_screen)


def cmd_screen(args) -> int:
    import re

    from ..evolution.rundir import RunDirectory
    from ..studies.lever_screen import Arm, check_screen_table, save_screen, screen

    if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_-]*", args.arm):
        raise ValueError(f"--arm must be letters, digits, '_' or '-', got {args.arm!r}")
    if args.model_version is not None:
        raise ValueError("--model-version: a screen runs the robots under their run's version")
    run = RunDirectory.open(args.run_dir)
    check_screen_table(args.out, run.out)  # before the screen, which takes a while
    arm = Arm(args.arm, world_config(args, run.settings.world), levers(args, run.settings.levers))
    table = screen(run.out, args.generation, [arm], args.phase, args.robots,
                   workers=args.workers)
    total = save_screen(table, args.out)
    print(f"{args.arm}: {table.height} trials; {args.out} holds {total.height} trials of "
          f"{total['arm'].n_unique()} arm(s)")
    return 0
