"""Post-evaluation of a trained run (section IV, Figs. 5-9).

The best ``robots`` (5) individuals of each replication of each trained phase are tested on the
45 systematic ball positions (5 per sector, ``World.systematic_points``) under one or more
conditions: the sensory conditions of section IV-B (normal, no-touch, no-sight, nothing:
``SENSES``, Fig. 9) and the ball-absent test of section IV-A-1 (no-ball: the ball out of the
scene, touch and sight reading "nothing sensed"; Fig. 8). The trials are deterministic:
positions are fixed and the robot starts every trial from the same state.

Output, in the run directory::

    evaluation.parquet   one row per trial: who (condition, phase, phase_key, notation,
                         replication, rank, lifetime_fitness), how (senses), where (trial,
                         sector, ball_x/y/z: where the ball hangs, or would in a no-ball
                         trial) and every measure of ``metrics.trial_metrics``, plus
                         ``recording`` (path of the trial's .rrd relative to the run, or null),
                         ``measures_version`` (``MEASURES_VERSION``) and ``session`` (who
                         wrote it); stored as ``results`` says (float32, provenance)
    baseline.parquet     the same for the random genomes (below)
    evaluation/<phase>/<senses>/rep<R>-rank<I>/trial<K>-sector<S>.rrd   (see ``Record``)
    evaluation/trial.rbl  their layout in the viewer: rerun TRIAL.rrd evaluation/trial.rbl

Random genomes of each phase can be post-evaluated beside the trained robots as the chance level
of every measure (``baseline``: ``evaluate --baseline N``): they are the rows of
baseline.parquet, with ``baseline`` true, replication = the random genome's index, rank 0,
lifetime_fitness NaN, drawn from the run's seed tree (``settings.baseline_genomes``) and decoded
with the phase's free groups and maturational state. ``load_evaluation`` leaves them out unless
asked.

Evaluating again adds only what is missing (another sensory condition, more robots); rows and
recordings already saved are kept, except rows measured by an older version of the measures
(``measures_version`` below ``MEASURES_VERSION``; ``results.migrate`` gives the rows of a table
written before version 2 of the measures version 1), which are evaluated and measured again when
their robot and condition are asked for. The table is saved every few seconds, so an interrupted
evaluation keeps the robots it finished.
"""

from __future__ import annotations

import enum
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable, Iterable, Sequence

import numpy as np
import polars as pl

from . import results
from ..evolution.backends import make_backend, worker_trial
from ..evolution.conditions import Phase
from ..evolution.genome import as_groups, decode
from ..evolution.rundir import RunDirectory, RunError
from ..evolution.settings import baseline_genomes, trial_config
from ..files import DirectoryLock, remove_temporaries
from ..measures.metrics import trial_metrics
from ..progress import evaluation_bar
from ..recording.rrd import RobotModel, TrialInfo, trial_rrd, write_blueprint, write_rrd
from ..model.task import Senses, TrialConfig, network_for
from ..model.world import POINTS_PER_SECTOR, WorldConfig

TABLE = "evaluation.parquet"
RECORDINGS = "evaluation"
#: The layout of the post-evaluation's recordings: ``rerun TRIAL.rrd evaluation/trial.rbl``.
BLUEPRINT = f"{RECORDINGS}/trial.rbl"
#: The sensory conditions of Fig. 9 (section IV-B).
SENSES = tuple(s.value for s in Senses if s is not Senses.NO_BALL)
#: The ball-absent test of section IV-A-1 (Fig. 8).
BALL_ABSENT = Senses.NO_BALL.value
#: Every post-evaluation condition (``--sensors all``).
TESTS = (*SENSES, BALL_ABSENT)
#: Version of the per-trial measures in evaluation.parquet: 1 (absent column), the first
#: measures (reach = an inner-face touch, straightness to the ball's centre); 2: the measures of
#: ``metrics.trial_metrics`` as documented in docs/model/measures.md.
MEASURES_VERSION = 2
_KEY = ("phase_key", "senses", "baseline", "replication", "rank")


