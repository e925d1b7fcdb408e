"""The physics-step study (``dart-reach bench --physics``): which physics step is converged?

A trial of a recurrent network in a contact-rich world is chaotic: two physics steps give two
different trajectories after a few seconds whatever the steps. What must not depend on the step
are the statistics the paper reports (section IV, Figs. 5-7): the post-evaluation means of
fitness, reach rate, grasp rate, reaching speed and straightness. The study runs a fixed panel
of controllers on the 45 systematic positions at each candidate step and at a quarter of it,
and compares the panel's statistics within ``Tolerances``; it also measures the open-loop hand
tracking error against a fine reference and the cost of each step in core time.

The panel: random networks of the pre- and gross-reaching phases (reflexes as in those phases)
and the scripted reach-and-grasp (``scripted.ScriptedController``), under a model version
(its numerics, levers, scene and self-collision: ``model.versions``), and, when run
directories are given, the best 5 evolved robots of each replication of each of their phases,
each in its own run's world (scene, self-collision) and numerics.

The chosen step is the largest candidate whose statistics agree with its quarter step, over
the whole panel and within each kind of controller.
docs/results/physics-step.md reports the study's figures and the command that reproduces them.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from ..evolution.backends import make_backend
from ..evolution.conditions import load_condition
from ..evolution.genome import as_groups, decode, random_genome
from ..evolution.settings import Settings, trial_config
from ..measures.metrics import trial_metrics
from ..model.scripted import ScriptedController
from ..model.servo import Servo
from ..model.task import Trial, TrialConfig, network_for
from ..model.versions import CURRENT_MODEL_VERSION
from ..model.world import POINTS_PER_SECTOR, World, WorldConfig
from ..postevaluation.systematic import open_finished

#: The statistics compared, each ``(key, kind)``: "rate" compared in absolute terms, "rel"
#: relative to the finer step's value.
STATISTICS = (("fitness", "rel"), ("reach_rate", "rate"), ("grasp_rate", "rate"),
              ("speed", "rel"), ("straightness", "rel"))
KINDS = ("random", "scripted", "evolved")


@dataclass(frozen=True)
class Tolerances:
    """How close two steps' panel statistics must be to agree: rates within ``rate_abs``
    (absolute), fitness, reaching speed and straightness within ``rel`` of the finer step's
    value (relative)."""

    rate_abs: float = 0.05
    rel: float = 0.10


@dataclass(frozen=True)
class Member:
    """One controller of the panel. ``genome`` None means the scripted reach-and-grasp;
    ``world`` the world it runs in (scene, self-collision; its physics step is replaced by the
    step judged)."""

    kind: str  # one of KINDS
    label: str
    genome: np.ndarray | None
    free_groups: frozenset
    trial: TrialConfig
    world: WorldConfig
    evolved_dt: float | None = None  # the physics step it evolved at (evolved robots only)

    def judges(self, candidate: float) -> bool:
        """Whether this member takes part in the comparison of ``candidate`` with its quarter:
        an evolved robot only at the step it evolved at (selection tunes a robot to the
        physics it evolved in; judged at another step it measures that, not the step)."""
        return self.evolved_dt is None or math.isclose(self.evolved_dt, candidate)


def panel(random: int = 20, seed: int = 0, runs=(), steps: int = 200,
          scripted: bool = True, evolved: int = 5,
          model_version: int = CURRENT_MODEL_VERSION) -> list[Member]:
    """The study's controllers: ``random`` random networks (half pre-, half gross-reaching)
    and the scripted reach-and-grasp (unless ``scripted`` is False) under ``model_version``
    (default: the version new runs use), and the best ``evolved`` robots of each replication
    of each phase of the finished run directories ``runs``, under their run's settings.
    Trials last ``steps`` control steps."""
    settings = Settings(steps=steps, model_version=model_version)
    standard = load_condition("standard").phases[:2]
    genomes = random_genome(np.random.default_rng(seed), random)
    members = []
    for i, genome in enumerate(genomes):
        phase = standard[i % 2]
        members.append(Member("random", f"random-{phase.name}-{i}", genome,
                              as_groups(phase.free_groups), trial_config(phase, settings),
                              settings.world))
    if scripted:
        trial = trial_config(standard[0], settings)
        members.append(Member("scripted", "scripted", None, frozenset(),
                              TrialConfig(steps=steps, numerics=trial.numerics),
                              settings.world))
    for run_dir in runs:
        run = open_finished(run_dir)
        for _, phase in run.unique_phases():
            population, _ = run.load_final(phase)
            trial = replace(trial_config(phase, run.settings), steps=steps)
            for r in range(population.shape[0]):
                for i in range(min(evolved, population.shape[1])):
                    members.append(Member("evolved", f"{run.out.name}/{phase.name}/rep{r}/{i}",
                                          population[r, i], as_groups(phase.free_groups),
                                          trial, run.settings.world,
                                          run.settings.world.physics_dt))
    return members


_WORLDS: dict[WorldConfig, World] = {}


def run_member(job: tuple[Member, float]) -> dict:
    """One member's 45 post-evaluation trials in its world at one physics step: the
    per-trial measures needed by the study and the core time they took (s)."""
    member, physics_dt = job
    config = replace(member.world, physics_dt=physics_dt)
    world = _WORLDS.get(config)
    if world is None:
        world = _WORLDS[config] = World(config)
    trial = Trial(world, member.trial)
    network = (None if member.genome is None
               else network_for(decode(member.genome, member.free_groups), member.trial))
    rows, core_s = [], 0.0
    for k, point in enumerate(world.systematic_points()):
        controller = network or ScriptedController(world, point)
        t0 = time.process_time()
        data = trial.run(controller, k // POINTS_PER_SECTOR, point)
        core_s += time.process_time() - t0
        m = trial_metrics(data, world.config.control_dt)
        rows.append((m["fitness"], m["reached"], m["grasped"], m["speed"], m["straightness"]))
    return {"kind": member.kind, "label": member.label, "physics_dt": physics_dt,
            "rows": rows, "core_s": core_s,
            "simulated_s": len(rows) * member.trial.steps * world.config.control_dt}


def panel_statistics(rows) -> dict[str, float]:
    """Means over trials of (fitness, reached, grasped, speed, straightness) rows; speed and
    straightness over the trials that reached (NaN-free mean), as in Fig. 6."""
    a = np.asarray(rows, dtype=float).reshape(-1, 5)
    reached = a[:, 3][np.isfinite(a[:, 3])], a[:, 4][np.isfinite(a[:, 4])]
    return {"fitness": float(a[:, 0].mean()), "reach_rate": float(a[:, 1].mean()),
            "grasp_rate": float(a[:, 2].mean()),
            "speed": float(reached[0].mean()) if reached[0].size else math.nan,
            "straightness": float(reached[1].mean()) if reached[1].size else math.nan,
            "trials": int(a.shape[0])}


def agreement(coarse: dict, fine: dict, tol: Tolerances = Tolerances()) -> dict:
    """Differences of the coarse step's statistics from the fine step's and whether each is
    within tolerance: ``{stat: {"diff": d, "limit": l, "ok": bool}}``. A statistic that is NaN
    at both steps (no reaching trial) agrees; NaN at one only does not."""
    out = {}
    for key, kind in STATISTICS:
        a, b = coarse[key], fine[key]
        if math.isnan(a) or math.isnan(b):
            out[key] = {"diff": math.nan, "limit": math.nan, "ok": math.isnan(a) == math.isnan(b)}
            continue
        if kind == "rate":
            diff, limit = a - b, tol.rate_abs
        else:
            diff, limit = (a - b) / abs(b) if b else (0.0 if a == b else math.inf), tol.rel
        out[key] = {"diff": float(diff), "limit": limit, "ok": bool(abs(diff) <= limit)}
    return out


def tracking_error(physics_dt: float, reference_dt: float, seeds: int = 5,
                   seconds: float = 10.0) -> dict:
    """Open-loop hand tracking: random motor targets, a new vector every second (moved at the
    bounded joint speed, the living model's servo: ``servo.Servo``), the ball out of reach;
    the palm's distance (m) from where it is at ``reference_dt``, every control step. Max and
    mean over ``seeds`` target sequences."""
    servos = {dt: Servo(World(WorldConfig(physics_dt=dt))) for dt in (physics_dt, reference_dt)}
    steps = round(seconds / servos[physics_dt].world.config.control_dt)
    errors = []
    for seed in range(seeds):
        targets = np.random.default_rng(seed).uniform(-1.0, 1.0, (steps // 10 + 1, 14))
        paths = {}
        for dt, servo in servos.items():
            world = servo.world
            servo.reset(world.sector_point(4, 0.5, 0.5) + [0.0, 0.0, 1.0])
            path = np.empty((steps, 3))
            for t in range(steps):
                servo.step(targets[t // 10])
                path[t] = world.hand_position()
            paths[dt] = path
        errors.append(np.linalg.norm(paths[physics_dt] - paths[reference_dt], axis=1))
    e = np.concatenate(errors)
    return {"tracking_max_m": float(e.max()), "tracking_mean_m": float(e.mean())}


def study(candidates=(0.02, 0.01), random: int = 20, runs=(), steps: int = 200,
          tolerances: Tolerances = Tolerances(), workers: int | None = None,
          reference_dt: float = 0.00125, seed: int = 0, scripted: bool = True,
          model_version: int = CURRENT_MODEL_VERSION, progress=None) -> dict:
    """Run the panel at every candidate step and at a quarter of it; compare. Returns the
    per-step panel statistics (per kind and over the whole panel), the agreement of each
    candidate with its quarter, the tracking errors, each step's cost (simulated s per core
    s) and ``chosen``: the largest candidate that agrees in every statistic, over the whole
    panel and within each kind of controller (random, scripted, evolved), or None."""
    candidates = sorted(set(float(c) for c in candidates), reverse=True)
    for c in candidates:  # a step that does not divide 0.1 s fails here, early, named as given
        WorldConfig(physics_dt=c)
    members = panel(random, seed, runs, steps, scripted, model_version=model_version)
    jobs = list(dict.fromkeys((i, dt) for c in candidates for dt in (c, c / 4)
                              for i, m in enumerate(members) if m.judges(c)))
    backend = make_backend(workers)
    results = {}
    try:
        for n, result in enumerate(backend.imap(run_member, [(members[i], dt)
                                                              for i, dt in jobs]), start=1):
            results[jobs[n - 1]] = result
            if progress:
                progress(n, len(jobs))
    finally:
        backend.close()
    comparisons = {}
    for c in candidates:
        judged = [i for i, m in enumerate(members) if m.judges(c)]
        steps_stats = {}
        for dt in (c, c / 4):
            mine = [results[(i, dt)] for i in judged]
            stats = {kind: panel_statistics([row for r in mine if r["kind"] == kind
                                             for row in r["rows"]])
                     for kind in KINDS if any(r["kind"] == kind for r in mine)}
            stats["panel"] = panel_statistics([row for r in mine for row in r["rows"]])
            steps_stats[dt] = {"statistics": stats,
                               "rtf_per_core": sum(r["simulated_s"] for r in mine)
                               / sum(r["core_s"] for r in mine)}
        coarse, fine = steps_stats[c]["statistics"], steps_stats[c / 4]["statistics"]
        checks = {group: agreement(coarse[group], fine[group], tolerances) for group in coarse}
        comparisons[c] = {
            "quarter": c / 4, "steps": steps_stats, "checks": checks,
            "members": {kind: sum(members[i].kind == kind for i in judged) for kind in KINDS},
            "agrees": all(v["ok"] for group in checks.values() for v in group.values()),
            "cost_ratio": steps_stats[c]["rtf_per_core"] / steps_stats[c / 4]["rtf_per_core"],
            **tracking_error(c, reference_dt)}
    chosen = next((c for c in candidates if comparisons[c]["agrees"]), None)
    return {"model_version": model_version, "steps": steps,
            "tolerances": {"rate_abs": tolerances.rate_abs,
                                           "rel": tolerances.rel},
            "reference_dt": reference_dt, "comparisons": comparisons, "chosen": chosen}


def format_study(r: dict) -> str:
    """The study as text tables: per candidate, the statistics at it and at its quarter,
    the agreement, the tracking error and the cost."""
    names = [k for k, _ in STATISTICS]
    lines = [f"model version {r['model_version']} (random and scripted); 45 trials of "
             f"{r['steps']} steps per controller; tolerances: rates within "
             f"{r['tolerances']['rate_abs']:g} absolute, fitness, speed and straightness "
             f"within {r['tolerances']['rel']:.0%} relative"]
    header = f"{'step [s]':>9} {'group':<9}" + "".join(f"{n:>13}" for n in names)
    for c, comp in r["comparisons"].items():
        m = comp["members"]
        lines += ["", f"candidate {c:g} s: {m['random']} random networks, {m['scripted']} "
                      f"scripted, {m['evolved']} evolved at {c:g} s", header, "-" * len(header)]
        for dt, s in comp["steps"].items():
            for group, stats in s["statistics"].items():
                lines.append(f"{dt:>9g} {group:<9}"
                             + "".join(f"{stats[n]:>13.4f}" for n in names))
        bad = [f"{g}:{k}" for g, checks in comp["checks"].items() for k, v in checks.items()
               if not v["ok"]]
        panel_diffs = ", ".join(
            f"{k} {v['diff']:+.3f}" for k, v in comp["checks"]["panel"].items())
        lines.append(f"{c:g} s vs {comp['quarter']:g} s: "
                     f"{'AGREES' if comp['agrees'] else 'differs'} (panel: {panel_diffs})")
        if bad:
            lines.append(f"    outside tolerance: {', '.join(bad)}")
        lines.append(f"    open-loop hand tracking vs {r['reference_dt']:g} s: max "
                     f"{comp['tracking_max_m'] * 100:.2f} cm, mean "
                     f"{comp['tracking_mean_m'] * 100:.2f} cm")
        rtf = [comp["steps"][dt]["rtf_per_core"] for dt in (c, comp["quarter"])]
        lines.append(f"    {rtf[0]:.0f} vs {rtf[1]:.0f} simulated s per core s "
                     f"({comp['cost_ratio']:.1f}x the throughput of the quarter step)")
    lines.append("")
    lines.append(f"chosen: {r['chosen']:g} s" if r["chosen"] is not None
                 else "chosen: none of the candidates agrees with its quarter step")
    return "\n".join(lines)
