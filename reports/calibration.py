"""The calibration table of docs/results/calibration.md, a compact result committed beside the
runs' (``recordings/calibration/calibration.parquet``): every verdict rule calibrated by
simulation (``dart_reach.analysis.calibration.calibrate``).

    python -m reports.calibration     # writes the table and prints it as the page shows it

About 11 minutes on 2 cores; tests/analysis/test_calibration.py checks the committed table and
recomputes parts of it.
"""

from __future__ import annotations

import math
from pathlib import Path

import polars as pl

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
    lowest coverage over the "at least" rows) and ``reported_low``, ``reported_high`` (the
    range of the coverages only reported: NaN without one). Rates in [0, 1]."""
    bounded = table.filter(pl.col("kind").is_in(["at most", "at least"]))
    errors = table.filter(pl.col("kind") == "at most").sort("value", descending=True)
    covers = table.filter(pl.col("kind") == "at least")
    reported = table.filter((pl.col("kind") == "reported")
                            & pl.col("measure").str.starts_with("coverage"))
    return {"bounded": bounded.height, "met": int(bounded["ok"].sum()),
            "highest_error": float(errors["value"][0]), "error_bound": float(errors["bound"][0]),
            "lowest_coverage": float(covers["value"].min()),
            "reported_low": float(reported["value"].min()) if reported.height else math.nan,
            "reported_high": float(reported["value"].max()) if reported.height else math.nan}


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


def main() -> int:
    table = calibrate()
    TABLE.parent.mkdir(parents=True, exist_ok=True)
    table.write_parquet(TABLE)
    print(markdown(table))
    for nest in NESTINGS:
        print(nest.label, robot_level_null(nest))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