class Record(enum.Enum):
    """Which robots get their trials recorded (the recordings' size per simulated minute:
    docs/results/benchmarks.md, ``rrd_mb_per_sim_min``): the best robot of the best
    replication of each phase, as in Figs. 6 and 8 (default), the best robot of each
    replication, every evaluated robot, or none."""

    BEST = "best"
    REPLICATIONS = "replications"
    ALL = "all"
    NONE = "none"

    def wants(self, replication: int, rank: int, best_replication: int) -> bool:
        return (self is Record.ALL or (rank == 0 and (
            self is Record.REPLICATIONS
            or (self is Record.BEST and replication == best_replication))))


@dataclass(frozen=True)
class RobotJob:
    """One robot under one sensory condition on the 45 systematic positions."""

    condition: str
    phase: Phase
    phase_dir: str
    replication: int
    rank: int
    lifetime_fitness: float
    genome: np.ndarray
    trial: TrialConfig
    world: WorldConfig
    record: bool
    baseline: bool = False
    #: Which of the 45 positions to run (None: all); a subset checks stored rows quickly.
    positions: tuple[int, ...] | None = None

    def recording_path(self, k: int, sector: int) -> str:
        """Path of trial k's recording, relative to the run directory."""
        return (f"{RECORDINGS}/{self.phase_dir}/{self.trial.senses.value}/"
                f"rep{self.replication:02d}-rank{self.rank}/trial{k:02d}-sector{sector}.rrd")


def stored_robot_job(run: RunDirectory, phase_key: str, senses: str, replication: int,
                     rank: int, baseline: bool = False, generation: int | None = None,
                     positions: tuple[int, ...] | None = None, record: bool = False
                     ) -> RobotJob:
    """The job that evaluates again one robot of a stored table: a trained robot (its phase's
    final population), a random genome of the baseline (``baseline``: ``replication`` is its
    index) or a snapshot's robot (``generation``), under ``senses``, on ``positions``."""
    condition, phase = next((c, p) for c, p in run.unique_phases() if p.key == phase_key)
    if baseline:
        genome = baseline_genomes(run.settings, phase, replication + 1)[replication]
        fitness = float("nan")
    else:
        genomes, fit = (run.load_final(phase) if generation is None else next(
            (g, f) for gen, g, f in run.snapshots(phase) if gen == generation))
        genome, fitness = genomes[replication, rank], float(fit[replication, rank])
    trial = replace(trial_config(phase, run.settings), senses=Senses(senses))
    return RobotJob(condition.name, phase, run.phase_dir(phase).name, replication, rank, fitness,
                    genome, trial, run.settings.world, record, baseline=baseline,
                    positions=positions)


_MODELS: dict[WorldConfig, RobotModel] = {}


def run_robot(job: RobotJob) -> tuple[list[dict], list[bytes | None]]:
    """The table rows and recordings (or None) of one robot's 45 trials."""
    runner = worker_trial(job.world, job.trial)
    world = runner.world
    model = _MODELS.get(job.world)
    if model is None and job.record:
        model = _MODELS[job.world] = RobotModel(world)
    network = network_for(decode(job.genome, as_groups(job.phase.free_groups)), job.trial)
    rows, recordings = [], []
    for k, position in enumerate(world.systematic_points()):
        if job.positions is not None and k not in job.positions:
            continue
        sector = k // POINTS_PER_SECTOR
        data = runner.run(network, sector, position)
        path = job.recording_path(k, sector) if job.record else None
        measures = trial_metrics(data, job.world.control_dt, job.world.ball.radius,
                                 world.motor_limit_upper - world.motor_limit_lower)
        rows.append({
            "condition": job.condition, "phase": job.phase.name, "phase_key": job.phase.key,
            "notation": job.phase.notation, "replication": job.replication, "rank": job.rank,
            "lifetime_fitness": job.lifetime_fitness, "baseline": job.baseline,
            "senses": job.trial.senses.value,
            "trial": k, "ball_x": float(position[0]), "ball_y": float(position[1]),
            "ball_z": float(position[2]), **measures, "recording": path,
            "measures_version": MEASURES_VERSION})
        recordings.append(trial_rrd(data, TrialInfo(
            job.condition, job.phase.name, job.replication, job.rank, sector, k, "systematic",
            job.trial.senses.value), model, job.world.control_dt, blueprint=False,
            measures=measures) if job.record else None)
    return rows, recordings


