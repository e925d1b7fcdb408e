"""The benchmark's machinery: paired timing in alternating order, ratios with quartiles, and
tiny real runs of its figures (their values are for `dart-reach bench`, not for tests)."""

from __future__ import annotations

import inspect
import math
import time

import pytest

from dart_reach.model.versions import model_version
from dart_reach.studies import bench, scaling


def test_pairs_alternate_their_order_and_time_each_side():
    # a clock that only the two sides move: each side's time is exactly what it spent
    now, calls = [0.0], []

    def side(name, cost):
        def run():
            calls.append(name)
            now[0] += cost
        return run

    a, b = bench.paired(side("a", 1.0), side("b", 3.0), 4, clock=lambda: now[0])
    assert calls == ["a", "b", "b", "a", "a", "b", "b", "a"]
    assert a.tolist() == [1.0] * 4 and b.tolist() == [3.0] * 4
    # by default this process's CPU time (a training beside the bench does not count)
    assert inspect.signature(bench.paired).parameters["clock"].default is time.process_time


def test_ratio_is_the_median_with_quartiles():
    r = bench.ratio("x", [1.0, 2.0, 3.0, 4.0, 100.0])
    assert r == {"x": 3.0, "x_iqr": [2.0, 4.0]}


def test_check_against_targets():
    met = bench.check({"controlled_over_limit": 0.95, "recording_overhead": 1.2})
    assert met == {"controlled_over_limit": True, "recording_overhead": False}


def test_tiny_real_figures():
    w = bench.world_rtf(seconds=0.2, pairs=2)
    assert w["ball_in_hand"] and w["limit_rtf"] > 0 and w["controlled_over_limit"] > 0
    p = bench.parallel(jobs=4, trials=1, pairs=1)
    assert p["parallel_efficiency"] > 0 and p["worker_peak_rss_mb"] > 50
    assert bench.panel_genomes("evolved", 3).shape == (3, bench.panel_genomes("random", 1).shape[1])


def test_the_model_versions_numerics_are_timed_on_the_same_trials():
    """The closed loop of versions 1 and 3 (version 2's numerics in its own scene) against
    its own replay, and a generation of version 1 against version 2's (two roundings of the
    same equations: lifetimes close, not equal); a version's generation runs in its world."""
    for version in (1, 3):
        c = bench.closed_loop("evolved", trials=1, records=False, model_version=version)
        assert math.isfinite(c["training_loop_over_limit_evolved"])
    for version in (1, 3):
        jobs = bench._generation("evolved", 2, 1, 0, version)
        assert all(job.world == model_version(version).world() for job in jobs)
    assert model_version(3).world() != model_version(1).world()
    n = bench.numerics_speedup(jobs=2, trials=1, pairs=1)
    assert n["numerics_speedup"] > 0 and n["generation_core_s_v2"] > 0
    assert n["numerics_fitness_rel_diff"] < 0.5


def test_the_tuned_physics_simulates_what_the_reference_does():
    """Every record of evolved robots' trials (they touch and grasp the ball) is the same to
    the last bit in the world as tuned for speed and in the reference configuration."""
    import numpy as np

    from dart_reach.evolution.settings import standard_trial
    from dart_reach.evolution.genome import ParamGroup, decode
    from dart_reach.model.task import Trial, network_for
    from dart_reach.model.world import World

    cfg = standard_trial("pre")
    tuned, reference = Trial(World(), cfg), Trial(bench.reference_world(), cfg)
    assert reference.world.world.getDeactivationOptions().mEnabled
    assert not tuned.world.world.getDeactivationOptions().mEnabled
    touched = 0
    for i, genome in enumerate(bench.panel_genomes("evolved", 3)):
        network = network_for(decode(genome, {ParamGroup.DIRECT}), cfg)
        for k in (1, 4, 7):
            ball = tuned.world.sector_point(k, 0.3, 0.6)
            a, b = tuned.run(network, k, ball), reference.run(network, k, ball)
            for name in ("dofs", "ball", "hand", "contacts", "sensors", "targets"):
                assert np.array_equal(getattr(a, name), getattr(b, name)), (i, k, name)
            touched += a.contacts.any()
    assert touched >= 3


def test_the_loops_parts_are_timed_on_the_living_model():
    parts = scaling.loop_parts(calls=20, repeats=1)
    assert set(parts) == {"control_step_us", "control_step_dispatched_us", "read_positions_us",
                          "read_ball_us", "read_collisions_us", "substep_us"}
    assert all(v > 0 for v in parts.values())


def test_physics_speedup_is_a_ratio_of_pairs():
    r = bench.physics_speedup(trials=2)
    assert r["physics_speedup"] > 0 and len(r["physics_speedup_iqr"]) == 2


