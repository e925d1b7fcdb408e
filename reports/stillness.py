"""What each strategy earns: docs/results/stillness.md's values, from the post-evaluated
pre-reachers' trials run again with their fitness taken apart (Eq. 5,
``dart_reach.studies.fitness_terms``).

``python -m reports.stillness [ROOT]`` runs the 45 systematic trials (normal senses) of every
pre-reaching robot that ``RUN``'s post-evaluation evaluated (the best 5 of each of its 10
replications' final populations, the robots of its evaluation.parquet) in this one process and
writes one row per trial to ``recordings/RUN/`` ``fitness_terms.TABLE``. 2,250 trials, about
six minutes on one core. The page is then rendered from that committed table and the run's
evaluation.parquet (``values``; ``make results``).

``python -m reports.stillness --generation G`` does the same for the snapshot of generation G
of the full-budget run (``FULL``: the best 5 robots of each replication that its
development.parquet post-evaluated there), adding its rows to its table (``generation`` in
every row; a generation run again replaces its rows): what each strategy earns at the paper's
budget (``budget_values``). ``--judged`` runs every generation of ``runs.JUDGED``
post-evaluated and not yet in the table (``fitness_terms.missing``; ``make
full-budget-snapshots`` does, on its copy of the run: ``--run-dir``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import polars as pl

from dart_reach.analysis import budgets, formatting, said, strategies
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.model.task import N_SEGMENTS
from dart_reach.postevaluation import results
from dart_reach.studies.fitness_terms import (SNAPSHOT_KEY, TABLE, build, by_snapshot,
                                              missing)

from . import calibration
from .runs import FULL, JUDGED, STILLNESS_RUN as RUN

#: The columns of the page's tables at the paper's budget (``strategies.COLUMNS``'s keys).
BUDGET_COLUMNS = ("fitness", "touch_share", "touch_level", "scoring_share", "touched",
                  "touches", "contact_after_first", "contact_bout_s")


def tables(recordings: Path, run_name: str = RUN) -> dict[str, pl.DataFrame]:
    """``strategy`` (per replication, from the run's evaluation.parquet), ``trials`` (the
    committed per-trial terms with their strategy) and the three summaries."""
    run_dir = recordings / run_name
    strategy = strategies.strategies(results.read_table(run_dir / results.EVALUATION))
    trials = strategies.with_strategy(results.read_table(run_dir / TABLE), strategy)
    return {"strategy": strategy, "trials": trials,
            "by_strategy": strategies.by_strategy(trials),
            "by_sector": strategies.by_sector(trials),
            "by_replication": strategies.by_replication(trials, strategy)}


def _sectors(by_sector: pl.DataFrame) -> dict[str, str]:
    """``sectors.still_ahead`` / ``sectors.babbling_ahead``: the sectors in which each
    strategy's mean fitness is the higher, as a list ("none" when none)."""
    wide = by_sector.pivot("strategy", index="sector", values="fitness").sort("sector")
    out = {}
    for s, other in ((strategies.STILL, strategies.BABBLING),
                     (strategies.BABBLING, strategies.STILL)):
        ahead = wide.filter(pl.col(s) > pl.col(other))["sector"].to_list()
        out[f"sectors.{s}_ahead"] = ", ".join(map(str, ahead)) or "none"
    return out


