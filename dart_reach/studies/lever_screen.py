"""Screening the model's levers without training (docs/model/levers.md).

A run's robots, as a snapshot kept them at one generation, are run again on the 45 systematic
positions under other levers (another scene, self-collision, another network start, the reflex
motors' evolved inputs) and measured as the post-evaluation measures them
(``metrics.trial_metrics``); every trial is also scored again under each touch pay
(``fitness.fitness_under_touch_pays``), so the touch lever needs no run of its own. What a
screen shows is what the lever does to robots evolved without it: a prediction of the
direction a training under the lever starts in, not its result.

One row per (arm, senses, replication, rank, trial), with ``arm`` the name given to the
lever setting, ``levers`` what it changes (JSON) and the robot's generation.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import polars as pl

from ..evolution.backends import make_backend, worker_trial
from ..evolution.genome import as_groups, decode
from ..evolution.rundir import RunDirectory
from ..evolution.settings import trial_config
from ..errors import UsageError
from ..files import atomic_write
from ..measures.fitness import fitness_under_touch_pays
from ..measures.metrics import trial_metrics
from ..model.levers import Levers
from ..model.scenes import scene_of
from ..model.task import Senses, TrialConfig, network_for
from ..model.world import POINTS_PER_SECTOR, WorldConfig

#: The key of a screen table's rows.
KEY = ("arm", "senses", "replication", "rank", "trial")


@dataclass(frozen=True)
class Arm:
    """A lever setting to screen: a name, the world (scene, self-collision) and the trial's
    levers."""

    name: str
    world: WorldConfig
    levers: Levers

    def describe(self, base: WorldConfig) -> dict:
        """What the arm changes from ``base`` and version 1's levers."""
        d = dict(self.levers.changed())
        if self.world.sectors != base.sectors:
            d["scene"] = scene_of(self.world.sectors) or f"radius {self.world.sectors.radius} m"
        if self.world.self_collision != base.self_collision:
            d["self_collision"] = "on" if self.world.self_collision else "off"
        return d


@dataclass(frozen=True)
class _Job:
    arm: str
    replication: int
    rank: int
    genome: np.ndarray
    free_groups: tuple
    trial: TrialConfig
    world: WorldConfig


def _run(job: _Job) -> list[dict]:
    runner = worker_trial(job.world, job.trial)
    world = runner.world
    network = network_for(decode(job.genome, as_groups(job.free_groups)), job.trial)
    ranges = world.motor_limit_upper - world.motor_limit_lower
    rows = []
    for k, position in enumerate(world.systematic_points()):
        data = runner.run(network, k // POINTS_PER_SECTOR, position)
        rows.append({"arm": job.arm, "senses": job.trial.senses.value,
                     "replication": job.replication, "rank": job.rank, "trial": k,
                     **trial_metrics(data, job.world.control_dt, job.world.ball.radius, ranges),
                     **fitness_under_touch_pays(data)})
    return rows


def screen(run_dir, generation: int, arms: list[Arm], phase: str = "pre", robots: int = 2,
           senses: tuple[str, ...] = ("normal", "no-ball"), workers: int | None = None,
           only=None) -> pl.DataFrame:
    """The best ``robots`` of every replication of ``phase`` at ``generation`` (a snapshot of
    the run in ``run_dir``) run on the 45 positions under each arm and each of ``senses``:
    one row per trial (the module's docstring). ``only``: a collection of (replication, rank)
    pairs, the robots to run among those (default all). Same input, same table, whatever
    ``workers``."""
    run = RunDirectory.open(run_dir)
    found = [(c, p) for c, p in run.unique_phases() if p.name == phase]
    if not found:
        raise ValueError(f"{run.out} has no phase {phase!r}")
    ph = found[0][1]
    snaps = {g: genomes for g, genomes, _ in run.snapshots(ph)}
    if generation not in snaps:
        raise ValueError(f"{run.out}: no snapshot of {phase} at generation {generation} "
                         f"(snapshots: {', '.join(map(str, sorted(snaps))) or 'none'})")
    genomes = snaps[generation]
    if not 1 <= robots <= genomes.shape[1]:
        raise ValueError(f"robots must be 1-{genomes.shape[1]} (the snapshot's), got {robots}")
    names = [a.name for a in arms]
    if len(set(names)) != len(names):
        raise ValueError(f"arm names must differ, got {names}")
    jobs = []
    for arm in arms:
        base = trial_config(ph, replace(run.settings, levers=arm.levers))
        for s in senses:
            trial = replace(base, senses=Senses(s))
            jobs += [_Job(arm.name, r, i, genomes[r, i], ph.free_groups, trial, arm.world)
                     for r in range(genomes.shape[0]) for i in range(robots)
                     if only is None or (r, i) in only]
    backend = make_backend(workers)
    try:
        rows = [row for job_rows in backend.imap(_run, jobs) for row in job_rows]
    finally:
        backend.close()
    described = {a.name: json.dumps(a.describe(run.settings.world), sort_keys=True) for a in arms}
    return (pl.DataFrame(rows)
            .with_columns(pl.col("arm").replace_strict(described).alias("levers"),
                          pl.lit(generation).alias("generation"), pl.lit(phase).alias("phase"))
            .sort(list(KEY)))


def check_screen_table(path, run_dir=None) -> Path:
    """``path`` where a screen table may be written or added to, checked before anything is
    screened: a name ending in .parquet in a directory that exists, outside the run
    ``run_dir`` (its files are the run's), and where it exists a screen table (``KEY``'s
    columns). Anything else is refused (``UsageError``): nothing is overwritten."""
    path = Path(path)
    if path.suffix.lower() != ".parquet" or path.is_dir():
        raise UsageError(f"out {path}: a screen table is a .parquet file",
                         cli=f"--out {path}: a screen table is a .parquet file")
    if not path.parent.is_dir():
        raise FileNotFoundError(f"{path}: no such directory {path.parent}; create it first")
    if run_dir is not None and Path(run_dir).resolve() in path.resolve().parents:
        raise UsageError(f"{path}: inside the run {run_dir}; write the screen table elsewhere")
    if path.exists():
        try:
            columns = pl.read_parquet_schema(path)
        except Exception:  # polars says why in many lines: one is enough here
            columns = {}
        if not set(KEY) <= set(columns):
            raise UsageError(f"{path}: not a screen table (no columns {', '.join(KEY)}); "
                             f"choose another (nothing is overwritten)")
    return path


def save_screen(table: pl.DataFrame, path: Path) -> pl.DataFrame:
    """Add ``table``'s arms to the screen table at ``path`` (zstd parquet; ``check_screen_table``),
    replacing the rows of arms screened again; the combined table, written atomically."""
    path = check_screen_table(path)
    if path.exists():
        old = pl.read_parquet(path)
        table = pl.concat([old.filter(~pl.col("arm").is_in(table["arm"].unique().implode())),
                           table], how="diagonal_relaxed").sort(list(KEY))
    atomic_write(path, lambda p: table.write_parquet(p, compression="zstd"))
    return table
