"""The cost of a run measured on its own generations (cost.py): a replication-generation costs
wall_s x the session's workers / replications core-seconds, every generation counted to the
session that trained it, checked on the committed replication-50."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import polars as pl
import pytest

from dart_reach.evolution import cost
from dart_reach.evolution.rundir import RunDirectory

RUN = Path(__file__).resolve().parents[2] / "recordings" / "replication-50"


def test_workers_as_recorded_else_the_default_else_unknown():
    manifest = {"machine": {"cores": 6}}
    assert cost.session_workers({"workers": 3, "command": "x --workers 3"}, manifest) == 3
    assert cost.session_workers({"command": "dart-reach train standard"}, manifest) == 6
    assert cost.session_workers({"command": "dart-reach train standard --workers 1"},
                                manifest) is None
    assert cost.session_workers({"command": "dart-reach train s --ray auto"}, manifest) is None


def test_a_runs_cost_is_its_generations_wall_time_on_its_workers():
    run = RunDirectory.open(RUN)
    per = cost.core_seconds(run)
    stats = pl.read_parquet(RUN / "generations.parquet")
    assert per.height == stats.select("phase_key", "generation").unique().height == 250
    # replication-50: 4 replications on the machine's 2 cores (its sessions predate "workers")
    assert np.array_equal(per["core_s"].to_numpy(), per["wall_s"].to_numpy() * 2 / 4)
    sessions = json.loads((RUN / "manifest.json").read_text())["sessions"]
    gross = per.filter(pl.col("phase") == "gross")
    resumed_at = sessions[1]["generations_done"]["standard/gross"]
    assert resumed_at == 40
    assert gross.filter(pl.col("generation") <= 40)["session"].unique().to_list() == [0]
    assert gross.filter(pl.col("generation") > 40)["session"].unique().to_list() == [1]

    table = cost.measured_cost(run)
    assert table["phase"].to_list() == ["pre", "gross", "fine", "gross-hat"]
    assert table["generations"].to_list() == [50, 50, 50, 100]
    assert table["sessions"].to_list() == [1, 2, 1, 2]
    row = table.row(1, named=True)
    assert row["core_s_median"] == np.median(gross["core_s"].to_numpy())
    assert row["wall_h"] == gross["wall_s"].sum() / 3600


def test_the_estimate_takes_a_machines_own_figure_and_the_reference_is_the_docs(tmp_path):
    """``cost_estimate`` scales the core-seconds it is given (default the reference machine's,
    which docs/results/benchmarks.md gives with the runs that measured it); a ``dart-reach
    bench --json`` file gives a machine's own."""
    import re

    from dart_reach.evolution.conditions import load_condition
    from dart_reach.evolution.settings import Settings

    conditions, settings = [load_condition("standard")], Settings()
    reference = cost.cost_estimate(conditions, settings)
    assert reference == cost.cost_estimate(conditions, settings, cost.GENERATION_CORE_S)
    bench = tmp_path / "bench.json"
    bench.write_text(json.dumps({"generation_core_s": 2 * cost.GENERATION_CORE_S[1]}))
    own = cost.cost_estimate(conditions, settings, cost.bench_core_s(bench))
    assert own.replication_generations == reference.replication_generations
    assert own.core_hours == (2 * reference.core_hours[1],) * 2
    bench.write_text(json.dumps({"limit_rtf": 300.0}))
    with pytest.raises(ValueError, match="generation_core_s"):
        cost.bench_core_s(bench)
    page = (Path(__file__).resolve().parents[2] / "docs" / "results" / "benchmarks.md").read_text()
    low, high = cost.GENERATION_CORE_S
    assert re.search(rf"\| `generation_core_s` \(.*\) \| {low:.1f}–{high:.1f} core-s \|", page)
