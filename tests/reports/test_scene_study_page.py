"""The scene study's page (``reports.scene_study``, docs/results/scene-study.md): its command on
real tiny runs trained and post-evaluated on two scenes writes its tables and figure, and
refuses a folder without post-evaluated runs."""

from __future__ import annotations

from pathlib import Path

import polars as pl
import pytest

from dart_reach.analysis import said
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train
from dart_reach.model.scenes import load_scene
from dart_reach.postevaluation.systematic import evaluate_run
from dart_reach.studies.scene_study import robots, study_runs, summary
from reports import calibration, scene_study

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """Two scenes, each: pre-reaching alone, 1 generation, 2 replications, trials of 6 steps,
    post-evaluated (2 robots per replication, 2 random genomes; normal senses, ball absent)."""
    root = tmp_path_factory.mktemp("scene-study")
    check = scaled(load_condition(ROOT / "docs" / "learning-check.toml"), 1)
    for name in ("near", "arm-length-shoulder"):
        settings = Settings(replications=2, trials=1, steps=6, seed=20,
                            world=load_scene(name).world())
        train([check], settings, root / name, workers=1, progress=False)
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


def _robot_table(shift: float, replications: int) -> pl.DataFrame:
    """A ``robots`` table of the study's three scenes, 2 robots a replication, every
    ``WORDED`` measure the replication's index (its tenth), shifted by ``shift`` per scene."""
    rows = [{"scene": scene, "replication": r, "rank": k,
             **{m: 0.1 * r + shift * i for m in scene_study.WORDED}}
            for i, scene in enumerate(("near", "near-shoulder", "arm-length-shoulder"))
            for r in range(replications) for k in range(2)]
    return pl.DataFrame(rows)


def test_the_levers_words_come_from_the_gated_rule_at_the_replications():
    """6 replications a scene, each scene's wholly above the one before: "higher" with the
    rule's p; 2 a scene, as in the study: underpowered, whatever the shift, and "about half"
    needs 3 replications."""
    calibrated = calibration.committed()
    words = scene_study.lever_words(_robot_table(1.0, 6), calibrated)
    assert words["rule.near.near-shoulder.reached"].startswith("near-shoulder higher (")
    assert words["rule.near.arm-length-shoulder.grasped"].startswith(
        "arm-length-shoulder higher (")
    two = scene_study.lever_words(_robot_table(1.0, 2), calibrated)
    assert all(two[f"rule.{b}.{a}.{m}"].startswith("underpowered (n = 2")
               for _, b, a in scene_study.LEVERS for m in scene_study.WORDED)
    assert two["rule.about_half"].startswith("underpowered (band 33 %-67 %, n = 2 replications")


def test_the_committed_pages_lever_words_are_the_replications_means_through_the_rule():
    """The page's words recomputed from the committed study: each scene's replication means
    (plain polars over the post-evaluated robots) through ``said.two_groups``."""
    runs = study_runs(ROOT / "recordings" / "scene-study")
    table = robots(runs)
    page = (ROOT / "docs" / "results" / "scene-study.md").read_text()
    calibrated = calibration.committed()
    for _, before, after in scene_study.LEVERS:
        units = [table.filter(pl.col("scene") == s).group_by("replication")
                 .agg(pl.col("reached").mean()).sort("replication")["reached"].to_numpy()
                 for s in (before, after)]
        sentence = said.two_groups(*units, before, after, calibrated)
        assert sentence == scene_study.lever_words(table, calibrated)[
            f"rule.{before}.{after}.reached"]
        if (before, after) != ("near", "arm-length-shoulder"):  # the page words two levers
            assert sentence in page
