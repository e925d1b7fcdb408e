"""The scene study's page (``reports.scene_study``, docs/results/scene-study.md): its command on
real tiny runs trained and post-evaluated on two scenes writes its tables and figure, and
refuses a folder without post-evaluated runs."""

from __future__ import annotations

from pathlib import Path

import pytest

from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train
from dart_reach.model.scenes import load_scene
from dart_reach.postevaluation.systematic import evaluate_run
from dart_reach.studies.scene_study import summary
from reports import scene_study


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
    table = summary(sorted(study.iterdir()))
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
