"""Development over generations (paper sections IV-A, IV-C, V; Table I): the course of the
behavioural measures through the phases of a condition, per replication.

The paper's claims about the course of training ("initial motor suppression" at the start of
gross-reaching, Table I; the freezing then un-freezing of distal joints and babbling appearing
then fading, V; fine* and fine^ "never display such behavior during the course of their
developmental process", IV-C) cannot be judged from final populations. Two sources:

- **snapshots** (``RunDirectory.snapshots``, ``train --snapshot-every``): the best robots of
  every replication after generations 1, 2, 5, 10, every K and the last of each phase.
  ``measure_snapshots`` post-evaluates the best ``robots`` of each on the 45 systematic
  positions (normal senses, and the other conditions of ``systematic.TESTS`` where asked:
  the ball-absent test of a pre-reaching claim), every measure of
  ``metrics.trial_metrics``, into ``development.parquet`` (one row per trial; resumable:
  what is there is kept), all snapshots or chosen generations, of a finished run or of one
  still training (the snapshots saved so far).
- **recordings** (``train --record-every``): one trial of each replication's best individual
  every K generations, at a random position. ``recorded_development`` measures them; it is
  all a run made before snapshots has. One trial per point, touches on inner faces only
  (recordings of layout 3 hold no other), no palm normal: noisier and fewer measures.

``course`` turns either table into one row per (condition, phase, replication, generation)
with the mean of each measure over the robots' trials, and ``x``, the generation counted
through the condition's phases (gross-reaching starts where pre-reaching ended).
``window`` averages a measure over a range of generations of a phase per replication: the
values the developmental claims compare.
"""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path
from typing import Callable, Sequence

import numpy as np
import polars as pl

from . import results
from .systematic import EvaluationProgress, RobotJob, open_finished, run_robot
from ..evolution.backends import make_backend
from ..evolution.rundir import RunDirectory
from ..evolution.settings import trial_config
from ..files import DirectoryLock, remove_temporaries
from ..measures.metrics import trial_metrics
from ..model.ctrnn import MOTOR_NAMES
from ..model.icub import HAND_SEGMENTS
from ..model.task import Senses, TrialData
from ..recording.rrd import read_properties, read_rrd

TABLE = results.DEVELOPMENT
_KEY = ("phase_key", "senses", "generation", "replication", "rank")

#: The measures whose course the report draws (column, label): performance, movement
#: amplitude (motor suppression), babbling, the joints' use (freezing), the arm's lever, the
#: reach's straightness.
MEASURES = (("fitness", "fitness (mean p_multimodal)"), ("reached", "reach rate"),
            ("grasped", "grasp rate"), ("hand_path", "hand path per trial (m)"),
            ("babbling", "babbling rate"), ("var_elbow", "elbow variability (rad)"),
            ("var_shoulder", "shoulder variability (rad)"),
            ("var_trunk", "trunk variability (rad)"),
            ("hand_shoulder_cv", "hand-shoulder distance CV"),
            ("straightness", "straightness"))


def _offsets(run: RunDirectory) -> dict[str, tuple[str, int, str]]:
    """phase key -> (condition, generations before the phase in that condition, notation),
    for each phase as ``RunDirectory.unique_phases`` trains it (with its first condition)."""
    first = {p.key: c for c, p in run.unique_phases()}
    out = {}
    for c in run.conditions:
        before = 0
        for p in c.phases:
            if first[p.key] is c:
                out[p.key] = (c.name, before, p.notation)
            before += p.generations
    return out


def load_development(run_dir, senses: str | None = "normal") -> pl.DataFrame | None:
    """``development.parquet`` of a run, the trials under ``senses`` (default normal, what the
    course and the developmental claims read; None: every condition), or None when there is
    none."""
    table = results.read_table(Path(run_dir) / TABLE)
    if table is None or senses is None:
        return table
    return table.filter(pl.col("senses") == senses)


