"""The paper's pre-reacher judged in the paper's own units (docs/results/campaign.md, (a)):
A1-A4 against their definitions on tables built trial by trial, and A3's measure."""

import math

import numpy as np
import polars as pl
import pytest

from dart_reach.analysis.profile import paper_units, robot_profiles
from dart_reach.measures.metrics import arm_extension


def _table(reach_by_robot, babbling_no_ball_by_robot, elbow=0.1, shoulder=0.2, trunk=0.3,
           babbling_normal=1.0, trials=20):
    """A post-evaluation table of robots (replication = index // 2, rank = index % 2): each
    robot reaches in ``reach`` of its normal trials and babbles in ``babbling_no_ball`` of its
    no-ball trials."""
    rows = []
    for i, (reach, babble) in enumerate(zip(reach_by_robot, babbling_no_ball_by_robot)):
        for senses, rate, share in (("normal", reach, babbling_normal), ("no-ball", 0.0, babble)):
            for t in range(trials):
                rows.append({"phase": "pre", "baseline": False, "senses": senses,
                             "replication": i // 2, "rank": i % 2, "trial": t,
                             "reached": t < round(rate * trials), "var_elbow": elbow,
                             "var_shoulder": shoulder, "var_trunk": trunk,
                             "hand_shoulder_mean": 0.33, "hand_shoulder_cv": 0.02,
                             "hand_path": 5.0, "fitness": 0.1,
                             "babbling": t < round(share * trials)})
    return pl.DataFrame(rows)


def test_a1_is_the_mean_over_the_best_robots_not_a_per_replication_conjunction():
    # two replications: one reaches always, the other never: the mean is one half (A1 met),
    # while neither replication is in the band on its own
    table = _table([1.0, 1.0, 0.0, 0.0], [1.0] * 4)
    j = paper_units(table, (0.33, 0.02))
    assert j["reach"] == 0.5 and j["A1"]
    assert j["A2"] and j["A3"] and j["A4"] and j["paper"]
    assert j["replications"] == 2 and j["robots"] == 4
    too_many = paper_units(_table([0.9, 0.7, 0.7, 0.7], [1.0] * 4), (0.33, 0.02))
    assert too_many["reach"] == pytest.approx(0.75) and not too_many["A1"]
    assert not too_many["paper"]


def test_a2_asks_the_elbow_below_both_the_shoulder_and_the_trunk():
    assert not paper_units(_table([0.5] * 4, [1.0] * 4, elbow=0.25), (0.33, 0.02))["A2"]
    assert not paper_units(_table([0.5] * 4, [1.0] * 4, elbow=0.35), (0.33, 0.02))["A2"]
    assert paper_units(_table([0.5] * 4, [1.0] * 4, elbow=0.19), (0.33, 0.02))["A2"]


def test_a3_is_the_best_robots_extension_long_and_constant():
    table = _table([0.5] * 4, [1.0] * 4)
    assert paper_units(table, (0.31, 0.049))["A3"]
    assert not paper_units(table, (0.309, 0.01))["A3"]
    assert not paper_units(table, (0.34, 0.05))["A3"]
    assert not paper_units(table, (math.nan, math.nan))["A3"]


def test_a4_counts_robots_that_babble_in_half_their_no_ball_trials():
    # 2 of 4 robots babble in at least half of their trials: met; 1 of 4: not
    j = paper_units(_table([0.5] * 4, [0.5, 0.6, 0.45, 0.0]), (0.33, 0.02))
    assert j["babbling_robots"] == 2 and j["A4"]
    j = paper_units(_table([0.5] * 4, [0.5, 0.4, 0.45, 0.0]), (0.33, 0.02))
    assert j["babbling_robots"] == 1 and not j["A4"]
    # babbling with the ball does not stand in for it
    j = paper_units(_table([0.5] * 4, [0.0] * 4, babbling_normal=1.0), (0.33, 0.02))
    assert not j["A4"]


def test_a4_fails_only_when_the_measures_misses_cannot_explain_the_shortfall():
    # no-ball rates 0.3, 0.3, 0.2, 0.0: A4 not met (no robot at 0.5); at a sensitivity of
    # 0.544 a robot at 0.3 (>= 0.272) could babble in half: 2 of 4 could, so not failed
    table = _table([0.5] * 4, [0.3, 0.3, 0.2, 0.0])
    j = paper_units(table, (0.33, 0.02), babbling_sensitivity=0.544)
    assert not j["A4"] and not j["A4_failed"]
    # at 0.25 a robot could not (0.25 < 0.272): only 0 of 4 could, failed
    j = paper_units(_table([0.5] * 4, [0.25, 0.25, 0.2, 0.0]), (0.33, 0.02),
                    babbling_sensitivity=0.544)
    assert not j["A4"] and j["A4_failed"]
    # a perfect measure: failed is not met
    j = paper_units(table, (0.33, 0.02))
    assert j["A4_failed"] and not j["A4"]
    # met stays met whatever the sensitivity
    j = paper_units(_table([0.5] * 4, [0.5, 0.6, 0.0, 0.0]), (0.33, 0.02),
                    babbling_sensitivity=0.544)
    assert j["A4"] and not j["A4_failed"]
    with pytest.raises(ValueError, match="sensitivity"):
        paper_units(table, (0.33, 0.02), babbling_sensitivity=0.0)


def test_a5_counts_still_replications_with_their_exact_interval():
    j = paper_units(_table([0.5] * 4, [1.0] * 4, babbling_normal=0.0), (0.33, 0.02))
    assert j["still"] == 2 and j["replications"] == 2
    assert j["still_interval"] == pytest.approx((0.1581, 1.0), abs=1e-4)  # Clopper-Pearson 2/2


def test_robot_profiles_mark_the_movement_of_the_paper_robot_by_robot():
    robots = robot_profiles(_table([0.9, 0.9], [1.0, 0.2]))
    assert robots["moves_as_paper"].to_list() == [True, False]
    with pytest.raises(ValueError, match="no-ball"):
        paper_units(_table([0.5, 0.5], [1.0, 1.0]).filter(pl.col("senses") == "normal"),
                    (0.33, 0.02))


def test_arm_extension_leaves_out_the_first_steps():
    shoulder = np.zeros((50, 3))
    hand = np.zeros((50, 3))
    hand[:20, 0] = np.linspace(0.1, 0.3, 20)  # the arm extending from the home posture
    hand[20:, 0] = 0.33 + 0.01 * np.sin(np.arange(30))  # then a long, nearly constant arm
    mean, cv = arm_extension(hand, shoulder, 20)
    d = hand[20:, 0]
    assert mean == pytest.approx(d.mean()) and cv == pytest.approx(d.std() / d.mean())
    whole, whole_cv = arm_extension(hand, shoulder)
    assert whole < mean and whole_cv > cv
    assert all(math.isnan(x) for x in arm_extension(hand, shoulder, 50))
