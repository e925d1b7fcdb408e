"""A run directory, read: its manifest, conditions and settings, where each file lies, the
committed statistics, the trained phases' finals and snapshots, where training stands
(``RunDirectory``). The trainer (``trainer.Trainer``) writes it; everything that reads a run
(the post-evaluation, the analysis, the shipped robots, the viewers) opens it with
``RunDirectory.open``, which loads neither the parallel back-ends nor Rerun.

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
                               generations, ``postevaluation.snapshots``)
    evaluation.parquet, evaluation/   the post-evaluation (``postevaluation.systematic``)
    baseline.parquet, development.parquet  its random genomes and snapshots
                               (``postevaluation.results``: the format, the provenance)
    findings.parquet           every claim judged at the run's budget (``make results``)
    ledger.json                the SHA-256 of every file above as it was written (``integrity``)
    .lock                      held by the process working in the directory (``files``)

Every file is checked against the ledger when it is read (``integrity``), the manifest
included, and ``RunDirectory.verify`` checks them all at once. A damaged file, or one the
ledger does not name, raises ``integrity.DamagedFile`` naming it and what to do.

Each phase's checkpoint carries its statistics rows: the statistics of a run are read from its
checkpoints (``generations.parquet`` and ``training.rrd`` are derived from them).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import polars as pl

from .. import integrity
from .conditions import Condition, Phase, condition_from_dict
from .ga import GAState, state_from_arrays
from .settings import Settings
from ..errors import UsageError
from ..files import TEMP_SUFFIX

#: Version of manifest.json's layout.
MANIFEST_FORMAT = 1
#: The columns of generations.parquet (and of the statistics each checkpoint carries).
STATS_SCHEMA = {
    "condition": pl.Utf8, "phase": pl.Utf8, "phase_key": pl.Utf8, "replication": pl.Int64,
    "generation": pl.Int64, "best": pl.Float64, "mean": pl.Float64, "min": pl.Float64,
    "wall_s": pl.Float64,
}


class RunError(UsageError):
    """A run directory cannot be used as asked (exists, foreign, corrupted, other settings)."""


def read_manifest(path: Path) -> dict:
    """A run's manifest as a dict of this version's format, checked against the run's ledger
    (``integrity``), or ``RunError`` (``integrity.DamagedFile``) naming it."""
    path = Path(path)
    try:
        if integrity.has_ledger(path.parent):
            integrity.check(path.parent, path)
        m = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise RunError(f"{path}: unreadable manifest ({exc})") from None
    if not isinstance(m, dict):
        raise RunError(f"{path}: malformed manifest (a JSON {type(m).__name__}, not an object)")
    if not integrity.RUN_MANIFEST_KEYS <= m.keys():
        raise RunError(f"{path}: not a run's manifest (a run's manifest.json, written by "
                       f"'dart-reach train', holds its format, conditions and settings)")
    if m.get("format") != MANIFEST_FORMAT:
        raise RunError(f"{path}: written by an incompatible version (format "
                       f"{m.get('format')}, this version reads {MANIFEST_FORMAT})")
    integrity.ledger(path.parent)  # a run without one: refused, naming 'migrate'
    return m


def described_run(out) -> tuple[Path, list[Condition], Settings]:
    """The directory, conditions and settings an existing run's manifest describes. Raises
    ``RunError`` naming the file and the problem when it is missing, not a run, or written by
    an incompatible version."""
    out = Path(out)
    if not out.is_dir():
        raise RunError(f"{out}: no such run directory" if not out.exists()
                       else f"{out}: not a directory")
    path = out / "manifest.json"
    if not path.is_file():
        raise RunError(f"{out}: not a run directory (no manifest.json)")
    m = read_manifest(path)
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
    return out, conditions, settings


def first_difference(a, b, path: str) -> tuple[str, str, str]:
    """Where two JSON values first differ: (dotted path, a's value, b's value). A condition's
    phase is named by its name (``conditions.standard.gross.generations``), a setting by its
    field (``settings.trials``)."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in list(a) + [k for k in b if k not in a]:
            if a.get(k) != b.get(k):
                return first_difference(a.get(k), b.get(k), f"{path}.{k}")
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            if x != y:
                name = x.get("name") if isinstance(x, dict) and x.get("name") == (
                    y.get("name") if isinstance(y, dict) else None) else None
                return first_difference(x, y, f"{path}.{name}" if name else f"{path}[{i}]")
    if isinstance(a, list) and isinstance(b, list):
        return f"{path} (how many)", str(len(a)), str(len(b))
    return path, json.dumps(a), json.dumps(b)


def manifest_of(conditions: list[Condition], settings: Settings) -> dict:
    """What a run's manifest says of its result: format, conditions and settings."""
    return {
        "format": MANIFEST_FORMAT,
        "conditions": [c.to_dict() for c in conditions],
        "settings": settings.to_json(),
    }


def check_same_run(manifest_path: Path, manifest: dict) -> None:
    """``RunError`` unless the manifest at ``manifest_path`` holds the conditions and settings
    of ``manifest`` (``manifest_of``), naming the first difference."""
    old = read_manifest(manifest_path)
    if "settings" in old:  # written before a setting existed: read with its default
        old = dict(old, settings=Settings.from_json(old["settings"]).to_json())
    for key in ("conditions", "settings"):
        asked = json.loads(json.dumps(manifest[key]))
        old_value = json.loads(json.dumps(old.get(key)))
        if old_value != asked:
            where, there, here = first_difference(old_value, asked, key)
            what = f"{where} is {there} in the run there, {here} now"
            raise RunError(f"{manifest_path}: the run there was made with other {key} "
                           f"({what}); resume it with the same conditions and Settings",
                           cli=f"{manifest_path}: the run there was made with other {key} "
                               f"({what}); resume it with the same command line")


