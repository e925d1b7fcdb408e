"""``train`` (evolve the conditions' phases into a run directory, announcing a long run's cost
first) and ``status`` (where a run's training stands)."""

from __future__ import annotations

import json
import shlex
import sys
from pathlib import Path

from ..progress import training_bar
from .arguments import (add_levers, add_scene, add_workers, command, cores, levers,
                        non_negative, path_arg, physics_dt, positive, world_config)
from .stopping import checked, interrupted


def register_train(subparsers) -> None:
    p = command(subparsers, "train", "train conditions (shipped names or condition files)")
    p.add_argument("conditions", nargs="+", metavar="CONDITION",
                   help="a shipped condition name (see 'conditions') or a condition file")
    p.add_argument("--out", type=path_arg, default=None,
                   help="run directory (default recordings/<conditions>-s<seed>)")
    p.add_argument("--generations", type=positive, default=None,
                   help="generations per standard phase (default: the condition's, 500)")
    p.add_argument("--replications", type=positive, default=None,
                   help="independent runs of the GA per phase (default 10)")
    p.add_argument("--trials", type=positive, default=None,
                   help="trials per evaluation (default 18)")
    p.add_argument("--steps", type=positive, default=None,
                   help="0.1 s steps per trial (default 200)")
    p.add_argument("--seed", type=non_negative, default=None,
                   help="root of the run's seed tree (same seed, same result; default 0)")
    p.add_argument("--physics-dt", type=physics_dt, default=None, metavar="DT",
                   help="physics step in s, a divisor of 0.1 (default 0.02, the step chosen "
                        "in docs/model/world.md)")
    add_scene(p)
    add_levers(p)
    add_workers(p)
    p.add_argument("--ray-block", type=positive, default=None, metavar="N",
                   help="with --ray: trials per Ray task (default: a lifetime in the first "
                        "generation, then sized from the last one's measured cost so that the "
                        "driver keeps up; the results are the same whatever N)")
    p.add_argument("--resume", action="store_true",
                   help="continue the run in --out under the settings its manifest records "
                        "(model version, levers, scene, budgets: nothing is typed again; an "
                        "option given that differs from the run's is refused)")
    p.add_argument("--yes", action="store_true",
                   help="start a run estimated at over an hour without asking (the question is "
                        "asked only when stdin is a terminal; scripts are never asked)")
    p.add_argument("--record-every", type=non_negative, default=100, metavar="K",
                   help="record one trial of each replication's best individual every K "
                        "generations and at the end of each phase (default 100; 0 = never)")
    p.add_argument("--snapshot-every", type=non_negative, default=50, metavar="K",
                   help="keep the best 5 genomes of each replication after generations 1, 2, "
                        "5, 10, every K and the last of each phase, for the development over "
                        "generations (default 50; 0 = never)")
    p.set_defaults(func=cmd_train)


