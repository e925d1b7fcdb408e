"""Behavioural measures (section IV-A, Figs. 5-7) on constructed trajectories with known
answers, worked out by hand in each test."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest

from dart_reach.measures import metrics as m
from dart_reach.analysis import summaries
from dart_reach.model.ctrnn import MOTOR_NAMES
from dart_reach.model.icub import HAND_SEGMENTS
from dart_reach.model.task import TrialData

N_SEG = len(HAND_SEGMENTS)


def no_contacts(T):
    return np.zeros((T, N_SEG), bool)


def square_path(T=20):
    """Hand from the origin: 4 steps of +2 cm in x (rows 0..4), 4 steps of +3 cm in y (rows
    4..8), then large wandering. Path length to row 8 = 0.08 + 0.12 = 0.20 m."""
    h = np.zeros((T, 3))
    h[1:5, 0] = 0.02 * np.arange(1, 5)
    h[5:, 0] = 0.08
    h[5:9, 1] = 0.03 * np.arange(1, 5)
    h[9:, 1] = 0.12
    h[9:, 2] = np.where(np.arange(9, T) % 2, 1.0, -1.0)  # after the touch: must not count
    return h


# ------------------------------------------------------------------ reach and grasp

def test_layout_constants_follow_the_motor_and_segment_names():
    assert HAND_SEGMENTS[m.PALM] == "r_hand"
    assert [MOTOR_NAMES[i] for i in m.ELBOW_JOINTS] == ["r_elbow"]
    assert m.SHOULDER_JOINTS == (6, 7, 8)
    assert [MOTOR_NAMES[i] for i in m.TRUNK_JOINTS] == ["torso_pitch", "torso_roll", "torso_yaw"]


def test_first_touch_and_reached():
    c = no_contacts(12)
    assert m.first_touch(c) == -1 and m.reached(c) is False
    c[7, 0] = True  # the palm at step 7
    c[4, 9] = True  # a finger phalanx at step 4: earlier
    assert m.first_touch(c) == 4 and m.reached(c) is True
    c0 = no_contacts(3)
    c0[0, 15] = True
    assert m.first_touch(c0) == 0
    assert m.first_touch(no_contacts(0)) == -1
    with pytest.raises(ValueError):
        m.first_touch(np.zeros(5, bool))


def test_grasp_needs_the_palm_and_a_finger_at_the_same_step():
    c = no_contacts(12)
    c[2, 0] = True  # palm alone
    c[3, 5] = True  # finger alone
    c[5, 0] = True  # palm at 5, finger at 6: not together
    c[6, 1] = True
    assert m.first_grasp(c) == -1 and m.grasped(c) is False
    assert m.reached(c)
    c[9, [0, 13]] = True  # palm + little finger
    assert m.first_grasp(c) == 9 and m.grasped(c) is True
    palm_only = no_contacts(5)
    palm_only[:, 0] = True
    assert not m.grasped(palm_only)
    fingers_only = no_contacts(5)
    fingers_only[:, 1:] = True
    assert not m.grasped(fingers_only)


# ------------------------------------------------------------------ kinematics

def test_path_length():
    p = np.array([[0, 0, 0], [3, 4, 0], [3, 4, 12], [3, 4, 12]], float)
    assert m.path_length(p) == pytest.approx(17.0)  # 5 + 12 + 0
    assert m.path_length(p[:1]) == 0.0
    assert m.path_length(np.zeros((0, 3))) == 0.0
    with pytest.raises(ValueError):
        m.path_length(np.zeros((4, 2)))


def test_reaching_speed_is_the_path_to_the_first_touch_over_its_duration():
    h = square_path()
    c = no_contacts(len(h))
    c[8, 3] = True
    c[15, 0] = True
    assert m.reaching_speed(h, c, dt=0.1) == pytest.approx(0.20 / 0.8)  # 0.25 m/s
    assert m.reaching_speed(h, c, dt=0.05) == pytest.approx(0.20 / 0.4)
    assert math.isnan(m.reaching_speed(h, no_contacts(len(h)), 0.1))
    c0 = no_contacts(len(h))
    c0[0, 0] = True
    assert math.isnan(m.reaching_speed(h, c0, 0.1))


def test_straightness_is_initial_distance_over_path_length():
    h = square_path()
    ball = np.tile([0.08, 0.12, 0.0], (len(h), 1))
    ball[1:] += 0.5  # the ball moves later: only its initial position counts
    c = no_contacts(len(h))
    c[8, 0] = True
    expected = math.hypot(0.08, 0.12) / 0.20  # 0.7211
    assert m.straightness(h, ball, c) == pytest.approx(expected)
    # a straight line to a ball 0.3 m away, touched at its surface 0.05 m short of the centre
    line = np.zeros((11, 3))
    line[:, 0] = np.linspace(0.0, 0.25, 11)
    b = np.tile([0.3, 0.0, 0.0], (11, 1))
    cl = no_contacts(11)
    cl[10, 0] = True
    assert m.straightness(line, b, cl) == pytest.approx(0.3 / 0.25)  # > 1, documented
    assert math.isnan(m.straightness(h, ball, no_contacts(len(h))))
    c0 = no_contacts(len(h))
    c0[0, 0] = True
    assert math.isnan(m.straightness(h, ball, c0))


def test_joint_variability_per_group():
    T = 10
    q = np.zeros((T, 14))
    sign = np.where(np.arange(T) % 2, 1.0, -1.0)  # +-1 alternating: std 1 (ddof 0)
    i = {n: k for k, n in enumerate(MOTOR_NAMES)}
    q[:, i["r_elbow"]] = 0.2 * sign
    q[:, i["r_shoulder_roll"]] = 0.3 * sign  # the other two shoulder joints still
    q[:, i["r_shoulder_pitch"]] = 1.5
    q[:, i["torso_pitch"]] = 0.6 * sign
    q[:, i["torso_roll"]] = 5.0
    q[:, i["torso_yaw"]] = 0.3 * sign - 2.0
    for other in ("neck_pitch", "r_wrist_prosup", "r_hand_fingers"):  # not in any group
        q[:, i[other]] = 10.0 * sign
    v = m.joint_variability(q)
    assert set(v) == {"elbow", "shoulder", "trunk"}
    assert v["elbow"] == pytest.approx(0.2)
    assert v["shoulder"] == pytest.approx(0.3 / 3)
    assert v["trunk"] == pytest.approx((0.6 + 0.0 + 0.3) / 3)
    assert all(math.isnan(x) for x in m.joint_variability(np.zeros((0, 14))).values())
    with pytest.raises(ValueError):
        m.joint_variability(np.zeros((5, 13)))


def test_distances():
    hand = np.array([[1.0, 2.0, 2.0], [0.0, 0.0, 0.5]])
    other = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    np.testing.assert_allclose(m.hand_shoulder_distance(hand, other), [3.0, 0.5])
    np.testing.assert_allclose(m.hand_ball_distance(hand, other + [0, 0, 0.5]),
                               [math.sqrt(1 + 4 + 2.25), 0.0])


def test_elbow_freezing_rigid_lever_vs_bending_arm():
    rng = np.random.default_rng(0)
    shoulder = rng.normal(size=(50, 3)) * 0.01  # the shoulder moves with the trunk
    u = rng.normal(size=(50, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    rigid = shoulder + 0.25 * u  # any direction, always 0.25 m from the shoulder
    assert m.elbow_freezing(rigid, shoulder) == pytest.approx(0.0, abs=1e-12)
    radius = np.where(np.arange(50) % 2, 0.3, 0.2)  # 0.2 / 0.3 m alternating: std 0.05
    bending = shoulder + radius[:, None] * u
    assert m.elbow_freezing(bending, shoulder) == pytest.approx(0.05)


# ------------------------------------------------------------------ periodicity

def circle(f, t, r=0.1):
    w = 2 * np.pi * f * t
    return np.column_stack([r * np.cos(w), r * np.sin(w), np.zeros_like(t)])


def test_periodicity_of_a_circle_at_half_a_hertz():
    t = np.arange(200) * 0.1  # 20 s
    freq, share = m.hand_periodicity(circle(0.5, t), 0.1)
    assert freq == pytest.approx(0.5)
    assert share > 0.99
    # offset and drift do not matter
    drifting = circle(0.5, t) + [0.2, -0.1, 0.3] + np.outer(t, [0.01, 0.02, -0.01])
    f2, s2 = m.hand_periodicity(drifting, 0.1)
    assert f2 == pytest.approx(0.5) and s2 == pytest.approx(share)
    # a 1.5 Hz circle sampled at 20 Hz for 10 s
    t2 = np.arange(200) * 0.05
    f3, s3 = m.hand_periodicity(circle(1.5, t2), 0.05)
    assert f3 == pytest.approx(1.5) and s3 > 0.99
    # 0.525 Hz falls between the bins 0.50 and 0.55 Hz: the neighbours hold much of the power,
    # which the share counts (the strongest bin alone holds about half)
    f4, s4 = m.hand_periodicity(circle(0.525, t), 0.1)
    assert f4 in (pytest.approx(0.5), pytest.approx(0.55)) and s4 > 0.8


def test_periodicity_share_is_low_for_several_circles_and_noise():
    t = np.arange(200) * 0.1
    freqs = (0.3, 0.7, 1.2, 2.0)
    f, share = m.hand_periodicity(sum(circle(fq, t) for fq in freqs), 0.1)
    assert any(f == pytest.approx(fq) for fq in freqs)
    assert 0.2 < share < 0.35  # ~1/4: four equal circles
    noise = np.random.default_rng(3).normal(scale=0.05, size=(200, 3))
    assert m.hand_periodicity(noise, 0.1)[1] < 0.2  # 100 bins: ~3/100 expected


def test_periodicity_of_a_hand_at_rest_or_on_a_straight_line_is_nan():
    for hand in (np.full((200, 3), 0.3), np.outer(np.arange(200) * 0.1, [0.01, 0.02, 0.03]),
                 np.zeros((3, 3))):
        f, s = m.hand_periodicity(hand, 0.1)
        assert math.isnan(f) and math.isnan(s)


# ------------------------------------------------------------------ one trial

def make_trial():
    """50-step record that diverged after 30 steps; rows 30.. hold junk that must be ignored."""
    T, n = 50, 30
    d = TrialData.empty(T, sector=5, ball_start=[0.08, 0.15, 0.0])
    d.steps_run, d.diverged = n, True
    d.hand[:n] = square_path(n)
    d.hand[8:n] = d.hand[8]  # the hand stays at the touch point after step 8
    d.ball[:n] = [0.08, 0.15, 0.0]  # 3 cm from the hand's resting point (0.08, 0.12, 0)
    d.ball[20:n, 1] = 0.13  # pushed towards the hand: 1 cm away from row 20 on
    d.shoulder[:n] = [0.0, 0.0, 0.3]
    d.contacts[8, 4] = True  # first touch: a finger phalanx at step 8
    d.contacts[20, [0, 2]] = True  # grasp at step 20
    d.contacts_any[:] = d.contacts  # inner faces are faces
    d.joints[:n, MOTOR_NAMES.index("r_elbow")] = np.where(np.arange(n) % 2, 0.1, -0.1)
    d.p_multimodal[:n] = 0.5
    # junk after steps_run
    d.hand[n:] = 100.0
    d.contacts[n:] = True
    d.joints[n:] = 50.0
    return d


def test_trial_metrics_uses_only_the_steps_run():
    d = make_trial()
    r = m.trial_metrics(d, dt=0.1)
    assert set(r) == {
        "sector", "fitness", "reached", "reached_inner", "grasped", "first_touch_s",
        "first_touch_inner_s", "first_grasp_s", "touches", "contact_after_first",
        "movement_onset_s", "speed",
        "speed_peak", "speed_final", "straightness", "straightness_centre",
        "straightness_onset", "movement_units", "var_elbow", "var_shoulder", "var_trunk",
        "var_elbow_before", "var_shoulder_before", "var_trunk_before", "var_elbow_norm",
        "var_shoulder_norm", "var_trunk_norm", "hand_shoulder_mean", "hand_shoulder_cv",
        "elbow_freezing", "hand_ball_initial", "hand_ball_min", "approach", "heading",
        "hand_path", "hand_amplitude", "babbling_freq_hz", "babbling_share", "babbling",
        "anticipatory_grasp", "grasp_lead_s", "palm_up_swipe", "swipes", "diverged",
        "steps_run"}
    assert r["sector"] == 5 and r["steps_run"] == 30 and r["diverged"] is True
    from dart_reach.measures.fitness import contact_after_first

    assert r["contact_after_first"] == contact_after_first(d.contacts[:30])  # inner faces
    assert r["fitness"] == 0.0  # diverged
    assert r["reached"] is True and r["grasped"] is True
    assert r["first_touch_s"] == pytest.approx(0.8)
    assert r["first_grasp_s"] == pytest.approx(2.0)
    assert r["speed"] == pytest.approx(0.25)
    assert r["straightness_centre"] == pytest.approx(0.17 / 0.2)  # hypot(0.08, 0.15) = 0.17
    assert r["straightness"] == pytest.approx((0.17 - m.BALL_RADIUS) / 0.2)  # to the surface
    assert r["var_elbow"] == pytest.approx(0.1)
    assert r["var_shoulder"] == 0.0 and r["var_trunk"] == 0.0
    assert r["hand_ball_initial"] == pytest.approx(0.17)
    assert r["hand_ball_min"] == pytest.approx(0.01)
    hs = np.linalg.norm(d.hand[:30] - [0.0, 0.0, 0.3], axis=1)
    assert r["hand_shoulder_mean"] == pytest.approx(hs.mean())
    assert r["elbow_freezing"] == pytest.approx(hs.std())
    assert np.isfinite(r["babbling_freq_hz"]) and 0.0 < r["babbling_share"] <= 1.0


def test_trial_metrics_of_a_full_trial_without_contact():
    d = TrialData.empty(200, sector=0, ball_start=[0.3, 0.0, 0.0])
    d.steps_run = 200
    t = np.arange(200) * 0.1
    d.hand[:] = circle(0.5, t) + [0.0, 0.0, 0.1]
    d.ball[:] = [0.3, 0.0, 0.0]
    d.p_multimodal[:] = np.linspace(0.0, 0.2, 200)
    r = m.trial_metrics(d)
    assert r["fitness"] == pytest.approx(0.1) and r["diverged"] is False
    assert r["reached"] is False and r["grasped"] is False
    for k in ("first_touch_s", "first_grasp_s", "speed", "straightness"):
        assert math.isnan(r[k])
    assert r["babbling_freq_hz"] == pytest.approx(0.5) and r["babbling_share"] > 0.99
    assert r["hand_shoulder_mean"] == pytest.approx(math.hypot(0.1, 0.1))
    assert r["elbow_freezing"] == pytest.approx(0.0, abs=1e-12)


def test_trial_metrics_of_a_trial_that_diverged_at_once():
    d = TrialData.empty(10, sector=2, ball_start=[0.3, 0.0, 0.0])
    d.diverged = True  # steps_run = 0
    r = m.trial_metrics(d)
    assert r["steps_run"] == 0 and r["reached"] is False and r["fitness"] == 0.0
    assert math.isnan(r["hand_ball_initial"]) and math.isnan(r["var_elbow"])


# ------------------------------------------------------------------ tables

def post_table():
    """Two phases, 2 robots each, a few sectors with known rates.

    pre:   sector 0: reached 1,1,0,0 (0.5), grasped 1,0,0,0 (0.25); sector 4: 1,1 / 0,0;
           sector 8: 0,0,0 / 0,0,0
    gross: sector 0: 1,0 (0.5) / 1,0; sector 4: 0,0 / 0,0; sector 8: 1,1,1 / 1,1,0
    """
    rows = []

    def add(phase, sector, reached, grasped, robots, fitness):
        for r, g, rank, f in zip(reached, grasped, robots, fitness):
            rows.append({"phase": phase, "senses": "normal", "replication": 0, "rank": rank,
                         "sector": sector, "reached": r, "grasped": g, "fitness": f})

    add("pre", 0, [1, 1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 1], [0.4, 0.2, 0.0, 0.0])
    add("pre", 4, [1, 1], [0, 0], [0, 1], [0.1, 0.3])
    add("pre", 8, [0, 0, 0], [0, 0, 0], [0, 1, 1], [0.0, 0.0, 0.0])
    add("gross", 0, [1, 0], [1, 0], [0, 1], [0.5, 0.0])
    add("gross", 4, [0, 0], [0, 0], [0, 1], [0.0, 0.0])
    add("gross", 8, [1, 1, 1], [1, 1, 0], [0, 0, 1], [0.6, 0.4, 0.2])
    t = pl.DataFrame(rows)
    return t.with_columns(pl.col("reached").cast(pl.Boolean), pl.col("grasped").cast(pl.Boolean))


def test_sector_success_and_grid():
    s = summaries.sector_success(post_table())
    assert s.columns == ["phase", "sector", "n", "reach_rate", "grasp_rate", "row", "col"]
    pre = s.filter(pl.col("phase") == "pre")
    assert pre["sector"].to_list() == [0, 4, 8]
    assert pre["n"].to_list() == [4, 2, 3]
    assert pre["reach_rate"].to_list() == [0.5, 1.0, 0.0]
    assert pre["grasp_rate"].to_list() == [0.25, 0.0, 0.0]
    assert pre["row"].to_list() == [0, 1, 2] and pre["col"].to_list() == [0, 1, 2]
    grid = summaries.sector_grid(pre)
    expected = np.full((3, 3), np.nan)
    expected[0, 0], expected[1, 1], expected[2, 2] = 0.5, 1.0, 0.0
    np.testing.assert_array_equal(grid, expected)
    gross = summaries.sector_grid(s.filter(pl.col("phase") == "gross"), "grasp_rate")
    assert gross[0, 0] == 0.5 and gross[2, 2] == pytest.approx(2 / 3) and np.isnan(gross[0, 1])
    with pytest.raises(ValueError, match="one group"):
        summaries.sector_grid(s)
    with pytest.raises(ValueError):
        summaries.sector_success(post_table().drop("reached"))


def test_sector_grid_row_and_col_of_sector_five():
    rates = pl.DataFrame({"sector": [5], "reach_rate": [0.7]})
    grid = summaries.sector_grid(rates)
    assert grid[1, 2] == 0.7 and np.isnan(grid).sum() == 8  # 5 // 3 = 1, 5 % 3 = 2


def test_reach_regression():
    r = summaries.reach_regression(post_table(), before="pre", after="gross")
    assert r.columns == ["sector", "row", "col", "n_before", "n_after", "reach_before",
                         "reach_after", "change"]
    assert r["sector"].to_list() == [0, 4, 8]
    assert r["reach_before"].to_list() == [0.5, 1.0, 0.0]
    assert r["reach_after"].to_list() == [0.5, 0.0, 1.0]
    assert r["change"].to_list() == [0.0, -1.0, 1.0]
    assert r["n_before"].to_list() == [4, 2, 3] and r["n_after"].to_list() == [2, 2, 3]
    by = summaries.reach_regression(post_table(), by=("senses",))
    assert by.columns[:2] == ["senses", "sector"] and by["change"].to_list() == [0.0, -1.0, 1.0]
    with pytest.raises(ValueError, match="fine"):
        summaries.reach_regression(post_table(), after="fine")


def test_robot_performance():
    p = summaries.robot_performance(post_table())
    assert p.columns == ["phase", "senses", "replication", "rank", "n", "fitness", "reach_rate",
                         "grasp_rate"]
    # sorted by phase: "gross" < "pre"
    assert p["phase"].to_list() == ["gross", "gross", "pre", "pre"]
    assert p["rank"].to_list() == [0, 1, 0, 1]
    # pre rank 0: sector 0 rows 1-2, sector 4 row 1, sector 8 row 1
    pre0 = p.row(2, named=True)
    assert pre0["n"] == 4
    assert pre0["fitness"] == pytest.approx((0.4 + 0.2 + 0.1 + 0.0) / 4)
    assert pre0["reach_rate"] == pytest.approx(3 / 4) and pre0["grasp_rate"] == pytest.approx(1 / 4)
    gross1 = p.row(1, named=True)  # sector 0 row 2, sector 4 row 2, sector 8 row 3
    assert gross1["n"] == 3 and gross1["fitness"] == pytest.approx(0.2 / 3)
    assert gross1["reach_rate"] == pytest.approx(1 / 3) and gross1["grasp_rate"] == 0.0
    with pytest.raises(ValueError):
        summaries.robot_performance(post_table().drop("fitness"))


# ------------------------------------------------------------------ figure summaries

def speed_table():
    """Robot (pre, rep 0, rank 0): speeds 1.0, NaN, 3.0 -> mean 2.0, reached 1, 0, 1.
    Robot (pre, rep 0, rank 1): speeds NaN, NaN -> NaN, reached 0, 0.
    Robot (pre, rep 1, rank 0): speed 4.0, reached 1. Robot (gross, rep 0, rank 0): 0.5, 1."""
    nan = math.nan
    return pl.DataFrame({
        "phase": ["pre"] * 6 + ["gross"],
        "senses": ["normal"] * 7,
        "replication": [0, 0, 0, 0, 0, 1, 0],
        "rank": [0, 0, 0, 1, 1, 0, 0],
        "speed": [1.0, nan, 3.0, nan, nan, 4.0, 0.5],
        "reached": [True, False, True, False, False, True, True],
    })


def test_robot_means_ignores_nan_and_counts_booleans():
    r = summaries.robot_means(speed_table(), ["speed", "reached"])
    assert r.columns == ["phase", "senses", "replication", "rank", "n", "speed", "reached"]
    assert r["phase"].to_list() == ["gross", "pre", "pre", "pre"]
    assert r["n"].to_list() == [1, 3, 2, 1]
    speed = r["speed"].to_list()
    assert speed[0] == 0.5 and speed[1] == 2.0 and math.isnan(speed[2]) and speed[3] == 4.0
    assert r["reached"].to_list() == [1.0, pytest.approx(2 / 3), 0.0, 1.0]
    with pytest.raises(ValueError):
        summaries.robot_means(speed_table(), ["nope"])
    with pytest.raises(ValueError):
        summaries.robot_means(speed_table(), [])


def test_group_summary_mean_sd_sem():
    robots = summaries.robot_means(speed_table(), ["speed", "reached"])
    s = summaries.group_summary(robots, ["speed", "reached"])
    assert s.columns == ["phase", "measure", "n", "mean", "sd", "sem"]
    assert s["phase"].to_list() == ["gross", "gross", "pre", "pre"]
    assert s["measure"].to_list() == ["speed", "reached"] * 2
    gross_speed, _, pre_speed, pre_reached = s.iter_rows(named=True)
    # gross: one robot -> mean 0.5, no sd
    assert gross_speed["n"] == 1 and gross_speed["mean"] == 0.5 and math.isnan(gross_speed["sd"])
    assert math.isnan(gross_speed["sem"])
    # pre speed: robots 2.0 and 4.0 (the NaN robot left out): sd = sqrt(2), sem = 1
    assert pre_speed["n"] == 2 and pre_speed["mean"] == 3.0
    assert pre_speed["sd"] == pytest.approx(math.sqrt(2)) and pre_speed["sem"] == pytest.approx(1)
    # pre reached: 2/3, 0, 1 -> mean 5/9
    assert pre_reached["n"] == 3 and pre_reached["mean"] == pytest.approx(5 / 9)
    # a group without any finite value: n 0, mean NaN
    empty = summaries.group_summary(robots.filter(pl.col("speed").is_nan()), ["speed"])
    assert empty["n"].to_list() == [0] and math.isnan(empty["mean"][0])
    # no grouping: one row per measure
    assert summaries.group_summary(robots, ["speed"], by=())["n"].to_list() == [3]


def test_replication_performance_best_robot_and_best_k():
    t = post_table().with_columns(
        pl.when(pl.col("rank") == 0).then(0.9).otherwise(0.5).alias("lifetime_fitness"))
    best = summaries.replication_performance(t)
    assert best.columns == ["phase", "replication", "robots", "fitness", "reach_rate",
                            "grasp_rate", "lifetime_fitness"]
    assert best["phase"].to_list() == ["gross", "pre"]
    assert best["robots"].to_list() == [1, 1]
    # pre rank 0: fitness 0.4, 0.2, 0.1, 0.0 (see test_robot_performance); gross rank 0:
    # sector 0 row 1 (0.5), sector 4 row 1 (0.0), sector 8 rows 1-2 (0.6, 0.4) -> 1.5 / 4
    assert best["fitness"].to_list() == [pytest.approx(1.5 / 4), pytest.approx(0.7 / 4)]
    assert best["lifetime_fitness"].to_list() == [0.9, 0.9]
    two = summaries.replication_performance(t, robots=2)
    assert two["robots"].to_list() == [2, 2]
    # pre: robot 0 -> 0.175, robot 1 -> (0 + 0 + 0.3 + 0 + 0) / 5 = 0.06
    assert two.filter(pl.col("phase") == "pre")["fitness"][0] == pytest.approx((0.175 + 0.06) / 2)
    assert two["lifetime_fitness"].to_list() == [pytest.approx(0.7)] * 2
    with pytest.raises(ValueError, match="no trials"):
        summaries.replication_performance(t, senses="nothing")
    with pytest.raises(ValueError):
        summaries.replication_performance(t, robots=0)


def test_a_touch_with_the_back_of_the_hand_is_a_reach_but_not_an_inner_touch():
    """The paper's reach is "touch the object at least once with the hand" (IV-A-1): any face.
    Grasp and the touch sensors keep the inner faces."""
    d = make_trial()
    d.contacts_any[5, 0] = True  # the back of the hand brushes the ball at step 5
    r = m.trial_metrics(d, dt=0.1)
    assert r["reached"] and r["reached_inner"]
    assert r["first_touch_s"] == pytest.approx(0.5)
    assert r["first_touch_inner_s"] == pytest.approx(0.8)
    assert r["speed"] == pytest.approx(path_length_of(d.hand[:6]) / 0.5)
    d.contacts[:] = False  # only back-of-hand touches
    r = m.trial_metrics(d, dt=0.1)
    assert r["reached"] and not r["reached_inner"] and not r["grasped"]
    assert math.isnan(r["first_touch_inner_s"])


def path_length_of(p):
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def test_variability_before_the_touch_is_not_lowered_by_holding_the_ball():
    d = TrialData.empty(200, sector=4, ball_start=[0.3, 0.0, 0.0])
    d.steps_run = 200
    elbow = MOTOR_NAMES.index("r_elbow")
    d.joints[:20, elbow] = np.where(np.arange(20) % 2, 0.2, -0.2)  # moves for 2 s...
    d.joints[20:, elbow] = 0.2  # ...then holds the ball for 18 s
    d.contacts[20:, [0, 3]] = d.contacts_any[20:, [0, 3]] = True
    ranges = np.full(len(MOTOR_NAMES), 2.0)
    r = m.trial_metrics(d, dt=0.1, joint_ranges=ranges)
    assert r["var_elbow_before"] == pytest.approx(0.2)
    assert r["var_elbow"] < 0.1  # the whole trial: diluted by the hold
    assert r["var_elbow_norm"] == pytest.approx(r["var_elbow"] / 2.0)
    assert math.isnan(m.trial_metrics(d, dt=0.1)["var_elbow_norm"])  # no ranges given
    d.contacts[:] = d.contacts_any[:] = False  # never touched: the whole trial is "before"
    r = m.trial_metrics(d, dt=0.1)
    assert r["var_elbow_before"] == r["var_elbow"]


def test_trial_metrics_default_ball_radius_is_the_shipped_balls():
    from dart_reach.model.world import BallConfig

    assert m.BALL_RADIUS == BallConfig().radius


def test_peripersonal_space_counts_and_spreads_the_sectors_a_robot_reaches():
    rows = []
    for rank, sectors in ((0, range(9)), (1, (4,)), (2, ())):  # everywhere, one sector, none
        for s in range(9):
            for _ in range(5):
                rows.append({"phase": "p", "senses": "normal", "replication": 0, "rank": rank,
                             "sector": s, "reached": s in sectors, "grasped": s == 4})
    space = summaries.peripersonal_space(pl.DataFrame(rows))
    assert space["trials"].to_list() == [45, 45, 45]
    assert space["sectors_reached"].to_list() == [9, 1, 0]
    assert space["sectors_grasped"].to_list() == [1, 1, 1]
    e = space["reach_entropy"].to_list()
    assert e[0] == pytest.approx(1.0) and e[1] == pytest.approx(0.0) and math.isnan(e[2])


def test_condition_contrast_pairs_each_robot_with_itself():
    rows = [{"phase": "fine", "replication": r, "rank": 0, "senses": s, "fitness": f,
             "reached": f > 0.05}
            for r, (normal, blind) in enumerate(((0.10, 0.02), (0.08, 0.08)))
            for s, f in (("normal", normal), ("no-sight", blind))]
    rows.append({"phase": "fine", "replication": 2, "rank": 0, "senses": "normal",
                 "fitness": 0.5, "reached": True})  # never tested blind: left out
    out = summaries.condition_contrast(pl.DataFrame(rows), ["fitness", "reached"])
    assert out["replication"].to_list() == [0, 1]
    assert out["fitness_drop"].to_list() == pytest.approx([0.08, 0.0])
    assert out["reached_a"].to_list() == [1.0, 1.0] and out["reached_b"].to_list() == [0.0, 1.0]
