"""``dart-reach export RUN --csv DIR``: every results table of a run as CSV, columns named
with their units, values as stored; ``read TABLE.parquet --csv`` the same for one table."""

from __future__ import annotations

import hashlib
import subprocess
import sys
from pathlib import Path

import polars as pl
import pytest

from dart_reach.measures.units import unit, with_unit

ROOT = Path(__file__).resolve().parents[2]


def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=600, cwd=cwd)


def _one_line_exit_2(result, needle):
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert result.stderr.count("\n") == 1 and needle in result.stderr, result.stderr


def _hashes(out: Path) -> dict:
    return {p: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(out.rglob("*"))
            if p.is_file()}


@pytest.fixture(scope="module")
def run(tmp_path_factory, in_process) -> Path:
    """A tiny run, trained with snapshots and post-evaluated with its development (seconds)."""
    out = tmp_path_factory.mktemp("export") / "run"
    assert in_process("train", "standard", "--generations", "2", "--replications", "2",
                      "--trials", "1", "--steps", "6", "--workers", "1", "--snapshot-every", "1",
                      "--record-every", "0", "--out", out).returncode == 0
    result = in_process("evaluate", out, "--robots", "1", "--record", "none", "--workers", "1",
                        "--development", "1")
    assert result.returncode == 0, result.stderr
    return out


def test_export_writes_every_table_with_units_and_stored_values(run, tmp_path, in_process):
    before = _hashes(run)
    result = _cli("export", run, "--csv", tmp_path / "csv")
    assert result.returncode == 0, result.stderr
    assert sorted(p.name for p in (tmp_path / "csv").iterdir()) == [
        "development.csv", "evaluation.csv", "generations.csv"]
    assert _hashes(run) == before  # nothing written into the run
    for name in ("evaluation", "development", "generations"):
        stored = pl.read_parquet(run / f"{name}.parquet")
        csv = pl.read_csv(tmp_path / "csv" / f"{name}.csv", infer_schema_length=None)
        assert csv.columns == [with_unit(c) for c in stored.columns]
        assert csv.height == stored.height
        for column, dtype in stored.schema.items():
            if dtype == pl.Float32:  # written with a float32's digits, read back bit for bit
                back = csv[with_unit(column)].cast(pl.Float32)
                assert back.fill_nan(0).equals(stored[column].fill_nan(0), check_names=False)
    header = (tmp_path / "csv" / "evaluation.csv").read_text().splitlines()[0].split(",")
    for column in ("first_touch_s [s]", "hand_path [m]", "speed [m/s]", "var_elbow [rad]",
                   "ball_x [m]", "babbling_freq_hz [Hz]", "fitness", "reached"):
        assert column in header
    assert "wall_s [s]" in (tmp_path / "csv" / "generations.csv").read_text().splitlines()[0]
    # the first touch as stored (a float32: 0.6 is written 0.6, not 0.6000000238418579)
    texts = pl.read_csv(tmp_path / "csv" / "evaluation.csv", infer_schema_length=0)
    touches = [t for t in texts["first_touch_s [s]"].to_list() if t != "NaN"]
    assert all(len(t) <= 12 for t in texts["hand_path [m]"]) and all(
        "0000000" not in t for t in touches)
    # again: refused, nothing overwritten
    saved = _hashes(tmp_path / "csv")
    _one_line_exit_2(_cli("export", run, "--csv", tmp_path / "csv"), "the file exists")
    assert _hashes(tmp_path / "csv") == saved
    _one_line_exit_2(in_process("export", run, "--csv", run / "csv"), "inside the run")
    _one_line_exit_2(in_process("read", run / "evaluation.parquet", "--csv",
                                run / "evaluation.csv"), "inside the run")
    assert _hashes(run) == before
    _one_line_exit_2(in_process("export", tmp_path / "none", "--csv", tmp_path / "x"),
                     "no such run directory")
    _one_line_exit_2(in_process("export", run, "--csv", tmp_path / "no" / "where"),
                     "no such directory")
    assert not (run / "csv").exists() and not (tmp_path / "no").exists()


def test_read_on_a_table_exports_it_or_says_how(run, tmp_path, in_process):
    result = _cli("read", run / "evaluation.parquet", "--csv", tmp_path / "e.csv")
    assert result.returncode == 0, result.stderr
    assert in_process("export", run, "--csv", tmp_path / "all").returncode == 0
    assert (tmp_path / "e.csv").read_bytes() == (tmp_path / "all" / "evaluation.csv").read_bytes()
    result = in_process("read", run / "evaluation.parquet")
    _one_line_exit_2(result, "dart-reach export RUN --csv DIR")
    assert "damaged .rrd" not in result.stderr
    # a committed run's findings table
    findings = ROOT / "recordings" / "replication-10" / "findings.parquet"
    assert in_process("read", findings, "--csv", tmp_path / "f.csv").returncode == 0
    csv = pl.read_csv(tmp_path / "f.csv", infer_schema_length=None)
    assert csv.height == pl.read_parquet(findings).height and "verdict" in csv.columns


def test_units_and_the_guides_names():
    assert unit("first_touch_s") == "s" and unit("hand_path") == "m"
    assert unit("robot/joints/arm_hand/r_elbow") == "rad" and unit("sim_time") == "s"
    assert unit("fitness") == unit("reached") == unit("network/hidden/h0") == ""
    from dart_reach import export_run, read_properties  # where the analysis guide says
    from dart_reach.recording.rrd import read_properties as defined

    assert read_properties is defined and callable(export_run)
