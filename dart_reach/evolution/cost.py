"""What a training run costs: known before it starts (``dart-reach train`` announces it for a
long run: generations to train and core-hours, from the benchmarked cost of one generation),
and measured on its own generations afterwards (``measured_cost``)."""

from __future__ import annotations

import json
import shlex
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import polars as pl

from .conditions import Condition
from .ga import Scheme
from .settings import Settings

#: Core-seconds of one replication-generation at the paper's budget (20 genotypes, steady
#: state: 40 lifetimes of 18 trials of 200 control steps, the shipped evolved robots), low and
#: high: ``dart-reach bench``'s ``generation_core_s`` on the project's reference machine, the
#: figure docs/results/benchmarks.md ("What a run costs") gives with the runs and the command
#: that measured it. ``cost_estimate`` takes a machine's own (``bench_core_s``: from a
#: ``dart-reach bench --json`` file).
GENERATION_CORE_S = (43.0, 44.7)


@dataclass(frozen=True)
class CostEstimate:
    """The size of a training run: ``replication_generations`` (generations of every phase
    trained, a phase shared by conditions once, times replications) and ``core_hours`` (low,
    high), from ``GENERATION_CORE_S`` scaled by lifetimes, trials and steps."""

    replication_generations: int
    core_hours: tuple[float, float]


def cost_estimate(conditions: list[Condition], settings: Settings,
                  generation_core_s: tuple[float, float] = GENERATION_CORE_S) -> CostEstimate:
    """How much training ``conditions`` under ``settings`` costs (see ``CostEstimate``) at
    ``generation_core_s`` (low, high) core-seconds per replication-generation of the paper's
    budget (default: the reference machine's, ``GENERATION_CORE_S``): the cost of a
    generation is taken proportional to lifetimes x trials x steps, and evolved robots (which
    touch the ball) cost more than the random networks a run starts from, so it is an
    upper-side estimate for short runs."""
    phases = {p.key: p for c in conditions for p in c.phases}
    rep_gens = sum(p.generations for p in phases.values()) * settings.replications
    lifetimes = settings.ga.population * (2 if settings.ga.scheme is Scheme.STEADY_STATE
                                          else 1)
    scale = lifetimes / 40 * settings.trials / 18 * settings.steps / 200
    return CostEstimate(rep_gens, tuple(rep_gens * scale * s / 3600 for s in generation_core_s))


def bench_core_s(path) -> tuple[float, float]:
    """The core-seconds of one replication-generation that a ``dart-reach bench --json PATH``
    run measured on its machine (its ``generation_core_s``), as ``cost_estimate`` takes them
    (low = high); ``ValueError`` when the file holds no such figure."""
    results = json.loads(Path(path).read_text(encoding="utf-8"))
    value = results.get("generation_core_s") if isinstance(results, dict) else None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
        raise ValueError(f"{path}: no generation_core_s of 'dart-reach bench --json' in it")
    return float(value), float(value)


def session_workers(session: dict, manifest: dict) -> int | None:
    """The workers a training session ran on: as the session recorded them, or, for a session
    of a version that did not record them and whose command gave neither ``--workers`` nor
    ``--ray``, the default, every core of the machine the manifest names; None when unknown."""
    if session.get("workers"):
        return int(session["workers"])
    words = shlex.split(session.get("command") or "")
    if "--workers" in words or "--ray" in words:
        return None
    return manifest.get("machine", {}).get("cores")


def core_seconds(run) -> pl.DataFrame:
    """One row per generation trained in the run directory ``run`` (a ``RunDirectory``):
    condition, phase, generation, ``wall_s`` (one generation of every replication,
    ``generations.parquet``), ``session`` (the index in the manifest's ``sessions`` of the
    session that trained it: the last one started before it) and ``core_s``, the core-seconds
    of one replication-generation, wall_s x the session's workers / replications (NaN where
    the workers are unknown). Cores shared with other work count as the run's."""
    manifest = json.loads((run.out / "manifest.json").read_text(encoding="utf-8"))
    sessions = manifest.get("sessions", [])
    frames = [pl.DataFrame(schema={"condition": pl.Utf8, "phase": pl.Utf8,
                                   "generation": pl.Int64, "wall_s": pl.Float64,
                                   "session": pl.Int64, "core_s": pl.Float64})]
    for condition, phase in run.unique_phases():
        walls = (run.stats.filter(pl.col("phase_key") == phase.key)
                 .group_by("generation").agg(pl.col("wall_s").first()).sort("generation"))
        name = f"{condition.name}/{phase.name}"
        starts = np.array([s.get("generations_done", {}).get(name, 0) for s in sessions])
        owner = [int(np.nonzero(starts < g)[0].max()) if (starts < g).any() else -1
                 for g in walls["generation"]]
        workers = [np.nan if k < 0 else (session_workers(sessions[k], manifest) or np.nan)
                   for k in owner]
        frames.append(walls.select(
            pl.lit(condition.name).alias("condition"), pl.lit(phase.name).alias("phase"),
            pl.col("generation").cast(pl.Int64), pl.col("wall_s"),
            pl.Series("session", owner, dtype=pl.Int64),
            (pl.col("wall_s") * pl.Series(workers, dtype=pl.Float64)
             / run.settings.replications).alias("core_s")))
    return pl.concat(frames)


def measured_cost(run) -> pl.DataFrame:
    """What each phase of the run directory ``run`` cost (``core_seconds``): one row per
    phase trained, with ``generations`` committed, ``sessions`` (how many sessions trained
    some of them), ``wall_h`` (hours) and the quartiles of its core-seconds per
    replication-generation, ``core_s_min``, ``core_s_q1``, ``core_s_median``, ``core_s_q3``.
    The upper quartile shows the hours the cores were shared with other work."""
    per = core_seconds(run)
    return (per.group_by("condition", "phase", maintain_order=True).agg(
        pl.len().alias("generations"),
        pl.col("session").filter(pl.col("session") >= 0).n_unique().alias("sessions"),
        (pl.col("wall_s").sum() / 3600).alias("wall_h"),
        *(pl.col("core_s").drop_nans().quantile(q, "linear").alias(name)
          for q, name in ((0.0, "core_s_min"), (0.25, "core_s_q1"), (0.5, "core_s_median"),
                          (0.75, "core_s_q3")))))
