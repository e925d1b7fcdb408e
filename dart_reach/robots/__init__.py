"""Evolved robots shipped with the package, so that a user sees a trained robot in seconds
(``dart-reach watch``) and benchmarks and tests have robots that move and touch the ball like
evolving ones, not only random networks.

Each JSON file of this folder holds robots of one phase of one condition with their
provenance (``ROBOTS_FORMAT``)::

    format         1
    what           a sentence: which run, which population
    command        the command line that trained them
    git_revision   the revision of dart_reach that trained them
    run            the name of the run directory they come from (``dart-reach robots``
                   lists the shipped runs; files written elsewhere before it may lack it)
    model_version  the model version the run was trained under (files without it: 1)
    budget         generations, replications, trials, steps, physics_dt, seed, scene and
                   sectors (where the ball hung: ``world.SectorConfig``)
    phase          condition, phase (a shipped condition's phase), free_groups, acuity,
                   reflexes (checked against the shipped condition when loaded)
    replication    per genome, its replication in the run
    lifetime_fitness  per genome, its lifetime fitness (mean p_multimodal over its evaluations)
    genomes_hex    per genome, its uint8 genes as hexadecimal

``robots()`` reads them all (``index()`` lists the files); ``export_robots()`` writes such a
file from one phase of a trained run, ``export_run()`` one per phase of every condition of a
run: a file dropped into this folder is shipped from then on. A file is named after the run
and the phase it came from (``<run>-<condition>-<phase>.json``; ``run`` in its provenance):
those shipped hold the best 2 robots of each replication of every phase of the project's
replication runs (docs/results/replication.md describes each run: its conditions, budget and
replications). ``evolved_pre.json``, which tests and benchmarks use, holds the best 10 robots
of each of the 2 replications of the scene study's ``arm-length-shoulder`` run
(docs/results/scene-study.md): the standard condition's pre-reaching phase alone, 60
generations, on the default scene.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from ..evolution.conditions import load_condition
from ..evolution.rundir import RunDirectory, RunError
from ..model.scenes import scene_of

ROBOTS_FORMAT = 1


@dataclass(frozen=True, eq=False)
class ShippedRobot:
    """An evolved genome with where it comes from. ``rank``: its place in its replication's
    final population (0 = best); ``lifetime_fitness``: mean p_multimodal (Eq. 5) over its
    evaluations during training; ``provenance``: the file's what, command, git_revision,
    run, budget and phase; ``source``: the file's name."""

    condition: str
    phase: str
    replication: int
    rank: int
    lifetime_fitness: float
    genome: np.ndarray = field(repr=False)
    source: str
    provenance: Mapping = field(repr=False)

    @property
    def model_version(self) -> int:
        """The model version its run was trained under (a file without one: version 1, the
        only version before versions were recorded)."""
        return int(self.provenance.get("model_version") or 1)

    def describe(self) -> str:
        """One line: which robot, from which run and budget."""
        b = self.provenance.get("budget", {})
        budget = ", ".join(f"{v} {k}" for k, v in b.items() if k in
                           ("generations", "replications", "trials", "steps"))
        run = self.provenance.get("run")
        return (f"{self.condition}/{self.phase} replication {self.replication} rank {self.rank} "
                f"(lifetime fitness {self.lifetime_fitness:.4f}; shipped {self.source}"
                f"{f' of run {run}' if run else ''}: "
                f"{budget}; revision {str(self.provenance.get('git_revision'))[:10]})")


def _files(directory=None) -> list:
    root = resources.files(__package__) if directory is None else Path(directory)
    return sorted((f for f in root.iterdir() if f.name.endswith(".json")),
                  key=lambda f: f.name)


def _read(file) -> dict:
    info = json.loads(file.read_text())
    if info.get("format") != ROBOTS_FORMAT:
        raise ValueError(f"{file.name}: not a robots file of format {ROBOTS_FORMAT}")
    return info