def check_snapshots(run: RunDirectory, generations: Sequence[int]) -> None:
    """``ValueError`` naming the generations of ``generations`` of which ``run`` kept no
    snapshot, before anything is evaluated."""
    saved = run.snapshot_generations()
    if missing := set(generations) - saved:
        raise ValueError(f"{run.out} has no snapshot of generation "
                         f"{', '.join(map(str, sorted(missing)))} (its snapshots: "
                         f"{', '.join(map(str, sorted(saved))) or 'none'})")


def measure_snapshots(run_dir, robots: int = 1, workers: int | None = None,
                      ray_address: str | None = None,
                      progress: Callable[[EvaluationProgress], None] | None = None,
                      save_every_s: float = 10.0, senses: Sequence[str] = ("normal",),
                      generations: Sequence[int] | None = None, finished_only: bool = False
                      ) -> pl.DataFrame:
    """Post-evaluate the best ``robots`` (<= the snapshots' 5) of every replication of every
    snapshot of a finished run on the 45 systematic positions under each of ``senses``
    (``systematic.TESTS``: normal, the deprivations, no-ball), and return the whole
    ``development.parquet`` (written in the run). ``generations``: only the snapshots of these
    generations (None: all). ``finished_only``: the snapshots a run still training has saved
    so far (on a copy of its directory: the training holds the run's lock). Columns:
    condition (the first that trains the phase), phase, phase_key, notation, replication,
    rank, generation, offset (generations of the condition's earlier phases),
    lifetime_fitness, senses, trial, sector, ball_x/y/z, every measure of
    ``metrics.trial_metrics`` and measures_version. Snapshots already evaluated are kept.
    ``progress`` is told a ``systematic.EvaluationProgress`` (robots done of those left, with
    an ETA) after each robot."""
    run = RunDirectory.open(run_dir) if finished_only else open_finished(run_dir)
    run.verify()  # a damaged file refused before anything is written
    if robots < 1:
        raise ValueError(f"robots must be at least 1, got {robots}")
    senses = tuple(Senses(s) for s in senses)
    wanted = None if generations is None else set(generations)
    if wanted is not None:
        check_snapshots(run, wanted)
    with DirectoryLock(run.out):
        remove_temporaries(run.out)
        path = run.out / TABLE
        table = load_development(run.out, senses=None)
        done = set() if table is None else set(table.select(_KEY).iter_rows())
        offsets = _offsets(run)
        jobs, extra = [], []
        for condition, phase in run.unique_phases():
            base = trial_config(phase, run.settings)
            for generation, genomes, fitness in run.snapshots(phase):
                if wanted is not None and generation not in wanted:
                    continue
                for s in senses:
                    trial = replace(base, senses=s)
                    for r in range(genomes.shape[0]):
                        for i in range(min(robots, genomes.shape[1])):
                            if (phase.key, s.value, generation, r, i) in done:
                                continue
                            jobs.append(RobotJob(condition.name, phase,
                                                 run.phase_dir(phase).name, r, i,
                                                 float(fitness[r, i]), genomes[r, i], trial,
                                                 run.settings.world, False))
                            extra.append({"generation": generation,
                                          "offset": offsets[phase.key][1]})
        if not jobs:
            return table if table is not None else pl.DataFrame()
        entry = results.session()
        backend = make_backend(workers, ray_address)
        rows: list[dict] = []
        t0 = last_save = time.monotonic()
        try:
            for n, (job, more, (job_rows, _)) in enumerate(
                    zip(jobs, extra, backend.imap(run_robot, jobs)), start=1):
                rows.extend(dict(row, **more) for row in job_rows)
                if time.monotonic() - last_save > save_every_s:
                    table, rows = results.save_table(path, table, rows, _KEY, entry), []
                    last_save = time.monotonic()
                if progress:
                    progress(EvaluationProgress(n, len(jobs), time.monotonic() - t0,
                                                f"{job.phase.name} @{more['generation']}",
                                                job.trial.senses.value))
        finally:
            backend.close()
            if rows:
                table = results.save_table(path, table, rows, _KEY, entry)
        return table