def test_the_environment_figure_times_the_same_trials():
    import pytest

    pytest.importorskip("gymnasium")
    g = bench.gym_env(trials=1)
    assert g["env_steps_per_s"] > 0 and math.isfinite(g["env_over_trial"])


def test_the_render_figure_times_frames_of_the_environment():
    import pytest

    pytest.importorskip("gymnasium")
    r = bench.env_render(frames=5, width=64, height=48)
    assert r["env_render_fps"] > 0 and len(r["env_render_fps_iqr"]) == 2
    assert r["env_render_ms"] > 0


def test_a_run_s_trial_cost_times_its_snapshots_and_its_population(tmp_path):
    import pytest

    from dart_reach.evolution.conditions import load_condition, scaled
    from dart_reach.evolution.settings import Settings
    from dart_reach.evolution.trainer import train

    run = train([scaled(load_condition("standard"), 2)],
                Settings(replications=2, trials=1, steps=4, seed=5), tmp_path / "run",
                workers=1, progress=False, snapshot_every=1)
    table = bench.trial_cost(run.out, [1, 2])
    assert table["robots"].to_list() == ["gen 1", "gen 2", "population",
                                         "gen 2", "gen 1", "population"]
    assert table["replication"].to_list() == [0, 0, 0, 1, 1, 1]
    assert table["trials"].to_list() == [9, 9, 20] * 2 and (table["cpu_s"] > 0).all()
    with pytest.raises(ValueError, match=r"no snapshot of generation\(s\) \[7\]"):
        bench.trial_cost(run.out, [1, 7])


def test_a_recordings_parts_add_up_to_it():
    """``recording_parts`` times the parts of a real recording (CPU times, so no comparison
    between them is asserted: a loaded machine may reorder them): every part, and the rest
    is what the parts leave of the whole."""
    r = bench.recording_parts(trials=1, rounds=1, model_version=1)
    assert all(r[name] > 0 for name in ("rrd_ms", "rrd_chunks_ms", "rrd_rows_ms", "rrd_poses_ms",
                                        "rrd_write_ms", "rrd_streamed_ms"))
    assert r["rrd_rest_ms"] == pytest.approx(r["rrd_ms"] - r["rrd_chunks_ms"] - r["rrd_write_ms"])


def test_the_late_population_is_timed_as_the_campaign_runs_it():
    from dart_reach.model.versions import model_version

    jobs = scaling.late_generation(3, trials=2, steps=5)
    assert len(jobs) == 40 and len({j.genome.tobytes() for j in jobs}) == 20  # 20, twice
    assert jobs[0].world == model_version(3).world() and jobs[0].trial.numerics.value == \
        "compiled" and jobs[0].trial.trials == 2
    found = scaling.late_population(versions=(1, 2), rounds=2, workers=2, trials=1, steps=5)
    assert set(found) == {"late_generation_core_s_v1", "late_generation_core_s_v2",
                          "numerics_speedup_late", "numerics_speedup_late_iqr"}
    assert found["late_generation_core_s_v1"] > 0 and found["numerics_speedup_late"] > 0


def test_a_generation_projected_from_measured_costs_follows_its_model():
    import polars as pl

    # driver 1 ms a task, a trial 50 ms: 7,200 trials
    one = scaling.project_generation(0.001, 0.05, 16, 1)
    assert one["wall_s"] == pytest.approx(7200 * 0.05 / 16 + 0.05)  # the workers set the pace
    one = scaling.project_generation(0.001, 0.05, 64, 1)
    assert one["wall_s"] == pytest.approx(7200 * 0.001 + 0.05)  # the driver does
    assert scaling.project_generation(0.001, 0.05, 256, 1)["driver_share"] > 0.5  # the driver's
    lifetime = scaling.project_generation(0.001, 0.05, 256, 18)
    assert lifetime["wall_s"] == pytest.approx(7200 * 0.05 / 256 + 18 * 0.05)
    measured = pl.DataFrame({"driver_ms_per_task": [0.8, 1.0], "trial_cpu_s": [0.05, 0.05]})
    table = scaling.scaling_projection(measured)
    assert table.height == 9 and set(table["how"]) == {"one trial", "a lifetime", "chosen"}
    chosen = table.filter(pl.col("how") == "chosen")
    assert chosen["block"].to_list() == [2, 6, 18]  # ray_block: ceil(4 x 1 ms x N / 50 ms)
    for n in (16, 64, 256):  # the chosen block is never worse than both others
        rows = table.filter(pl.col("cpus") == n)
        best = rows["efficiency"].max()
        assert rows.filter(pl.col("how") == "chosen")["efficiency"][0] >= best - 0.05