@dataclass
class EvaluationProgress:
    robots_done: int
    robots_total: int
    elapsed_s: float
    phase: str
    senses: str

    @property
    def eta_s(self) -> float:
        if not self.robots_done:
            return float("nan")
        return self.elapsed_s / self.robots_done * (self.robots_total - self.robots_done)


def parse_senses(text: str) -> tuple[str, ...]:
    """``"all"`` (every condition: the four of Fig. 9 and the ball-absent test) or condition
    names separated by commas ("normal,no-ball"), as a tuple of names."""
    if text == "all":
        return TESTS
    names = tuple(dict.fromkeys(n.strip() for n in text.split(",")))
    unknown = [n for n in names if n not in TESTS]
    if unknown:
        raise ValueError(f"unknown sensory condition {unknown[0]!r}: expected one of "
                         f"{', '.join(TESTS)}, several separated by commas, or all")
    return names


def finished_phases(run_dir) -> int:
    """How many of a run's phases have finished training (hold their final population)."""
    run = RunDirectory.open(run_dir)
    return sum(run.final_path(p).exists() for _, p in run.unique_phases())


def open_finished(run_dir, finished_only: bool | None = None) -> RunDirectory:
    """The run in ``run_dir``, refusing one whose training has not finished (with
    ``finished_only`` True: one in which no phase has; False: the message names the option,
    None: it does not offer it)."""
    run = RunDirectory.open(run_dir)
    missing = run.unfinished()
    if finished_only and len(missing) < sum(len(c.phases) for c in run.conditions):
        return run
    if missing:
        unfinished = f"{run.out}: unfinished run: {', '.join(missing)} not trained to the end " \
                     f"(no final.npz)" + {True: "; no phase has finished yet",
                                          False: " (--finished-only: the finished phases alone)",
                                          None: ""}[finished_only] + "; finish it with "
        raise RunError(unfinished + f"dart_reach.train(..., out={str(run.out)!r}, resume=True)",
                       cli=unfinished + f"'dart-reach train ... --resume --out {run.out}'")
    return run


def load_evaluation(run_dir, baseline: bool | None = False) -> pl.DataFrame:
    """The post-evaluation of a run: the trained robots' trials (``evaluation.parquet``;
    ``baseline`` False, the default), the random baseline's (``baseline.parquet``; True) or
    both (None). Stored float32 measures read as float64 (``results``)."""
    run_dir = Path(run_dir)
    if not results.exists(run_dir / TABLE) and not (
            baseline is not False and results.exists(run_dir / results.BASELINE)):
        raise RunError(f"{run_dir / TABLE}: no post-evaluation yet; run "
                       f"'dart-reach evaluate {run_dir}'")
    parts = [t for t in (results.read_table(run_dir / TABLE),
                         results.read_table(run_dir / results.BASELINE)) if t is not None]
    table = pl.concat(parts, how="diagonal_relaxed") if len(parts) > 1 else parts[0]
    return table if baseline is None else table.filter(pl.col("baseline") == baseline)


def run_phases(run_dir) -> pl.DataFrame:
    """Every (condition, phase) of a run in training order, with the phase's notation and key
    (to join with the evaluation table, in which a phase shared by conditions appears once)."""
    run = RunDirectory.open(run_dir)
    return pl.DataFrame([
        {"condition": c.name, "order": i, "phase": p.name, "notation": p.notation,
         "phase_key": p.key, "generations": p.generations}
        for c in run.conditions for i, p in enumerate(c.phases)])


def evaluate_run(run_dir, senses: Iterable[str] = ("normal",), robots: int = 5,
                 record: Record | str = Record.BEST, workers: int | None = None,
                 ray_address: str | None = None,
                 progress: Callable[[EvaluationProgress], None] | bool = True,
                 save_every_s: float = 10.0, baseline: int = 0, finished_only: bool = False
                 ) -> pl.DataFrame:
    """Post-evaluate a finished run (the function ``dart-reach evaluate`` calls) and return its
    whole evaluation table, baseline rows included. ``baseline``: random genomes per phase
    evaluated beside the trained robots (never recorded). ``progress``: True (default) shows
    a progress bar (plain lines where the output is not a terminal), False nothing, a
    callable is told each ``EvaluationProgress``. ``finished_only``: evaluate the phases that
    have finished training in a run that has not (a look at a long run part-way, on a copy of
    its directory: the training holds the run's lock), and the random genomes of every phase
    (they need no training). Its ``evaluation.parquet``, copied into
    the run once it has finished, is kept: evaluating the run then adds only the rest."""
    run = (RunDirectory.open(run_dir) if finished_only and baseline
           else open_finished(run_dir, finished_only))
    run.verify()  # a damaged file refused before anything is written
    bar = evaluation_bar() if progress is True else None
    try:
        with DirectoryLock(run.out):
            remove_temporaries(run.out)
            return _evaluate(run, senses, robots, Record(record), workers, ray_address,
                             bar or progress or None, save_every_s, baseline)
    finally:
        if bar is not None:
            bar.close()


