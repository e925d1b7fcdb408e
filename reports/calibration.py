"""The calibration table of docs/results/calibration.md, a compact result committed beside the
runs' (``recordings/calibration/calibration.parquet``): every verdict rule calibrated by
simulation (``dart_reach.analysis.calibration.calibrate``) and beside it what the headline
avoids (``ROBOT_LEVEL``: the robot as the unit), and the page's values (``values``:
the table and every number its prose states, read from the table; ``make results`` renders
docs/results/templates/calibration.md with them).

    python -m reports.calibration     # writes the table and prints it as the page shows it
    python -m reports.calibration --blocks paired_rates    # recomputes one block of it
    python -m reports.calibration --robot-level            # the robot-level table alone
    python -m reports.calibration --pilot                  # the run-shaped rules' pilot

About an hour on 2 cores beside a training run; tests/analysis/test_calibration.py checks the
committed table and recomputes parts of it.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import polars as pl

from dart_reach.analysis import calibration as cal
from dart_reach.analysis import calibration_core, coverage
from dart_reach.analysis import paired_calibration as paired_cal
from dart_reach.analysis import run_shaped_calibration as run_shaped
from dart_reach.analysis import verdicts
from dart_reach.analysis.calibration import NESTINGS, calibrate, robot_level

TABLE = Path(__file__).resolve().parents[1] / "recordings" / "calibration" / "calibration.parquet"
#: What the headline avoids, beside the table (``calibration.robot_level``): one row per
#: nesting.
ROBOT_LEVEL = TABLE.with_name("robot-level.parquet")
#: The pilot that chose the gates and levels of the rules on rates
#: (``run_shaped_calibration.pilot``): one row per rule, size and level.
PILOT = TABLE.with_name("run-shaped-pilot.parquet")


def committed() -> pl.DataFrame:
    """The committed calibration table (``TABLE``), as ``main`` wrote it: what the pages'
    labels of coverage read (``analysis.coverage``)."""
    return pl.read_parquet(TABLE)


def held(table: pl.DataFrame) -> dict[str, float | int]:
    """What a calibration table (``calibrate``'s) shows, for the prose of the pages that cite
    it, so that no page states it as fixed text: ``bounded`` (rows with a bound: error rates
    under a null and coverages), ``met`` (of them, those within Monte-Carlo error of their
    bound), ``highest_error`` and ``error_bound`` (the highest rate of a wrong decision under
    a null over the "at most" rows, and the bound of that row), ``lowest_coverage`` (the
    lowest coverage over the "at least" rows), ``reported_low``, ``reported_high`` (the
    range of theta's coverages only reported, ``coverage.RULE``'s: NaN without one; a paired
    claim of no change's are ``coverage.paired_coverage``'s), ``unbounded`` (the rules in use
    whose error rate under some null is only reported, with that null) and
    ``unbounded_high`` (the highest of those rates: NaN without one). Rates in [0, 1]."""
    bounded = table.filter(pl.col("kind").is_in(["at most", "at least"]))
    errors = table.filter(pl.col("kind") == "at most").sort("value", descending=True)
    covers = table.filter(pl.col("kind") == "at least")
    reported = table.filter((pl.col("kind") == "reported") & (pl.col("rule") == coverage.RULE)
                            & pl.col("measure").str.starts_with("coverage"))
    # a rule in use (one with bounded rows) whose error rate under some null is only reported
    unbounded = table.filter((pl.col("kind") == "reported")
                             & pl.col("rule").is_in(bounded["rule"].unique().implode())
                             & ~pl.col("measure").str.starts_with("coverage"))
    return {"bounded": bounded.height, "met": int(bounded["ok"].sum()),
            "highest_error": float(errors["value"][0]), "error_bound": float(errors["bound"][0]),
            "lowest_coverage": float(covers["value"].min()),
            "reported_low": float(reported["value"].min()) if reported.height else math.nan,
            "reported_high": float(reported["value"].max()) if reported.height else math.nan,
            "unbounded": ", ".join(f"{r}: {s.split(' (')[0]}" for r, s in unbounded.select(
                "rule", "scenario").unique(maintain_order=True).rows()),
            "unbounded_high": float(unbounded["value"].max()) if unbounded.height else math.nan}


def markdown(table: pl.DataFrame) -> str:
    """The calibration table as Markdown: one row per rule, scenario and measure, one column
    per nesting (rates in [0, 1]); the bound a rate must meet, and whether every nesting met
    it."""
    nests = table.select("replications", "robots", "between_sd", "within_sd").unique(
        maintain_order=True).rows()
    heads = [f"{r} x {k}, within s.d. {w:g}" for r, k, b, w in nests]
    lines = ["| rule | scenario | measure | " + " | ".join(heads) + " | bound | met |",
             "|---|---|---|" + "---:|" * len(heads) + "---:|---|"]
    keys = table.select("rule", "scenario", "measure", "kind").unique(maintain_order=True)
    first = {r: i for i, r in enumerate(table["rule"].unique(maintain_order=True))}
    # rows grouped by rule (a rule's rows that only some nestings have come after the others)
    for rule, scenario, measure, kind in sorted(keys.rows(), key=lambda k: first[k[0]]):
        rows = table.filter((pl.col("rule") == rule) & (pl.col("scenario") == scenario)
                            & (pl.col("measure") == measure))
        values = []
        for r, k, b, w in nests:
            cell = rows.filter((pl.col("replications") == r) & (pl.col("within_sd") == w))
            values.append(f"{cell['value'][0]:.3f}" if cell.height else "")
        bound = (kind if kind in ("power", "reported") else
                 f"≤ {rows['bound'][0]:g}" if kind == "at most" else f"≥ {rows['bound'][0]:g}")
        met = "" if kind in ("power", "reported") else ("yes" if rows["ok"].all() else "**no**")
        lines.append(f"| {rule} | {scenario} | {measure} | " + " | ".join(values)
                     + f" | {bound} | {met} |")
    return "\n".join(lines) + "\n"


def cells(table: pl.DataFrame, rule: str, scenario: str, measure: str,
          replications: int | None = None) -> list[float]:
    """The values of one row of ``table`` over its nestings (those of ``replications`` only,
    when given), in the table's order."""
    rows = table.filter((pl.col("rule") == rule) & (pl.col("scenario") == scenario)
                        & (pl.col("measure") == measure))
    if replications is not None:
        rows = rows.filter(pl.col("replications") == replications)
    if rows.height == 0:
        raise KeyError(f"no calibration row {rule!r} / {scenario!r} / {measure!r}")
    return rows["value"].to_list()


def span(values, digits: int = 2) -> str:
    """The range of ``values`` as the prose writes it: "0.12-0.14", or one number when both
    ends round alike."""
    low, high = f"{min(values):.{digits}f}", f"{max(values):.{digits}f}"
    return low if low == high else f"{low}-{high}"


def _paired_values(table: pl.DataFrame) -> dict[str, str]:
    """The numbers of the page's paragraphs on the paired claims of no change (the rate rule,
    the relative-change rule, senses differ's equivalence; ``paired_calibration``), at 3 and
    10 pairs: the rule, beside it the rule without its gate for lopsided changes, with its
    one-sided tests at 0.05 (the rule before ``PAIRED_EQUIVALENCE_LEVEL``) and the t TOST
    before both (rates in [0, 1])."""
    rate, rel = "paired rate no change", "paired no change"
    lopsided = [s for s, symmetric in cal.RATE_SHAPES.items() if not symmetric]
    symmetric = [s for s, sym in cal.RATE_SHAPES.items() if sym]
    at_margin = lambda shapes, rule, k=10: [  # noqa: E731
        x for s in shapes for x in cells(table, rule, f"{s}, change at the margin", "reproduced",
                                         k)]
    at_10 = table.filter((pl.col("replications") == 10) & (pl.col("kind") == "at most")
                         & pl.col("rule").is_in([rate, rel, "senses differ"]))
    both = lambda values: " / ".join(f"{x:.3f}" for x in values)  # noqa: E731
    mean_sd = paired_cal.CONSISTENT
    consistent = f"small consistent change ({mean_sd[0]:g} margin, s.d. {mean_sd[1]:g})"
    # the power rows (words, scenario, rule), each beside the rule without its gate and at 0.05
    power = [("a rate in fifths", "rates in fifths, no change", rate),
             ("with half the replications still", "50 % of replications still, no change",
              rate),
             ("two-mode changes", "two-mode changes, no change", rate),
             ("a measure's relative change (s.d. one margin)", "no change", rel),
             (f"a small consistent relative change ({mean_sd[0]:g} margin, s.d. {mean_sd[1]:g}),"
              " most replications moving the same way", consistent, rel)]
    beside = {rate: (cal.RATE_UNGATED, paired_cal.RATE_AT_ALPHA),
              rel: (cal.PAIRED_UNGATED, paired_cal.PAIRED_AT_ALPHA)}
    reproduced = lambda rule, scenario: cells(table, rule, scenario, "reproduced", 10)  # noqa
    straddling = [paired_cal.straddling_scenario(s) for s in paired_cal.STRADDLING]
    at = lambda rule: [x for s in straddling for x in reproduced(rule, s)]  # noqa: E731
    skewed_none = f"{lopsided[1]}, no change"
    senses = lambda rule: both(cells(table, rule, "no difference", "contradicted", 10))  # noqa
    return {
        "t_two_mode_3": span(cells(table, cal.RATE_BEFORE, "two-mode changes, no change, 3 pairs",
                                   "contradicted")
                             + cells(table, cal.PAIRED_BEFORE, "no change, two-mode changes, "
                                     "3 pairs", "contradicted")),
        "t_skewed_3": span(cells(table, cal.RATE_BEFORE, f"{lopsided[1]}, change at the margin, "
                                 "3 pairs", "reproduced")),
        "t_lopsided_10": span(at_margin(lopsided, cal.RATE_BEFORE)),
        "t_still_10": span(cells(table, cal.RATE_BEFORE, "50 % of replications still, change "
                                 "at the margin", "reproduced", 10)),
        "symmetric_10": span(at_margin(symmetric, rate), 3),
        "ungated_lopsided_10": span(at_margin(lopsided, cal.RATE_UNGATED), 3),
        "gated_lopsided_10": span(at_margin(lopsided, rate), 3),
        "highest_10": f"{at_10['value'].max():.3f}",
        "gate_rule": (f"at most {verdicts.LOPSIDED_MINORITY} of the replications that changed "
                      "at all moved against the rest"),
        "gate_cost": "; ".join(
            f"{words} {both(reproduced(rule, scenario))} against "
            f"{both(reproduced(beside[rule][0], scenario))}" for words, scenario, rule in power)
        + f"; \"senses differ\" contradicted where the senses are alike "
          f"{senses('senses differ')} against {senses(cal.SENSES_UNGATED)}",
        "level_cost": "; ".join(
            f"{words} {both(reproduced(rule, scenario))} against "
            f"{both(reproduced(beside[rule][1], scenario))}" for words, scenario, rule in power),
        "skewed_contradicted": span(cells(table, rate, skewed_none, "contradicted", 10), 3),
        "skewed_contradicted_ungated": span(cells(table, cal.RATE_UNGATED, skewed_none,
                                                  "contradicted", 10), 3),
        "straddling_scales": ", ".join(f"{s:g}" for s in paired_cal.STRADDLING),
        "straddling_rate": f"{span(at(rate), 3)} (rates), {span(at(rel), 3)} (relative changes)",
        "straddling_at_alpha": (f"{span(at(paired_cal.RATE_AT_ALPHA))} (rates), "
                                f"{span(at(paired_cal.PAIRED_AT_ALPHA))} (relative changes)"),
        "equivalence_level": f"{verdicts.PAIRED_EQUIVALENCE_LEVEL:g}",
        "interval_level": f"{100 * (1 - 2 * verdicts.PAIRED_EQUIVALENCE_LEVEL):g}"}


def _interval_short(table: pl.DataFrame) -> str:
    """The directional interval's coverage away from theta = 0.5 with unequal shapes (only
    reported), per shape and within-replication s.d., as the page's sentence."""
    theta = f"theta {cal.COVERAGE_THETA:g}"
    parts = []
    for shape, words in zip(cal.SHAPES[1:], ("with a zero-inflated group against a continuous "
                                             "one", "with spreads 1 : 4")):
        rows = table.filter(pl.col("scenario") == f"{theta}, {shape}")
        parts.append(f"{words} " + " and ".join(
            f"{r['value']:.3f} (within s.d. {r['within_sd']:g})" for r in rows.iter_rows(
                named=True)))
    return ", ".join(parts)


def paired_interval(table: pl.DataFrame) -> str:
    """The label of a paired claim of no change's interval (the centres its one-sided tests at
    ``verdicts.PAIRED_EQUIVALENCE_LEVEL`` do not reject): its nominal level and the coverage
    the calibration ``table`` measured per number of pairs and shape of the changes
    (``coverage.paired_label``)."""
    return coverage.paired_label(table)


def _paired_coverage(table: pl.DataFrame) -> dict[str, str]:
    """The page's sentences on a paired claim of no change's interval, from ``table``:
    ``paired_coverage`` (its coverage per number of pairs and shape, the lowest and where),
    ``paired_coverage_se`` (the Monte-Carlo standard error of a coverage at the nominal level
    over ``DATASETS`` data sets, and 2.33 of it), ``straddling_clipped`` (the true mean of the
    clipped relative changes straddling 0 at the widest ``STRADDLING``) and
    ``paired_coverage_short`` (the lowest measured, for the closing lines)."""
    measured = coverage.paired_coverage(table)
    nominal = coverage.PAIRED_NOMINAL
    se = math.sqrt(nominal * (1 - nominal) / calibration_core.DATASETS)
    if not measured.height:
        return {"paired_coverage": "not measured", "paired_coverage_se": "",
                "paired_coverage_short": "not measured", "straddling_clipped": ""}
    lowest = measured.sort("low").row(0, named=True)
    scale = max(paired_cal.STRADDLING)
    clipped = paired_cal.straddling_mean(scale, verdicts.PAIRED_MARGIN, paired_cal.RELATIVE_CLIP)
    parts = "; ".join(
        f"{span([r['low'], r['high']], 3)} at {r['pairs']} pairs "
        f"{coverage.SHAPE_WORDS[r['shape']]} ({r['rows']} rows)"
        for r in measured.iter_rows(named=True))
    return {"paired_coverage": f"{parts}; the lowest, {lowest['low']:.3f}, under "
                               f"\"{lowest['lowest_at']}\"",
            "paired_coverage_se": (f"{se:.4f} at {calibration_core.DATASETS:,} data sets at "
                                   f"{nominal:g} ({calibration_core.Z_MC:g} s.e. = "
                                   f"{calibration_core.Z_MC * se:.3f})"),
            "straddling_clipped": (f"{clipped:.3f} at {scale:g} margins against "
                                   f"{verdicts.PAIRED_MARGIN:g}"),
            "paired_coverage_short": (f"{lowest['low']:.3f} at the lowest "
                                      f"(\"{lowest['lowest_at']}\", {lowest['pairs']} pairs)")}


def robot_level_markdown(table: pl.DataFrame) -> str:
    """The robot-level rates under the null (``ROBOT_LEVEL``'s rows) as the page's table."""
    rates = [c for c in table.columns
             if c not in ("replications", "robots", "between_sd", "within_sd")]
    lines = ["| nesting | " + " | ".join(rates) + " |", "|---|" + "---:|" * len(rates)]
    for r in table.iter_rows(named=True):
        nest = cal.Nesting(r["replications"], r["robots"], r["between_sd"], r["within_sd"])
        lines.append(f"| {nest.label} | " + " | ".join(f"{r[c]:.3f}" for c in rates) + " |")
    return "\n".join(lines)


def _ungated_split(table: pl.DataFrame) -> str:
    """How often the no-difference and not-better rules without their two-mode gate
    contradicted the null at ``calibration.SPLIT`` (3 vs 7), over the nestings."""
    scenario = f"null, {cal.SHAPES[0]}, {cal.SPLIT[0]} vs {cal.SPLIT[1]}"
    return " and ".join(f"{span(cells(table, cal.UNGATED[rule], scenario, 'contradicted'))} "
                        f"({rule})" for rule in cal.UNGATED)


def failing(table: pl.DataFrame) -> pl.DataFrame:
    """The bounded rows of ``table`` not met within Monte-Carlo error (``ok`` false)."""
    return table.filter(pl.col("ok").is_not_null() & ~pl.col("ok"))


def _over(table: pl.DataFrame, rule: str, scenarios) -> str:
    """Where ``rule`` (a reported rule, unbounded) decides above ``ALPHA`` + ``Z_MC`` s.e. at
    ``DATASETS`` data sets under ``scenarios``: "under S at R and R replications; ..." or
    "under none of them"."""
    bound = verdicts.ALPHA + calibration_core.Z_MC * math.sqrt(
        verdicts.ALPHA * (1 - verdicts.ALPHA) / calibration_core.DATASETS)
    rows = table.filter((pl.col("rule") == rule) & pl.col("scenario").is_in(list(scenarios))
                        & (pl.col("value") > bound))
    parts = [f"{scenario.removeprefix('null, ')} at " + " and ".join(
        map(str, sorted(set(block["replications"])))) for (scenario,), block in
        rows.group_by("scenario", maintain_order=True)]
    return "under " + "; ".join(parts) if parts else "under none of them"


def _holds(table: pl.DataFrame, rules, replications: int | None = None) -> str:
    """Whether every bounded row of ``rules`` (at ``replications``, when given) is met: "holds
    its level under every null" or "exceeds it under: ..." (the failing scenarios)."""
    rows = table.filter(pl.col("rule").is_in(list(rules)) & pl.col("ok").is_not_null())
    if replications is not None:
        rows = rows.filter(pl.col("replications") == replications)
    bad = failing(rows)
    if not bad.height:
        return f"hold their bounds (all {rows.height} rows)"
    return ("miss their bounds in " + "; ".join(
        f"{r} ({s}, {m})" for r, s, m in bad.select("rule", "scenario", "measure").unique(
            maintain_order=True).rows()))


def _gate(table: pl.DataFrame, rule: str) -> str:
    """The sizes at which ``rule``'s bounded rows fail (from the scenario's "N replications" /
    "N pairs", else the nesting's) and the smallest size above them all where every row
    holds."""
    rows = table.filter((pl.col("rule") == rule) & pl.col("ok").is_not_null()).with_columns(
        run_shaped.scenario_size().fill_null(pl.col("replications")).alias("n"))
    bad = sorted(set(failing(rows)["n"]))
    if not bad:
        return f"{rule}: every bounded row met"
    ok = sorted(n for n in set(rows["n"]) if n > max(bad))
    return (f"{rule}: fails at {', '.join(map(str, bad))}"
            + (f", holds from {ok[0]}" if ok else " (no larger size simulated)"))


def _shaped_values(table: pl.DataFrame) -> dict[str, str]:
    """The page's paragraph on the rules under run-shaped nulls (``run_shaped_calibration``):
    the data sets a row is over and their Monte-Carlo error, each rule's bounded rows failed
    (``shaped_failed``), where each rule holds (``shaped_gates``), the intervals' labels."""
    n = run_shaped.DATASETS
    se = math.sqrt(verdicts.ALPHA * (1 - verdicts.ALPHA) / n)
    se_cover = math.sqrt(0.95 * 0.05 / n)
    rules = (run_shaped.BAND, run_shaped.SECTORS, run_shaped.CHANGE, run_shaped.SENSES)
    shaped = table.filter(pl.col("rule").is_in(rules))
    bad = failing(shaped)
    listed = "\n".join(
        f"- {rule} ({block.height} rows): " + "; ".join(
            f"{r['scenario']} ({r['measure']}): {r['value']:.3f} at within s.d. "
            f"{r['within_sd']:g}" for r in block.iter_rows(named=True))
        for (rule,), block in bad.sort("rule", "scenario").group_by("rule",
                                                                     maintain_order=True))
    return {"shaped_datasets": (f"{n:,} data sets a row (a rate near 0.05 has a Monte-Carlo "
                                f"standard error of {se:.4f}: a row fails above "
                                f"{verdicts.ALPHA + calibration_core.Z_MC * se:.3f}; a "
                                f"coverage at 0.95, s.e. {se_cover:.4f}, fails below "
                                f"{0.95 - calibration_core.Z_MC * se_cover:.3f}, over the data "
                                "sets with an interval)"),
            "shaped_failed": (f"{bad.height} of the {shaped['ok'].is_not_null().sum()} bounded "
                              "rows are not met" + (
                                  ", every one a coverage of an interval (every error rate "
                                  "holds its bound; the pages label the intervals with the "
                                  "coverage measured, below)"
                                  if bad["measure"].str.starts_with("coverage").all() else "")
                              + ":\n\n" + listed + "\n") if bad.height else
                             (f"all {shaped['ok'].is_not_null().sum()} bounded rows are met"),
            "shaped_gates": "; ".join(_gate(table, r) for r in rules),
            "band_interval": coverage.shaped_label(table, "band"),
            "sector_interval": coverage.shaped_label(table, "sector"),
            "change_interval": coverage.shaped_label(table, "change")}


def pilot_values(pilot: pl.DataFrame) -> dict[str, str]:
    """The page's account of the pilot (``PILOT``): what it chose (``pilot_choice``, from
    ``run_shaped_calibration.choose``) and, per rule and size, its largest error over the
    family at the level before (the largest it tried) and at the one chosen (``pilot_table``)."""
    chosen = run_shaped.choose(pilot)
    what = {run_shaped.BAND: ("the band", "each edge", lambda lv: 1 - 2 * lv),
            run_shaped.SECTORS: ("every sector", "each cell's lower bound",
                                 lambda lv: 1 - 2 * lv),
            run_shaped.CHANGE: ("the paired change", "its Wilcoxon test", lambda lv: 1 - lv),
            run_shaped.SENSES: ('"senses differ"', "its Friedman test", None)}
    parts = []
    for rule, (gate, level) in chosen.items():
        name, bound, interval = what[rule]
        fewest = min(run_shaped.PILOT_SIZES[rule])
        parts.append(f"{name}: " + (f"from {gate} replications, " if gate > fewest else "")
                     + f"{bound} at {level:g}"
                     + (f" (its interval {100 * interval(level):g} %)" if interval else ""))
    lines = ["| rule | units | level before | its largest error | level chosen | its largest "
             "error | where (at the level chosen) |", "|---|---:|---:|---:|---:|---:|---|"]
    for rule, (gate, level) in chosen.items():
        before = max(run_shaped.PILOT_LEVELS[rule])
        for size in run_shaped.PILOT_SIZES[rule]:
            at = pilot.filter((pl.col("rule") == rule) & (pl.col("size") == size))
            old = at.filter(pl.col("level") == before).row(0, named=True)
            new = at.filter(pl.col("level") == level).row(0, named=True)
            gated = (" (below the gate: not decided)" if size < gate else
                     " (the test cannot decide: its smallest p is "
                     f"{verdicts.smallest_signed_rank_p(size):.3f})" if rule == run_shaped.CHANGE
                     and verdicts.smallest_signed_rank_p(size) >= level else "")
            lines.append(f"| {rule.removesuffix(', run-shaped rates')} | {size} | {before:g} | "
                         f"{old['error']:.3f} | {level:g} | {new['error']:.3f} | "
                         f"{new['worst']}{gated} |")
    return {"pilot_choice": "; ".join(parts), "pilot_table": "\n".join(lines)}


def _prose(table: pl.DataFrame) -> dict[str, str]:
    """The page's sentences that read the table rather than state it: where Mann-Whitney
    decides above its level (``mann_whitney_over``) and its power at 4 replications
    (``mann_whitney_2sd_4``), whether the directional rule and the
    no-difference and not-better rules hold their bounds (``directional_holds``,
    ``two_group_holds_10``), their powers beside Mann-Whitney's at 10 (``power_beside``),
    theta's reported coverage away from 0.5 (``reported_span``) and the whole table's count
    (``every_rule``)."""
    old = "directional: Mann-Whitney (the rule before, reported)"
    shape_nulls = [f"null, {s}" for s in cal.SHAPES]
    mw = lambda d: span(cells(table, old, f"shift {d} s.d.", "reproduced", 10))  # noqa: E731
    bm = lambda d: span(cells(table, "directional", f"shift {d} s.d.", "reproduced",  # noqa
                              10))
    kept = held(table)
    bad = failing(table)
    return {"mann_whitney_over": _over(table, old, shape_nulls),
            "mann_whitney_2sd_4": span(cells(table, old, "shift 2 s.d.", "reproduced", 4)),
            "directional_holds": _holds(table, ["directional"], 10),
            "two_group_holds_10": _holds(table, ["no difference", "not better"], 10),
            "power_beside": (f"a 1-s.d. shift {bm(1)} against Mann-Whitney's {mw(1)}, a "
                             f"2-s.d. one {bm(2)} against {mw(2)}"),
            "reported_span": (f"{kept['reported_low']:.2f}-{kept['reported_high']:.2f}"
                              if kept["reported_low"] == kept["reported_low"] else
                              "not measured"),
            "every_rule": (f"{kept['met']} of the {kept['bounded']} bounded rows are met "
                           "within Monte-Carlo error" + (
                               f"; not met: {bad.height}, all of the rules "
                               + ", ".join(sorted(set(bad["rule"])))
                               + " (below)" if bad.height else ""))}


def values(recordings: Path | None = None) -> dict[str, str]:
    """The values of docs/results/templates/calibration.md, from the committed table
    (``committed``): ``table`` (``markdown``), the prose's numbers of the directional rule
    (``shift_coverage``, ``interval_short``), of the paired rules (``_paired_values``) and of
    the spreads (``band_power_10``, ``senses_power_4``: at 10 and 4 replications, within s.d.
    3 and 0.6), the powers the closing lines read, the rows under run-shaped nulls
    (``_shaped_values``), the pilot (``pilot_values``) and the sentences that read the table
    (``_prose``). ``recordings`` is
    unused (the table has its own path): the signature of ``reports.results.DOCS``."""
    table = committed()
    band = cells(table, "band", "mean 0.5", "reproduced", 10)
    senses = cells(table, "senses differ", "conditions 1 s.d. apart", "reproduced", 4)
    pct = lambda x: f"{100 * x:.0f} %"  # noqa: E731
    return {"table": markdown(table).rstrip("\n"),
            "shift_coverage": span(cells(table, "directional", "shift 1 s.d.",
                                         "coverage of the 95 % interval", 10), 3),
            "interval_short": _interval_short(table),
            "band_power_10": f"{pct(band[1])} of the time at 10 replications against "
                            f"{pct(band[0])} at 0.6",
            "senses_power_4": f"{pct(senses[1])} against {pct(senses[0])}",
            "ungated_split": _ungated_split(table),
            "power_4": span(cells(table, "directional", "shift 2 s.d.", "reproduced", 4)
                            + cells(table, "no difference", "no difference", "reproduced", 4)
                            + cells(table, "not better", "no difference", "reproduced", 4), 3),
            "power_1sd_10": span(cells(table, "directional", "shift 1 s.d.", "reproduced", 10)),
            "power_2sd_10": span(cells(table, "directional", "shift 2 s.d.", "reproduced", 10)),
            "equivalence_power": span(cells(table, "no difference", "no difference",
                                            "reproduced"), 3),
            "not_better_power_10": span(cells(table, "not better", "no difference",
                                              "reproduced", 10)),
            "robot_level": robot_level_markdown(pl.read_parquet(ROBOT_LEVEL)),
            **_paired_values(table), **_paired_coverage(table), **_shaped_values(table),
            **_prose(table), **pilot_values(pl.read_parquet(PILOT))}


def merged(table: pl.DataFrame, blocks: dict[str, pl.DataFrame]) -> pl.DataFrame:
    """``table`` with each block of ``blocks`` (a block of ``calibration.RULES`` by name ->
    ``calibrate(rules=(block,))``: each block has its own seed, so a block computed alone is
    the block of the whole table) in place of the rows of the same rules, nesting by nesting,
    where the block's first row was (its new rules beside its old ones)."""
    out = []
    for nest in NESTINGS:
        at = (pl.col("replications") == nest.replications) & (pl.col("within_sd") == nest.within_sd)
        new = {b: rows.filter(at) for b, rows in blocks.items()}
        names = {b: set(rows["rule"]) for b, rows in new.items() if rows.height}
        done = set()
        for row in table.filter(at).iter_rows(named=True):
            block = next((b for b, rules in names.items() if row["rule"] in rules), None)
            if block is None:
                out.append(pl.DataFrame([row], schema=table.schema))
            elif block not in done:
                done.add(block)
                out.append(new[block])
        out += [new[b] for b in names if b not in done]
    return pl.concat(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m reports.calibration",
                                     description="write the calibration table")
    parser.add_argument("--blocks", nargs="+", metavar="RULE",
                        help="recompute only these blocks of calibration.RULES (e.g. paired "
                             "senses paired_rates) and merge them into the committed table")
    parser.add_argument("--robot-level", action="store_true",
                        help="recompute only the robot-level table (ROBOT_LEVEL)")
    parser.add_argument("--pilot", action="store_true",
                        help="recompute only the pilot that chose the gates and levels of the "
                             "rules on rates (PILOT; about 7 min on one core)")
    args = parser.parse_args(argv)
    if args.pilot:
        run_shaped.pilot().write_parquet(PILOT)
        print(pilot_values(pl.read_parquet(PILOT))["pilot_table"])
        return 0
    if args.robot_level or not args.blocks:
        ROBOT_LEVEL.parent.mkdir(parents=True, exist_ok=True)
        robot_level().write_parquet(ROBOT_LEVEL)
        print(robot_level_markdown(pl.read_parquet(ROBOT_LEVEL)))
        if args.robot_level:
            return 0
    if args.blocks:
        rules = [r for r in cal.RULES if r.__name__.lstrip("_") in args.blocks]
        if len(rules) != len(args.blocks):
            parser.error(f"known blocks: {', '.join(r.__name__.lstrip('_') for r in cal.RULES)}")
        table = merged(committed(), {r.__name__: calibrate(rules=(r,)) for r in rules})
    else:
        table = calibrate()
    TABLE.parent.mkdir(parents=True, exist_ok=True)
    table.write_parquet(TABLE)
    print(markdown(table))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
