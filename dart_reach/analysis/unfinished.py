"""An unfinished run in the report: where its training stands, and the snapshots of it that are
post-evaluated judged in place of the final populations it does not have yet.

A run still training (or stopped part-way, in the middle of its first phase) has no final
population to post-evaluate, but ``evaluate --development``
post-evaluates its snapshots (``postevaluation.snapshots``). ``snapshot_trials`` takes, for each
phase, the trials of its latest post-evaluated snapshot (every sense evaluated at that
generation): the same columns as ``evaluation.parquet``, so the findings, the measures and
Fig. 10 judge the robots as they stand; ``standing`` says where that is, in words the report
puts at its top. A finished run, or one with ``evaluation.parquet``, is judged as ever.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from pathlib import Path

import polars as pl

from ..evolution.rundir import RunDirectory
from ..postevaluation import results
from ..postevaluation.snapshots import load_development
from ..postevaluation.systematic import load_evaluation


def _unfinished(run: RunDirectory) -> bool:
    return bool(run.unfinished())


def snapshot_trials(run_dir) -> pl.DataFrame | None:
    """The trials of each phase's latest post-evaluated snapshot (the latest generation with
    trials under normal senses, every sense evaluated at it) of an unfinished run without
    ``evaluation.parquet``, with their ``generation``; None for any other run, or one whose
    snapshots are not post-evaluated."""
    run_dir = Path(run_dir)
    if results.exists(run_dir / results.EVALUATION) or not _unfinished(RunDirectory.open(run_dir)):
        return None
    table = load_development(run_dir, senses=None)
    if table is None or table.height == 0:
        return None
    latest = (table.filter(pl.col("senses") == "normal").group_by("phase_key")
              .agg(pl.col("generation").max().alias("_latest")))
    if latest.height == 0:
        return None
    return (table.join(latest, on="phase_key", how="inner", maintain_order="left")
            .filter(pl.col("generation") == pl.col("_latest")).drop("_latest"))


def judged(run_dir) -> bool:
    """Whether the report can judge ``run_dir``: it has ``evaluation.parquet``, or it is
    unfinished and some of its snapshots are post-evaluated."""
    return (results.exists(Path(run_dir) / results.EVALUATION)
            or snapshot_trials(run_dir) is not None)


def trials(run_dir) -> pl.DataFrame:
    """The trained robots' trials the report judges: ``evaluation.parquet``, else those of
    ``snapshot_trials`` (``load_evaluation``'s error when there are neither)."""
    snapshots = snapshot_trials(run_dir)
    return snapshots if snapshots is not None else load_evaluation(run_dir)


def standing(run_dir) -> str | None:
    """Where an unfinished run's training stands and what the report judges of it, in plain
    words ("RUN is unfinished: standard: pre at generation 250 of 500, gross, fine not run.
    ..."); None for a finished run."""
    run_dir = Path(run_dir)
    run = RunDirectory.open(run_dir)
    if not _unfinished(run):
        return None
    stats = run.committed_stats()
    trained = dict(stats.group_by("phase_key").agg(pl.col("generation").max()).iter_rows())
    conditions = []
    for c in run.conditions:
        done, at, not_run = [], [], []
        for p in c.phases:
            g = p.generations if run.final_path(p).exists() else trained.get(p.key, 0)
            (done if g == p.generations else at if g else not_run).append((p.notation, g,
                                                                             p.generations))
        words = ([f"{n} finished ({total} generations)" for n, _, total in done]
                 + [f"{n} at generation {g} of {total}" for n, g, total in at])
        if not_run:
            words.append(", ".join(n for n, _, _ in not_run) + " not run")
        conditions.append(f"{c.name}: {', '.join(words)}")
    text = f"{run_dir.name} is unfinished: {'; '.join(conditions)}."
    snapshots = snapshot_trials(run_dir)
    if results.exists(run_dir / results.EVALUATION):
        return text + " Judged here: its finished phases' post-evaluation (evaluation.parquet)."
    if snapshots is None:
        return text + (" None of its snapshots is post-evaluated: nothing of it is judged "
                       "here (dart-reach evaluate RUN --development 5 --development-sensors "
                       "all --finished-only).")
    judged_ = (snapshots.group_by("notation", "generation", maintain_order=True)
               .agg(pl.col("replication").n_unique().alias("replications"),
                    pl.struct("replication", "rank").n_unique().alias("robots"),
                    pl.col("senses").unique(maintain_order=True)))
    parts = [f"{r['notation']} at generation {r['generation']} ({r['robots']} robots of "
             f"{r['replications']} replications; senses {', '.join(r['senses'])})"
             for r in judged_.iter_rows(named=True)]
    return (text + " Judged here in place of final populations: its latest post-evaluated "
            f"snapshots, {'; '.join(parts)}; the claims of the phases not reached are "
            "\"not run\". Figs. 5-9 and their statistics draw a finished run's "
            "post-evaluation and are not drawn for it.")


def standing_html(run_dirs: Sequence) -> str:
    """``standing`` of each unfinished run among ``run_dirs``, a paragraph each (the top of
    the report)."""
    return "".join(f"<p class='missing'>{html.escape(text)}</p>" for d in run_dirs
                   if (text := standing(d)) is not None)
