"""The committed results (recordings/<run>/*.parquet) are what the model gives today: a slice
of every committed table runs again in the real DART world, to the last bit, and every table
is complete. A change to the model, the measures or the settings fails here instead of
silently invalidating the docs generated from these tables."""

from __future__ import annotations

from pathlib import Path

import pytest

from dart_reach.postevaluation import checks, results

ROOT = Path(__file__).resolve().parents[2]
RUNS = sorted(p.parent for p in (ROOT / "recordings").rglob(results.EVALUATION))


def test_the_runs_the_docs_cite_have_their_results_committed():
    names = {str(r.relative_to(ROOT / "recordings")) for r in RUNS}
    assert {"scene-study/near", "scene-study/near-shoulder",
            "scene-study/arm-length-shoulder"} <= names


@pytest.mark.parametrize("run", RUNS, ids=lambda p: str(p.relative_to(ROOT / "recordings")))
def test_a_slice_of_every_committed_table_reproduces(run):
    status = checks.table_status(run)
    assert status and all(s.complete for s in status), [s.missing for s in status]
    assert all(s.sessions and s.sessions[0].get("revision") for s in status)
    found = checks.reproduce(run, points=5)
    assert set(found["table"]) == {s.name for s in status}
    bad = found.filter(~found["equal"])
    assert bad.height == 0, bad.to_dicts()


def test_a_stored_value_that_the_model_does_not_give_is_found(tmp_path):
    import shutil

    import polars as pl

    run = tmp_path / "near"
    shutil.copytree(ROOT / "recordings/scene-study/near", run)
    path = run / results.EVALUATION
    table = results.read_table(path)
    table = table.with_columns(pl.when(pl.col("trial") < 45).then(pl.col("hand_path") * 1.01)
                               .otherwise(pl.col("hand_path")).alias("hand_path"))
    results.write_table(path, table, results.sessions(path))
    found = checks.reproduce(run, points=5).filter(pl.col("table") == results.EVALUATION)
    assert not found["equal"].any() and found["differ"].to_list() == [["hand_path"]]
    assert found["max_abs_diff"][0] > 0


def test_status_says_what_the_results_hold_and_reproduces_them():
    import subprocess
    import sys

    run = ROOT / "recordings/scene-study/near"
    out = subprocess.run([sys.executable, "-m", "dart_reach.cli", "status", str(run),
                          "--reproduce"], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    (entry,) = results.sessions(run / results.EVALUATION)
    assert ("results: evaluation.parquet: 900 trials, 1 phase(s) x 2 replications x 5 robots x "
            f"2 senses (no-ball, normal): complete; written at {entry['revision'][:7]} in 1 "
            "session(s)") in lines
    assert any(line.startswith("results: baseline.parquet: 900 trials, 1 phase(s) x 10 random "
                               "genomes") for line in lines)
    assert sum("the same to the last bit" in line for line in lines) == 2
