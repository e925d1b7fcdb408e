"""What a campaign costs where it runs: a generation of a late, contact-heavy population timed
as a run counts it, the genetic algorithm's control step besides the physics part by part
(``loop_parts``), and a generation on a Ray cluster measured on local nodes and projected to
a cluster's size (``dart-reach bench``; docs/guides/cluster.md, "Blocks"; the figures measured
here: docs/results/benchmarks.md, "Scaling").
"""

from __future__ import annotations

import math
import time
from typing import Sequence

import numpy as np
import polars as pl

from .. import robots
from ..evolution.backends import (Job, LocalRayCluster, MapCost, PoolBackend, RayBackend,
                                  ray_block)
from ..evolution.conditions import load_condition
from ..evolution.genome import ParamGroup, as_groups, decode
from ..evolution.settings import Settings, standard_trial, trial_config
from ..model.compiled import control_step
from ..model.compiled_trial import entry_point
from ..model.task import Trial, network_for
from ..model.versions import CURRENT_MODEL_VERSION, numerics_of
from ..model.versions import model_version as version_record  # a parameter is model_version
from ..model.world import World
from . import bench
from .bench import ratio


def late_robots() -> list:
    """The late population: the shipped pre-reachers of the standard condition that trained
    longest (``robots.index``: the file whose budget has the most generations; today the best
    2 of each replication of the paper-budget run at generation 250), robots that sweep and
    touch as an evolved population does, so that contacts weigh in the cost as they will in a
    campaign."""
    rows = [r for r in robots.index() if (r["condition"], r["phase"]) == ("standard", "pre")]
    latest = max(rows, key=lambda r: r["budget"]["generations"])
    return robots.robots("pre", run=latest["run"])


def late_generation(model_version: int, seed: int = 0, trials: int = 18, steps: int = 200
                    ) -> list[Job]:
    """A replication-generation of the late population as the genetic algorithm runs it: its
    20 genomes evaluated twice (40 lifetimes) of ``trials`` trials of ``steps`` steps (the
    paper's 18 of 200), at the GA's positions, under ``model_version`` (its numerics, levers
    and scene)."""
    phase = load_condition("standard").phases[0]
    settings = Settings(model_version=model_version, trials=trials, steps=steps)
    trial = trial_config(phase, settings)
    genomes = [r.genome for r in late_robots()]
    return [Job(genomes[i % len(genomes)], as_groups(phase.free_groups), trial,
                settings.world, (seed, 0, i)) for i in range(2 * len(genomes))]


def late_population(versions: Sequence[int] = (1, 2, 3), rounds: int = 3,
                    workers: int | None = None, trials: int = 18, steps: int = 200) -> dict:
    """What the campaign pays: a replication-generation of the late population through the
    local pool on every core, timed as a run counts it (wall time x workers, the core-seconds
    of generations.parquet's ``wall_s``), under each of ``versions`` in ``rounds`` rounds, the
    order reversed every other round: ``late_generation_core_s_v<N>`` (median) and
    ``numerics_speedup_late`` (version 1's time over version 2's in the same round: the same
    robots, scene and trials, only the numerics differ)."""
    pool = PoolBackend(workers)
    times = {v: [] for v in versions}
    try:
        batches = {v: late_generation(v, trials=trials, steps=steps) for v in versions}
        for v in versions:
            pool.map(batches[v][:pool.workers])  # worlds built and code compiled in every worker
        for k in range(rounds):
            for v in (versions if k % 2 == 0 else versions[::-1]):
                t0 = time.perf_counter()
                pool.map(batches[v])
                times[v].append((time.perf_counter() - t0) * pool.workers)
    finally:
        pool.close()
    out = {f"late_generation_core_s_v{v}": float(np.median(t)) for v, t in times.items()}
    if 1 in times and 2 in times:
        out.update(ratio("numerics_speedup_late", np.array(times[1]) / np.array(times[2])))
    return out


def ray_scaling(nodes: Sequence[int] = (2, 4), blocks: Sequence[int | None] = (1, 18, None),
                lifetimes: int = 10, model_version: int = CURRENT_MODEL_VERSION
                ) -> pl.DataFrame:
    """What a generation costs on local Ray clusters of ``nodes`` one-CPU nodes (one cluster
    grown to each size in turn; more nodes than cores oversubscribes them: the driver's share
    shows) in blocks of each of ``blocks``
    trials (None: ``RayBackend``'s own choice, measured on its second generation):
    ``lifetimes`` lifetimes of the late population (``late_generation``). One row per cluster
    and block: tasks, trials, the driver's CPU per task (ms), per generation (s) and over its
    wall time (``driver_busy``: the share of a core it took), a trial's
    CPU on a worker (s), the wall time (s) and the workers' idle share (1 - worker CPU /
    (wall x CPUs)). The inputs of ``project_generation``."""
    import ray

    batch = late_generation(model_version)[:lifetimes]
    rows = []
    with LocalRayCluster(nodes=1) as cluster:
        for n in sorted(set(nodes)):
            while len(cluster.nodes) < n:  # one cluster, grown: each node starts once
                cluster.add_node()
            for block in blocks:
                backend = RayBackend(cluster.address, block=block)
                try:
                    backend.map(batch[:n])  # every node's world built
                    if block is None:
                        backend.map(batch)  # its first generation: blocks of a lifetime
                    chosen = backend.block_for(batch[0].trial.trials)
                    backend.map(batch)
                finally:
                    ray.shutdown()
                c = backend.last_cost
                rows.append({"cpus": n, "block": chosen, "chosen": block is None,
                             "tasks": c.tasks, "trials": c.trials,
                             "driver_ms_per_task": 1e3 * c.driver_cpu_s / c.tasks,
                             "driver_cpu_s": c.driver_cpu_s,
                             "driver_busy": c.driver_cpu_s / c.wall_s,
                             "trial_cpu_s": c.worker_cpu_s / c.trials, "wall_s": c.wall_s,
                             "idle": 1.0 - c.worker_cpu_s / (c.wall_s * n)})
    return pl.DataFrame(rows)


