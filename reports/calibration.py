"""The calibration table of docs/results/calibration.md, a compact result committed beside the
runs' (``recordings/calibration/calibration.parquet``): every verdict rule calibrated by
simulation (``dart_reach.analysis.calibration.calibrate``).

    python -m reports.calibration     # writes the table and prints it as the page shows it

About 11 minutes on 2 cores; tests/analysis/test_calibration.py checks the committed table and
recomputes parts of it.
"""

from __future__ import annotations

from pathlib import Path

import polars as pl

from dart_reach.analysis.calibration import NESTINGS, calibrate, markdown, robot_level_null

TABLE = Path(__file__).resolve().parents[1] / "recordings" / "calibration" / "calibration.parquet"


def committed() -> pl.DataFrame:
    """The committed calibration table (``TABLE``), as ``main`` wrote it: what the pages'
    labels of coverage read (``analysis.coverage``)."""
    return pl.read_parquet(TABLE)


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
