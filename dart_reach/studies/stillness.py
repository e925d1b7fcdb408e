"""Why stillness pays (issue 48, point 4): the post-evaluated pre-reachers' trials run again,
their fitness taken apart (Eq. 5), and the values of docs/results/stillness.md.

``python -m dart_reach.studies.stillness [ROOT]`` runs the 45 systematic trials (normal
senses) of every pre-reaching robot that ``RUN``'s post-evaluation evaluated (the best 5 of
each of its 10 replications' final populations, the robots of its evaluation.parquet) in this
one process and writes one row per trial with ``measures.fitness.fitness_terms`` to
``recordings/RUN/TABLE``, stored as the post-evaluation's tables are
(``postevaluation.results``: zstd, float32, the session that wrote it). 2,250 trials, about
six minutes on one core. The docs are then rendered from that committed table and the run's
evaluation.parquet (``values``; ``make results``).

``python -m dart_reach.studies.stillness --generation G`` does the same for the snapshot of
generation G of the full-budget run (``FULL``: the best 5 robots of each replication that its
development.parquet post-evaluated there), adding its rows to ``recordings/FULL/TABLE``
(``generation`` in every row; a generation run again replaces its rows): what each strategy
earns at the paper's budget (``budget_values``). ``--judged`` runs every judged generation
post-evaluated and not yet in the table (``judged_missing``; ``make full-budget-snapshots``
does, on its copy of the run: ``--run-dir``).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
import polars as pl

from ..analysis import budgets, said, stillness
from ..analysis.strategy_course import JUDGED
from ..evolution.backends import worker_trial
from ..evolution.genome import as_groups, decode
from ..evolution.rundir import RunDirectory
from ..measures.fitness import trial_fitness_terms
from ..model.task import N_SEGMENTS, network_for
from ..model.world import POINTS_PER_SECTOR
from ..postevaluation import results
from ..postevaluation.snapshots import load_development
from ..postevaluation.systematic import stored_robot_job
from .doc_text import FULL

RUN = "replication-50x10"
TABLE = "fitness-terms.parquet"
#: A snapshot's rows in ``FULL``'s table: one robot of one generation.
SNAPSHOT_KEY = ("generation", "replication", "rank")
#: The columns of the page's tables at the paper's budget (``stillness.COLUMNS``'s keys).
BUDGET_COLUMNS = ("fitness", "touch_share", "touch_level", "scoring_share", "touched",
                  "touches", "contact_after_first", "contact_bout_s")


def robot_trials(run: RunDirectory, replication: int, rank: int,
                 positions: int | None = None, generation: int | None = None) -> list[dict]:
    """One row per systematic trial of a pre-reacher of ``run``'s final population (its
    ``replication`` and ``rank``; ``generation``: of that generation's snapshot) under normal
    senses, run as the post-evaluation runs it (``systematic.run_robot``): who, where,
    ``fitness_terms``; ``positions``: only the first so many of the 45 (a check)."""
    phase_key = next(p.key for c, p in run.unique_phases()
                     if c.name == "standard" and p.name == "pre")
    job = stored_robot_job(run, phase_key, "normal", replication, rank, generation=generation)
    runner = worker_trial(job.world, job.trial)
    network = network_for(decode(job.genome, as_groups(job.phase.free_groups)), job.trial)
    rows = []
    for k, position in enumerate(runner.world.systematic_points()[:positions]):
        sector = k // POINTS_PER_SECTOR
        data = runner.run(network, sector, position)
        rows.append({"phase": "pre", "replication": replication, "rank": rank, "trial": k,
                     "sector": sector, **trial_fitness_terms(data, job.world.control_dt)})
    return rows


def evaluated_pre(run_dir: Path) -> list[tuple[int, int]]:
    """The (replication, rank) of every trained pre-reacher in ``run_dir``'s
    evaluation.parquet, sorted."""
    table = stillness.trained_trials(results.read_table(run_dir / results.EVALUATION))
    return sorted(table.select("replication", "rank").unique().iter_rows())


def snapshot_pre(run_dir: Path, generation: int) -> list[tuple[int, int]]:
    """The (replication, rank) of every pre-reacher of the snapshot of ``generation`` that
    ``run_dir``'s development.parquet post-evaluated under normal senses, sorted; ValueError
    when there is none."""
    table = load_development(run_dir)
    rows = (pl.DataFrame() if table is None else
            table.filter((pl.col("phase") == "pre") & (pl.col("generation") == generation)))
    if not rows.height:
        raise ValueError(f"{run_dir}: no pre-reaching snapshot of generation {generation} "
                         f"post-evaluated (make full-budget-snapshots)")
    return sorted(rows.select("replication", "rank").unique().iter_rows())


def build(run_dir: Path, progress=print, generation: int | None = None) -> pl.DataFrame:
    """Every post-evaluated pre-reacher of the run in ``run_dir`` (``evaluated_pre``;
    ``generation``: of that snapshot, ``snapshot_pre``, with ``generation`` in each row): its
    trials (``robot_trials``), one table."""
    robots_ = (evaluated_pre(run_dir) if generation is None
               else snapshot_pre(run_dir, generation))
    run = RunDirectory.open(run_dir)
    more = {} if generation is None else {"generation": generation}
    rows = []
    for i, (replication, rank) in enumerate(robots_):
        rows += [dict(row, **more) for row in robot_trials(run, replication, rank,
                                                           generation=generation)]
        progress(f"{i + 1}/{len(robots_)} replication {replication} rank {rank}")
    return pl.DataFrame(rows)


def judged_missing(run_dir: Path) -> list[int]:
    """The generations of ``strategy_course.JUDGED`` whose snapshot ``run_dir``'s
    development.parquet post-evaluated and its Eq. 5 table does not yet hold, in order."""
    development = load_development(run_dir)
    done = results.read_table(run_dir / TABLE)
    there = (set() if development is None else
             set(development.filter(pl.col("phase") == "pre")["generation"].unique()))
    held = set() if done is None else set(done["generation"].unique())
    return [g for g in JUDGED if g in there and g not in held]


def tables(recordings: Path, run_name: str = RUN) -> dict[str, pl.DataFrame]:
    """``strategy`` (per replication, from the run's evaluation.parquet), ``trials`` (the
    committed per-trial terms with their strategy) and the three summaries."""
    run_dir = recordings / run_name
    strategy = stillness.strategies(results.read_table(run_dir / results.EVALUATION))
    trials = stillness.with_strategy(results.read_table(run_dir / TABLE), strategy)
    return {"strategy": strategy, "trials": trials,
            "by_strategy": stillness.by_strategy(trials),
            "by_sector": stillness.by_sector(trials),
            "by_replication": stillness.by_replication(trials, strategy)}


def _number(value) -> str:
    return f"{value:.3g}" if value is not None and np.isfinite(value) else "–"


def _sectors(by_sector: pl.DataFrame) -> dict[str, str]:
    """``sectors.still_ahead`` / ``sectors.babbling_ahead``: the sectors in which each
    strategy's mean fitness is the higher, as a list ("none" when none)."""
    wide = by_sector.pivot("strategy", index="sector", values="fitness").sort("sector")
    out = {}
    for s, other in ((stillness.STILL, stillness.BABBLING), (stillness.BABBLING, stillness.STILL)):
        ahead = wide.filter(pl.col(s) > pl.col(other))["sector"].to_list()
        out[f"sectors.{s}_ahead"] = ", ".join(map(str, ahead)) or "none"
    return out


