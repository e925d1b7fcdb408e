"""Eq. 5's fitness taken apart trial by trial: a run's post-evaluated pre-reachers run again.

``build`` runs the 45 systematic trials (normal senses) of every pre-reaching robot that a
run's post-evaluation evaluated (the robots of its evaluation.parquet; or, with
``generation``, those of that snapshot that its development.parquet post-evaluated) in one
process, one row per trial with ``measures.fitness.fitness_terms``; a run's table of them is
``TABLE`` in its directory, stored as the post-evaluation's tables are
(``postevaluation.results``: zstd, float32, the session that wrote it, ``SNAPSHOT_KEY`` the
rows of one snapshot's robot). ``analysis.strategies`` averages the rows per strategy.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import polars as pl

from ..analysis import strategies
from ..evolution.backends import worker_trial
from ..evolution.genome import as_groups, decode
from ..evolution.rundir import RunDirectory
from ..measures.fitness import trial_fitness_terms
from ..model.task import network_for
from ..model.world import POINTS_PER_SECTOR
from ..postevaluation import results
from ..postevaluation.snapshots import load_development
from ..postevaluation.systematic import stored_robot_job

#: The table's name in a run directory.
TABLE = "fitness-terms.parquet"
#: A snapshot's rows: one robot of one generation.
SNAPSHOT_KEY = ("generation", "replication", "rank")


def pre_phase_key(run: RunDirectory, condition: str | None = None) -> str:
    """The key of the pre-reaching phase (the phase named ``pre``) that ``run`` trained: its
    ``condition``'s (a condition's name), or by default the run's one pre-reaching phase
    (conditions that share it count once); ValueError when there is none, or several and no
    ``condition`` chooses."""
    found = {c.name: p.key for c in run.conditions for p in c.phases if p.name == "pre"}
    if condition is not None:
        if condition not in found:
            raise ValueError(f"{run.out}: condition {condition!r} has no pre-reaching phase "
                             f"(conditions with one: {sorted(found) or 'none'})")
        return found[condition]
    if len(set(found.values())) != 1:
        raise ValueError(f"{run.out}: no single pre-reaching phase to take apart "
                         f"(conditions with one: {sorted(found) or 'none'}); name the "
                         f"condition")
    return next(iter(found.values()))


def robot_trials(run: RunDirectory, replication: int, rank: int,
                 positions: int | None = None, generation: int | None = None,
                 condition: str | None = None) -> list[dict]:
    """One row per systematic trial of a pre-reacher of ``run``'s final population (its
    ``replication`` and ``rank``; ``generation``: of that generation's snapshot; of the
    pre-reaching phase of ``pre_phase_key(run, condition)``) under normal senses, run as the
    post-evaluation runs it (``systematic.run_robot``): who, where, ``fitness_terms``;
    ``positions``: only the first so many of the 45 (a check)."""
    job = stored_robot_job(run, pre_phase_key(run, condition), "normal", replication, rank,
                           generation=generation)
    runner = worker_trial(job.world, job.trial)
    network = network_for(decode(job.genome, as_groups(job.phase.free_groups)), job.trial)
    rows = []
    for k, position in enumerate(runner.world.systematic_points()[:positions]):
        sector = k // POINTS_PER_SECTOR
        data = runner.run(network, sector, position)
        rows.append({"phase": "pre", "replication": replication, "rank": rank, "trial": k,
                     "sector": sector, **trial_fitness_terms(data, job.world.control_dt)})
    return rows


def evaluated_pre(run_dir: Path) -> list[tuple[int, int]]:
    """The (replication, rank) of every trained pre-reacher in ``run_dir``'s
    evaluation.parquet, sorted."""
    table = strategies.trained_trials(results.read_table(run_dir / results.EVALUATION))
    return sorted(table.select("replication", "rank").unique().iter_rows())


def snapshot_pre(run_dir: Path, generation: int) -> list[tuple[int, int]]:
    """The (replication, rank) of every pre-reacher of the snapshot of ``generation`` that
    ``run_dir``'s development.parquet post-evaluated under normal senses, sorted; ValueError
    when there is none."""
    table = load_development(run_dir)
    rows = (pl.DataFrame() if table is None else
            table.filter((pl.col("phase") == "pre") & (pl.col("generation") == generation)))
    if not rows.height:
        raise ValueError(f"{run_dir}: no pre-reaching snapshot of generation {generation} "
                         f"post-evaluated (dart-reach evaluate RUN --finished-only "
                         f"--development 5)")
    return sorted(rows.select("replication", "rank").unique().iter_rows())


def build(run_dir: Path, progress=print, generation: int | None = None,
          condition: str | None = None) -> pl.DataFrame:
    """Every post-evaluated pre-reacher of the run in ``run_dir`` (``evaluated_pre``;
    ``generation``: of that snapshot, ``snapshot_pre``, with ``generation`` in each row): its
    trials (``robot_trials``; ``condition``: whose pre-reaching phase, ``pre_phase_key``),
    one table."""
    robots_ = (evaluated_pre(run_dir) if generation is None
               else snapshot_pre(run_dir, generation))
    run = RunDirectory.open(run_dir)
    more = {} if generation is None else {"generation": generation}
    rows = []
    for i, (replication, rank) in enumerate(robots_):
        rows += [dict(row, **more) for row in robot_trials(run, replication, rank,
                                                           generation=generation,
                                                           condition=condition)]
        progress(f"{i + 1}/{len(robots_)} replication {replication} rank {rank}")
    return pl.DataFrame(rows)


def missing(run_dir: Path, generations: Sequence[int]) -> list[int]:
    """The ``generations`` whose snapshot ``run_dir``'s development.parquet post-evaluated and
    its Eq. 5 table (``TABLE``) does not yet hold, in order."""
    development = load_development(run_dir)
    done = results.read_table(run_dir / TABLE)
    there = (set() if development is None else
             set(development.filter(pl.col("phase") == "pre")["generation"].unique()))
    held = set() if done is None else set(done["generation"].unique())
    return [g for g in generations if g in there and g not in held]


def by_snapshot(run_dir: Path) -> dict[int, dict[str, pl.DataFrame]]:
    """Per snapshot generation in a run's Eq. 5 table (``build(..., generation=G)``'s rows):
    ``by_strategy`` and ``compare`` (``analysis.strategies``; None when one strategy has every
    population), each population's strategy by ``strategies.strategies``'s rule from the
    snapshot's normal trials in development.parquet; empty without the table."""
    terms = results.read_table(run_dir / TABLE)
    if terms is None:
        return {}
    development = load_development(run_dir)
    out = {}
    for generation in terms["generation"].unique().sort().to_list():
        strategy = strategies.strategies(
            development.filter(pl.col("generation") == generation))
        trials = strategies.with_strategy(terms.filter(pl.col("generation") == generation),
                                         strategy)
        both = strategy["strategy"].n_unique() == 2
        out[generation] = {"by_strategy": strategies.by_strategy(trials),
                           "compare": strategies.compare(strategies.by_replication(
                               trials, strategy)) if both else None}
    return out
