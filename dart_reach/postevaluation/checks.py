"""Whether a run's post-evaluation results are complete, and whether they still reproduce.

``table_status`` says, for each of a run's three tables (``results``), what it holds against
what the run's phases, replications and snapshots allow: a table is complete when every
phase has every replication's robots (the same ranks) under every sensory condition it holds,
every random genome under them, every snapshot's robots, each on the 45 positions.

``reproduce`` runs a slice of the stored rows again in the real DART world (one robot per
phase and table, on a few of the 45 positions: trials are independent, each starts from the
same state) and compares the rows, as stored (``results.quantised``), with the table's:
equal to the last bit, or the columns that differ. A model, measure or setting changed since
the table was written shows here instead of silently invalidating what the docs say.
``reproduced`` judges such a slice: to the last bit where the table was written at this
process's numpy dispatch level (``provenance.simd``), else up to ``OTHER_SIMD_SHARE`` of
its robots may differ.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import polars as pl

from . import results
from .systematic import load_evaluation, run_robot, stored_robot_job
from ..evolution.provenance import simd
from ..evolution.rundir import RunDirectory, RunError
from ..model.world import N_SECTORS, POINTS_PER_SECTOR

POSITIONS = N_SECTORS * POINTS_PER_SECTOR


@dataclass(frozen=True)
class TableStatus:
    """One results table of a run: ``trials`` rows, what they cover (``summary``), whether
    that is all the run allows (``complete``; ``missing`` names what is not there) and the
    sessions that wrote it (``results.session`` entries)."""

    name: str
    trials: int
    summary: str
    complete: bool
    missing: tuple[str, ...]
    sessions: tuple[dict, ...]


def _robots(table: pl.DataFrame, keys: list[str]) -> dict[tuple, int]:
    """Trials per robot: ``keys`` (a robot's columns) -> rows."""
    return {k[:-1]: k[-1] for k in table.group_by(keys).len().rows()}


def _finished(run: RunDirectory):
    return [(c, p) for c, p in run.unique_phases() if run.final_path(p).exists()]


def _evaluation_status(run: RunDirectory, table: pl.DataFrame, name: str) -> TableStatus:
    baseline = name == results.BASELINE
    senses = sorted(set(table["senses"]))
    if baseline:  # a random genome's index is its "replication", its rank 0
        units, ranks = sorted(set(table["replication"])), [0]
    else:
        units, ranks = list(range(run.settings.replications)), sorted(set(table["rank"]))
    have = _robots(table, ["phase_key", "senses", "replication", "rank"])
    missing = []
    for _, phase in _finished(run):
        for s in senses:
            gaps = [(u, i) for u in units for i in ranks
                    if have.get((phase.key, s, u, i)) != POSITIONS]
            if gaps:
                missing.append(f"{phase.name}/{s}: {len(gaps)} of {len(units) * len(ranks)} "
                               f"robots missing")
    phases = len({p for p, *_ in have})
    what = (f"{len(units)} random genomes" if baseline else
            f"{len(units)} replications x {len(ranks)} robots")
    return TableStatus(name, table.height,
                       f"{phases} phase(s) x {what} x {len(senses)} senses ({', '.join(senses)})",
                       not missing, tuple(missing), tuple(results.sessions(run.out / name)))


def _development_status(run: RunDirectory, table: pl.DataFrame) -> TableStatus:
    """Complete when every snapshot the table holds (phase, generation, condition) holds the
    best robots of every replication, each on every position: a table may hold chosen
    snapshots (``evaluate --snapshots``) or those a run still training has saved, never part
    of one."""
    robots = int(table["rank"].max()) + 1
    have = _robots(table, ["phase_key", "senses", "generation", "replication", "rank"])
    shapes = {(p.key, g): (p.name, genomes.shape[:2]) for _, p in run.unique_phases()
              for g, genomes, _ in run.snapshots(p)}
    held = sorted({k[:3] for k in have})
    expected = found = 0
    missing = []
    for key, senses, generation in held:
        if (key, generation) not in shapes:
            missing.append(f"phase {key} @{generation}: no such snapshot in the run")
            continue
        name, (replications, best) = shapes[(key, generation)]
        gaps = sum(have.get((key, senses, generation, r, i)) != POSITIONS
                   for r in range(replications) for i in range(min(robots, best)))
        expected += replications * min(robots, best)
        found += replications * min(robots, best) - gaps
        if gaps:
            missing.append(f"{name} @{generation} ({senses}): {gaps} snapshot robots missing")
    snapshots = len({(k, g) for k, _, g in held})
    conditions = sorted({s for _, s, _ in held})
    return TableStatus(results.DEVELOPMENT, table.height,
                       f"{found} of {expected} snapshot robots (the best {robots} of each "
                       f"replication) in {snapshots} of the run's {len(shapes)} snapshots "
                       f"({', '.join(conditions)})", not missing, tuple(missing),
                       tuple(results.sessions(run.out / results.DEVELOPMENT)))


def table_status(run_dir) -> list[TableStatus]:
    """The status of each results table the run has (none: an empty list)."""
    run = RunDirectory.open(run_dir)
    out = []
    for name in (results.EVALUATION, results.BASELINE):
        table = results.read_table(run.out / name)
        if table is not None:
            out.append(_evaluation_status(run, table, name))
    development = results.read_table(run.out / results.DEVELOPMENT)
    if development is not None:
        out.append(_development_status(run, development))
    return sorted(out, key=lambda s: [results.EVALUATION, results.BASELINE,
                                      results.DEVELOPMENT].index(s.name))


def _compare(stored: pl.DataFrame, rows: list[dict]) -> tuple[list[str], float]:
    """Columns of the re-run ``rows`` that differ from ``stored`` (the same trials), and the
    largest absolute difference among their floats."""
    again = results.quantised(pl.DataFrame(rows, schema_overrides={"recording": pl.Utf8},
                                           infer_schema_length=None)).sort("trial")
    stored = stored.sort("trial")
    if stored.height != again.height:
        return ["rows"], float("nan")
    columns = [c for c in again.columns if c in stored.columns and c != "recording"]
    differ = [c for c in columns if not stored[c].equals(again[c])]
    worst = 0.0
    for c in differ:
        if again[c].dtype.is_float():
            worst = max(worst, float((stored[c] - again[c]).abs().max() or 0.0))
    return differ, worst


def reproduce(run_dir, points: int = N_SECTORS) -> pl.DataFrame:
    """Run again, for each phase and each results table, one stored robot on ``points`` of
    the 45 positions (spread over the sectors; the robot, position and sensory condition
    rotate with the phase) and compare the rows. One row per robot checked: table, phase,
    senses, replication, rank, generation (development; else null), trials, equal (every
    column to the last bit), differ (the columns that do not) and max_abs_diff. A run with
    no post-evaluated robot is refused (``RunError``)."""
    run = RunDirectory.open(run_dir)
    step = POSITIONS // points
    checks = []
    tables = {name: results.read_table(run.out / name) for name in
              (results.EVALUATION, results.BASELINE, results.DEVELOPMENT)}
    if tables[results.EVALUATION] is not None:
        every = load_evaluation(run.out, None)
        tables[results.EVALUATION] = every.filter(~pl.col("baseline"))
        tables[results.BASELINE] = every.filter(pl.col("baseline"))
    for n, (_, phase) in enumerate(_finished(run)):
        positions = tuple(range(n % step, POSITIONS, step))[:points]
        for name, table in tables.items():
            if table is None or not table.height:
                continue
            table = table.filter(pl.col("phase_key") == phase.key)
            if not table.height:
                continue
            generation = None
            if name == results.DEVELOPMENT:
                generation = sorted(set(table["generation"]))[n % table["generation"].n_unique()]
                table = table.filter(pl.col("generation") == generation)
            senses = sorted(set(table["senses"]))[n % table["senses"].n_unique()]
            table = table.filter(pl.col("senses") == senses)
            replication = sorted(set(table["replication"]))[n % table["replication"].n_unique()]
            stored = table.filter((pl.col("replication") == replication) & (pl.col("rank") == 0)
                                  & pl.col("trial").is_in(positions))
            job = stored_robot_job(run, phase.key, senses, replication, 0,
                                   baseline=name == results.BASELINE, generation=generation,
                                   positions=positions)
            rows, _ = run_robot(job)
            differ, worst = _compare(stored, rows)
            checks.append({"table": name, "phase": phase.name, "senses": senses,
                           "replication": replication, "rank": 0, "generation": generation,
                           "trials": len(rows), "equal": not differ, "differ": differ,
                           "max_abs_diff": worst})
    if not checks:
        raise RunError(f"{run.out}: no post-evaluated robot to run again (post-evaluate the run "
                       f"first: dart-reach evaluate {run.out})")
    return pl.DataFrame(checks, schema_overrides={"generation": pl.Int64,
                                                  "differ": pl.List(pl.Utf8)})


#: The share of a run's checked robots that may differ where a table was written at another
#: numpy dispatch level than this process's, or one not recorded (tables written before
#: ``simd`` was). Chosen from the committed tables, written on an AVX-512 machine and run
#: again on an AVX2 one (docs/guides/runs.md, "Determinism", gives how many differed): a
#: trial that rounds one exp differently drifts apart, the others stay bit-identical. A
#: changed model changes nearly every robot.
OTHER_SIMD_SHARE = 0.1


def reproduced(found: pl.DataFrame, statuses) -> tuple[bool, str]:
    """Whether the slice ``found`` (``reproduce``) of a run whose tables are ``statuses``
    (``table_status``) reproduces its tables, and why: every robot to the last bit where
    every session that wrote its table ran at this process's ``simd``; else at most
    ``OTHER_SIMD_SHARE`` of the run's robots checked (at least one) differ."""
    here = simd()
    other = {s.name for s in statuses
             if not s.sessions or any(e.get("simd") != here for e in s.sessions)}
    differ = found.filter(~pl.col("equal"))
    strict = differ.filter(~pl.col("table").is_in(list(other)))
    if strict.height:
        return False, (f"{strict.height} robot(s) differ in tables written at this machine's "
                       f"numpy dispatch level ({here}): {sorted(set(strict['table']))}")
    allowed = max(1, int(OTHER_SIMD_SHARE * found.height))
    if differ.height > allowed:
        return False, (f"{differ.height} of {found.height} robots differ, more than the "
                       f"{allowed} a table written at another numpy dispatch level allows")
    if differ.height:
        return True, (f"{differ.height} of {found.height} robots differ, in "
                      f"{sorted(set(differ['table']))}, written at another numpy dispatch "
                      f"level than this machine's ({here}) or one not recorded: at most "
                      f"{allowed} may (checks.OTHER_SIMD_SHARE)")
    return True, f"all {found.height} robots the same to the last bit"


def describe(run_dir) -> list[str]:
    """Lines for ``dart-reach status``: each table's status and where it came from, against
    the revision that trained the run."""
    run_dir = Path(run_dir)
    statuses = table_status(run_dir)
    if not statuses:
        return ["results: no post-evaluation (dart-reach evaluate RUN)"]
    trained = json.loads((run_dir / "manifest.json").read_text()).get("git_revision")
    lines = []
    for s in statuses:
        state = "complete" if s.complete else "incomplete: " + "; ".join(s.missing)
        revisions = sorted({str(e.get("revision"))[:7] for e in s.sessions}) or ["unknown"]
        lines.append(f"results: {s.name}: {s.trials:,} trials, {s.summary}: {state}; written "
                     f"at {', '.join(revisions)} in {len(s.sessions) or 'unknown'} session(s)")
    written = {e.get("revision") for s in statuses for e in s.sessions}
    if written == {trained}:
        lines.append(f"results: written at the revision that trained the run ({trained[:7]})")
    else:
        lines.append(f"results: trained at {str(trained)[:7]}, written at another revision: "
                     f"'dart-reach status {run_dir} --reproduce' runs a slice again to check")
    return lines