class RunDirectory:
    """The run of ``conditions`` under ``settings`` in the directory ``out``, read: ``stats``
    holds the statistics of its committed generations. Open an existing run with
    ``RunDirectory.open(out)``."""

    def __init__(self, out: Path, conditions: list[Condition], settings: Settings):
        self.out = Path(out)
        self.conditions = conditions
        self.settings = settings
        self.manifest = manifest_of(conditions, settings)
        self.stats = self.committed_stats()

    @classmethod
    def open(cls, out) -> "RunDirectory":
        """Reopen an existing run directory to analyse it. Raises ``RunError`` naming the file
        and the problem when it is missing, not a run, or written by an incompatible version."""
        out, conditions, settings = described_run(out)
        check_same_run(out / "manifest.json", manifest_of(conditions, settings))
        return cls(out, conditions, settings)

    def unfinished(self) -> list[str]:
        """The phases not trained to the end, as "condition/phase"."""
        return [f"{c.name}/{p.name}" for c in self.conditions for p in c.phases
                if not self.final_path(p).exists()]

    def unsettled(self) -> list[str]:
        """What a killed write or a deletion left for a resume to settle, as run-relative
        names: the files the ledger names that are missing, and the temporaries of a write."""
        names = [n for n in integrity.ledger(self.out) if not (self.out / n).exists()]
        return names + [str(p.relative_to(self.out))
                        for p in self.out.rglob(f".*{TEMP_SUFFIX}") if p.is_file()]

    # -------------------------------------------------------------- stats and checkpoints
    def committed_stats(self) -> pl.DataFrame:
        """The statistics rows of every committed generation, from the phases' checkpoints,
        in training order."""
        tables = [pl.DataFrame(schema=STATS_SCHEMA)]
        for _, phase in self.unique_phases():
            loaded = self.load_checkpoint(phase)
            if loaded is not None:
                tables.append(loaded[1])
        return pl.concat(tables)

    def load_checkpoint(self, phase: Phase) -> tuple[list[GAState], pl.DataFrame] | None:
        """The GA states and statistics rows of a phase's last committed generation (None
        before its first)."""
        path = self.checkpoint_path(phase)
        if not path.exists():
            return None
        integrity.check(self.out, path)
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
        table = (pl.read_parquet(integrity.verified(path)) if path.exists()
                 else pl.DataFrame(schema=STATS_SCHEMA))
        return table.filter((pl.col("phase_key") == phase.key)
                            & (pl.col("generation") <= generation))

    # -------------------------------------------------------------- where things lie
    def phase_dir(self, phase: Phase) -> Path:
        return self.out / "phases" / f"{phase.name}-{phase.key[:8]}"

    def checkpoint_path(self, phase: Phase) -> Path:
        return self.phase_dir(phase) / "checkpoint.npz"

    def final_path(self, phase: Phase) -> Path:
        return self.phase_dir(phase) / "final.npz"

    def snapshot_path(self, phase: Phase, generation: int) -> Path:
        return self.phase_dir(phase) / "snapshots" / f"gen{generation:04d}.npz"

    # -------------------------------------------------------------- results
    def load_final(self, phase: Phase) -> tuple[np.ndarray, np.ndarray]:
        """Final populations (R, P, L) and lifetime fitness (R, P) of a trained phase, best
        first within each replication."""
        path = self.final_path(phase)
        integrity.check(self.out, path)
        try:
            with np.load(path, allow_pickle=False) as d:
                return d["population"], d["fitness"]
        except Exception as exc:
            raise RunError(f"{path}: unreadable phase result ({exc})") from None

    def snapshot_generations(self) -> set[int]:
        """The generations some phase of the run kept a snapshot of (read from the names of
        its files, ``snapshot_path``)."""
        return {int(path.stem[3:]) for _, phase in self.unique_phases()
                for path in (self.phase_dir(phase) / "snapshots").glob("gen*.npz")}

    def snapshots(self, phase: Phase) -> list[tuple[int, np.ndarray, np.ndarray]]:
        """(generation, genomes (R, k, L), lifetime fitness (R, k)) of every snapshot a phase
        kept, in generation order; [] for a run made without snapshots."""
        out = []
        for path in sorted((self.phase_dir(phase) / "snapshots").glob("gen*.npz")):
            integrity.check(self.out, path)
            try:
                with np.load(path, allow_pickle=False) as d:
                    if str(d["phase_key"]) != phase.key:
                        raise ValueError("a snapshot of another phase")
                    out.append((int(d["generation"]), d["genomes"], d["fitness"]))
            except Exception as exc:
                raise RunError(f"{path}: unreadable snapshot ({exc})") from None
        return out

    def verify(self) -> None:
        """Check every file of the run before anything is done with it: its SHA-256 against
        the run's ledger (``integrity.verify_run``). Raises ``integrity.DamagedFile`` naming
        the first damaged file, or one the ledger does not name, and what to do; changes
        nothing on disk."""
        integrity.verify_run(self.out)

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