def index(directory=None) -> list[dict]:
    """One row per robots file (default: the package's): file, condition, phase, robots,
    run (None in files that predate it), budget, what, command, git_revision."""
    rows = []
    for f in _files(directory):
        info = _read(f)
        rows.append({"file": f.name, "condition": info["phase"]["condition"],
                     "phase": info["phase"]["phase"], "robots": len(info["genomes_hex"]),
                     **{k: info.get(k) for k in ("run", "budget", "what", "command",
                                                 "git_revision")}})
    return rows


def robots(phase: str | None = None, condition: str | None = "standard",
           directory=None, run: str | None = None) -> list[ShippedRobot]:
    """The shipped robots of ``phase`` ("pre", "gross", "fine"; None: every phase) of
    ``condition`` (None: every condition), best lifetime fitness first; empty when none
    ships. ``run``: only those of the run directory of that name (every shipped file names
    it, ``index()`` lists it; lifetime fitness compares robots of one run and budget only).
    ``directory``: read robots files there instead of the package's."""
    out = []
    for f in _files(directory):
        info = _read(f)
        where = info["phase"]
        if (phase is not None and where["phase"] != phase) or (
                condition is not None and where["condition"] != condition) or (
                run is not None and info.get("run") != run):
            continue
        fitness = info["lifetime_fitness"]
        reps = info.get("replication") or [0] * len(fitness)
        provenance = {k: info.get(k) for k in ("what", "command", "git_revision", "run",
                                               "model_version", "budget", "phase")}
        seen: dict[int, int] = {}
        for h, fit, r in zip(info["genomes_hex"], fitness, reps):
            rank = seen[r] = seen.get(r, -1) + 1  # files list each replication best first
            out.append(ShippedRobot(where["condition"], where["phase"], int(r), rank,
                                    float(fit), np.frombuffer(bytes.fromhex(h), np.uint8),
                                    f.name, provenance))
    return sorted(out, key=lambda r: -r.lifetime_fitness)


def evolved_pre() -> tuple[np.ndarray, np.ndarray, dict]:
    """The shipped pre-reaching robots (``evolved_pre.json``: 60 generations on the default
    scene, the best 10 of each of 2 replications): genomes (20, N_GENES) uint8, best lifetime
    fitness first over both replications, their lifetime fitness, and the provenance (command,
    git revision, budget, phase; ``replication`` in the same order as the genomes)."""
    info = _read(resources.files(__package__).joinpath("evolved_pre.json"))
    genomes = np.array([np.frombuffer(bytes.fromhex(h), np.uint8)
                        for h in info.pop("genomes_hex")])
    fitness = np.array(info.pop("lifetime_fitness"))
    order = np.argsort(-fitness, kind="stable")
    info["replication"] = [info["replication"][i] for i in order]
    return genomes[order], fitness[order], info


