"""Benchmarks (``dart-reach bench``): speed figures measured as ratios within one run.

Targets are checked here, not in timed tests. Every figure is simulated seconds per wall-clock
second (real-time factor, RTF) on one core unless its name says otherwise.
"""

from __future__ import annotations

import os
import platform
import time
from importlib import metadata

import numpy as np

from .scripted import ScriptedReach
from .world import World, WorldConfig


def machine() -> dict:
    return {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "dartpy": metadata.version("dartpy"),
    }


def _grasping_world(config: WorldConfig) -> tuple[World, np.ndarray]:
    """A world whose hand holds the ball (after a scripted reach of 4 s), and the hold targets."""
    world = World(config)
    ball = world.sector_point(4, 0.5, 0.5)
    world.reset(ball)
    reach = ScriptedReach(world, ball)
    for _ in range(40):
        world.step(reach.targets(world.hand_contacts()))
    return world, reach.targets(world.hand_contacts())


def world_rtf(seconds: float = 20.0, repeats: int = 5, config: WorldConfig | None = None) -> dict:
    """``limit_rtf``: the bare physics step loop with the ball in the hand; ``controlled_rtf``:
    the same world driven by new targets every 0.1 s. Blocks of both are interleaved ``repeats``
    times and the medians compared, so that machine noise hits both alike."""
    config = config or WorldConfig()
    world, hold = _grasping_world(config)
    n_control = int(round(seconds / config.control_dt))
    n_physics = n_control * config.substeps
    # A new target vector every control step, holding the grasp: both loops then simulate the
    # same physical state, and the difference is the cost of the control interface (scaling,
    # validation, spring rest positions, gravity compensation).
    targets = np.repeat(hold[None, :], n_control, axis=0)
    limit, controlled = [], []
    for _ in range(repeats):
        step = world.world.step
        t0 = time.perf_counter()
        for _ in range(n_physics):
            step(False)
        limit.append(seconds / (time.perf_counter() - t0))
        t0 = time.perf_counter()
        for k in range(n_control):
            world.step(targets[k])
        controlled.append(seconds / (time.perf_counter() - t0))
    limit_rtf, controlled_rtf = float(np.median(limit)), float(np.median(controlled))
    return {
        "limit_rtf": limit_rtf,
        "controlled_rtf": controlled_rtf,
        "controlled_over_limit": controlled_rtf / limit_rtf,
        "ball_in_hand": bool(world.hand_contacts().any()),
    }


def closed_loop_rtf(config: WorldConfig | None = None, seed: int = 0) -> dict:
    """A whole 18-trial evaluation of a random network with every per-step record kept
    (section III-C), simulated seconds per wall second on one core."""
    from .ctrnn import random_params
    from .task import Trial, TrialConfig, evaluate

    world = World(config or WorldConfig())
    cfg = TrialConfig()
    trial = Trial(world, cfg)
    params = random_params(np.random.default_rng(seed))
    t0 = time.perf_counter()
    result = evaluate(params, world, cfg, np.random.default_rng(seed), trial)
    wall = time.perf_counter() - t0
    simulated = cfg.trials * cfg.steps * world.config.control_dt
    return {"closed_loop_rtf": simulated / wall, "closed_loop_fitness": result.fitness}


def parallel_efficiency(jobs: int = 40, trials: int = 2, seed: int = 0) -> dict:
    """Speed-up of one generation (``jobs`` evaluations of random genomes) on all cores over
    one core, divided by the number of cores. The pool is warmed up (worlds built) first."""
    from .conditions import load_condition
    from .evaluator import Job, PoolEvaluator, SerialEvaluator
    from .experiment import Settings, trial_config
    from .genome import random_genome

    phase = load_condition("standard").phases[1]
    settings = Settings(trials=trials)
    trial = trial_config(phase, settings)
    genomes = random_genome(np.random.default_rng(seed), jobs)
    batch = [Job(g, frozenset(phase.free_groups), trial, settings.world, (seed, 0, i))
             for i, g in enumerate(genomes)]
    cores = os.cpu_count() or 1
    serial, pool = SerialEvaluator(), PoolEvaluator(cores)
    try:
        pool.map(batch[:cores])
        serial.map(batch[:1])
        t0 = time.perf_counter()
        a = serial.map(batch)
        t_serial = time.perf_counter() - t0
        t0 = time.perf_counter()
        b = pool.map(batch)
        t_pool = time.perf_counter() - t0
    finally:
        pool.close()
    if not np.array_equal(a, b):
        raise RuntimeError("the pool's results differ from the serial ones")
    return {"parallel_speedup": t_serial / t_pool, "parallel_efficiency": t_serial / t_pool / cores,
            "generation_core_s": t_serial * (18 / trials) / jobs}


