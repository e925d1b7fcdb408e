"""Scenes as data (``dart_reach/model/scenes``, docs/model/scene.md): the shipped files follow
the rule that defines them, bad files are refused naming the problem, and a run keeps its scene
(sections II-B, III, Fig. 2)."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from dart_reach.studies import validate
from dart_reach.postevaluation.systematic import evaluate_run
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.model.scenes import (DEFAULT_SCENE, SceneError, load_scene, scene_from_dict,
                               scene_names, scene_of)
from dart_reach.model.world import World, WorldConfig, sector_angles, sphere_point


def test_the_default_scene_is_world_configs_default():
    assert DEFAULT_SCENE in scene_names()
    assert load_scene(DEFAULT_SCENE).sectors == WorldConfig().sectors
    assert scene_of(WorldConfig().sectors) == DEFAULT_SCENE


def _corners(world: World) -> np.ndarray:
    s = world.config.sectors
    return np.array([sphere_point(world.neck_centre, s.radius, *sector_angles(s, k, u, v))
                     for k in range(9) for u in (0, 1) for v in (0, 1)])


@pytest.mark.parametrize("name", ["near-shoulder", "arm-length-shoulder"])
def test_shoulder_centred_scenes_centre_their_band_on_shoulder_height(name):
    """The elevation band's middle is the elevation, seen from the neck, of the shoulder's
    height on the sphere (to the file's 0.1 deg), and the band is 45 deg wide as before."""
    world = World(load_scene(name).world())
    s = world.config.sectors
    centre = math.degrees(math.asin((world.shoulder_position()[2] - world.neck_centre[2])
                                    / s.radius))
    assert (s.elevation_edges[0] + s.elevation_edges[3]) / 2 == pytest.approx(centre, abs=0.06)
    assert s.elevation_edges[3] - s.elevation_edges[0] == pytest.approx(45.0)


def test_arm_length_scene_puts_the_farthest_ball_at_arms_length():
    """Every start within reach of the straight arm without leaning, the farthest at arm's
    length: the largest ball-surface distance from the shoulder is the arm's length (within
    1 mm), while the nearer scenes stay well inside it."""
    for name, lo, hi in (("arm-length-shoulder", -0.001, 0.001), ("near", -0.06, -0.03),
                         ("near-shoulder", -0.06, -0.03)):
        world = World(load_scene(name).world())
        arm = validate.arm_length(world)
        farthest = np.linalg.norm(_corners(world) - world.shoulder_position(), axis=1).max()
        assert lo <= farthest - world.config.ball.radius - arm <= hi, name


def test_scene_geometry_reports_what_the_doc_says():
    g = validate.scene_geometry(World(load_scene("near").world()))
    assert g["arm_length_m"] == pytest.approx(0.343, abs=0.001)
    assert (g["arm_fraction_min"], g["arm_fraction_max"]) == pytest.approx((0.59, 0.95), abs=0.01)
    assert g["lateral_min_m"] > 0  # every start right of the midline


@pytest.mark.parametrize("change, message", [
    ({"colour": "red"}, "unknown key(s) 'colour'"),
    ({"sectors": {"radius": 0.3, "azimuth_edges": [0, 15, 30, 45]}},
     "missing key(s) 'elevation_edges'"),
    ({"sectors": {"radius": -0.3, "azimuth_edges": [0, 15, 30, 45],
                  "elevation_edges": [-45, -30, -15, 0]}}, "radius must be a positive"),
    ({"sectors": {"radius": 0.3, "azimuth_edges": [0, 30, 15, 45],
                  "elevation_edges": [-45, -30, -15, 0]}}, "azimuth_edges must be 4 increasing"),
    ({"sectors": {"radius": 0.3, "azimuth_edges": [0, 15, 30, 45],
                  "elevation_edges": [-95, -30, -15, 0]}}, "elevation_edges must be 4"),
    ({"name": "a b"}, "name must be"),
])
def test_bad_scene_files_are_refused_naming_the_problem(change, message):
    data = {"name": "mine", "description": "x",
            "sectors": {"radius": 0.3, "azimuth_edges": [0, 15, 30, 45],
                        "elevation_edges": [-45, -30, -15, 0]}}
    data.update(change)
    with pytest.raises(SceneError) as err:
        scene_from_dict(data, "mine.toml")
    assert str(err.value).startswith("mine.toml: ") and message in str(err.value)


def test_a_users_scene_file_loads_and_unknown_names_list_the_shipped(tmp_path):
    path = tmp_path / "far.toml"
    path.write_text('name = "far"\ndescription = "x"\n[sectors]\nradius = 0.4\n'
                    'azimuth_edges = [0, 15, 30, 45]\nelevation_edges = [-45, -30, -15, 0]\n')
    assert load_scene(path).sectors.radius == 0.4
    assert scene_of(load_scene(path).sectors) is None
    with pytest.raises(SceneError, match="shipped scenes: arm-length-shoulder"):
        load_scene("nowhere")


def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=600)


def test_a_run_keeps_its_scene_and_resume_refuses_another(tmp_path, in_process):
    out = tmp_path / "run"
    tiny = ["train", "docs/learning-check.toml", "--generations", "1", "--replications", "1",
            "--trials", "1", "--steps", "3", "--workers", "1", "--record-every", "0",
            "--out", str(out)]
    root = Path(__file__).parents[2]
    # a run on a scene that is not the default
    other = next(n for n in ("near", "arm-length-shoulder") if n != DEFAULT_SCENE)
    assert load_scene(other).sectors != WorldConfig().sectors
    done = _cli(*tiny, "--scene", other, cwd=root)
    assert done.returncode == 0, done.stderr
    assert RunDirectory.open(out).settings.world.sectors == load_scene(other).sectors
    assert json.loads((out / "manifest.json").read_text())["scene"] == other
    # the post-evaluation puts the ball where the run's own scene does, not the default
    table = evaluate_run(out, robots=1, record="none", workers=1, progress=False)
    world = World(load_scene(other).world())
    positions = table.sort("trial").select("ball_x", "ball_y", "ball_z").to_numpy()
    assert np.allclose(positions, world.systematic_points())
    refused = in_process(*tiny, "--scene", DEFAULT_SCENE, "--resume", cwd=root)
    assert refused.returncode == 2 and len(refused.stderr.strip().splitlines()) == 1
    assert "scene" in refused.stderr
    bad = in_process(*tiny[:-1], str(tmp_path / "other"), "--scene", "nowhere", cwd=root)
    assert bad.returncode == 2 and "unknown scene 'nowhere'" in bad.stderr
    assert not (tmp_path / "other").exists()
