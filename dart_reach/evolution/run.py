"""Training a condition: phases, replications, transitions, checkpoints and the run directory
(paper sections III-C, III-D, IV-C).

A run trains one or more conditions in one directory. Each phase of a condition is trained with
``replications`` independent runs of the GA; the first phase starts from random genomes, every
later phase from the best ``population / replications`` genomes of each replication of the
previous phase (the best 2 of each of 10 in the paper), with the maturational changes of the new
phase. A phase shared by several conditions (same content, same preceding phases: the same
``Phase.key``) is trained once.

Randomness: one ``SeedSequence`` tree per run, addressed by (phase key, replication, purpose,
generation, individual): nothing depends on the order of evaluation or the number of workers.

Run directory::

    manifest.json              conditions, settings, seeds, package versions, git revision
                               (and whether the working tree had uncommitted changes)
    generations.parquet        one row per (condition, phase, replication, generation)
    training.rrd               the same statistics as Rerun time series (timeline generation)
    phases/<phase>/checkpoint.npz  the GA states after the last complete generation (atomic)
    phases/<phase>/final.npz   per replication: final population, lifetime fitness, best genome
    phases/<phase>/best.parquet  the final populations as a table, best first
    phases/<phase>/best/gen<G>-rep<R>.rrd  a trial of each replication's best individual,
                               every ``record_every`` generations
    phases/<phase>/snapshots/gen<G>.npz  the best ``SNAPSHOT_ROBOTS`` genomes of every
                               replication and their lifetime fitness, after generations 1, 2,
                               5, 10, every ``snapshot_every`` and the last (development over
                               generations, ``development.py``)
    evaluation.parquet, evaluation/   the post-evaluation (``evaluation.py``)
    .lock                      held by the process working in the directory (``files``)

A generation is committed by its phase's checkpoint alone, written atomically (a temporary file
renamed over the old one). Everything a generation adds is either written before that commit
(the best-of-generation recordings and the snapshots, which a redone generation rewrites
identically) or derived
from the committed checkpoints and rebuilt from them on resume (generations.parquet and
training.rrd: each checkpoint carries its phase's statistics rows; best.parquet from final.npz,
which commits the end of a phase). So however a run stops (a signal, a full disk, a power
loss), ``--resume`` redoes at most the generation in progress and ends with the same directory
as an uninterrupted run. Resume refuses, naming the file, what it cannot rebuild: a checkpoint
missing or older than the generations the table records.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import platform
import subprocess
import time
from dataclasses import asdict, dataclass, field, replace
from importlib import metadata
from pathlib import Path
from typing import Callable

import numpy as np
import polars as pl

from .. import __version__
from .conditions import Condition, Phase, condition_from_dict
from .backends import Evaluator, Job, make_evaluator, worker_trial
from .ga import (GAConfig, GAState, Scheme, ask, best_k, generation_stats, init_state,
                        state_from_arrays, state_to_arrays, tell, transition_population)
from ..errors import UsageError
from ..files import LOCK_NAME, DirectoryLock, atomic_write, remove_temporaries
from .genome import ParamGroup, as_groups, decode, free_mask, random_genome, release
from ..progress import training_bar
from ..recording.rrd import RobotModel, TrialInfo, training_rrd, trial_rrd, write_rrd
from ..model.task import TrialConfig, network_for, trial_positions
from ..model.scenes import scene_of
from ..model.world import BallConfig, SectorConfig, WorldConfig

MANIFEST_FORMAT = 1
STATS_SCHEMA = {
    "condition": pl.Utf8, "phase": pl.Utf8, "phase_key": pl.Utf8, "replication": pl.Int64,
    "generation": pl.Int64, "best": pl.Float64, "mean": pl.Float64, "min": pl.Float64,
    "wall_s": pl.Float64,
}


class RunError(UsageError):
    """A run directory cannot be used as asked (exists, foreign, corrupted, other settings)."""


@dataclass(frozen=True)
class Settings:
    """Budgets and seeds of a run: everything besides the conditions that defines its result."""

    replications: int = 10
    trials: int = 18  # trials per evaluation: 2 per sector (section III-C)
    steps: int = 200  # control steps per trial (20 s)
    seed: int = 0
    ga: GAConfig = field(default_factory=GAConfig)
    world: WorldConfig = field(default_factory=WorldConfig)

    def __post_init__(self):
        for name in ("replications", "trials", "steps"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be a positive integer, got {getattr(self, name)}")
        if self.seed < 0:
            raise ValueError(f"seed must be a non-negative integer, got {self.seed}")
        if self.ga.population % self.replications:
            raise ValueError(
                f"the population ({self.ga.population}) must be a multiple of the number of "
                f"replications ({self.replications}): the next phase starts from the best "
                f"population / replications genomes of each (section III-D)")

    def to_json(self) -> dict:
        d = asdict(self)
        d["ga"]["scheme"] = self.ga.scheme.value
        d["world"]["skeleton"] = str(self.world.skeleton) if self.world.skeleton else None
        return d

    @classmethod
    def from_json(cls, d: dict) -> "Settings":
        """The inverse of ``to_json`` (a manifest's ``settings``)."""
        w = dict(d["world"])
        w["skeleton"] = Path(w["skeleton"]) if w.get("skeleton") else None
        w["ball"] = BallConfig(**{k: tuple(v) if isinstance(v, list) else v
                                  for k, v in w["ball"].items()})
        w["sectors"] = SectorConfig(**{k: tuple(v) if isinstance(v, list) else v
                                       for k, v in w["sectors"].items()})
        ga = dict(d["ga"], scheme=Scheme(d["ga"]["scheme"]))
        return cls(**dict(d, ga=GAConfig(**ga), world=WorldConfig(**w)))


#: Core-seconds of one replication-generation at the paper's budget (20 genotypes, steady
#: state: 40 evaluations of 18 trials of 200 control steps, the shipped evolved robots):
#: ``generation_core_s`` of ``dart-reach bench``, low and high of five quiet runs on the
#: project's 2-core reference machine on 2026-11-24 (README, Benchmarks; the host's speed
#: varies by about a third from day to day).
GENERATION_CORE_S = (43.0, 44.7)


@dataclass(frozen=True)
class CostEstimate:
    """The size of a training run: ``replication_generations`` (generations of every phase
    trained, a phase shared by conditions once, times replications) and ``core_hours`` (low,
    high), from ``GENERATION_CORE_S`` scaled by evaluations, trials and steps."""

    replication_generations: int
    core_hours: tuple[float, float]


def cost_estimate(conditions: list[Condition], settings: Settings) -> CostEstimate:
    """How much training ``conditions`` under ``settings`` costs (see ``CostEstimate``): the
    cost of a generation is taken proportional to evaluations x trials x steps, and evolved
    robots (which touch the ball) cost more than the random networks a run starts from, so
    it is an upper-side estimate for short runs."""
    phases = {p.key: p for c in conditions for p in c.phases}
    rep_gens = sum(p.generations for p in phases.values()) * settings.replications
    evaluations = settings.ga.population * (2 if settings.ga.scheme is Scheme.STEADY_STATE
                                            else 1)
    scale = evaluations / 40 * settings.trials / 18 * settings.steps / 200
    return CostEstimate(rep_gens, tuple(rep_gens * scale * s / 3600 for s in GENERATION_CORE_S))


def trial_config(phase: Phase, settings: Settings) -> TrialConfig:
    """The maturational state of a phase as the task sees it."""
    groups = as_groups(phase.free_groups)
    return TrialConfig(acuity=phase.acuity, offset_sensors=phase.offset_sensors,
                       hidden_frozen=ParamGroup.HIDDEN not in groups, reflexes=phase.reflexes,
                       steps=settings.steps, trials=settings.trials)


def standard_trial(phase: str = "pre", **changes) -> TrialConfig:
    """The maturational state of a phase of the shipped ``standard`` condition (default
    pre-reaching: low acuity, internal neurons frozen, reflexes), with ``changes``."""
    from .conditions import load_condition

    phases = {p.name: p for p in load_condition("standard").phases}
    return replace(trial_config(phases[phase], Settings()), **changes)


def _phase_id(phase: Phase) -> int:
    return int(phase.key[:8], 16)


def _seed(settings: Settings, phase: Phase, *path: int) -> np.random.SeedSequence:
    return np.random.SeedSequence(settings.seed, spawn_key=(_phase_id(phase), *path))


# purposes of the seed tree
_INIT, _MUTATE, _EVALUATE, _RECORD, _BASELINE = 0, 1, 2, 3, 4

#: Genomes per replication a snapshot keeps: the best 5, the robots the paper post-evaluates.
SNAPSHOT_ROBOTS = 5
#: Generations after which a snapshot is always kept (when snapshots are on): the first ones,
#: where the start of a phase (the motor suppression at the start of gross-reaching, Table I)
#: shows.
SNAPSHOT_EARLY = (1, 2, 5, 10)


def snapshot_due(generation: int, generations: int, every: int) -> bool:
    """Whether a phase of ``generations`` keeps a snapshot after ``generation`` (1-based)
    when snapshots are taken every ``every`` generations (0 = never)."""
    return every > 0 and (generation in SNAPSHOT_EARLY or generation % every == 0
                          or generation == generations)


def baseline_genomes(settings: Settings, phase: Phase, n: int) -> np.ndarray:
    """``n`` random genomes for the chance level of ``phase`` (``evaluate --baseline``): drawn
    like an initial population, from the run's seed tree, so the first k are the same whatever
    ``n`` >= k."""
    return random_genome(np.random.default_rng(_seed(settings, phase, _BASELINE)), n)


def _git(directory: Path, *args: str) -> bytes | None:
    try:
        out = subprocess.run(["git", *args], capture_output=True, cwd=directory, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout if out.returncode == 0 else None


def git_state(directory=None) -> dict:
    """The state of the git working tree holding ``directory`` (default: this package's
    source), for a run's manifest: ``git_revision`` (the commit), ``git_dirty`` (True when
    tracked files differ from it or files git does not ignore are untracked) and
    ``git_diff_sha256`` (SHA-256 of ``git diff HEAD --binary`` followed by each untracked
    file's path and content: two runs with the same revision and the same hash ran the same
    code). Run directories under ``recordings/`` are not source: left out of both. All None
    outside a git working tree."""
    directory = Path(directory) if directory is not None else Path(__file__).parent
    head = _git(directory, "rev-parse", "HEAD")
    if not head:
        return {"git_revision": None, "git_dirty": None, "git_diff_sha256": None}
    root = Path((_git(directory, "rev-parse", "--show-toplevel") or b".").decode().strip())
    outside = ("--", ".", ":(exclude)recordings")
    diff = _git(root, "diff", "HEAD", "--binary", *outside) or b""
    untracked = (_git(root, "ls-files", "--others", "--exclude-standard", "-z", *outside)
                 or b"")
    digest = hashlib.sha256(diff)
    for name in sorted(n for n in untracked.split(b"\0") if n):
        digest.update(b"\0untracked\0" + name + b"\0")
        try:
            digest.update((root / name.decode()).read_bytes())
        except OSError:
            pass
    return {"git_revision": head.decode().strip(), "git_dirty": bool(diff or untracked),
            "git_diff_sha256": digest.hexdigest()}


def _machine() -> dict:
    """Where a run was created (its speed figures depend on it)."""
    return {"platform": platform.platform(), "processor": platform.machine(),
            "cores": os.cpu_count()}


def _versions() -> dict:
    versions = {"dart_reach": __version__, "python": platform.python_version()}
    for pkg in ("dartpy", "numpy", "scipy", "polars", "rerun-sdk"):
        try:
            versions[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            versions[pkg] = None
    return versions


# ---------------------------------------------------------------- the run
@dataclass
class Progress:
    """What a progress display is told after each generation."""

    condition: str
    phase: str
    generation: int
    generations: int
    replications: int
    best: float
    mean: float
    done_generations: int
    total_generations: int
    elapsed_s: float

    @property
    def eta_s(self) -> float:
        if self.done_generations == 0:
            return float("nan")
        return self.elapsed_s / self.done_generations * (
            self.total_generations - self.done_generations)


class Run:
    """A run directory: creates it, or reopens it to resume."""

    def __init__(self, out: Path, conditions: list[Condition], settings: Settings,
                 resume: bool = False, command: str | None = None):
        self.out = Path(out)
        self.conditions = conditions
        self.settings = settings
        self.manifest = {
            "format": MANIFEST_FORMAT,
            "conditions": [c.to_dict() for c in conditions],
            "settings": settings.to_json(),
        }
        manifest_path = self.out / "manifest.json"
        if manifest_path.exists():
            if not resume:
                raise RunError(f"{self.out} already holds a run (manifest.json); pass "
                               f"resume=True to continue it or choose another out",
                               cli=f"{self.out} already holds a run (manifest.json); use "
                                   f"--resume to continue it or choose another --out")
            self._check_same_run(manifest_path)
        elif self.out.exists() and any(p.name != LOCK_NAME for p in self.out.iterdir()):
            raise RunError(f"{self.out} is not empty and holds no run: choose another out",
                           cli=f"{self.out} is not empty and holds no run: choose another "
                               f"--out")
        else:
            if resume:
                raise RunError(f"nothing to resume: {self.out} holds no run")
            full = dict(self.manifest, created=time.strftime("%Y-%m-%dT%H:%M:%S%z"),
                        versions=_versions(), **git_state(),
                        machine=_machine(), command=command,
                        scene=scene_of(settings.world.sectors) or "custom (see settings.world)",
                        seeds={"root": settings.seed,
                               "tree": "SeedSequence(seed, spawn_key=(phase key[:8] as int, "
                                       "replication, purpose 0 init|1 mutate|2 evaluate, "
                                       "generation, individual))"})
            atomic_write(manifest_path, lambda p: p.write_text(json.dumps(full, indent=2)))
        self.stats = self._committed_stats()
        self._model: RobotModel | None = None

    @classmethod
    def open(cls, out) -> "Run":
        """Reopen an existing run directory to analyse it. Raises ``RunError`` naming the file
        and the problem when it is missing, not a run, or written by an incompatible version."""
        out = Path(out)
        if not out.is_dir():
            raise RunError(f"{out}: no such run directory" if not out.exists()
                           else f"{out}: not a directory")
        path = out / "manifest.json"
        if not path.is_file():
            raise RunError(f"{out}: not a run directory (no manifest.json)")
        m = _read_manifest(path)
        try:
            conditions = []
            for c in m["conditions"]:
                plain = dict(c, phases=[{k: v for k, v in p.items()
                                         if k not in ("generations", "key")}
                                        for p in c["phases"]])
                condition = condition_from_dict(plain, str(path))
                if [p.key for p in condition.phases] != [p["key"] for p in c["phases"]]:
                    raise ValueError("its phase keys are computed differently")
                conditions.append(condition)
            settings = Settings.from_json(m["settings"])
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise RunError(f"{path}: malformed or written by an incompatible version "
                           f"({type(exc).__name__}: {exc})") from None
        return cls(out, conditions, settings, resume=True)

    def record_session(self, command: str | None, workers: int | None = None) -> None:
        """Append to the manifest's ``sessions`` the source this invocation trains with (its
        revision, whether the tree was dirty, the hash of its diff), when and how it started,
        on how many ``workers`` (local processes, or the Ray cluster's CPUs when it started:
        with the generations' ``wall_s``, the core-seconds a generation took) and the
        generations committed before it: a run resumed over days records every revision it
        was trained with."""
        path = self.out / "manifest.json"
        manifest = _read_manifest(path)
        done = {f"{c.name}/{p.name}": int(self.stats.filter(pl.col("phase_key") == p.key)
                                          ["generation"].max() or 0)
                for c, p in self.unique_phases()}
        manifest.setdefault("sessions", []).append(
            {"started": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "command": command,
             **git_state(), "generations_done": done,
             **({"workers": workers} if workers is not None else {})})
        atomic_write(path, lambda p: p.write_text(json.dumps(manifest, indent=2)))

    def unfinished(self) -> list[str]:
        """The phases not trained to the end, as "condition/phase"."""
        return [f"{c.name}/{p.name}" for c in self.conditions for p in c.phases
                if not self.final_path(p).exists()]

    def _check_same_run(self, manifest_path: Path) -> None:
        old = _read_manifest(manifest_path)
        for key in ("conditions", "settings"):
            asked = json.loads(json.dumps(self.manifest[key]))
            if old.get(key) != asked:
                where, there, here = _first_difference(old.get(key), asked, key)
                what = f"{where} is {there} in the run there, {here} now"
                raise RunError(f"{manifest_path}: the run there was made with other {key} "
                               f"({what}); resume it with the same conditions and Settings",
                               cli=f"{manifest_path}: the run there was made with other {key} "
                                   f"({what}); resume it with the same command line")

    # -------------------------------------------------------------- stats and checkpoints
    def _committed_stats(self) -> pl.DataFrame:
        """The statistics rows of every committed generation, from the phases' checkpoints,
        in training order."""
        tables = [pl.DataFrame(schema=STATS_SCHEMA)]
        for _, phase in self.unique_phases():
            loaded = self._load_checkpoint(phase)
            if loaded is not None:
                tables.append(loaded[1])
        return pl.concat(tables)

    def _save_stats(self) -> None:
        atomic_write(self.out / "generations.parquet", lambda p: self.stats.write_parquet(p))
        write_rrd(self.out / "training.rrd", training_rrd(self.stats, self.out.name))

    def repair(self) -> None:
        """Before training on: check that the directory agrees with its committed state,
        rebuild what is derived from it (generations.parquet, training.rrd, best.parquet).
        Raises ``RunError`` naming the file when something cannot be rebuilt. Call it while
        holding the directory's lock."""
        recorded = self._recorded_generations()
        for _, phase in self.unique_phases():
            committed = self.stats.filter(pl.col("phase_key") == phase.key)
            done = int(committed["generation"].max() or 0)
            checkpoint = self._checkpoint_path(phase)
            if self.final_path(phase).exists() and done < phase.generations:
                raise RunError(f"{checkpoint}: missing or older than {self.final_path(phase).name}"
                               f" (the statistics of phase {phase.name} cannot be rebuilt); "
                               f"restore it or start a new run")
            if recorded.get(phase.key, 0) > done:
                raise RunError(f"{checkpoint}: missing or older than generations.parquet "
                               f"({recorded[phase.key]} generations of phase {phase.name} "
                               f"recorded, {done} in the checkpoint); restore it or start a new "
                               f"run")
            if self.final_path(phase).exists() and not (self.phase_dir(phase)
                                                          / "best.parquet").exists():
                self._save_best_table(phase, *self.load_final(phase))
        self._save_stats()

    def _recorded_generations(self) -> dict[str, int]:
        """Generations per phase key that generations.parquet records ({} if it is missing or
        unreadable: it is rebuilt)."""
        try:
            table = pl.read_parquet(self.out / "generations.parquet")
            return dict(table.group_by("phase_key").agg(pl.col("generation").max()).iter_rows())
        except Exception:  # missing or damaged: derived, so rebuilt
            return {}

    def phase_dir(self, phase: Phase) -> Path:
        return self.out / "phases" / f"{phase.name}-{phase.key[:8]}"

    def _checkpoint_path(self, phase: Phase) -> Path:
        return self.phase_dir(phase) / "checkpoint.npz"

    def _commit(self, phase: Phase, states: list[GAState]) -> None:
        """Commit a generation: the phase's GA states and its statistics rows, in one atomic
        checkpoint; then the files derived from it."""
        arrays = {"phase_key": np.array(phase.key)}
        for r, s in enumerate(states):
            arrays.update({f"rep{r}/{k}": v for k, v in state_to_arrays(s).items()})
        rows = self.stats.filter(pl.col("phase_key") == phase.key)
        arrays.update({f"stats/{c}": np.array(rows[c].to_list(), dtype=np.str_)
                       if t == pl.Utf8 else rows[c].to_numpy() for c, t in STATS_SCHEMA.items()})
        atomic_write(self._checkpoint_path(phase), lambda p: _savez(p, arrays))
        self._save_stats()

    def _load_checkpoint(self, phase: Phase) -> tuple[list[GAState], pl.DataFrame] | None:
        """The GA states and statistics rows of a phase's last committed generation."""
        path = self._checkpoint_path(phase)
        if not path.exists():
            return None
        try:
            with np.load(path, allow_pickle=False) as d:
                if str(d["phase_key"]) != phase.key:
                    raise RunError(f"{path}: checkpoint of another phase")
                states = [state_from_arrays({k.split("/", 1)[1]: d[k] for k in d.files
                                             if k.startswith(f"rep{r}/")})
                          for r in range(self.settings.replications)]
                if "stats/generation" in d.files:
                    rows = pl.DataFrame({c: d[f"stats/{c}"] for c in STATS_SCHEMA},
                                        schema=STATS_SCHEMA)
                else:  # written before checkpoints carried their statistics
                    rows = self._legacy_rows(phase, states[0].generation)
        except RunError:
            raise
        except Exception as exc:
            raise RunError(f"{path}: corrupted or foreign checkpoint ({exc})") from None
        if len({s.generation for s in states}) != 1:
            raise RunError(f"{path}: replications at different generations")
        if rows.height != states[0].generation * len(states):
            raise RunError(f"{path}: its statistics do not match its generation")
        return states, rows

    def _legacy_rows(self, phase: Phase, generation: int) -> pl.DataFrame:
        """A phase's statistics rows up to ``generation`` from generations.parquet, for a
        checkpoint written before checkpoints carried them."""
        path = self.out / "generations.parquet"
        table = pl.read_parquet(path) if path.exists() else pl.DataFrame(schema=STATS_SCHEMA)
        return table.filter((pl.col("phase_key") == phase.key)
                            & (pl.col("generation") <= generation))

    def final_path(self, phase: Phase) -> Path:
        return self.phase_dir(phase) / "final.npz"

    def _save_final(self, condition: Condition, phase: Phase, states: list[GAState]) -> None:
        pop = self.settings.ga.population
        ranked = [best_k(s, pop) for s in states]
        genomes = np.stack([g for g, _ in ranked])
        fitness = np.stack([f for _, f in ranked])
        self._save_best_table(phase, genomes, fitness)  # derived: before the commit
        atomic_write(self.final_path(phase), lambda p: _savez(p, {
            "population": genomes, "fitness": fitness, "best": genomes[:, 0],
            "phase_key": np.array(phase.key)}))

    def _save_best_table(self, phase: Phase, genomes: np.ndarray, fitness: np.ndarray) -> None:
        pop = genomes.shape[1]
        table = pl.DataFrame({
            "phase": [phase.name] * genomes.shape[0] * pop,
            "phase_key": [phase.key] * genomes.shape[0] * pop,
            "replication": np.repeat(np.arange(genomes.shape[0]), pop),
            "rank": np.tile(np.arange(pop), genomes.shape[0]),
            "fitness": fitness.reshape(-1),
            "genome": [g.tolist() for g in genomes.reshape(-1, genomes.shape[-1])],
        }, schema_overrides={"genome": pl.List(pl.UInt8)})
        atomic_write(self.phase_dir(phase) / "best.parquet", lambda p: table.write_parquet(p))

    def load_final(self, phase: Phase) -> tuple[np.ndarray, np.ndarray]:
        """Final populations (R, P, L) and lifetime fitness (R, P) of a trained phase, best
        first within each replication."""
        path = self.final_path(phase)
        try:
            with np.load(path, allow_pickle=False) as d:
                return d["population"], d["fitness"]
        except Exception as exc:
            raise RunError(f"{path}: unreadable phase result ({exc})") from None

    # -------------------------------------------------------------- training
    def train(self, evaluator: Evaluator, progress: Callable[[Progress], None] | None = None,
              record_every: int = 0, snapshot_every: int = 0) -> None:
        """Train every phase of every condition not trained yet. After each generation the
        fitness statistics are also written to ``training.rrd``; with ``record_every`` = K > 0,
        one trial of the best individual of each replication is recorded every K generations
        and at the end of each phase (``phases/<phase>/best/gen<G>-rep<R>.rrd``); with
        ``snapshot_every`` = K > 0, the best ``SNAPSHOT_ROBOTS`` of each replication are kept
        after the generations of ``snapshot_due`` (``phases/<phase>/snapshots/gen<G>.npz``).
        Neither changes what is trained."""
        if record_every < 0:
            raise ValueError(f"record_every must be >= 0, got {record_every}")
        if snapshot_every < 0:
            raise ValueError(f"snapshot_every must be >= 0, got {snapshot_every}")
        s = self.settings
        total = sum(p.generations for _, p in self.unique_phases())
        done = sum(p.generations for _, p in self.unique_phases()
                   if self.final_path(p).exists())
        t_start, done_at_start = time.monotonic(), done
        for condition in self.conditions:
            previous: Phase | None = None
            for phase in condition.phases:
                if not self.final_path(phase).exists():
                    loaded = self._load_checkpoint(phase)
                    if loaded is None:
                        states = self._initial_states(phase, previous)
                    else:
                        states = loaded[0]
                        # Trained by an earlier process: neither done here nor left to do.
                        done += states[0].generation
                        done_at_start += states[0].generation
                    trial = trial_config(phase, s)
                    mask = free_mask(phase.free_groups)
                    groups = as_groups(phase.free_groups)
                    while states[0].generation < phase.generations:
                        g = states[0].generation
                        t0 = time.monotonic()
                        states, rows = self._generation(evaluator, condition, phase, states,
                                                        trial, mask, groups)
                        wall = time.monotonic() - t0
                        self.stats = pl.concat([self.stats, pl.DataFrame(
                            [dict(r, wall_s=wall) for r in rows], schema=STATS_SCHEMA)])
                        if record_every and (g + 1 == phase.generations
                                             or (g + 1) % record_every == 0):
                            self.record_best(condition, phase, states, trial)
                        if snapshot_due(g + 1, phase.generations, snapshot_every):
                            self.save_snapshot(phase, states)
                        self._commit(phase, states)
                        done += 1
                        if progress:
                            progress(Progress(
                                condition.name, phase.name, g + 1, phase.generations,
                                s.replications, max(r["best"] for r in rows),
                                float(np.mean([r["mean"] for r in rows])), done - done_at_start,
                                total - done_at_start, time.monotonic() - t_start))
                    self._save_final(condition, phase, states)
                previous = phase

    def record_best(self, condition: Condition, phase: Phase, states: list[GAState],
                    trial: TrialConfig) -> list[Path]:
        """Record one trial of the best individual of each replication (at a random position
        drawn from the run's seed tree), as ``phases/<phase>/best/gen<G>-rep<R>.rrd``."""
        runner = worker_trial(self.settings.world, trial)
        if self._model is None:
            self._model = RobotModel(runner.world)
        paths = []
        for r, state in enumerate(states):
            g = state.generation
            genome = best_k(state, 1)[0][0]
            network = network_for(decode(genome, as_groups(phase.free_groups)), trial)
            seed = _seed(self.settings, phase, r, _RECORD, g)
            sector, position = trial_positions(runner.world, np.random.default_rng(seed), 1)[0]
            data = runner.run(network, sector, position)
            info = TrialInfo(condition.name, phase.name, r, 0, sector, 0,
                             trial_seed=f"SeedSequence({seed.entropy}, {seed.spawn_key})",
                             generation=g)
            paths.append(write_rrd(self.phase_dir(phase) / "best" / f"gen{g:04d}-rep{r:02d}.rrd",
                                   trial_rrd(data, info, self._model,
                                             self.settings.world.control_dt)))
        return paths

    def snapshot_path(self, phase: Phase, generation: int) -> Path:
        return self.phase_dir(phase) / "snapshots" / f"gen{generation:04d}.npz"

    def save_snapshot(self, phase: Phase, states: list[GAState]) -> Path:
        """Keep the best ``SNAPSHOT_ROBOTS`` genomes of every replication and their lifetime
        fitness after the states' generation (written atomically, before the generation's
        commit: a redone generation writes the same file again)."""
        k = min(SNAPSHOT_ROBOTS, self.settings.ga.population)
        ranked = [best_k(s, k) for s in states]
        path = self.snapshot_path(phase, states[0].generation)
        atomic_write(path, lambda p: _savez(p, {
            "genomes": np.stack([g for g, _ in ranked]),
            "fitness": np.stack([f for _, f in ranked]),
            "generation": np.array(states[0].generation), "phase_key": np.array(phase.key)}))
        return path

    def snapshots(self, phase: Phase) -> list[tuple[int, np.ndarray, np.ndarray]]:
        """(generation, genomes (R, k, L), lifetime fitness (R, k)) of every snapshot a phase
        kept, in generation order; [] for a run made without snapshots."""
        out = []
        for path in sorted((self.phase_dir(phase) / "snapshots").glob("gen*.npz")):
            try:
                with np.load(path, allow_pickle=False) as d:
                    if str(d["phase_key"]) != phase.key:
                        raise ValueError("a snapshot of another phase")
                    out.append((int(d["generation"]), d["genomes"], d["fitness"]))
            except Exception as exc:
                raise RunError(f"{path}: unreadable snapshot ({exc})") from None
        return out

    def status(self) -> pl.DataFrame:
        """Where training stands (``dart-reach status``): one row per phase trained in this run
        and replication: condition, phase, replication, generations (committed), of (the
        phase's budget), best and mean fitness at the last committed generation, and wall_h,
        the phase's wall time so far in hours (a generation of all replications counted
        once)."""
        rows = []
        for c, p in self.unique_phases():
            stats = self.stats.filter(pl.col("phase_key") == p.key)
            wall = float(stats.group_by("generation", maintain_order=True)
                         .agg(pl.col("wall_s").first())["wall_s"].sum()) / 3600
            for r in range(self.settings.replications):
                last = stats.filter(pl.col("replication") == r).sort("generation").tail(1)
                done = last.height > 0
                rows.append({"condition": c.name, "phase": p.name, "replication": r,
                             "generations": int(last["generation"][0]) if done else 0,
                             "of": p.generations,
                             "best": float(last["best"][0]) if done else float("nan"),
                             "mean": float(last["mean"][0]) if done else float("nan"),
                             "wall_h": wall})
        return pl.DataFrame(rows)

    def unique_phases(self) -> list[tuple[Condition, Phase]]:
        """Each phase trained in this run once (a phase shared by conditions comes with the
        first of them), in training order."""
        seen: dict[str, tuple[Condition, Phase]] = {}
        for c in self.conditions:
            for p in c.phases:
                seen.setdefault(p.key, (c, p))
        return list(seen.values())

    def _initial_states(self, phase: Phase, previous: Phase | None) -> list[GAState]:
        s = self.settings
        pop = s.ga.population
        if previous is None:
            return [init_state(random_genome(np.random.default_rng(_seed(s, phase, r, _INIT)),
                                             pop)) for r in range(s.replications)]
        finals, _ = self.load_final(previous)
        merged = transition_population(list(finals), n=pop // s.replications, population=pop)
        newly_free = as_groups(phase.free_groups) - as_groups(previous.free_groups)
        merged = np.stack([release(g, newly_free) for g in merged])
        return [init_state(merged) for _ in range(s.replications)]

    def _generation(self, evaluator, condition, phase, states, trial, mask, groups):
        """One generation of every replication, evaluated in one batch."""
        s = self.settings
        asked, candidates = [], []
        for r, state in enumerate(states):
            g = state.generation
            cands, state = ask(state, s.ga, mask,
                               np.random.default_rng(_seed(s, phase, r, _MUTATE, g)))
            asked.append(state)
            candidates.append(cands)
        jobs = [Job(genome=c, free_groups=frozenset(groups), trial=trial, world=s.world,
                    seed=(s.seed, _phase_id(phase), r, _EVALUATE, states[r].generation, i))
                for r, cands in enumerate(candidates) for i, c in enumerate(cands)]
        fitness = evaluator.map(jobs)
        new_states, rows, k = [], [], 0
        for r, state in enumerate(asked):
            n = candidates[r].shape[0]
            f = fitness[k:k + n]
            k += n
            new_states.append(tell(state, f))
            rows.append(dict(condition=condition.name, phase=phase.name, phase_key=phase.key,
                             replication=r, generation=state.generation + 1,
                             **generation_stats(f)))
        return new_states, rows


def _first_difference(a, b, path: str) -> tuple[str, str, str]:
    """Where two JSON values first differ: (dotted path, a's value, b's value). A condition's
    phase is named by its name (``conditions.standard.gross.generations``), a setting by its
    field (``settings.trials``)."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in list(a) + [k for k in b if k not in a]:
            if a.get(k) != b.get(k):
                return _first_difference(a.get(k), b.get(k), f"{path}.{k}")
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            if x != y:
                name = x.get("name") if isinstance(x, dict) and x.get("name") == (
                    y.get("name") if isinstance(y, dict) else None) else None
                return _first_difference(x, y, f"{path}.{name}" if name else f"{path}[{i}]")
    if isinstance(a, list) and isinstance(b, list):
        return f"{path} (how many)", str(len(a)), str(len(b))
    return path, json.dumps(a), json.dumps(b)


def _read_manifest(path: Path) -> dict:
    """A run's manifest as a dict of this version's format, or ``RunError`` naming it."""
    try:
        m = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise RunError(f"{path}: unreadable manifest ({exc})") from None
    if not isinstance(m, dict):
        raise RunError(f"{path}: malformed manifest (a JSON {type(m).__name__}, not an object)")
    if m.get("format") != MANIFEST_FORMAT:
        raise RunError(f"{path}: written by an incompatible version (format "
                       f"{m.get('format')}, this version reads {MANIFEST_FORMAT})")
    return m


def _savez(path: Path, arrays: dict) -> None:
    with open(path, "wb") as f:
        np.savez(f, **arrays)


def train(conditions: list[Condition], settings: Settings, out: Path, workers: int | None = None,
          ray_address: str | None = None, resume: bool = False,
          progress: Callable[[Progress], None] | bool = True, record_every: int = 0,
          command: str | None = None, snapshot_every: int = 0) -> Run:
    """Train ``conditions`` into the run directory ``out`` (the function the CLI calls;
    ``command``, the command line that made the run, goes into a new run's manifest).
    ``progress``: True (default) shows a progress bar (a widget in Jupyter, plain lines where
    the output is not a terminal), False nothing, a callable is told each ``Progress``."""
    names = [c.name for c in conditions]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise RunError(f"two conditions are named {', '.join(twice)}: a run's conditions need "
                       f"distinct names")
    out = Path(out)
    if resume and not (out / "manifest.json").is_file():
        raise RunError(f"nothing to resume: {out} holds no run")
    with DirectoryLock(out):
        remove_temporaries(out)  # of a killed write: the lock says no one else is writing
        run = Run(out, conditions, settings, resume=resume, command=command)
        if resume:
            run.repair()
        with contextlib.ExitStack() as stack:  # closed in reverse: the bar, then the workers
            evaluator = make_evaluator(workers, ray_address)
            stack.callback(evaluator.close)
            run.record_session(command, evaluator.workers)
            bar = training_bar() if progress is True else None
            if bar is not None:
                stack.callback(bar.close)
            run.train(evaluator, bar or progress or None, record_every, snapshot_every)
    return run
