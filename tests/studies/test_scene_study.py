"""A scene study's levers table (``dart_reach.studies.scene_study``) against its definition on
hand-made robots; the project's study and its page: tests/reports/test_scene_study.py."""

from __future__ import annotations

import polars as pl
import pytest
from scipy import stats as sps

from dart_reach.analysis.verdicts import hodges_lehmann
from dart_reach.studies import scene_study

MEASURES = [m for m, _ in scene_study.MEASURES]
#: Contrasts of a study (lever, scene before, scene after): the first has both its scenes below
PAIRS = (("height", "near", "near-shoulder"), ("distance", "near-shoulder", "far"))


def _robots(scene: str, reach_by_replication: dict[int, list[float]]) -> pl.DataFrame:
    rows = [{"scene": scene, "replication": r, "rank": k,
             **{m: float(v) for m in MEASURES}}
            for r, values in reach_by_replication.items() for k, v in enumerate(values)]
    return pl.DataFrame(rows)


def test_levers_follow_their_definition():
    before = _robots("near", {0: [0.1, 0.2, 0.3], 1: [0.2, 0.25, 0.3]})
    after = _robots("near-shoulder", {0: [0.5, 0.6, 0.4], 1: [0.7, 0.45, 0.5]})
    table = scene_study.levers(pl.concat([before, after]), PAIRS)
    # only the lever whose two scenes are present, one row per measure
    assert table["lever"].unique().to_list() == ["height"]
    assert table.height == len(MEASURES)
    row = table.row(0, named=True)
    a, b = before["reached"].to_numpy(), after["reached"].to_numpy()
    assert (row["mean_before"], row["mean_after"]) == pytest.approx((a.mean(), b.mean()))
    assert (row["shift"], row["shift_low"], row["shift_high"]) == pytest.approx(
        hodges_lehmann(a, b))
    assert row["p"] == pytest.approx(sps.mannwhitneyu(b, a, alternative="two-sided").pvalue)
    assert row["shift"] > 0 and row["replications_agree"]


def test_replications_that_disagree_are_reported():
    """A shift carried by one replication: the other replication's mean after lies below a
    mean before."""
    before = _robots("near", {0: [0.1, 0.1, 0.1], 1: [0.5, 0.5, 0.5]})
    after = _robots("near-shoulder", {0: [0.9, 0.9, 0.9], 1: [0.3, 0.3, 0.3]})
    row = scene_study.levers(pl.concat([before, after]), PAIRS).row(0, named=True)
    assert row["shift"] > 0 and not row["replications_agree"]
