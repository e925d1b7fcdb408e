"""docs/results/benchmarks.md's generated part (its template
docs/results/templates/benchmarks-cost.md): what the committed runs cost, measured from their
generation tables and manifests (``dart_reach.evolution.cost``), and the paper's budgets
recomputed from those measurements. Rendered by ``reports.results``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import polars as pl

from dart_reach.analysis.formatting import significant
from dart_reach.evolution import cost
from dart_reach.evolution.conditions import list_conditions
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.evolution.settings import Settings

from .runs import FULL, REPLICATIONS, TEN
from .text import markdown_table


#: ``ray_efficiency`` of ``dart-reach bench``, lowest and highest over the benchmark runs of
#: docs/results/benchmarks.md; and the cluster the docs size the paper's budget for.
RAY_EFFICIENCY = (0.78, 0.92)
CLUSTER_CORES = 96


def values(recordings: Path) -> dict[str, str]:
    """The values of docs/results/templates/benchmarks-cost.md: ``cost`` (per run and phase,
    ``cost.measured_cost``) and, for the ten-replication run, ``ten.*``: its
    replication-generations, wall hours, sessions and resumes, the quartiles of its
    core-seconds per replication-generation, and the paper's Fig. 10 budget (every shipped
    condition at its 500 generations per phase, 10 replications) recomputed from them:
    ``fig10.*`` core-hours and hours on ``CLUSTER_CORES`` cores at ``RAY_EFFICIENCY``."""
    runs = {name: RunDirectory.open(recordings / name) for name in REPLICATIONS}
    table = pl.concat(cost.measured_cost(run).select(pl.lit(f"`{name}`").alias("run"), pl.all())
                      for name, run in runs.items()).rename({
        "wall_h": "wall (h)", "core_s_min": "core-s: min", "core_s_q1": "lower quartile",
        "core_s_median": "median", "core_s_q3": "upper quartile"})
    ten = runs[TEN]
    sessions = json.loads((ten.out / "manifest.json").read_text())["sessions"]
    per = cost.core_seconds(ten)
    q1, median = np.quantile(per["core_s"].drop_nans().to_numpy(), [0.25, 0.5])
    fig10 = cost.cost_estimate(list(list_conditions()), Settings()).replication_generations
    hours = [fig10 * c / 3600 for c in (q1, median)]
    full = full_values(recordings / FULL, (q1, median))
    return {"cost": markdown_table(table), **full,
            "ten.replication_generations": f"{per.height * ten.settings.replications:,}",
            "ten.wall_h": significant(float(per["wall_s"].sum()) / 3600),
            "ten.sessions": str(len(sessions)), "ten.resumes": str(max(len(sessions) - 1, 0)),
            "ten.q1": significant(q1), "ten.median": significant(median),
            "fig10.replication_generations": f"{fig10:,}",
            "fig10.core_hours": f"{hours[0]:,.0f}–{hours[1]:,.0f}",
            "fig10.cluster_hours": (f"{hours[0] / (CLUSTER_CORES * RAY_EFFICIENCY[1]):.0f}–"
                                    f"{hours[1] / (CLUSTER_CORES * RAY_EFFICIENCY[0]):.0f}"),
            "fig10.cores": str(CLUSTER_CORES),
            "fig10.efficiency": f"{RAY_EFFICIENCY[0]:g}–{RAY_EFFICIENCY[1]:g}"}


def cpu_text(found: dict | None) -> str:
    """A session's processor (``provenance.cpu``) in a few words, or that it was not recorded
    (sessions before 2026-11-27)."""
    if not found:
        return "not recorded"
    mhz = f"{found['mhz']:,.0f} MHz" if found.get("mhz") else None
    return ", ".join(str(v) for v in (found.get("model"), mhz, found.get("vector")) if v)


def full_values(directory: Path, quiet: tuple[float, float]) -> dict[str, str]:
    """``full.*`` of docs/results/templates/benchmarks-cost.md, the full-budget run where it
    is: its replication-generations done of all, its sessions (revision, the generation it
    started from, workers, processor, the generations each trained and their core-seconds per
    replication-generation), the quartiles of its core-seconds per replication-generation and
    the rest of the campaign at the median (core-hours; hours on the run's last workers) and
    at ``quiet``, the core-seconds (low, high) of a run on cores it had mostly to itself."""
    keys = ("full.done", "full.sessions", "full.q1", "full.median", "full.rest_core_h",
            "full.rest_h", "full.workers", "full.rest_quiet_h", "full.latest",
            "full.rest_latest_h")
    if not (directory / "manifest.json").is_file():
        return dict.fromkeys(keys, "not started")
    run = RunDirectory.open(directory)
    status = run.status()
    done, total = int(status["generations"].sum()), int(status["of"].sum())
    sessions = json.loads((directory / "manifest.json").read_text())["sessions"]
    generations = cost.core_seconds(run)
    by_session = {r["session"]: r for r in generations.group_by("session").agg(
        pl.len().alias("n"), pl.col("core_s").drop_nans().min().alias("min"),
        pl.col("core_s").drop_nans().median().alias("median")).iter_rows(named=True)}
    none = {"n": 0, "min": None, "median": None}
    rows = [{"session": i, "started": s["started"][:16].replace("T", " "),
             "revision": (s.get("git_revision") or "?")[:7],
             "from generation (pre)": s.get("generations_done", {}).get("standard/pre", 0),
             "workers": s.get("workers"), "cpu": cpu_text(s.get("cpu")),
             "generations": c["n"], "core-s: min": c["min"], "median": c["median"]}
            for i, s in enumerate(sessions) for c in [by_session.get(i, none)]]
    per = generations["core_s"].drop_nans().to_numpy()
    q1, median = np.quantile(per, [0.25, 0.5]) if per.size else (np.nan, np.nan)
    workers = sessions[-1].get("workers") or 1
    rest = (total - done) * median / 3600
    latest = by_session.get(max(by_session, default=-1), {}).get("median")
    return {"full.done": f"{done:,} of {total:,}", "full.sessions": markdown_table(
        pl.DataFrame(rows)), "full.q1": significant(q1), "full.median": significant(median),
        "full.rest_core_h": f"{rest:,.0f}", "full.rest_h": f"{rest / workers:,.0f}",
        "full.workers": str(workers), "full.latest": significant(latest),
        "full.rest_latest_h": f"{(total - done) * latest / 3600 / workers:,.0f}"
        if latest is not None else "–", "full.rest_quiet_h": "–".join(
            f"{(total - done) * c / 3600 / workers:,.0f}" for c in quiet)}
