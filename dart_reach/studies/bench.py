"""Benchmarks (``dart-reach bench``): speed figures whose ratios can be trusted.

A machine's speed drifts within minutes (docs/results/benchmarks.md), so every ratio is
measured in many short back-to-back pairs, the two sides in alternating order (AB, BA, AB,
...), and reported as the median of the pairwise ratios with its interquartile range
(``<name>_iqr``): a drift of the machine hits both sides of a pair alike and cancels. Targets
are checked here, never in timed tests. A real-time factor (RTF) is simulated seconds per
wall-clock second on one core.
"""

from __future__ import annotations

import importlib.util
import os
import platform
import resource
import tempfile
import time
from importlib import metadata
from dataclasses import replace
from pathlib import Path
from typing import Callable, Sequence

import numpy as np
import polars as pl

from ..evolution.backends import (Job, LocalRayCluster, PoolBackend, RayBackend, SerialBackend,
                                  peak_rss_mb, worker_trial)
from ..evolution.conditions import load_condition
from ..evolution.genome import ParamGroup, as_groups, decode, random_genome
from ..evolution.rundir import RunDirectory
from ..evolution.settings import Settings, standard_trial, trial_config
from ..measures.metrics import trial_metrics
from ..model.versions import CURRENT_MODEL_VERSION, numerics_of
from ..model.versions import model_version as version_record  # a parameter is model_version
from ..model.scripted import ScriptedReach
from ..model.servo import Servo
from ..model.task import Trial, network_for
from ..model.world import World, WorldConfig
from ..recording import rrd
from ..recording.rrd import RobotModel, TrialInfo, trial_rrd, write_rrd
from ..robots import evolved_pre

#: Robots of the closed-loop figures: random pre-reaching networks and evolved ones.
PANEL = 5


def machine(config: WorldConfig | None = None) -> dict:
    config = config or WorldConfig()
    return {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "dartpy": metadata.version("dartpy"),
        "physics_dt": config.physics_dt,
    }