def values(recordings: Path, markdown_table) -> dict[str, str]:
    """The values of docs/results/templates/stillness.md: the tables (``by_strategy``,
    ``by_sector``, ``by_replication``, through ``markdown_table``), the rule's threshold and
    the replications of each strategy, and ``<strategy>.<factor>`` for the prose: each
    factor's mean over the strategy's trials (``stillness.COLUMNS``), with ``.segments`` (the
    inner faces touching when in touch) and ``.replications``."""
    t = tables(recordings)
    run = RunDirectory.open(recordings / RUN)
    robots_per = t["trials"].select("replication", "rank").unique().group_by("replication").len()
    evaluated = t["strategy"]["trials"].max() // t["trials"].group_by(
        "replication", "rank").len()["len"].max()
    out = {"run": RUN, "still_share": f"{stillness.STILL_SHARE:.0%}".replace("%", " %"),
           "trials_per_robot": str(t["trials"].group_by("replication", "rank").len()["len"]
                                   .max()),
           "replications": str(t["strategy"].height), "steps": str(run.settings.steps),
           "generations": str(budgets.generations_per_phase(run)[0]),
           "robots_per_replication": str(robots_per["len"].max()),
           "evaluated_robots": str(evaluated),
           "by_strategy": markdown_table(stillness.headed(t["by_strategy"])),
           "by_sector": markdown_table(stillness.headed(
               t["by_sector"].select("strategy", "sector", "trials", "touched", "touch_share",
                                     "touch_level", "sight_level", "scoring_share",
                                     "touches", "contact_after_first", "contact_bout_s",
                                     "fitness"))),
           "by_replication": markdown_table(stillness.headed(
               t["by_replication"].select("replication", "strategy", "babbling_share",
                                          "fitness", "sight_share", "touch_share",
                                          "touch_level", "touched", "touches",
                                          "contact_after_first")))}
    compared = stillness.compare(t["by_replication"])
    out["compare"] = markdown_table(compared)
    p = dict(zip(compared["factor"], compared["p"]))
    counts = [t["strategy"].filter(pl.col("strategy") == s).height
              for s in (stillness.STILL, stillness.BABBLING)]
    out["p.smallest"] = _number(2 / math.comb(sum(counts), counts[0]))
    out["p.fitness"] = _number(p["fitness"])
    fit = {s: t["by_replication"].filter(pl.col("strategy") == s)["fitness"].to_numpy()
           for s in (stillness.STILL, stillness.BABBLING)}
    out["said.fitness"] = said.two_groups(fit[stillness.STILL], fit[stillness.BABBLING],
                                          stillness.STILL, stillness.BABBLING)
    out["p.touch_share"] = _number(p["steps in touch"])
    out["p.touch_level"] = _number(p["p_touch in touch"])
    out.update(_sectors(t["by_sector"]))
    per = {r["strategy"]: r for r in t["by_strategy"].iter_rows(named=True)}
    still, babbling = per[stillness.STILL], per[stillness.BABBLING]
    wrong = stillness.contradicted(still, babbling)
    if wrong:
        raise ValueError(f"docs/results/templates/stillness.md states what the data no longer "
                         f"say: {'; '.join(wrong)}")
    out["ratio.touch_share"] = f"{still['touch_share'] / babbling['touch_share']:.1f}"
    out["ratio.touch_level"] = f"{babbling['touch_level'] / still['touch_level']:.1f}"
    out["ratio.bout"] = f"{still['contact_bout_s'] / babbling['contact_bout_s']:.1f}"
    for row in t["by_strategy"].iter_rows(named=True):
        s = row["strategy"]
        for column in stillness.COLUMNS:
            out[f"{s}.{column}"] = _number(row[column])
        for column in ("sight_share", "touch_share", "scoring_share", "touched",
                       "contact_after_first", "touch_limits"):
            out[f"{s}.{column}_pc"] = f"{row[column]:.0%}".replace("%", " %")
        out[f"{s}.segments"] = f"{row['touch_level'] * N_SEGMENTS:.1f}"
        reps = t["strategy"].filter(pl.col("strategy") == s)["replication"].to_list()
        out[f"{s}.replications"] = ", ".join(map(str, reps))
        out[f"{s}.count"] = str(len(reps))
    out.update(budget_values(recordings, markdown_table))
    return out