def values(recordings: Path, markdown_table) -> dict[str, str]:
    """The values of docs/results/templates/stillness.md: the tables (``by_strategy``,
    ``by_sector``, ``by_replication``, through ``markdown_table``), the rule's threshold and
    the replications of each strategy, and ``<strategy>.<factor>`` for the prose: each
    factor's mean over the strategy's trials (``strategies.COLUMNS``), with ``.segments`` (the
    inner faces touching when in touch) and ``.replications``; ``ratio.*``, ratios of those
    means (descriptions, not tests); which strategy is higher only from the gated rule:
    ``rule.words`` (``strategies.decided``) and ``said.*`` (``said.two_groups``)."""
    t = tables(recordings)
    run = RunDirectory.open(recordings / RUN)
    robots_per = t["trials"].select("replication", "rank").unique().group_by("replication").len()
    evaluated = t["strategy"]["trials"].max() // t["trials"].group_by(
        "replication", "rank").len()["len"].max()
    out = {"run": RUN, "still_share": formatting.percent(strategies.STILL_SHARE),
           "trials_per_robot": str(t["trials"].group_by("replication", "rank").len()["len"]
                                   .max()),
           "replications": str(t["strategy"].height), "steps": str(run.settings.steps),
           "generations": str(budgets.generations_per_phase(run)[0]),
           "robots_per_replication": str(robots_per["len"].max()),
           "evaluated_robots": str(evaluated),
           "by_strategy": markdown_table(strategies.headed(t["by_strategy"])),
           "by_sector": markdown_table(strategies.headed(
               t["by_sector"].select("strategy", "sector", "trials", "touched", "touch_share",
                                     "touch_level", "sight_level", "scoring_share",
                                     "touches", "contact_after_first", "contact_bout_s",
                                     "fitness"))),
           "by_replication": markdown_table(strategies.headed(
               t["by_replication"].select("replication", "strategy", "babbling_share",
                                          "fitness", "sight_share", "touch_share",
                                          "touch_level", "touched", "touches",
                                          "contact_after_first")))}
    compared = strategies.compare(t["by_replication"])
    out["compare"] = markdown_table(compared)
    out["p.smallest"] = formatting.significant(compared["smallest p"][0])
    calibrated = calibration.committed()
    for column in ("fitness", "touch_share", "touch_level", "sight_share"):
        units = {s: t["by_replication"].filter(pl.col("strategy") == s)[column].to_numpy()
                 for s in (strategies.STILL, strategies.BABBLING)}
        out[f"said.{column}"] = said.two_groups(units[strategies.STILL],
                                                units[strategies.BABBLING], strategies.STILL,
                                                strategies.BABBLING, calibrated)
    out.update(_sectors(t["by_sector"]))
    per = {r["strategy"]: r for r in t["by_strategy"].iter_rows(named=True)}
    still, babbling = per[strategies.STILL], per[strategies.BABBLING]
    out["rule.words"] = strategies.decided(compared)
    out["ratio.touch_share"] = f"{still['touch_share'] / babbling['touch_share']:.1f}"
    out["ratio.touch_level"] = f"{babbling['touch_level'] / still['touch_level']:.1f}"
    out["ratio.bout"] = f"{still['contact_bout_s'] / babbling['contact_bout_s']:.1f}"
    for row in t["by_strategy"].iter_rows(named=True):
        s = row["strategy"]
        for column in strategies.COLUMNS:
            out[f"{s}.{column}"] = formatting.significant(row[column])
        for column in ("sight_share", "touch_share", "scoring_share", "touched",
                       "contact_after_first", "touch_limits"):
            out[f"{s}.{column}_pc"] = formatting.percent(row[column])
        out[f"{s}.segments"] = f"{row['touch_level'] * N_SEGMENTS:.1f}"
        reps = t["strategy"].filter(pl.col("strategy") == s)["replication"].to_list()
        out[f"{s}.replications"] = ", ".join(map(str, reps))
        out[f"{s}.count"] = str(len(reps))
    out.update(budget_values(recordings, markdown_table))
    return out


def budget_values(recordings: Path, markdown_table) -> dict[str, str]:
    """``budget.generations`` and ``budget.body`` of docs/results/templates/stillness.md:
    ``FULL``'s snapshots taken apart (``fitness_terms.by_snapshot``): the means per strategy
    and the replication-as-unit comparison, each with a generation column, and per generation
    what the gated rule says of each factor (``strategies.decided``) beside ratios of the
    means, which are descriptions, not tests."""
    tables_ = by_snapshot(recordings / FULL)
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
        smallest.append(f"{formatting.significant(t['compare']['smallest p'][0])} at "
                        f"{generation}")
        still, babbling = per[strategies.STILL], per[strategies.BABBLING]
        stated.append(
            f"at {generation}, {still['replications']} still against "
            f"{babbling['replications']} babbling replications, the gated rule: "
            f"{strategies.decided(t['compare'])}; the means of the pooled trials, not a test: "
            f"steps in touch, still / babbling "
            f"{still['touch_share'] / babbling['touch_share']:.1f}; p_touch in touch "
            f"{still['touch_level'] / babbling['touch_level']:.2f}; fitness "
            f"{formatting.significant(still['fitness'])} and "
            f"{formatting.significant(babbling['fitness'])}")
    body = ("Means over each strategy's trials, as in \"Per strategy\" above:\n\n"
            + markdown_table(strategies.headed(by_strategy))
            + "\n\nThe replication as the unit, as in \"The replication as the unit\" above "
            "(the gated rule, `verdicts.directional`; the smallest p the two strategies' "
            "numbers of populations allow: "
            + (", ".join(smallest) or "none") + "):\n\n"
            + (markdown_table(stacked("compare")) if smallest else "(none)")
            + "\n\nIn words, as in \"In plain words\" above (which strategy is higher only "
            "from the gated rule, `analysis.strategies.decided`): " + "; ".join(stated) + ".")
    return {"budget.generations": ", ".join(map(str, tables_)), "budget.body": body}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m reports.stillness",
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
        for generation in [*args.generation, *(missing(run_dir, JUDGED) if args.judged else [])]:
            rows = build(run_dir, generation=generation).to_dicts()
            results.save_table(path, results.read_table(path), rows, SNAPSHOT_KEY, entry)
            print(f"wrote {path}: generation {generation}, {len(rows)} trials")
    except (ValueError, FileNotFoundError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