def _evaluate(run: RunDirectory, senses, robots, record, workers, ray_address, progress,
              save_every_s, baseline) -> pl.DataFrame:
    senses = tuple(Senses(s) for s in senses)
    population = run.settings.ga.population
    if not 1 <= robots <= population:
        raise ValueError(f"robots must be between 1 and the population ({population}), "
                         f"got {robots}")
    if baseline < 0:
        raise ValueError(f"baseline must be 0 or more random genomes, got {baseline}")
    table = (load_evaluation(run.out, baseline=None) if results.exists(run.out / TABLE)
             or results.exists(run.out / results.BASELINE) else None)
    done = set() if table is None else set(
        table.filter(pl.col("measures_version") >= MEASURES_VERSION).select(_KEY).iter_rows())
    tables = {flag: None if table is None else table.filter(pl.col("baseline") == flag)
              for flag in (False, True)}
    jobs = []
    for condition, phase in run.unique_phases():
        if run.final_path(phase).exists():
            genomes, fitness = run.load_final(phase)
            best_replication = int(np.argmax(fitness[:, 0]))
        else:  # not trained to the end (finished_only): its random genomes alone
            genomes, fitness, best_replication = np.zeros((0, 0, 0)), None, -1
        base = trial_config(phase, run.settings)
        chance = baseline_genomes(run.settings, phase, baseline)
        for s in senses:
            trial = replace(base, senses=s)
            for r in range(genomes.shape[0]):
                for i in range(robots):
                    if (phase.key, s.value, False, r, i) not in done:
                        jobs.append(RobotJob(
                            condition.name, phase, run.phase_dir(phase).name, r, i,
                            float(fitness[r, i]), genomes[r, i], trial, run.settings.world,
                            record.wants(r, i, best_replication)))
            for b, genome in enumerate(chance):
                if (phase.key, s.value, True, b, 0) not in done:
                    jobs.append(RobotJob(condition.name, phase, run.phase_dir(phase).name, b,
                                         0, float("nan"), genome, trial, run.settings.world,
                                         False, baseline=True))
    if not jobs:
        return table if table is not None else pl.DataFrame()
    entry = results.session()
    paths = {False: run.out / TABLE, True: run.out / results.BASELINE}

    def save(rows: list[dict]) -> None:
        for flag in (True, False):
            part = [row for row in rows if row["baseline"] is flag]
            if part:
                tables[flag] = results.save_table(paths[flag], tables[flag], part, _KEY, entry)

    backend = make_backend(workers, ray_address)  # first: a refused one writes nothing
    rows: list[dict] = []
    t0 = last_save = time.monotonic()
    try:
        if any(job.record for job in jobs) and not (run.out / BLUEPRINT).exists():
            write_blueprint(run.out / BLUEPRINT)
        for n, (job, (job_rows, recordings)) in enumerate(
                zip(jobs, backend.imap(run_robot, jobs)), start=1):
            for row, content in zip(job_rows, recordings):
                if content is not None:
                    write_rrd(run.out / row["recording"], content)
            rows.extend(job_rows)
            if time.monotonic() - last_save > save_every_s:
                save(rows)
                rows, last_save = [], time.monotonic()
            if progress:
                progress(EvaluationProgress(n, len(jobs), time.monotonic() - t0, job.phase.name,
                                            job.trial.senses.value))
    finally:
        backend.close()
        if rows:
            save(rows)
    return pl.concat([t for t in tables.values() if t is not None], how="diagonal_relaxed")