def project_generation(driver_s_per_task: float, trial_s: float, cpus: int, block: int,
                       trials: int = 7200) -> dict:
    """A generation of ``trials`` trials (the paper's: 10 replications x 40 lifetimes x 18) on
    ``cpus`` workers in blocks of ``block``, from a task's driver cost and a trial's cost (s):
    the workers need trials x trial_s / cpus, the driver trials / block x driver_s_per_task
    (it submits while they run: the longer of the two sets the pace), and the generation ends
    with a tail of about one block (block x trial_s) on the last worker. ``wall_s`` and
    ``efficiency`` (the workers' share of it). The model of docs/guides/cluster.md, "Blocks"."""
    work = trials * trial_s / cpus
    driver = trials / block * driver_s_per_task
    wall = max(work, driver) + block * trial_s
    return {"cpus": cpus, "block": block, "wall_s": wall, "efficiency": work / wall,
            "driver_share": driver / wall}


def scaling_projection(measured: pl.DataFrame, cpus: Sequence[int] = (16, 64, 256),
                       trials: int = 7200, lifetime: int = 18) -> pl.DataFrame:
    """``project_generation`` at ``cpus`` from ``ray_scaling``'s measured costs (the driver's
    per task: the largest measured, oversubscribed nodes included; a trial's: the median),
    for blocks of one trial, of a lifetime, and of ``ray_block``'s choice there."""
    d = float(measured["driver_ms_per_task"].max()) / 1e3
    c = float(measured["trial_cpu_s"].median())
    rows = []
    for n in cpus:
        chosen = ray_block(MapCost(1, 1, d, c, 0.0), n, lifetime)
        for block, how in ((1, "one trial"), (lifetime, "a lifetime"), (chosen, "chosen")):
            rows.append({"how": how, **project_generation(d, c, n, block, trials),
                         "driver_ms_per_task": d * 1e3, "trial_cpu_s": c})
    return pl.DataFrame(rows)


def loop_parts(model_version: int = CURRENT_MODEL_VERSION, calls: int = 20_000,
               repeats: int = 5) -> dict:
    """What the genetic algorithm's trial does per control step besides the physics, part by
    part (µs a call, CPU time, the fastest of ``repeats`` runs of ``calls`` calls), for the
    first shipped evolved robot at its home posture in ``model_version``'s world: the compiled
    control step (``compiled.control_step``) through its entry point, as the trial calls it
    (``compiled_trial.entry_point``), and through Numba's dispatcher; the joint positions and
    the ball's centre read from DART; the collision result read after a substep (5 a control
    step); a physics substep without contact, for scale. Only the compiled numerics (versions
    2 and up) have that step."""
    world = World(version_record(model_version).world())
    cfg = standard_trial("pre", numerics=numerics_of(model_version))
    runner = Trial(world, cfg)
    network = network_for(decode(bench.panel_genomes("evolved", 1)[0], {ParamGroup.DIRECT}), cfg)
    steps = runner.steps
    steps.reset(world.sector_point(0, 0.5, 0.5))
    network.reset(motor=steps.home_motor)
    robot, ball, physics = world.robot, world.ball_body, world.world
    positions, centre, gravity = robot.getPositions(), ball.getCOM(), robot.getGravityForces()
    p = np.zeros(cfg.steps)

    def timed(fn) -> float:
        best = math.inf
        for _ in range(repeats):
            t0 = time.process_time()
            for _ in range(calls):
                fn()
            best = min(best, (time.process_time() - t0) / calls * 1e6)
        return best

    args = (0, positions, centre, gravity, steps.state, network.state, p)
    step = entry_point(control_step, *args)
    return {"control_step_us": timed(lambda: step(*args)),
            "control_step_dispatched_us": timed(lambda: control_step(*args)),
            "read_positions_us": timed(robot.getPositions),
            "read_ball_us": timed(ball.getCOM),
            "read_collisions_us": timed(lambda: physics.getLastCollisionResult()
                                        .getNumContacts()),
            "substep_us": timed(lambda: physics.step(False))}