def recording_overhead(robots: int = 2, seed: int = 0) -> dict:
    """``recording_overhead``: wall time of a post-evaluation trial (the trial and its
    measures) plus building and writing its .rrd file, over the time of the trial alone; the
    median over the 45 systematic positions of ``robots`` random gross-reaching robots. Each
    trial is timed and then immediately recorded, so that both see the same machine load (this
    machine's speed drifts by 10-20% within seconds). ``rrd_mb_per_sim_min``: size of the
    recordings per simulated minute."""
    import tempfile
    from pathlib import Path

    from .conditions import load_condition
    from .evaluator import worker_trial
    from .experiment import Settings, trial_config
    from .genome import as_groups, decode, random_genome
    from .metrics import trial_metrics
    from .recording import RobotModel, TrialInfo, trial_rrd, write_rrd
    from .task import network_for

    settings = Settings()
    phase = load_condition("standard").phases[1]
    trial = trial_config(phase, settings)
    runner = worker_trial(settings.world, trial)
    model = RobotModel(runner.world)
    ratios, size, steps = [], 0, 0
    with tempfile.TemporaryDirectory() as tmp:
        for i, genome in enumerate(random_genome(np.random.default_rng(seed), robots)):
            network = network_for(decode(genome, as_groups(phase.free_groups)), trial)
            for k, position in enumerate(runner.world.systematic_points()):
                t0 = time.perf_counter()
                data = runner.run(network, k // 5, position)
                trial_metrics(data)
                t1 = time.perf_counter()
                info = TrialInfo("bench", phase.name, 0, i, k // 5, k, "systematic")
                path = write_rrd(Path(tmp) / f"{i}-{k}.rrd",
                                 trial_rrd(data, info, model, blueprint=False))
                t2 = time.perf_counter()
                ratios.append((t2 - t0) / (t1 - t0))
                size += path.stat().st_size
                steps += data.steps_run
    minutes = steps * settings.world.control_dt / 60
    return {"recording_overhead": float(np.median(ratios)),
            "rrd_mb_per_sim_min": size / 1e6 / minutes}


#: name -> (target, comparison) checked by ``check``; ratios are the headline figures.
TARGETS = {
    "controlled_rtf": (300.0, ">="),
    "controlled_over_limit": (0.9, ">="),
    "closed_loop_over_limit": (0.85, ">="),
    "parallel_efficiency": (0.9, ">="),
    "recording_overhead": (1.15, "<="),
}


def _meets(value: float, target: float, comparison: str) -> bool:
    return value >= target if comparison == ">=" else value <= target


def check(results: dict) -> dict[str, bool]:
    """Which targets of ``TARGETS`` the results meet."""
    return {name: _meets(results[name], *TARGETS[name]) for name in TARGETS if name in results}


def run(seconds: float = 20.0, repeats: int = 5) -> dict:
    results = {"machine": machine()}
    results.update(world_rtf(seconds, repeats))
    results.update(closed_loop_rtf())
    results["closed_loop_over_limit"] = results["closed_loop_rtf"] / results["limit_rtf"]
    results.update(parallel_efficiency())
    results.update(recording_overhead())
    results["targets_met"] = check(results)
    return results


def format_table(results: dict) -> str:
    lines = [f"{'figure':<24}{'value':>12}  target", "-" * 46]
    for name, value in results.items():
        if isinstance(value, float):
            target = TARGETS.get(name)
            mark = ""
            if target:
                mark = f"{target[1]} {target[0]:g}  " + ("met" if _meets(value, *target)
                                                         else "MISSED")
            lines.append(f"{name:<24}{value:>12.3f}  {mark}")
    m = results["machine"]
    lines.append(f"machine: {m['processor']}, {m['cores']} cores, {m['platform']}, "
                 f"Python {m['python']}, dartpy {m['dartpy']}")
    return "\n".join(lines)
