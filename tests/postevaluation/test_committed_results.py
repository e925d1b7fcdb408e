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
    ok, why = checks.reproduced(found, status)
    assert ok, (why, found.filter(~found["equal"]).to_dicts())


def test_an_incomplete_table_names_what_is_missing(tmp_path):
    """A robot's trials removed from a copy of a complete table: its status is incomplete and
    counts that one robot as missing of those its phase and senses should hold."""
    import shutil

    import polars as pl

    run = tmp_path / "near"
    shutil.copytree(ROOT / "recordings/scene-study/near", run)
    path = run / results.EVALUATION
    table = results.read_table(path)
    robot = table.row(0, named=True)
    keys = ["phase_key", "senses", "replication", "rank"]
    gone = pl.all_horizontal([pl.col(k) == robot[k] for k in keys])
    expected = table.filter((pl.col("phase_key") == robot["phase_key"])
                            & (pl.col("senses") == robot["senses"])).select(keys[2:]).unique()
    results.write_table(path, table.filter(~gone), results.sessions(path))
    status = {s.name: s for s in checks.table_status(run)}[results.EVALUATION]
    assert not status.complete
    assert status.missing == (f"{robot['phase']}/{robot['senses']}: 1 of {expected.height} "
                              f"robots missing",)


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


def test_a_slice_reproduces_bit_for_bit_at_the_same_dispatch_level_else_nearly():
    """checks.reproduced: a table written at this process's numpy dispatch level must give
    every robot to the last bit; one written at another level (or not recorded) may differ in
    at most OTHER_SIMD_SHARE of the robots checked, never in most of them."""
    import polars as pl

    from dart_reach.evolution.provenance import simd

    def status(name, level):
        return checks.TableStatus(name, 45, "", True, (), ({"simd": level},) if level else ())

    def found(differ):
        return pl.DataFrame({"table": ["evaluation.parquet"] * 10 + ["baseline.parquet"] * 10,
                             "equal": [i not in differ for i in range(20)]})

    here, other = [status("evaluation.parquet", simd()), status("baseline.parquet", simd())], [
        status("evaluation.parquet", "X86_V4"), status("baseline.parquet", None)]
    assert checks.reproduced(found(set()), here)[0]
    assert not checks.reproduced(found({3}), here)[0]
    assert not checks.reproduced(found({15}), here)[0]
    assert checks.reproduced(found({3}), other)[0]
    assert checks.reproduced(found({3, 15}), other)[0]  # 2 of 20: the 10 % allowed
    assert not checks.reproduced(found({3, 4, 15}), other)[0]
    mixed = [here[0], other[1]]  # only the baseline was written elsewhere
    assert checks.reproduced(found({15}), mixed)[0] and not checks.reproduced(found({3}), mixed)[0]


def test_status_says_what_the_results_hold_and_reproduces_them(in_process):
    run = ROOT / "recordings/scene-study/near"
    out = in_process("status", run, "--reproduce")  # its own process: tests/test_cli.py
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    (entry,) = results.sessions(run / results.EVALUATION)
    assert ("results: evaluation.parquet: 900 trials, 1 phase(s) x 2 replications x 5 robots x "
            f"2 senses (no-ball, normal): complete; written at {entry['revision'][:7]} in 1 "
            "session(s)") in lines
    assert any(line.startswith("results: baseline.parquet: 900 trials, 1 phase(s) x 10 random "
                               "genomes") for line in lines)
    assert sum(" rank " in line and "the same to the last bit" in line for line in lines) == 2
    assert lines[-1] == "reproduce: reproduces: all 2 robots the same to the last bit"
