"""Training a condition: phases, replications, transitions and checkpoints (paper sections
III-C, III-D, IV-C). The run directory it writes is described in ``rundir``.

A run trains one or more conditions in one directory. Each phase of a condition is trained with
``replications`` independent runs of the GA; the first phase starts from random genomes, every
later phase from the best ``population / replications`` genomes of each replication of the
previous phase (the best 2 of each of 10 in the paper), with the maturational changes of the new
phase. A phase shared by several conditions (same content, same preceding phases: the same
``Phase.key``) is trained once. Every random draw comes from the run's seed tree
(``settings.seed_sequence``).

A generation is committed by its phase's checkpoint alone, written atomically (a temporary file
renamed over the old one), its SHA-256 committed in the run's ledger around the rename
(``integrity.recorded_write``; finals and snapshots too), so that a damaged file is refused
when it is read. Everything a generation adds is either written before that commit
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
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import polars as pl

from .backends import Backend, Job, make_backend, worker_trial
from .conditions import Condition, Phase
from .ga import (GAState, ask, best_k, generation_stats, init_state, state_to_arrays, tell,
                 transition_population)
from .genome import as_groups, decode, free_mask, random_genome, release
from .. import integrity
from ..integrity import recorded_write
from .provenance import cpu, git_state, machine, versions
from .rundir import (STATS_SCHEMA, RunDirectory, RunError, check_same_run, described_run,
                     manifest_of, read_manifest)
from .settings import (SEED_INIT, SEED_LIFETIME, SEED_MUTATE, SEED_RECORD, SNAPSHOT_ROBOTS,
                       Settings, seed_address, seed_sequence, snapshot_due, trial_config)
from ..files import LOCK_NAME, DirectoryLock, remove_temporaries, write_parquet
from ..model.scenes import scene_of
from ..model.task import TrialConfig, network_for, trial_positions
from ..model.versions import Numerics, numerics_of
from ..pinning import require_pinned_kernels
from ..progress import training_bar
from ..recording.rrd import RobotModel, TrialInfo, training_rrd, trial_rrd, write_rrd


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
    #: the generation's tasks on the back-end and the CPU seconds the driver (this process)
    #: spent submitting and collecting them (``backends.MapCost``)
    tasks: int = 0
    driver_cpu_s: float = float("nan")

    @property
    def eta_s(self) -> float:
        if self.done_generations == 0:
            return float("nan")
        return self.elapsed_s / self.done_generations * (
            self.total_generations - self.done_generations)


class Trainer(RunDirectory):
    """A run directory being trained: creates it, or reopens it to resume (``resume``)."""

    def __init__(self, out: Path, conditions: list[Condition], settings: Settings,
                 resume: bool = False, command: str | None = None):
        out = Path(out)
        if any(len(c.phases) > 1 for c in conditions) and settings.ga.population % \
                settings.replications:
            raise ValueError(
                f"the population ({settings.ga.population}) must be a multiple of the number of "
                f"replications ({settings.replications}) when a condition has a phase after "
                f"the first: it starts from the best population / replications genomes of each "
                f"(section III-D)")
        manifest = manifest_of(conditions, settings)
        manifest_path = out / "manifest.json"
        if manifest_path.exists():
            if not resume:
                raise RunError(f"{out} already holds a run (manifest.json); pass "
                               f"resume=True to continue it or choose another out",
                               cli=f"{out} already holds a run (manifest.json); use "
                                   f"--resume to continue it or choose another --out")
            check_same_run(manifest_path, manifest)
        elif out.exists() and any(p.name not in (LOCK_NAME, integrity.LEDGER_FILE)
                                  for p in out.iterdir()):
            raise RunError(f"{out} is not empty and holds no run: choose another out",
                           cli=f"{out} is not empty and holds no run: choose another "
                               f"--out")
        else:
            if resume:
                raise RunError(f"nothing to resume: {out} holds no run")
            full = dict(manifest, created=time.strftime("%Y-%m-%dT%H:%M:%S%z"),
                        versions=versions(), **git_state(),
                        machine=machine(), command=command,
                        scene=scene_of(settings.world.sectors) or "custom (see settings.world)",
                        model=settings.model_record(),
                        seeds={"root": settings.seed,
                               "tree": "SeedSequence(seed, spawn_key=(phase key[:8] as int, "
                                       "replication, purpose 0 init|1 mutate|2 evaluate, "
                                       "generation, individual))"})
            recorded_write(out, manifest_path, lambda p: p.write_text(json.dumps(full, indent=2)))
        super().__init__(out, conditions, settings)
        self._model: RobotModel | None = None

    @classmethod
    def open(cls, out) -> "Trainer":
        """Reopen an existing run directory to train it on (``resume=True``). Raises
        ``RunError`` as ``RunDirectory.open`` does."""
        return cls(*described_run(out), resume=True)

    def record_session(self, command: str | None, workers: int | None = None) -> None:
        """Append to the manifest's ``sessions`` the source this invocation trains with (its
        revision, whether the tree was dirty, the hash of its diff), when and how it started,
        on how many ``workers`` (local processes, or the Ray cluster's CPUs when it started:
        with the generations' ``wall_s``, the core-seconds a generation took), on which
        ``cpu`` (``provenance.cpu``; this process's, not a Ray cluster's) and the generations
        committed before it: a run resumed over days records every revision and machine it
        was trained with."""
        path = self.out / "manifest.json"
        manifest = read_manifest(path)
        done = {f"{c.name}/{p.name}": int(self.stats.filter(pl.col("phase_key") == p.key)
                                          ["generation"].max() or 0)
                for c, p in self.unique_phases()}
        manifest.setdefault("sessions", []).append(
            {"started": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "command": command,
             **git_state(), "cpu": cpu(), "generations_done": done,
             **({"workers": workers} if workers is not None else {})})
        recorded_write(self.out, path, lambda p: p.write_text(json.dumps(manifest, indent=2)))

    # -------------------------------------------------------------- commit and repair
    def _save_stats(self) -> None:
        recorded_write(self.out, self.out / "generations.parquet",
                       lambda p: write_parquet(self.stats, p))
        write_rrd(self.out / "training.rrd", training_rrd(self.stats, self.out.name))

    def repair(self) -> None:
        """Before training on: check that the directory agrees with its committed state,
        rebuild what is derived from it (generations.parquet, training.rrd, best.parquet).
        Raises ``RunError`` naming the file when something cannot be rebuilt, and
        ``integrity.DamagedFile`` (before writing anything) when a file of the run's state is
        damaged. Call it while holding the directory's lock."""
        self.verify()
        recorded = self._recorded_generations()
        for _, phase in self.unique_phases():
            committed = self.stats.filter(pl.col("phase_key") == phase.key)
            done = int(committed["generation"].max() or 0)
            checkpoint = self.checkpoint_path(phase)
            if self.final_path(phase).exists() and done < phase.generations:
                raise RunError(f"{checkpoint}: missing or older than {self.final_path(phase).name}"
                               f" (the statistics of phase {phase.name} cannot be rebuilt); "
                               f"restore it or start a new run")
            if recorded.get(phase.key, 0) > done:
                raise RunError(f"{checkpoint}: missing or older than generations.parquet "
                               f"({recorded[phase.key]} generations of phase {phase.name} "
                               f"recorded, {done} in the checkpoint); restore it or start a new "
                               f"run")
        integrity.settle(self.out)  # checked: only now may anything on disk change
        for _, phase in self.unique_phases():
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

    def _commit(self, phase: Phase, states: list[GAState]) -> None:
        """Commit a generation: the phase's GA states and its statistics rows, in one atomic
        checkpoint; then the files derived from it."""
        arrays = {"phase_key": np.array(phase.key)}
        for r, s in enumerate(states):
            arrays.update({f"rep{r}/{k}": v for k, v in state_to_arrays(s).items()})
        rows = self.stats.filter(pl.col("phase_key") == phase.key)
        arrays.update({f"stats/{c}": np.array(rows[c].to_list(), dtype=np.str_)
                       if t == pl.Utf8 else rows[c].to_numpy() for c, t in STATS_SCHEMA.items()})
        recorded_write(self.out, self.checkpoint_path(phase), lambda p: _savez(p, arrays))
        self._save_stats()

    def _save_final(self, condition: Condition, phase: Phase, states: list[GAState]) -> None:
        pop = self.settings.ga.population
        ranked = [best_k(s, pop) for s in states]
        genomes = np.stack([g for g, _ in ranked])
        fitness = np.stack([f for _, f in ranked])
        self._save_best_table(phase, genomes, fitness)  # derived: before the commit
        recorded_write(self.out, self.final_path(phase), lambda p: _savez(p, {
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
        recorded_write(self.out, self.phase_dir(phase) / "best.parquet",
                       lambda p: write_parquet(table, p))

    # -------------------------------------------------------------- training
    def train(self, backend: Backend, progress: Callable[[Progress], None] | None = None,
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
            for index, phase in enumerate(condition.phases):
                if not self.final_path(phase).exists():
                    loaded = self.load_checkpoint(phase)
                    if loaded is None:
                        states = self._initial_states(condition, index)
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
                        states, rows = self._generation(backend, condition, phase, states,
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
                            cost = backend.last_cost
                            progress(Progress(
                                condition.name, phase.name, g + 1, phase.generations,
                                s.replications, max(r["best"] for r in rows),
                                float(np.mean([r["mean"] for r in rows])), done - done_at_start,
                                total - done_at_start, time.monotonic() - t_start,
                                cost.tasks, cost.driver_cpu_s))
                    self._save_final(condition, phase, states)

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
            seed = seed_sequence(self.settings, phase, r, SEED_RECORD, g)
            sector, position = trial_positions(runner.world, np.random.default_rng(seed), 1)[0]
            data = runner.run(network, sector, position)
            info = TrialInfo(condition.name, phase.name, r, 0, sector, 0,
                             trial_seed=f"SeedSequence({seed.entropy}, {seed.spawn_key})",
                             generation=g)
            paths.append(write_rrd(self.phase_dir(phase) / "best" / f"gen{g:04d}-rep{r:02d}.rrd",
                                   trial_rrd(data, info, self._model,
                                             self.settings.world.control_dt)))
        return paths

    def save_snapshot(self, phase: Phase, states: list[GAState]) -> Path:
        """Keep the best ``SNAPSHOT_ROBOTS`` genomes of every replication and their lifetime
        fitness after the states' generation (written atomically, before the generation's
        commit: a redone generation writes the same file again)."""
        k = min(SNAPSHOT_ROBOTS, self.settings.ga.population)
        ranked = [best_k(s, k) for s in states]
        path = self.snapshot_path(phase, states[0].generation)
        recorded_write(self.out, path, lambda p: _savez(p, {
            "genomes": np.stack([g for g, _ in ranked]),
            "fitness": np.stack([f for _, f in ranked]),
            "generation": np.array(states[0].generation), "phase_key": np.array(phase.key)}))
        return path

    def _initial_states(self, condition: Condition, index: int) -> list[GAState]:
        """Phase ``index``'s first populations: random for the first phase, else the merged
        best of the phase before, the genes it frees released (III-D)."""
        s = self.settings
        pop = s.ga.population
        if index == 0:
            phase = condition.phases[0]
            return [init_state(random_genome(np.random.default_rng(
                seed_sequence(s, phase, r, SEED_INIT)), pop)) for r in range(s.replications)]
        finals, _ = self.load_final(condition.phases[index - 1])
        merged = transition_population(list(finals), n=pop // s.replications, population=pop)
        merged = np.stack([release(g, condition.newly_free(index)) for g in merged])
        return [init_state(merged) for _ in range(s.replications)]

    def _generation(self, backend, condition, phase, states, trial, mask, groups):
        """One generation of every replication, its lifetimes run in one batch."""
        s = self.settings
        asked, candidates = [], []
        for r, state in enumerate(states):
            g = state.generation
            cands, state = ask(state, s.ga, mask,
                               np.random.default_rng(seed_sequence(s, phase, r, SEED_MUTATE, g)))
            asked.append(state)
            candidates.append(cands)
        jobs = [Job(genome=c, free_groups=frozenset(groups), trial=trial, world=s.world,
                    seed=seed_address(s, phase, r, SEED_LIFETIME, states[r].generation, i))
                for r, cands in enumerate(candidates) for i, c in enumerate(cands)]
        fitness = backend.map(jobs)
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


def _savez(path: Path, arrays: dict) -> None:
    with open(path, "wb") as f:
        np.savez(f, **arrays)


def train(conditions: list[Condition], settings: Settings, out: Path, workers: int | None = None,
          ray_address: str | None = None, ray_block: int | None = None, resume: bool = False,
          progress: Callable[[Progress], None] | bool = True, record_every: int = 0,
          command: str | None = None, snapshot_every: int = 0) -> Trainer:
    """Train ``conditions`` into the run directory ``out`` (the function the CLI calls;
    ``command``, the command line that made the run, goes into a new run's manifest;
    ``ray_block``: trials per Ray task, ``backends.RayBackend``).
    ``progress``: True (default) shows a progress bar (a widget in Jupyter, plain lines where
    the output is not a terminal), False nothing, a callable is told each ``Progress``."""
    names = [c.name for c in conditions]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise RunError(f"two conditions are named {', '.join(twice)}: a run's conditions need "
                       f"distinct names")
    out = Path(out)
    if numerics_of(settings.model_version) is Numerics.REFERENCE:
        require_pinned_kernels()  # refused before anything is written: the run can start again
    if resume and not (out / "manifest.json").is_file():
        raise RunError(f"nothing to resume: {out} holds no run")
    if resume:  # a damaged file refused before anything is written, the lock file included
        done = RunDirectory(*described_run(out))
        done.verify()
        if not done.unfinished() and not done.unsettled():  # finished: nothing written
            return Trainer(out, conditions, settings, resume=True, command=command)
    with DirectoryLock(out):
        remove_temporaries(out)  # of a killed write: the lock says no one else is writing
        run = Trainer(out, conditions, settings, resume=resume, command=command)
        if resume:
            run.repair()
            if not run.unfinished():  # finished, its derived files rebuilt: no session
                return run
        with contextlib.ExitStack() as stack:  # closed in reverse: the bar, then the workers
            backend = make_backend(workers, ray_address, ray_block)
            stack.callback(backend.close)
            run.record_session(command, backend.workers)
            bar = training_bar() if progress is True else None
            if bar is not None:
                stack.callback(bar.close)
            run.train(backend, bar or progress or None, record_every, snapshot_every)
    return run