def trial_from_recording(rec: pl.DataFrame, sector: int) -> TrialData:
    """The ``TrialData`` fields a trial recording holds (``recording.read_rrd``): joints,
    hand, shoulder and ball positions, inner-face contacts, p_multimodal. Any-face contacts
    and the palm's normal are not recorded (None)."""
    n = rec.height
    data = TrialData.empty(n, sector, np.zeros(3))
    data.contacts_any = data.palm_normal = None
    xyz = ("x", "y", "z")
    for name in ("hand", "shoulder", "ball"):
        getattr(data, name)[:] = rec.select(
            [f"robot/positions/{name}/{a}" for a in xyz]).to_numpy()
    joints = [f"robot/joints/{'head_torso' if i < 6 else 'arm_hand'}/{m}"
              for i, m in enumerate(MOTOR_NAMES)]
    data.joints[:] = rec.select(joints).to_numpy()
    data.contacts[:] = rec.select([f"robot/contacts/{s}" for s in HAND_SEGMENTS]
                                  ).to_numpy() > 0.5
    data.p_multimodal[:] = rec["fitness/p_multimodal"].to_numpy()
    data.ball_start = data.ball[0].copy() if n else data.ball_start
    data.steps_run = n
    return data


def recorded_development(run_dir) -> pl.DataFrame:
    """The measures of every best-of-generation recording of a run
    (``phases/<phase>/best/gen<G>-rep<R>.rrd``): one row per recording, with condition,
    phase, phase_key, notation, replication, rank (0), generation, offset, sector and every
    measure of ``metrics.trial_metrics`` (reach on inner faces; no swipes). Empty when the run
    recorded none."""
    run = RunDirectory.open(run_dir)
    offsets = _offsets(run)
    rows = []
    for _, phase in run.unique_phases():
        condition, offset, notation = offsets[phase.key]
        for path in sorted((run.phase_dir(phase) / "best").glob("gen*-rep*.rrd")):
            props = read_properties(path)
            data = trial_from_recording(read_rrd(path), int(props["sector"]))
            rows.append({"condition": condition, "phase": phase.name, "phase_key": phase.key,
                         "notation": notation, "replication": int(props["replication"]),
                         "rank": 0, "generation": int(props["generation"]), "offset": offset,
                         **trial_metrics(data, run.settings.world.control_dt,
                                         run.settings.world.ball.radius)})
    return pl.DataFrame(rows, infer_schema_length=None) if rows else pl.DataFrame()


def course(table: pl.DataFrame, measures: Sequence[str] = tuple(m for m, _ in MEASURES)
           ) -> pl.DataFrame:
    """One row per (condition, phase, notation, replication, generation): the mean of each
    measure over each robot's trials, then over the robots (NaN ignored; booleans as rates),
    and ``x`` = offset + generation, the generation counted through the condition. Sorted
    by condition, x, replication."""
    measures = [m for m in measures if m in table.columns]
    keys = ["condition", "phase", "notation", "replication", "generation", "offset"]
    values = [pl.col(m).cast(pl.Float64).fill_nan(None) for m in measures]
    robots = table.group_by([*keys, "rank"]).agg([v.mean() for v in values]).sort([*keys, "rank"])
    out = (robots.group_by(keys).agg(pl.len().alias("robots"),
                                     *[pl.col(m).mean() for m in measures])
           .with_columns((pl.col("offset") + pl.col("generation")).alias("x"),
                         *[pl.col(m).fill_null(float("nan")) for m in measures]))
    return out.sort(["condition", "x", "replication"])


def window(course_table: pl.DataFrame, measure: str, notation: str, first: int | None = None,
           last: int | None = None) -> pl.DataFrame:
    """Per replication, the mean of ``measure`` over the generations ``first`` .. ``last``
    (inclusive; None = from the start / to the end) of the phase ``notation``: e.g. the
    first 10 generations of gross-reaching (motor suppression) or the last generation of
    pre-reaching. Columns: replication, points (generations averaged), value."""
    sub = course_table.filter(pl.col("notation") == notation)
    if first is not None:
        sub = sub.filter(pl.col("generation") >= first)
    if last is not None:
        sub = sub.filter(pl.col("generation") <= last)
    return (sub.group_by("replication")
            .agg(pl.len().alias("points"),
                 pl.col(measure).fill_nan(None).mean().fill_null(float("nan")).alias("value"))
            .sort("replication"))