def paired(first: Callable[[], object], second: Callable[[], object], pairs: int,
           clock: Callable[[], float] = time.process_time) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) of ``first()`` and ``second()`` run back to back ``pairs`` times, in
    alternating order, so that pair i of both saw the same machine. By default the CPU time
    of this process (``time.process_time``): on an idle machine the wall time, on a busy one
    without the time other processes held the core (a training beside the bench); work in
    other processes (a pool) needs the wall time (``clock=time.perf_counter``)."""
    a, b = np.empty(pairs), np.empty(pairs)
    for i in range(pairs):
        order = ((first, a), (second, b)) if i % 2 == 0 else ((second, b), (first, a))
        for fn, out in order:
            t0 = clock()
            fn()
            out[i] = clock() - t0
    return a, b


def ratio(name: str, values) -> dict:
    """``name``: the median of pairwise ratios; ``name_iqr``: their quartiles."""
    v = np.asarray(values, float)
    return {name: float(np.median(v)),
            f"{name}_iqr": [float(np.percentile(v, 25)), float(np.percentile(v, 75))]}


# ------------------------------------------------------------------------------- physics
def _grasping_world(config: WorldConfig) -> tuple[World, Servo, np.ndarray]:
    """A world whose hand holds the ball (after a scripted reach of 4 s, stepped by the living
    model's servo), its servo and the hold targets."""
    world = World(config)
    servo = Servo(world)
    ball = world.sector_point(4, 0.5, 0.5)
    servo.reset(ball)
    reach = ScriptedReach(world, ball)
    for _ in range(40):
        servo.step(reach.targets(world.hand_contacts()))
    return world, servo, reach.targets(world.hand_contacts())


def world_rtf(config: WorldConfig | None = None, seconds: float = 2.0, pairs: int = 30) -> dict:
    """``limit_rtf``: the bare physics step loop with the ball in the hand; ``controlled_rtf``:
    the same world through the living model's servo (``Servo.step``: new targets every 0.1 s,
    touch gathered) holding the same grasp; ``controlled_over_limit``: their pairwise ratio,
    in blocks of ``seconds``."""
    config = config or WorldConfig()
    world, servo, hold = _grasping_world(config)
    n_control = int(round(seconds / config.control_dt))
    n_physics = n_control * config.substeps
    step, world_step = world.world.step, servo.step

    def limit():
        for _ in range(n_physics):
            step(False)

    def controlled():
        for _ in range(n_control):
            world_step(hold)

    t_limit, t_controlled = paired(limit, controlled, pairs)
    return {"limit_rtf": seconds / float(np.median(t_limit)),
            "controlled_rtf": seconds / float(np.median(t_controlled)),
            **ratio("controlled_over_limit", t_limit / t_controlled),
            "ball_in_hand": bool(world.hand_contacts().any())}


# ------------------------------------------------------------------------------ closed loop
def panel_genomes(kind: str, n: int = PANEL, seed: int = 0) -> np.ndarray:
    """``n`` pre-reaching genomes: ``random`` ones, or the best ``evolved`` ones shipped with
    the package (``robots.evolved_pre``: they touch the ball in most trials)."""
    if kind == "random":
        return random_genome(np.random.default_rng(seed), n)
    return evolved_pre()[0][:n]


def closed_loop(kind: str, config: WorldConfig | None = None, trials: int = 9,
                records: bool = True, model_version: int = 1) -> dict:
    """A full trial (observation, network, touch; section III-C) against the bare physics
    replaying the same targets (the same motion to the last bit), in pairs over the sector
    centres, for ``PANEL`` robots of ``kind``: with every per-step record kept
    (``Trial.run``, post-evaluation; figures ``closed_loop_*``) or, ``records`` False, only
    the fitness (``Trial.fitness``, what the genetic algorithm runs; figures
    ``training_loop_*``). Figures (suffix ``_evolved`` for evolved robots): ``*_rtf``,
    ``*_over_limit`` (physics time over the whole loop's) and ``python_us_per_control_step``
    / ``training_python_us_per_control_step`` (what the loop adds to the physics per 0.1 s
    step, µs). The trial computes with ``model_version``'s numerics in its world (its scene
    and self-collision; ``config`` replaces it); the replay commands the motors as that trial
    does (``Trial.command``)."""
    world = World(config or version_record(model_version).world())
    cfg = standard_trial("pre", numerics=numerics_of(model_version))
    runner = Trial(world, cfg)
    networks = [network_for(decode(g, {ParamGroup.DIRECT}), cfg) for g in panel_genomes(kind)]
    centres = [world.sector_point(k, 0.5, 0.5) for k in range(9)]
    closed, replay, steps = [], [], []
    for i in range(trials * len(networks)):
        network, k = networks[i % len(networks)], i % 9
        data = runner.run(network, k, centres[k])  # the targets the replay sends
        targets, n = data.targets, data.steps_run

        def whole():
            if records:
                runner.run(network, k, centres[k])
            else:
                runner.fitness(network, centres[k])

        def physics():
            _replay(runner, centres[k], targets, n)

        t_whole, t_physics = paired(whole, physics, 1) if i % 2 == 0 else \
            paired(physics, whole, 1)[::-1]
        closed.append(t_whole[0])
        replay.append(t_physics[0])
        steps.append(n)
    closed, replay, steps = map(np.asarray, (closed, replay, steps))
    suffix = "" if kind == "random" else f"_{kind}"
    loop, python = ("closed_loop", "python") if records else ("training_loop", "training_python")
    return {f"{loop}_rtf{suffix}": float(np.median(steps * world.config.control_dt / closed)),
            **ratio(f"{loop}_over_limit{suffix}", replay / closed),
            f"{python}_us_per_control_step{suffix}": float(np.median((closed - replay) / steps))
            * 1e6}


def gym_env(trials: int = 9, model_version: int = 1) -> dict:
    """The Gymnasium environment (``envs``, the ``gym`` extra) against the trial it wraps:
    the shipped evolved pre-reaching robots' networks stepped through ``ReachGraspEnv`` as
    ``envs.NetworkPolicy`` (with its reflexes off: the networks have theirs) and run by
    ``Trial.run``, the same trials to the last bit, in pairs over the sector centres.
    ``env_steps_per_s``: control steps of 0.1 s per second of one core (one process; a vector
    environment runs one per core); ``env_over_trial``: the trial's time over the
    environment's (1: the wrapper costs nothing)."""
    from ..envs import NetworkPolicy, ReachGraspEnv  # the gym extra

    env = ReachGraspEnv(phase="pre", reflexes=False, model_version=model_version)
    runner = Trial(World(env.world.config), env.config)
    networks = [network_for(decode(g, {ParamGroup.DIRECT}), replace(env.config, reflexes=True))
                for g in panel_genomes("evolved")]
    policies = [NetworkPolicy(n) for n in networks]
    centres = [env.world.sector_point(k, 0.5, 0.5) for k in range(9)]
    in_env, in_trial, steps = [], [], []
    for i in range(trials * len(networks)):
        network, policy, k = networks[i % len(networks)], policies[i % len(networks)], i % 9

        def episode():
            x, info = env.reset(options={"sector": k, "ball_position": centres[k]})
            policy.reset(info)
            over = False
            while not over:
                x, _, terminated, truncated, _ = env.step(policy(x))
                over = terminated or truncated

        def trial():
            runner.run(network, k, centres[k])

        t_env, t_trial = paired(episode, trial, 1) if i % 2 == 0 else \
            paired(trial, episode, 1)[::-1]
        in_env.append(t_env[0])
        in_trial.append(t_trial[0])
        steps.append(env.trial_data.steps_run)
    in_env, in_trial = np.asarray(in_env), np.asarray(in_trial)
    return {"env_steps_per_s": float(np.median(np.asarray(steps) / in_env)),
            **ratio("env_over_trial", in_trial / in_env)}


def env_render(frames: int = 100, width: int = 320, height: int = 240, seed: int = 0) -> dict:
    """The Gymnasium environment's ``render_mode="rgb_array"`` (``viewing.camera``, drawn in
    numpy): ``frames`` steps of random actions (drawn from ``seed``), each rendered.
    ``env_render_fps``: frames per second of one core, the median over frames of one over a
    ``render()`` call's time (quartiles beside it); ``env_render_ms``: the median time of a
    call (ms)."""
    from ..envs import ReachGraspEnv  # the gym extra

    env = ReachGraspEnv(phase="gross", render_mode="rgb_array", width=width, height=height)
    env.reset(seed=seed)
    env.action_space.seed(seed)
    env.render()  # the camera is built at the first frame
    times = []
    for _ in range(frames):
        if env.step(env.action_space.sample())[3]:
            env.reset()
        t0 = time.perf_counter()
        env.render()
        times.append(time.perf_counter() - t0)
    env.close()
    times = np.asarray(times)
    return {**ratio("env_render_fps", 1.0 / times),
            "env_render_ms": float(np.median(times)) * 1e3}


def _replay(runner: Trial, ball: np.ndarray, targets: np.ndarray, steps: int) -> None:
    """The bare physics of a trial: its first ``steps`` motor targets commanded as ``runner``
    commands them, the physics substeps run, nothing observed."""
    runner.reset(ball)
    world, command = runner.world, runner.command
    substeps, step = world.config.substeps, world.world.step
    for t in range(steps):
        command(targets[t])
        for _ in range(substeps):
            step(False)


def reference_world(config: WorldConfig | None = None) -> World:
    """The world in the configuration it had before the physics was tuned for speed:
    DART's deactivation test on. Kept to measure ``physics_speedup`` against, and to test
    that the tuning changes no result."""
    world = World(config or WorldConfig())
    options = world.world.getDeactivationOptions()
    options.mEnabled = True
    world.world.setDeactivationOptions(options)
    return world


def physics_speedup(config: WorldConfig | None = None, trials: int = 45) -> dict:
    """``physics_speedup``: the physics of evolved robots' trials (their motor targets
    replayed) in the reference configuration over the same in this world's, in pairs, one
    trial each side."""
    config = config or WorldConfig()
    world, reference = World(config), reference_world(config)
    cfg = standard_trial("pre")
    runner = Trial(world, cfg)
    networks = [network_for(decode(g, {ParamGroup.DIRECT}), cfg)
                for g in panel_genomes("evolved")]
    ratios = []
    for i in range(trials):
        k = i % 9
        ball = world.sector_point(k, 0.5, 0.5)
        data = runner.run(networks[i % len(networks)], k, ball)
        old, new = (lambda r=r: _replay(r, ball, data.targets, data.steps_run)
                    for r in (Trial(reference, cfg), runner))
        t_ref, t_new = paired(old, new, 1) if i % 2 == 0 else paired(new, old, 1)[::-1]
        ratios.append(t_ref[0] / t_new[0])
    return ratio("physics_speedup", ratios)


# --------------------------------------------------------------------------------- parallel
def _generation(kind: str, jobs: int, trials: int, seed: int, model_version: int = 1) -> list:
    """The jobs of one pre-reaching generation of ``jobs`` lifetimes of ``trials`` trials,
    under ``model_version``'s whole model (numerics, scene, self-collision)."""
    phase = load_condition("standard").phases[0]
    trial = trial_config(phase, Settings(trials=trials, model_version=model_version))
    genomes = panel_genomes(kind, PANEL, seed)
    return [Job(genomes[i % len(genomes)], as_groups(phase.free_groups), trial,
                version_record(model_version).world(),
                (seed, 0, i)) for i in range(jobs)]


def ray_efficiency(jobs: int = 40, trials: int = 2, pairs: int = 5, seed: int = 0) -> dict:
    """``ray_efficiency``: a generation on a local cluster of two Ray nodes of one CPU each
    (``LocalRayCluster``: real ``ray start`` nodes) against the same on a pool of two local
    processes, in pairs (pool time over Ray time). Results must be identical."""
    import ray

    batch = _generation("evolved", jobs, trials, seed)
    pool = PoolBackend(2)
    try:
        with LocalRayCluster(nodes=2) as cluster:
            try:
                t_pool, t_ray = _time_backends(pool, RayBackend(cluster.address), batch,
                                               pairs, warm=2)
            finally:
                ray.shutdown()
    finally:
        pool.close()
    return ratio("ray_efficiency", t_pool / t_ray)


def _time_backends(a, b, batch: list, pairs: int, warm: int) -> tuple:
    """Wall times of back-ends ``a`` and ``b`` on ``batch`` in ``pairs`` alternating pairs,
    after ``warm`` jobs on each (worlds built in every worker); their results must agree."""
    a.map(batch[:warm])
    b.map(batch[:warm])
    results = {}
    t_a, t_b = paired(lambda: results.__setitem__("a", a.map(batch)),
                      lambda: results.__setitem__("b", b.map(batch)), pairs,
                      clock=time.perf_counter)
    if not np.array_equal(results["a"], results["b"]):
        raise RuntimeError(f"{type(b).__name__}'s results differ from {type(a).__name__}'s")
    return t_a, t_b


def parallel(kind: str = "evolved", jobs: int = 40, trials: int = 2, pairs: int = 10,
             seed: int = 0) -> dict:
    """One generation of ``jobs`` lifetimes (``trials`` trials of 20 s) on one core and on
    every core, in pairs: ``parallel_efficiency`` = speed-up / cores (median of the pairs);
    ``generation_core_s``: core-seconds of one replication-generation of the paper (40
    lifetimes of 18 trials) from the serial time; peak memory of the workers and of this
    process (MB). Results must be identical on both sides."""
    batch = _generation(kind, jobs, trials, seed)
    cores = os.cpu_count() or 1
    serial, pool = SerialBackend(), PoolBackend(cores)
    try:
        t_serial, t_pool = _time_backends(serial, pool, batch, pairs, warm=cores)
        worker_mb = max(pool.imap(peak_rss_mb, range(4 * cores)))
    finally:
        pool.close()
    suffix = "" if kind == "evolved" else f"_{kind}"
    return {**ratio(f"parallel_efficiency{suffix}", t_serial / t_pool / cores),
            f"generation_core_s{suffix}": float(np.median(t_serial)) * (18 / trials)
            * (40 / jobs),
            "worker_peak_rss_mb": worker_mb,
            "parent_peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def numerics_speedup(jobs: int = 10, trials: int = 18, pairs: int = 5, seed: int = 0) -> dict:
    """A generation of the evolved robots (``jobs`` lifetimes of ``trials`` trials, on one
    core) under model version 1's numerics against the same under version 2's compiled
    numerics, in alternating pairs: ``numerics_speedup`` (version 1's time over version
    2's), and ``generation_core_s_v1`` and ``_v2``, the core-seconds of one replication-
    generation of the paper (40 lifetimes of 18 trials) under each;
    ``numerics_fitness_rel_diff``: the largest relative difference of a lifetime's fitness
    between the two (the same equations: their trials part only as rounding differences grow
    in a chaotic system)."""
    serial = SerialBackend()
    batches = [_generation("evolved", jobs, trials, seed, version) for version in (1, 2)]
    for batch in batches:
        serial.map(batch[:1])  # each version's world and trial built, its code compiled
    results = {}
    t1, t2 = paired(lambda: results.__setitem__(1, np.asarray(serial.map(batches[0]))),
                    lambda: results.__setitem__(2, np.asarray(serial.map(batches[1]))), pairs)
    scale = (18 / trials) * (40 / jobs)
    diff = np.abs(results[1] - results[2]) / np.maximum(np.abs(results[1]), 1e-12)
    return {**ratio("numerics_speedup", t1 / t2),
            "generation_core_s_v1": float(np.median(t1)) * scale,
            "generation_core_s_v2": float(np.median(t2)) * scale,
            "numerics_fitness_rel_diff": float(diff.max())}


# -------------------------------------------------------------------------------- a run's trials
def trial_cost(run_dir, generations: Sequence[int]) -> pl.DataFrame:
    """What the genetic algorithm's trial (``Trial.fitness``, section III-C) costs for a run's
    own robots on this machine: CPU seconds per trial of each replication's best robot at the
    first phase's snapshots of ``generations``, and of the whole population at its last
    committed generation (``robots`` "population"). Whether a run's generations grow dearer
    as it evolves, apart from the machine. Each robot runs one trial per sector centre (the
    population: one trial a genome, sectors in turn); the robots of a replication are timed
    back to back, the generations in alternating order, so that a drift of the machine hits
    them alike. One row per robots and replication: ``robots`` ("gen G" or "population"),
    ``replication``, ``trials``, ``cpu_s`` (median CPU seconds a trial)."""
    run = RunDirectory.open(run_dir)
    _, phase = run.unique_phases()[0]
    trial = trial_config(phase, run.settings)
    runner = worker_trial(run.settings.world, trial)
    centres = runner.world.systematic_points()[2::5]  # the middle position of each sector
    snapshots = {g: genomes[:, 0] for g, genomes, _ in run.snapshots(phase) if g in generations}
    missing = sorted(set(generations) - snapshots.keys())
    if missing:
        raise ValueError(f"{run_dir}: no snapshot of generation(s) {missing}")
    found = run.load_checkpoint(phase)
    groups = as_groups(phase.free_groups)

    def timed(genome, positions) -> list[float]:
        network = network_for(decode(genome, groups), trial)
        out = []
        for position in positions:
            t0 = time.process_time()
            runner.fitness(network, position)
            out.append(time.process_time() - t0)
        return out

    rows = []
    for rep in range(run.settings.replications):
        order = sorted(snapshots) if rep % 2 == 0 else sorted(snapshots, reverse=True)
        for g in order:
            cost = timed(snapshots[g][rep], centres)
            rows.append({"robots": f"gen {g}", "replication": rep, "trials": len(cost),
                         "cpu_s": float(np.median(cost))})
        if found is not None:
            genomes = found[0][rep].genomes
            cost = [timed(g, [centres[i % len(centres)]])[0] for i, g in enumerate(genomes)]
            rows.append({"robots": "population", "replication": rep, "trials": len(cost),
                         "cpu_s": float(np.median(cost))})
    return pl.DataFrame(rows)


# -------------------------------------------------------------------------------- recording
def _gross_recorded(model_version: int):
    """The recording benchmarks' trial: the standard condition's gross-reaching phase under
    ``model_version`` (settings, phase, trial config, its trial runner, the robot's drawing
    model)."""
    settings = Settings(model_version=model_version)
    phase = load_condition("standard").phases[1]
    trial = trial_config(phase, settings)
    runner = worker_trial(settings.world, trial)
    return settings, phase, trial, runner, RobotModel(runner.world)


def recording_overhead(robots: int = 2, seed: int = 0, model_version: int = 1) -> dict:
    """``recording_overhead``: the CPU time of this process (its threads included) for a
    post-evaluation trial (the trial and its measures) plus building and writing its .rrd
    file, over the time of the trial alone; the
    median over the 45 systematic positions of ``robots`` random gross-reaching robots. Each
    trial is timed and then immediately recorded, so that both see the same machine load.
    ``rrd_mb_per_sim_min``: size of the recordings per simulated minute."""
    settings, phase, trial, runner, model = _gross_recorded(model_version)
    ratios, size, steps = [], 0, 0
    with tempfile.TemporaryDirectory() as tmp:
        for i, genome in enumerate(random_genome(np.random.default_rng(seed), robots)):
            network = network_for(decode(genome, as_groups(phase.free_groups)), trial)
            for k, position in enumerate(runner.world.systematic_points()):
                t0 = time.process_time()  # CPU time: Rerun's encoding threads count too
                data = runner.run(network, k // 5, position)
                measures = trial_metrics(data)
                t1 = time.process_time()
                info = TrialInfo("bench", phase.name, 0, i, k // 5, k, "systematic")
                path = write_rrd(Path(tmp) / f"{i}-{k}.rrd", trial_rrd(
                    data, info, model, blueprint=False, measures=measures))
                t2 = time.process_time()
                ratios.append((t2 - t0) / (t1 - t0))
                size += path.stat().st_size
                steps += data.steps_run
    minutes = steps * settings.world.control_dt / 60
    return {**ratio("recording_overhead", ratios),
            "rrd_mb_per_sim_min": size / 1e6 / minutes}


def recording_parts(trials: int = 6, rounds: int = 9, seed: int = 0,
                    model_version: int = CURRENT_MODEL_VERSION) -> dict:
    """Where a trial recording's CPU time goes (``recording_overhead``'s recording, ms a
    trial, the median over ``rounds`` rounds in alternating order of ``trials`` trials of a
    random gross-reaching robot): ``rrd_ms`` the whole .rrd built (``trial_rrd``, no layout);
    of it ``rrd_chunks_ms`` its 41 chunks built (``trial_chunks``), of which
    ``rrd_rows_ms`` the time series and the scene per step (18 entities' chunks, from one
    record batch), of which ``rrd_poses_ms`` the scene's poses computed; ``rrd_write_ms`` the
    chunks written by rerun's chunk writer (``chunks_rrd``); ``rrd_rest_ms`` what these leave
    of the whole. Beside it, ``rrd_streamed_ms``: the same chunks sent through a recording
    stream instead (``streamed_rrd``, what a recording with its layout costs)."""
    settings, phase, trial, runner, model = _gross_recorded(model_version)
    network = network_for(decode(random_genome(np.random.default_rng(seed), 1)[0],
                                 as_groups(phase.free_groups)), trial)
    data = [runner.run(network, k // 5, position)
            for k, position in enumerate(runner.world.systematic_points()[:trials])]
    measures = [trial_metrics(d) for d in data]
    info = TrialInfo("bench", phase.name, 0, 0, 0, 0, "systematic")
    dt = settings.world.control_dt
    chunks = [rrd.trial_chunks(d, info, model, dt, m) for d, m in zip(data, measures)]
    parts = {
        "rrd_ms": lambda i: trial_rrd(data[i], info, model, dt, blueprint=False,
                                      measures=measures[i]),
        "rrd_chunks_ms": lambda i: rrd.trial_chunks(data[i], info, model, dt, measures[i]),
        "rrd_rows_ms": lambda i: rrd.row_chunks(data[i], model, dt, 0, data[i].steps_run),
        "rrd_poses_ms": lambda i: model.shape_poses(data[i].dofs),
        "rrd_write_ms": lambda i: rrd.chunks_rrd(info.name(), chunks[i]),
        "rrd_streamed_ms": lambda i: rrd.streamed_rrd(info.name(), chunks[i])}
    times = {name: [] for name in parts}
    for r in range(rounds):
        for name, part in (parts.items() if r % 2 == 0 else reversed(parts.items())):
            t0 = time.process_time()
            for i in range(trials):
                part(i)
            times[name].append((time.process_time() - t0) / trials * 1e3)
    out = {name: float(np.median(t)) for name, t in times.items()}
    out["rrd_rest_ms"] = out["rrd_ms"] - out["rrd_chunks_ms"] - out["rrd_write_ms"]
    return out


#: name -> (target, comparison) checked by ``check``; ratios are the headline figures.
TARGETS = {
    "physics_speedup": (1.5, ">="),
    "controlled_rtf": (300.0, ">="),
    "controlled_over_limit": (0.9, ">="),
    "closed_loop_over_limit": (0.85, ">="),
    "closed_loop_over_limit_evolved": (0.85, ">="),
    "training_loop_over_limit": (0.9, ">="),
    "training_loop_over_limit_evolved": (0.9, ">="),
    "parallel_efficiency": (0.95, ">="),
    "ray_efficiency": (0.8, ">="),
    "recording_overhead": (1.15, "<="),
    "numerics_speedup": (1.3, ">="),
    "worker_peak_rss_mb": (300.0, "<="),
    "env_render_fps": (10.0, ">="),
}


def _meets(value: float, target: float, comparison: str) -> bool:
    return value >= target if comparison == ">=" else value <= target


def check(results: dict) -> dict[str, bool]:
    """Which targets of ``TARGETS`` the results meet."""
    return {name: _meets(results[name], *TARGETS[name]) for name in TARGETS if name in results}


def run(seconds: float = 2.0, pairs: int = 30, model_version: int = CURRENT_MODEL_VERSION
        ) -> dict:
    """Every figure, in one run: ``pairs`` pairs of ``seconds`` simulated seconds for the
    physics ratio; the closed loop over 45 trials of each kind; 10 pairs of generations on the
    pool, 5 on a local Ray cluster (when the ``cluster`` extra is installed); the Gymnasium
    environment over 45 trials and its rgb_array frames (when the ``gym`` extra is). The
    trials compute with ``model_version``'s numerics (default: the version new runs use)."""
    results = {"machine": machine(), "model_version": model_version}
    results.update(world_rtf(seconds=seconds, pairs=pairs))
    results.update(physics_speedup())
    for kind in ("random", "evolved"):
        for records in (True, False):
            results.update(closed_loop(kind, records=records, model_version=model_version))
    results.update(parallel())
    results.update(numerics_speedup())
    try:
        import ray  # noqa: F401
    except ImportError:
        results["ray_efficiency_skipped"] = "Ray is not installed (the 'cluster' extra)"
    else:
        results.update(ray_efficiency())
    results.update(recording_overhead(model_version=model_version))
    if importlib.util.find_spec("gymnasium") is None:
        results["env_skipped"] = "Gymnasium is not installed (the 'gym' extra)"
    else:
        results.update(gym_env(model_version=model_version))
        results.update(env_render())
    results["targets_met"] = check(results)
    return results


def format_table(results: dict) -> str:
    lines = [f"{'figure':<34}{'value':>10}  {'quartiles':<17}  target", "-" * 78]
    for name, value in results.items():
        if isinstance(value, float):
            iqr = results.get(f"{name}_iqr")
            spread = f"{iqr[0]:.3f}-{iqr[1]:.3f}" if iqr else ""
            target = TARGETS.get(name)
            mark = ""
            if target:
                mark = f"{target[1]} {target[0]:g}  " + ("met" if _meets(value, *target)
                                                         else "MISSED")
            lines.append(f"{name:<34}{value:>10.3f}  {spread:<17}  {mark}")
    m = results["machine"]
    lines.append(f"machine: {m['processor']}, {m['cores']} cores, {m['platform']}, "
                 f"Python {m['python']}, dartpy {m['dartpy']}, physics step {m['physics_dt']} s")
    return "\n".join(lines)
