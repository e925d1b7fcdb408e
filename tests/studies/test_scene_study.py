"""The scene study's tables (``dart_reach.studies.scene_study``, docs/results/scene-study.md): the levers
table against its definition on hand-made robots, and the whole study's command on real tiny
runs trained and post-evaluated on two scenes."""

from __future__ import annotations

from pathlib import Path

import polars as pl
import pytest
from scipy import stats as sps

from dart_reach.studies import scene_study
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.postevaluation.systematic import evaluate_run
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train
from dart_reach.model.scenes import load_scene
from dart_reach.analysis.verdicts import hodges_lehmann

MEASURES = [m for m, _ in scene_study.MEASURES]


def _robots(scene: str, reach_by_replication: dict[int, list[float]]) -> pl.DataFrame:
    rows = [{"scene": scene, "replication": r, "rank": k,
             **{m: float(v) for m in MEASURES}}
            for r, values in reach_by_replication.items() for k, v in enumerate(values)]
    return pl.DataFrame(rows)


def test_levers_follow_their_definition():
    before = _robots("near", {0: [0.1, 0.2, 0.3], 1: [0.2, 0.25, 0.3]})
    after = _robots("near-shoulder", {0: [0.5, 0.6, 0.4], 1: [0.7, 0.45, 0.5]})
    table = scene_study.levers(pl.concat([before, after]))
    # only the lever whose two scenes are present, one row per measure
    assert table["lever"].unique().to_list() == [scene_study.LEVERS[0][0]]
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
    row = scene_study.levers(pl.concat([before, after])).row(0, named=True)
    assert row["shift"] > 0 and not row["replications_agree"]


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """Two scenes, each: pre-reaching alone, 1 generation, 2 replications, trials of 6 steps,
    post-evaluated (2 robots per replication, 2 random genomes; normal senses, ball absent)."""
    root = tmp_path_factory.mktemp("scene-study")
    for name in ("near", "arm-length-shoulder"):
        settings = Settings(replications=2, trials=1, steps=6, seed=20,
                            world=load_scene(name).world())
        train([scaled(load_condition(Path(__file__).parents[2] / "docs" / "learning-check.toml"), 1)], settings, root / name,
              workers=1, progress=False)
        evaluate_run(root / name, senses=("normal", "no-ball"), robots=2, workers=1,
                     progress=False, baseline=2, record="none")
    return root


def test_the_study_command_writes_its_tables_and_figure(study, tmp_path):
    assert scene_study.main([str(study), str(tmp_path)]) == 0
    text = (tmp_path / "scene-study.md").read_text()
    table = scene_study.summary(sorted(study.iterdir()))
    assert sorted(table["scene"].unique()) == ["arm-length-shoulder", "near"]
    robots = {(r["scene"], r["group"]): r["robots"] for r in table.iter_rows(named=True)}
    assert robots == {(s, g): n for s in ("near", "arm-length-shoulder")
                      for g, n in (("evolved", 4), ("random", 2))}
    for scene in ("near", "arm-length-shoulder"):
        assert f"| {scene} | evolved | 4 |" in text
    assert "| both | reach |" in text  # the one lever of these two scenes
    assert (tmp_path / "scene-study.png").stat().st_size > 10_000


def test_the_study_command_refuses_a_folder_without_evaluated_runs(tmp_path, capsys):
    assert scene_study.main([str(tmp_path), str(tmp_path)]) == 2
    assert "no post-evaluated scene run" in capsys.readouterr().err