def export_robots(run_dir, phase: str, path, condition: str | None = None,
                  per_replication: int = 2, what: str = "", ship_as: str | None = None,
                  generation: int | None = None) -> Path:
    """Write the best ``per_replication`` robots of each replication of a trained run's
    ``phase`` (of ``condition``; default the run's first condition that has it) as a robots
    file at ``path`` (a new file): put it in ``dart_reach/robots/`` to ship them. The
    condition must be a shipped one (``conditions.load_condition(name)``), so that a user's
    installation can rebuild the phase's maturational state; ``ship_as``: the shipped
    condition to file them under when the run's is not shipped (the learning check's
    ``pre-only``): its phase of that name must be its first and train the same maturational
    state (acuity, offset sensors, free groups, reflexes), else ValueError. ``generation``:
    the robots of the phase's snapshot of that generation instead of its final population
    (a run still training, or a late population for the bench)."""
    run = RunDirectory.open(run_dir)
    found = [(c, p) for c in run.conditions for p in c.phases
             if p.name == phase and (condition is None or c.name == condition)]
    if not found:
        raise ValueError(f"{run.out}: no phase {phase!r}"
                         + (f" in condition {condition!r}" if condition else ""))
    cond, ph = found[0]
    shipped_name = cond.name
    if ship_as is not None:
        twin = {p.name: p for p in load_condition(ship_as).phases}.get(ph.name)
        same = ("acuity", "offset_sensors", "free_groups", "reflexes", "previous_key")
        differ = (f"{ship_as} has no phase {ph.name!r}" if twin is None else ", ".join(
            k for k in same if getattr(twin, k) != getattr(ph, k)))
        if differ:
            raise ValueError(f"{run.out}: {cond.name}/{ph.name} cannot ship as {ship_as}/"
                             f"{ph.name}: {differ}" + (" differ" if twin else ""))
        shipped_name = ship_as
    if generation is None:
        genomes, fitness = run.load_final(ph)
    else:
        kept = {g: (genomes, fitness) for g, genomes, fitness in run.snapshots(ph)}
        if generation not in kept:
            raise ValueError(f"{run.out}: phase {ph.name} kept no snapshot of generation "
                             f"{generation} (it kept {', '.join(map(str, kept)) or 'none'})")
        genomes, fitness = kept[generation]
    n = min(per_replication, genomes.shape[1])
    if n < 1:
        raise ValueError(f"per_replication must be at least 1, got {per_replication}")
    manifest = json.loads((run.out / "manifest.json").read_text())
    s = run.settings
    info = {
        "format": ROBOTS_FORMAT,
        "what": what or f"best {n} robots of each replication of {cond.name}/{ph.name}, "
                        f"{run.out.name}"
                        + (f", at generation {generation}" if generation else ""),
        "command": manifest.get("command"), "git_revision": manifest.get("git_revision"),
        "run": run.out.name,
        "model_version": s.model_version,
        "budget": {"generations": generation or ph.generations, "replications": s.replications,
                   "trials": s.trials, "steps": s.steps, "physics_dt": s.world.physics_dt,
                   "seed": s.seed, "scene": manifest.get("scene") or scene_of(s.world.sectors),
                   "sectors": dataclasses.asdict(s.world.sectors)},
        "phase": {"condition": shipped_name, "phase": ph.name,
                  "free_groups": [g.value for g in ph.free_groups], "acuity": ph.acuity,
                  "reflexes": ph.reflexes},
        "replication": [r for r in range(genomes.shape[0]) for _ in range(n)],
        "lifetime_fitness": [round(float(f), 6) for row in fitness[:, :n] for f in row],
        "genomes_hex": [g.tobytes().hex() for row in genomes[:, :n] for g in row],
    }
    path = Path(path)
    with open(path, "x") as f:
        f.write(json.dumps(info, indent=1) + "\n")
    return path


def export_run(run_dir, directory, per_replication: int = 2) -> list[Path]:
    """``export_robots`` for every phase of every condition of a trained run: one robots file
    ``RUN-CONDITION-PHASE.json`` each in ``directory`` (RUN: the run directory's name), a
    phase shared by two conditions under each. Every phase must have finished training and
    no file may exist yet: the run is checked first, so that nothing is written when one
    fails (RunError, FileExistsError; FileNotFoundError when ``directory`` does not exist)."""
    run = RunDirectory.open(run_dir)
    if not Path(directory).is_dir():
        raise FileNotFoundError(f"{directory}: no such directory; nothing exported")
    jobs = [(c.name, p, Path(directory) / f"{run.out.name}-{c.name}-{p.name}.json")
            for c in run.conditions for p in c.phases]
    for _, p, path in jobs:
        if not run.final_path(p).is_file():
            raise RunError(f"{run.out}: phase {p.name} has not finished training "
                           f"(no {run.final_path(p).name}); nothing exported")
        if path.exists():
            raise FileExistsError(f"{path} exists; nothing exported")
    return [export_robots(run.out, p.name, path, condition=c, per_replication=per_replication)
            for c, p, path in jobs]
