"""The physics-step study: its comparisons, and a tiny real run of it in DART."""

from __future__ import annotations

import math
import subprocess
import sys
from dataclasses import replace

import pytest

from dart_reach.model.world import WorldConfig

from dart_reach.studies.physics_step import (Tolerances, agreement, panel, panel_statistics,
                                      run_member, study, tracking_error)


def _stats(**kw):
    base = {"fitness": 0.02, "reach_rate": 0.5, "grasp_rate": 0.2, "speed": 0.3,
            "straightness": 0.8}
    return {**base, **kw}


def test_agreement_rates_absolute_others_relative():
    fine = _stats()
    ok = agreement(_stats(reach_rate=0.54, fitness=0.0219, speed=0.27), fine)
    assert all(v["ok"] for v in ok.values())
    assert ok["reach_rate"]["diff"] == pytest.approx(0.04)
    assert ok["fitness"]["diff"] == pytest.approx(0.095)
    bad = agreement(_stats(grasp_rate=0.26, straightness=0.95), fine)
    assert not bad["grasp_rate"]["ok"] and not bad["straightness"]["ok"]
    assert bad["reach_rate"]["ok"]
    strict = agreement(_stats(reach_rate=0.54), fine, Tolerances(rate_abs=0.01))
    assert not strict["reach_rate"]["ok"]


def test_agreement_without_reaching_trials():
    nan = _stats(speed=math.nan, straightness=math.nan)
    assert agreement(nan, nan)["speed"]["ok"]
    assert not agreement(nan, _stats())["speed"]["ok"]
    zero = _stats(fitness=0.0)
    assert agreement(zero, zero)["fitness"]["ok"]
    assert not agreement(_stats(fitness=0.001), zero)["fitness"]["ok"]


def test_panel_statistics_speed_over_reaching_trials_only():
    rows = [(0.1, True, False, 0.4, 0.9), (0.0, False, False, math.nan, math.nan),
            (0.2, True, True, 0.2, 0.7), (0.1, False, False, math.nan, math.nan)]
    s = panel_statistics(rows)
    assert s == pytest.approx({"fitness": 0.1, "reach_rate": 0.5, "grasp_rate": 0.25,
                               "speed": 0.3, "straightness": 0.8, "trials": 4})
    assert math.isnan(panel_statistics(rows[1:2])["speed"])


def test_tracking_error_shrinks_with_the_step():
    coarse = tracking_error(0.02, 0.0025, seeds=2, seconds=5.0)
    fine = tracking_error(0.005, 0.0025, seeds=2, seconds=5.0)
    assert 0 < fine["tracking_max_m"] < coarse["tracking_max_m"]
    assert 0 < fine["tracking_mean_m"] < coarse["tracking_mean_m"]


def test_evolved_robots_are_judged_at_the_step_they_evolved_at():
    from dart_reach.studies.physics_step import Member
    from dart_reach.model.task import TrialConfig

    member = Member("evolved", "x", None, frozenset(), TrialConfig(), WorldConfig(),
                    evolved_dt=0.01)
    assert member.judges(0.01) and not member.judges(0.02)
    assert Member("random", "y", None, frozenset(), TrialConfig(), WorldConfig()).judges(0.02)


@pytest.mark.parametrize("version", [1, 3])
def test_the_panel_runs_in_its_model_versions_world(version):
    """Random networks and the scripted reach run under the version's whole model: its
    scene and numerics, in a world of that scene at the step judged."""
    from dart_reach.model.versions import model_version
    from dart_reach.studies import physics_step

    record = model_version(version)
    members = panel(random=1, steps=2, model_version=version)
    assert [m.kind for m in members] == ["random", "scripted"]
    for m in members:
        assert m.world == record.world() and m.trial.numerics is record.numerics
    assert len(run_member((members[0], 0.01))["rows"]) == 45  # a random network: no planning
    world = physics_step._WORLDS[replace(record.world(), physics_dt=0.01)]
    assert world.config.sectors == record.sectors() and world.config.physics_dt == 0.01


def test_tiny_study_is_deterministic_and_complete():
    members = panel(random=2, steps=10, scripted=False)
    assert [m.kind for m in members] == ["random", "random"]
    assert members[0].trial.hidden_frozen and not members[1].trial.hidden_frozen
    a, b = run_member((members[1], 0.02)), run_member((members[1], 0.02))
    assert a["rows"] == b["rows"] and len(a["rows"]) == 45
    r = study(candidates=(0.02,), random=2, steps=10, workers=1, scripted=False,
              reference_dt=0.005)
    comparison = r["comparisons"][0.02]
    assert set(comparison["steps"]) == {0.02, 0.005}
    assert comparison["steps"][0.02]["statistics"]["panel"]["trials"] == 90
    assert comparison["agrees"] == all(v["ok"] for group in comparison["checks"].values()
                                       for v in group.values())
    assert set(comparison["checks"]) == {"random", "panel"}
    assert r["chosen"] == (0.02 if comparison["agrees"] else None)
    # a ratio of measured core-seconds: its value is the study's figure, not a test's
    assert math.isfinite(comparison["cost_ratio"]) and comparison["cost_ratio"] > 0
    with pytest.raises(ValueError, match="whole multiple"):
        study(candidates=(0.03,), random=1, steps=2, workers=1)


def test_cli_bad_input(tmp_path, in_process):
    existing = tmp_path / "out.json"
    existing.write_text("{}")
    for i, (args, fragment) in enumerate(((["--physics", "--json", existing], "exists"),
                                          (["--physics", "--physics-steps", "0.03"],
                                           "--physics-steps: 0.03 s does not divide"),
                                          (["--physics", "--physics-steps", "-0.02"],
                                           "--physics-steps: expected a positive number"),
                                          (["--physics", "--json", tmp_path / "no" / "x.json"],
                                           "no such directory"),
                                          (["--physics", "--networks", "0"], "--networks"))):
        if i:  # the others in this process: the same code, without a process's imports
            result = in_process("bench", *args)
        else:
            result = subprocess.run([sys.executable, "-m", "dart_reach.cli", "bench",
                                     *map(str, args)], capture_output=True, text=True,
                                    timeout=120)
        assert result.returncode == 2, result.stderr
        assert result.stderr.count("\n") == 1 and fragment in result.stderr, result.stderr
    assert existing.read_text() == "{}"


def test_panel_takes_the_best_robots_of_a_run_with_their_step(tmp_path):
    from dart_reach.evolution.conditions import load_condition, scaled
    from dart_reach.evolution.settings import Settings
    from dart_reach.evolution.trainer import train
    from dart_reach.model.world import WorldConfig

    settings = Settings(replications=2, trials=1, steps=3, world=WorldConfig(physics_dt=0.01))
    run = train([scaled(load_condition("standard"), 1)], settings, tmp_path / "r", workers=1)
    members = panel(random=1, runs=[run.out], steps=5, scripted=False, evolved=2)
    evolved = [m for m in members if m.kind == "evolved"]
    assert len(evolved) == 3 * 2 * 2  # phases x replications x best 2
    assert all(m.evolved_dt == 0.01 and m.trial.steps == 5 for m in evolved)
    assert all(m.world == run.settings.world for m in evolved)
    population, _ = run.load_final(run.conditions[0].phases[2])
    assert (evolved[-1].genome == population[1, 1]).all()