def cmd_train(args) -> int:
    from ..evolution.conditions import load_condition, scaled
    from ..evolution.trainer import train

    conditions = [load_condition(c) for c in args.conditions]
    if args.generations is not None:
        conditions = [scaled(c, args.generations) for c in conditions]
    out = args.out or (Path("recordings")
                       / f"{'+'.join(c.name for c in conditions)}-s{args.seed or 0}")
    settings = run_settings(args, out)
    if not args.resume:
        hours = announce_cost(conditions, settings, None if args.ray else args.workers or cores())
        if hours > ASK_HOURS and not args.yes and sys.stdin.isatty() and not _agreed():
            print("not started", file=sys.stderr)
            return 1
    try:
        with training_bar() as bar:
            run = train(conditions, settings, out, workers=args.workers, ray_address=args.ray,
                        ray_block=args.ray_block, resume=args.resume, progress=checked(bar),
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
        return interrupted(exc)
    print(f"\ndone: results in {run.out} (manifest.json, generations.parquet, training.rrd, "
          f"phases/*/); post-evaluate with: {shlex.join(['dart-reach', 'evaluate', str(run.out)])}",
          file=sys.stderr)
    return 0


#: ``train``'s budget options and their defaults for a new run.
BUDGETS = {"replications": 10, "trials": 18, "steps": 200, "seed": 0}


def run_settings(args, out: Path):
    """The ``Settings`` a ``train`` command line asks for. A new run: its model version's
    whole record (``--model-version``, default the current one), with the scene,
    self-collision and levers given beside it (a named variant, recorded in the manifest).
    ``--resume`` of a run in ``out``: the settings its manifest records; an option given that
    differs from them raises ``ValueError`` naming it (nothing is typed twice)."""
    from ..evolution.rundir import described_run
    from ..evolution.settings import Settings
    from ..model.versions import CURRENT_MODEL_VERSION, model_version
    from ..model.world import WorldConfig

    budgets = {k: getattr(args, k) for k in BUDGETS if getattr(args, k) is not None}
    if args.resume and (out / "manifest.json").is_file():
        settings = described_run(out)[2]
        asked = dict(budgets, model_version=args.model_version,
                     physics_dt=args.physics_dt)
        have = dict(vars(settings), physics_dt=settings.world.physics_dt)
        given = [k for k, v in asked.items() if v is not None and have[k] != v]
        world = world_config(args, settings.world)
        given += [name for k, name in (("sectors", "scene"), ("self_collision", "self_collision"))
                  if getattr(world, k) != getattr(settings.world, k)]
        given += list(levers(args, settings.levers).changed_from(settings.levers))
        if given:
            raise ValueError(f"{out}: --resume continues the run under the settings its "
                             f"manifest records, and {', '.join(sorted(given))} given here "
                             f"differ{'s' if len(given) == 1 else ''} from them: leave "
                             f"{'it' if len(given) == 1 else 'them'} out")
        return settings
    version = model_version(CURRENT_MODEL_VERSION if args.model_version is None
                            else args.model_version)
    base = version.world(None if args.physics_dt is None
                         else WorldConfig(physics_dt=args.physics_dt))
    return Settings(**{**BUDGETS, **budgets}, world=world_config(args, base),
                    levers=levers(args, version.levers), model_version=version.number)


#: Core-hours from which ``train`` announces the size of a run before starting it.
LONG_RUN_CORE_HOURS = 1.0
#: Hours (wall time on the local workers, core-hours on a cluster) from which ``train`` asks
#: a person at the terminal before it starts (``--yes`` skips the question).
ASK_HOURS = 1.0


def _agreed() -> bool:
    """The person at the terminal's answer to: start this long run?"""
    print("start it? [y/N] ", end="", file=sys.stderr, flush=True)
    return sys.stdin.readline().strip().lower() in ("y", "yes")


def announce_cost(conditions, settings, workers: int | None) -> float:
    """Before a long run: its size, the core-hours it will take and how to make it smaller
    (stderr); the progress bar's ETA takes over once generations finish. Returns the upper
    estimate in hours: of wall time on ``workers`` local workers, of core-hours on a cluster
    (``workers`` None)."""
    from ..evolution.cost import GENERATION_CORE_S, cost_estimate

    est = cost_estimate(conditions, settings)
    low, high = est.core_hours
    if high < LONG_RUN_CORE_HOURS:
        return high / (workers or 1)
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
    return high / (workers or 1)


def register_status(subparsers) -> None:
    p = command(subparsers, "status", "where a run's training stands: generations, fitness and "
                                      "wall time per phase and replication")
    p.add_argument("run_dir", type=path_arg, metavar="RUN_DIR", help="a run directory of 'train'")
    p.add_argument("--markdown", action="store_true",
                   help="print the table as markdown, e.g. for docs/results/replication.md "
                        "(default: a plain table)")
    p.add_argument("--reproduce", action="store_true",
                   help="also run one stored robot per phase and results table again on 9 of "
                        "the 45 positions and check that the rows are the stored ones to the "
                        "last bit (a few seconds per phase; exit code 1 when they are not)")
    p.set_defaults(func=cmd_status)


def cmd_status(args) -> int:
    """Where a run's training stands: generations, fitness and wall time per phase and
    replication, and the sessions that trained it; then its post-evaluation results: complete
    or not, written where, and (``--reproduce``) whether a slice of them runs again the same."""
    from ..evolution.rundir import RunDirectory
    from ..postevaluation import checks

    run = RunDirectory.open(args.run_dir)
    run.verify()
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
    print("\n".join(checks.describe(run.out)))
    if not args.reproduce:
        return 0
    found = checks.reproduce(run.out)
    for r in found.iter_rows(named=True):
        at = f" @{r['generation']}" if r["generation"] is not None else ""
        print(f"reproduce: {r['table']} {r['phase']}{at} {r['senses']} replication "
              f"{r['replication']} rank {r['rank']}, {r['trials']} trials: "
              + ("the same to the last bit" if r["equal"] else
                 f"DIFFERENT in {', '.join(r['differ'])} (max |diff| {r['max_abs_diff']:.3g})"))
    ok, why = checks.reproduced(found, checks.table_status(run.out))
    print(f"reproduce: {'reproduces' if ok else 'DOES NOT REPRODUCE'}: {why}")
    return 0 if ok else 1
