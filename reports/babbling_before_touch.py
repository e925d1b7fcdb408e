"""Babbling before the touch (``kinematics.babbling_before_touch``, the measure of babbling
validated with and without the ball: docs/results/babbling-detector.md) for every pre-reaching
trial under normal senses and with the ball absent of the committed runs on which claim A1 is
judged: the replication runs' final pre-reachers and ``FULL``'s judged snapshots.

A trial without a touch (every trial with the ball absent, and those under normal senses that
never touch the ball) is the detector on the whole trial, its committed ``babbling``; a trial
with a touch is run again from its robot's genome (the trial is deterministic: its committed
``first_touch_s`` is checked) for the hand path up to the touch. Stored as ``TABLE`` beside
each run (keys and ``babbling_before_touch``), in the run's ledger.

    python -m reports.babbling_before_touch .        # every run; resumable per run
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import polars as pl

from dart_reach import integrity
from dart_reach.evolution.backends import worker_trial
from dart_reach.evolution.genome import as_groups, decode
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.files import write_parquet
from dart_reach.measures import kinematics as k
from dart_reach.measures.contacts import first_touch
from dart_reach.model.task import network_for
from dart_reach.model.world import POINTS_PER_SECTOR
from dart_reach.postevaluation.snapshots import load_development
from dart_reach.postevaluation.systematic import load_evaluation, stored_robot_job

from .runs import FULL, JUDGED, REPLICATIONS

#: The table written beside each run.
TABLE = "babbling-before-touch.parquet"
#: The senses of claim A1's two conditions.
SENSES = ("normal", "no-ball")
#: The keys of a trial in ``TABLE`` (``generation``: null for a run's final robots).
KEYS = ("phase_key", "generation", "senses", "replication", "rank", "trial")


def trials(run_dir: Path) -> pl.DataFrame:
    """The pre-reaching trials of ``run_dir`` A1 is judged on: ``FULL``'s judged snapshots,
    else the run's final robots; ``KEYS``, ``first_touch_s`` and ``babbling``."""
    if run_dir.name == FULL:
        table = load_development(run_dir, senses=None).filter(
            pl.col("generation").is_in(JUDGED))
    else:
        table = load_evaluation(run_dir).filter(pl.col("notation") == "pre").with_columns(
            pl.lit(None, pl.Int64).alias("generation"))
    return table.filter(pl.col("senses").is_in(SENSES)).select(
        *KEYS, "first_touch_s", "babbling")


def _robot(args) -> list[tuple[int, bool, float]]:
    """(trial, babbling before the touch, first touch s) of one robot's trials ``positions``
    run again."""
    run_dir, phase_key, generation, senses, replication, rank, positions = args
    run = RunDirectory.open(run_dir)
    job = stored_robot_job(run, phase_key, senses, replication, rank, generation=generation,
                           positions=tuple(positions))
    runner = worker_trial(job.world, job.trial)
    network = network_for(decode(job.genome, as_groups(job.phase.free_groups)), job.trial)
    points = runner.world.systematic_points()
    out = []
    for trial in positions:
        data = runner.run(network, trial // POINTS_PER_SECTOR, points[trial])
        n = data.steps_run
        any_face = data.contacts if data.contacts_any is None else data.contacts_any
        end = first_touch(any_face[:n])
        out.append((trial, k.babbling_before_touch(np.asarray(data.hand[:n]), end),
                    end * job.world.control_dt if end >= 0 else math.nan))
    return out


def compute(run_dir: Path, workers: int = 1) -> pl.DataFrame:
    """``KEYS`` and ``babbling_before_touch`` of every trial of ``trials(run_dir)``: the
    committed ``babbling`` without a touch, the trial run again with one (ValueError when its
    first touch differs from the committed one)."""
    table = trials(run_dir)
    touched = table.filter(pl.col("first_touch_s").is_not_nan())
    robots = (touched.group_by("phase_key", "generation", "senses", "replication", "rank",
                               maintain_order=True).agg(pl.col("trial").sort()))
    jobs = [(run_dir, *row) for row in robots.iter_rows()]
    rows = []
    # spawned, not forked: a fork after polars' threads have run can hang the workers
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        for job, result in zip(jobs, pool.map(_robot, jobs)):
            for trial, babbling, touch in result:
                rows.append({**dict(zip(KEYS, (*job[1:6], trial))),
                             "babbling_before_touch": babbling, "rerun_touch_s": touch})
    rerun = pl.DataFrame(rows, schema={**{c: table.schema[c] for c in KEYS},
                                       "babbling_before_touch": pl.Boolean,
                                       "rerun_touch_s": pl.Float64})
    check = touched.join(rerun, on=list(KEYS), how="left", nulls_equal=True)
    off = check.filter((pl.col("rerun_touch_s") - pl.col("first_touch_s")).abs() > 1e-4)
    if off.height or check["babbling_before_touch"].null_count():
        raise ValueError(f"{run_dir}: {off.height} trials run again touch otherwise than "
                         "committed")
    untouched = table.filter(pl.col("first_touch_s").is_nan()).select(
        *KEYS, pl.col("babbling").alias("babbling_before_touch"))
    return pl.concat([untouched, rerun.drop("rerun_touch_s")]).sort(*KEYS)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m reports.babbling_before_touch",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("root", type=Path, help="the repository's root")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--runs", nargs="*", default=[*REPLICATIONS, FULL])
    args = parser.parse_args(argv)
    for name in args.runs:
        run_dir = args.root / "recordings" / name
        out = run_dir / TABLE
        if out.exists():
            continue
        table = compute(run_dir, args.workers)
        integrity.write(out, lambda p: write_parquet(table, p))
        print(out, table.height, file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
