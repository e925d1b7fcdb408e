"""The calibration table of docs/results/calibration.md, a compact result committed beside the
runs' (``recordings/calibration/calibration.parquet``): every verdict rule calibrated by
simulation (``dart_reach.analysis.calibration.calibrate``), and the page's values (``values``:
the table and every number its prose states, read from the table; ``make results`` renders
docs/results/templates/calibration.md with them).

    python -m reports.calibration     # writes the table and prints it as the page shows it

About an hour on 2 cores beside a training run; tests/analysis/test_calibration.py checks the
committed table and recomputes parts of it.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import polars as pl

from dart_reach.analysis import calibration as cal
from dart_reach.analysis import paired_calibration as paired_cal
from dart_reach.analysis import verdicts
from dart_reach.analysis.calibration import NESTINGS, calibrate, robot_level_null

TABLE = Path(__file__).resolve().parents[1] / "recordings" / "calibration" / "calibration.parquet"


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
    range of the coverages only reported: NaN without one), ``unbounded`` (the rules in use
    whose error rate under some null is only reported, with that null) and
    ``unbounded_high`` (the highest of those rates: NaN without one). Rates in [0, 1]."""
    bounded = table.filter(pl.col("kind").is_in(["at most", "at least"]))
    errors = table.filter(pl.col("kind") == "at most").sort("value", descending=True)
    covers = table.filter(pl.col("kind") == "at least")
    reported = table.filter((pl.col("kind") == "reported")
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
    """The numbers of the page's paragraph on the paired claims of no change (the rate rule,
    the relative-change rule, senses differ's equivalence; ``paired_calibration``), at 3 and
    10 pairs, the rule, the rule without its gate for lopsided changes and the t TOST before
    it (rates in [0, 1])."""
    rate, rel = "paired rate no change", "paired no change"
    lopsided = [s for s, symmetric in cal.RATE_SHAPES.items() if not symmetric]
    symmetric = [s for s, sym in cal.RATE_SHAPES.items() if sym]
    at_margin = lambda shapes, rule, k=10: [  # noqa: E731
        x for s in shapes for x in cells(table, rule, f"{s}, change at the margin", "reproduced",
                                         k)]
    at_10 = table.filter((pl.col("replications") == 10) & (pl.col("kind") == "at most")
                         & pl.col("rule").is_in([rate, rel, "senses differ"]))
    power = {
        "fifths": ("rates in fifths, no change", rate, cal.RATE_UNGATED),
        "still": ("50 % of replications still, no change", rate, cal.RATE_UNGATED),
        "two_mode": ("two-mode changes, no change", rate, cal.RATE_UNGATED),
        "relative": ("no change", rel, cal.PAIRED_UNGATED)}
    out = {
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
        "ungated_lopsided_10": span(at_margin(lopsided, cal.RATE_UNGATED)),
        "gated_lopsided_10": span(at_margin(lopsided, rate), 3),
        "highest_10": f"{at_10['value'].max():.3f}",
        "minority": str(verdicts.LOPSIDED_MINORITY),
        "senses_power": span(cells(table, "senses differ", "no difference", "contradicted", 10)),
        "senses_power_ungated": span(cells(table, cal.SENSES_UNGATED, "no difference",
                                           "contradicted", 10))}
    for key, (scenario, rule, ungated) in power.items():
        out[f"power_{key}"] = span(cells(table, rule, scenario, "reproduced", 10), 3)
        out[f"power_{key}_ungated"] = span(cells(table, ungated, scenario, "reproduced", 10), 3)
    words = {"fifths": "a rate in fifths", "still": "with half the replications still",
             "two_mode": "two-mode changes", "relative": "a measure's relative change (s.d. one "
             "margin)"}
    both = lambda values: " / ".join(f"{x:.3f}" for x in values)  # noqa: E731
    consistent = (f"small consistent change ({paired_cal.CONSISTENT[0]:g} margin, "
                  f"s.d. {paired_cal.CONSISTENT[1]:g})")
    rows = {k: (cells(table, rule, scenario, "reproduced", 10),
                cells(table, ungated, scenario, "reproduced", 10))
            for k, (scenario, rule, ungated) in power.items()}
    rows["consistent"] = (cells(table, rel, consistent, "reproduced", 10),
                          cells(table, cal.PAIRED_UNGATED, consistent, "reproduced", 10))
    mean_sd = paired_cal.CONSISTENT
    words["consistent"] = (f"a small consistent relative change ({mean_sd[0]:g} margin, s.d. "
                           f"{mean_sd[1]:g}), most replications moving the same way")
    out["gate_cost"] = "; ".join(f"{words[k]} {both(g)} against {both(u)}"
                                 for k, (g, u) in rows.items()) + (
        "; \"senses differ\" contradicted where the senses are alike "
        f"{both(cells(table, 'senses differ', 'no difference', 'contradicted', 10))} against "
        f"{both(cells(table, cal.SENSES_UNGATED, 'no difference', 'contradicted', 10))}")
    skewed_none = f"{lopsided[1]}, no change"
    out["skewed_contradicted"] = span(cells(table, rate, skewed_none, "contradicted", 10), 3)
    out["skewed_contradicted_ungated"] = span(cells(table, cal.RATE_UNGATED, skewed_none,
                                                    "contradicted", 10), 3)
    straddling = table.filter((pl.col("rule") == rate) & (pl.col("replications") == 10)
                              & pl.col("scenario").str.contains("straddling"))
    out["straddling"] = (f"the margin plus an exponential of {paired_cal.STRADDLING:g} margins "
                         "less its mean")
    out["straddling_rate"] = span(straddling["value"].to_list())
    out["straddling_ungated"] = span(cells(table, cal.RATE_UNGATED, straddling["scenario"][0],
                                           "reproduced", 10))
    out["gate_rule"] = (f"at most {verdicts.LOPSIDED_MINORITY} of the replications that "
                        "changed at all moved against the rest")
    return out


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


def values(recordings: Path | None = None) -> dict[str, str]:
    """The values of docs/results/templates/calibration.md, from the committed table
    (``committed``): ``table`` (``markdown``), the prose's numbers of the directional rule
    (``shift_coverage``, ``interval_short``), of the paired rules (``_paired_values``) and of
    the spreads (``band_power``, ``senses_power_4``: at 4 replications, within s.d. 3 and
    0.6). ``recordings`` is unused (the table has its own path): the signature of
    ``reports.results.DOCS``."""
    table = committed()
    band = cells(table, "band", "mean 0.5", "reproduced", 4)
    senses = cells(table, "senses differ", "conditions 1 s.d. apart", "reproduced", 4)
    pct = lambda x: f"{100 * x:.0f} %"  # noqa: E731
    return {"table": markdown(table).rstrip("\n"),
            "shift_coverage": span(cells(table, "directional", "shift 1 s.d.",
                                         "coverage of the 95 % interval", 10), 3),
            "interval_short": _interval_short(table),
            "band_power_4": f"{pct(band[1])} of the time at 4 replications against "
                            f"{pct(band[0])} at 0.6",
            "senses_power_4": f"{pct(senses[1])} against {pct(senses[0])}",
            **_paired_values(table)}


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
    args = parser.parse_args(argv)
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
    if not args.blocks:
        for nest in NESTINGS:
            print(nest.label, robot_level_null(nest))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