def budget_tables(run_dir: Path) -> dict[int, dict[str, pl.DataFrame]]:
    """Per snapshot generation in a run's Eq. 5 table (``FULL``'s: ``--generation``):
    ``by_strategy`` and ``compare`` (``analysis.stillness``; None when one strategy has every
    population), each population's strategy by the same rule as at 50 generations, from the
    snapshot's normal trials in development.parquet; empty without the table."""
    terms = results.read_table(run_dir / TABLE)
    if terms is None:
        return {}
    development = load_development(run_dir)
    out = {}
    for generation in terms["generation"].unique().sort().to_list():
        strategy = stillness.strategies(
            development.filter(pl.col("generation") == generation))
        trials = stillness.with_strategy(terms.filter(pl.col("generation") == generation),
                                         strategy)
        both = strategy["strategy"].n_unique() == 2
        out[generation] = {"by_strategy": stillness.by_strategy(trials),
                           "compare": stillness.compare(stillness.by_replication(
                               trials, strategy)) if both else None}
    return out


def budget_values(recordings: Path, markdown_table) -> dict[str, str]:
    """``budget.generations`` and ``budget.body`` of docs/results/templates/stillness.md:
    ``FULL``'s snapshots taken apart (``budget_tables``): the means per strategy and the
    replication-as-unit comparison, each with a generation column, and per generation which
    of the page's statements (``stillness.STATED``) its means contradict."""
    tables_ = budget_tables(recordings / FULL)
    if not tables_:
        return {"budget.generations": "none yet",
                "budget.body": "Nothing taken apart yet: no snapshot's rows in the table."}

    def stacked(name: str) -> pl.DataFrame:
        return pl.concat([t[name].select(pl.lit(g).alias("generation"), pl.all())
                          for g, t in tables_.items() if t[name] is not None])

    by_strategy = stacked("by_strategy").select("generation", "strategy", "replications",
                                                "robots", "trials", *BUDGET_COLUMNS)
    stated, smallest = [], []
    for generation, t in tables_.items():
        per = {r["strategy"]: r for r in t["by_strategy"].iter_rows(named=True)}
        if t["compare"] is None:
            stated.append(f"at {generation} all the populations are {next(iter(per))}: "
                          f"nothing to compare")
            continue
        counts = [r["replications"] for r in per.values()]
        smallest.append(f"{_number(2 / math.comb(sum(counts), counts[0]))} at {generation}")
        still, babbling = per[stillness.STILL], per[stillness.BABBLING]
        wrong = stillness.contradicted(still, babbling)
        p = dict(zip(t["compare"]["factor"], t["compare"]["p"]))
        stated.append(
            f"at {generation} " + ("every one holds" if not wrong
                                   else "these do not: " + "; ".join(wrong))
            + f" (a still robot is in touch on "
            f"{still['touch_share'] / babbling['touch_share']:.1f} times as many steps as a "
            f"babbling one, with {still['touch_level'] / babbling['touch_level']:.2f} times "
            f"the faces; fitness {_number(still['fitness'])} against "
            f"{_number(babbling['fitness'])}, p = {_number(p['fitness'])} with the "
            f"replication as the unit)")
    body = ("Means over each strategy's trials, as in \"Per strategy\" above:\n\n"
            + markdown_table(stillness.headed(by_strategy))
            + "\n\nThe replication as the unit, as in \"The replication as the unit\" above "
            "(the smallest p the two strategies' numbers of populations allow: "
            + (", ".join(smallest) or "none") + "):\n\n"
            + (markdown_table(stacked("compare")) if smallest else "(none)")
            + "\n\nThe statements of \"In plain words\" (`analysis.stillness.STATED`), "
            "checked on these means: " + "; ".join(stated) + ".")
    return {"budget.generations": ", ".join(map(str, tables_)), "budget.body": body}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m dart_reach.studies.stillness",
                                     description=f"run {RUN}'s post-evaluated pre-reachers "
                                                 f"again and write recordings/{RUN}/{TABLE}; "
                                                 f"with --generation or --judged, {FULL}'s "
                                                 f"snapshots")
    parser.add_argument("root", nargs="?", type=Path, default=Path("."),
                        help="the repository (default: the current directory)")
    parser.add_argument("--generation", type=int, action="append", default=[],
                        help=f"the snapshot of this generation of {FULL} instead, added to "
                             f"its {TABLE} (repeat for more)")
    parser.add_argument("--judged", action="store_true",
                        help="every judged generation (50, 100, ...) post-evaluated in the "
                             "run's development.parquet and not yet in its table")
    parser.add_argument("--run-dir", type=Path, default=None,
                        help=f"the run of the snapshots (default ROOT/recordings/{FULL}; a "
                             f"copy of a run still training, as make full-budget-snapshots "
                             f"makes)")
    args = parser.parse_args(argv)
    entry = results.session()
    if not (args.generation or args.judged):
        path = args.root / "recordings" / RUN / TABLE
        table = build(path.parent)
        entry["rows"] = table.height
        results.write_table(path, table, [entry])
        print(f"wrote {path}: {table.height} trials")
        return 0
    run_dir = args.run_dir or args.root / "recordings" / FULL
    path = run_dir / TABLE
    try:
        for generation in [*args.generation, *(judged_missing(run_dir) if args.judged else [])]:
            rows = build(run_dir, generation=generation).to_dicts()
            results.save_table(path, results.read_table(path), rows, SNAPSHOT_KEY, entry)
            print(f"wrote {path}: generation {generation}, {len(rows)} trials")
    except (ValueError, FileNotFoundError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
