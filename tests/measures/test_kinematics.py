"""The hand's kinematic measures (``kinematics.py``; sections IV-A, V, Table I) on constructed
paths where each must fire and where it must not."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dart_reach.measures import kinematics as k

DT = 0.1


def line(start, step, n: int) -> np.ndarray:
    """n points from ``start`` moving by ``step`` (m) each step."""
    return np.asarray(start, float) + np.outer(np.arange(n), step)


def still(point, n: int) -> np.ndarray:
    return np.tile(np.asarray(point, float), (n, 1))


def circle(radius: float, freq: float, n: int = 200, centre=(0.0, 0.0, 0.0)) -> np.ndarray:
    t = np.arange(n) * DT
    return np.asarray(centre) + radius * np.column_stack(
        [np.cos(2 * np.pi * freq * t), np.sin(2 * np.pi * freq * t), np.zeros(n)])


def test_movement_onset_is_the_first_step_faster_than_the_threshold():
    hand = np.vstack([still([0, 0, 0], 10), line([0, 0, 0], [0.01, 0, 0], 10)[1:]])
    assert k.movement_onset(hand) == 9  # step 9 -> 10 moves 1 cm in 0.1 s = 0.1 m/s
    assert k.movement_onset(still([0, 0, 0], 20)) == -1
    creep = line([0, 0, 0], [0.004, 0, 0], 20)  # 0.04 m/s, under the 0.05 m/s threshold
    assert k.movement_onset(creep) == -1
    assert k.movement_onset(hand, end=5) == -1  # only steps before the touch count


def test_peak_and_final_speeds_are_not_diluted_by_waiting():
    ball = still([0.3, 0, 0], 31)
    # 20 steps at rest, then 10 steps straight at the ball at 0.2 m/s, touching at row 30
    hand = np.vstack([still([0.0, 0, 0], 21), line([0.0, 0, 0], [0.02, 0, 0], 11)[1:]])
    assert k.reaching_speed(hand, 30) == pytest.approx(0.2 * 10 / 30)  # diluted
    assert k.final_speed(hand, ball, 30) == pytest.approx(0.2)
    assert k.final_approach(hand, ball, 30) == 20
    assert k.peak_speed(hand, 30) == pytest.approx(0.2)
    # the ball swings into a still hand: no final movement toward it
    swing = line([0.3, 0, 0], [-0.01, 0, 0], 31)
    assert math.isnan(k.final_speed(still([0.0, 0, 0], 31), swing, 30))
    assert math.isnan(k.final_speed(hand, ball, -1)) and math.isnan(k.peak_speed(hand, 0))


def test_final_approach_stops_at_the_last_step_away_from_the_ball():
    ball = still([0.3, 0, 0], 21)
    away = line([0.1, 0, 0], [-0.01, 0, 0], 11)  # 10 steps away, then 10 toward
    back = line(away[-1], [0.02, 0, 0], 11)[1:]
    hand = np.vstack([away, back])
    assert k.final_approach(hand, ball, 20) == 10
    assert k.final_speed(hand, ball, 20) == pytest.approx(0.2)


def test_straightness_from_the_surface_is_one_for_a_straight_reach():
    r = 0.035
    ball = still([0.2, 0, 0], 12)
    hand = line([0, 0, 0], [0.015, 0, 0], 12)  # reaches the surface (0.165 m) at row 11
    assert k.straightness(hand, ball, 11, r) == pytest.approx(1.0)
    # to the centre the same reach scores 0.2 / 0.165: the bias measuring to the surface removes
    assert k.straightness(hand, ball, 11) == pytest.approx(0.2 / 0.165)
    # 10 cm sideways, then diagonally onto the surface: 0.165 / (0.1 + hypot(0.165, 0.1))
    detour = np.vstack([line([0, 0, 0], [0, 0.01, 0], 11),
                        line([0, 0.1, 0], [0.0165, -0.01, 0], 11)[1:]])
    assert k.straightness(detour, still([0.2, 0, 0], 21), 20, r) == pytest.approx(
        0.165 / (0.1 + math.hypot(0.165, 0.1)))
    assert math.isnan(k.straightness(hand, ball, -1, r))


def test_straightness_from_onset_ignores_the_wait_and_the_ball():
    hand = np.vstack([still([0, 0, 0], 5), line([0, 0, 0], [0.01, 0, 0], 11)[1:]])
    assert k.straightness_onset(hand, 14) == pytest.approx(1.0)
    corner = np.vstack([line([0, 0, 0], [0.01, 0, 0], 11), line([0.1, 0, 0], [0, 0.01, 0], 11)[1:]])
    assert k.straightness_onset(corner, 20) == pytest.approx(math.sqrt(2) / 2)
    assert math.isnan(k.straightness_onset(still([0, 0, 0], 10), 9))  # never moved


def _bell(n: int, peak: float) -> np.ndarray:
    """Step displacements of a smooth movement whose speed rises to ``peak`` and back."""
    return peak * DT * np.sin(np.linspace(0, np.pi, n + 2)[1:-1])


def test_movement_units_count_the_speed_peaks_of_a_reach():
    one = np.concatenate([[0.0], np.cumsum(_bell(10, 0.5))])
    hand = np.column_stack([one, np.zeros_like(one), np.zeros_like(one)])
    assert k.movement_units(hand, len(hand) - 1) == 1
    two = np.concatenate([[0.0], np.cumsum(np.concatenate([_bell(10, 0.5), _bell(10, 0.4)]))])
    hand2 = np.column_stack([two, np.zeros_like(two), np.zeros_like(two)])
    assert k.movement_units(hand2, len(hand2) - 1) == 2
    # a wobble of 0.02 m/s on a steady 0.3 m/s is no new unit
    steps = 0.3 * DT + 0.02 * DT * np.sin(np.arange(20) * 1.3)
    wobble = np.concatenate([[0.0], np.cumsum(steps)])
    hand3 = np.column_stack([wobble, np.zeros_like(wobble), np.zeros_like(wobble)])
    assert k.movement_units(hand3, len(hand3) - 1) == 1
    assert math.isnan(k.movement_units(hand, -1))


def test_approach_and_heading_tell_a_directed_arm_from_a_flailing_one():
    ball = still([0.3, 0, 0], 21)
    toward = line([0, 0, 0], [0.01, 0, 0], 21)
    assert k.heading(toward, ball) == pytest.approx(1.0)
    assert k.approach(toward, ball) == pytest.approx(2 / 3)
    away = line([0, 0, 0], [-0.01, 0, 0], 21)
    assert k.heading(away, ball) == pytest.approx(-1.0)
    assert k.approach(away, ball) == pytest.approx(0.0)
    around = circle(0.1, 1.0, centre=(0.3, 0, 0))  # circling the ball at a constant distance
    assert k.heading(around, still([0.3, 0, 0], 200)) == pytest.approx(0.0, abs=1e-9)
    assert k.approach(around, still([0.3, 0, 0], 200)) == pytest.approx(0.0, abs=1e-9)
    assert math.isnan(k.heading(still([0, 0, 0], 10), still([0.3, 0, 0], 10)))


def test_amplitude_of_a_circle_is_its_radius():
    assert k.hand_amplitude(circle(0.08, 1.0)) == pytest.approx(0.08, rel=0.02)
    assert k.hand_amplitude(still([0.1, 0.2, 0.3], 50)) == pytest.approx(0.0, abs=1e-12)
    assert k.hand_amplitude(line([0, 0, 0], [0.01, 0, 0], 50)) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("hand, babbles", [
    (circle(0.1, 1.0), True),  # large, quasi-periodic: babbling
    (circle(0.1, 0.8) + circle(0.03, 1.7), True),  # a dominant rhythm with a harmonic
    (circle(0.02, 1.0), False),  # periodic but small (2 cm)
    (circle(0.1, 0.1), False),  # large but 2 cycles in 20 s: a slow sweep, not a rhythm
    (np.random.default_rng(0).normal(scale=0.1, size=(200, 3)), False),  # large, no rhythm
    (still([0.1, 0.1, 0.1], 200), False),  # at rest: not babbling (not NaN)
])
def test_babbling_needs_a_rhythm_and_a_large_movement(hand, babbles):
    f, share = k.hand_periodicity(hand)
    assert k.is_babbling(f, share, k.hand_amplitude(hand)) is babbles


def test_before_touch_is_the_path_to_the_touch_over_at_least_ten_seconds():
    hand = circle(0.1, 0.5)
    assert len(k.before_touch(hand, -1)) == 200  # no touch: the whole trial
    assert len(k.before_touch(hand, 150)) == 150  # rows 0..149, before the touch at row 150
    assert len(k.before_touch(hand, 30)) == 100  # an early touch: the first 10 s
    assert len(k.before_touch(hand[:80], 30)) == 80  # never more than the trial
    np.testing.assert_array_equal(k.before_touch(hand, 150), hand[:150])


def _sweep_then(after: np.ndarray, touch: int, freq: float = 0.5) -> np.ndarray:
    """A 15 cm to-and-fro sweep at ``freq`` Hz up to row ``touch``, ``after`` from then on
    (starting where the sweep stopped)."""
    t = np.arange(touch) * DT
    sweep = np.column_stack([0.15 * np.sin(2 * np.pi * freq * t), np.zeros(touch),
                             np.zeros(touch)])
    return np.vstack([sweep, sweep[-1] + after[:200 - touch] - after[0]])


@pytest.mark.parametrize("touch", [60, 110, 140])
def test_a_sweep_broken_at_the_touch_is_babbling_before_it(touch):
    """The first sample's misses with the ball: a sweep that stops at the ball or turns
    irregular after the touch. The detector on the whole trial misses them; before the touch
    (at least 10 s) they babble."""
    held = _sweep_then(still([0, 0, 0], 200), touch)  # held at the ball to the end
    rng = np.random.default_rng(touch)
    raw = rng.normal(size=(240, 3))
    kernel = np.exp(-0.5 * (np.arange(-20, 21) / 6.0) ** 2)
    smooth = np.stack([np.convolve(raw[:, i], kernel, "same") for i in range(3)], 1)[20:-20]
    irregular = _sweep_then(0.2 * smooth / np.sqrt((smooth ** 2).sum(1).mean()), touch)
    f, share = k.hand_periodicity(irregular)
    assert not k.is_babbling(f, share, k.hand_amplitude(irregular))  # the detector misses it
    for hand in (held, irregular):
        f, share = k.hand_periodicity(hand)
        assert k.babbling_before_touch(hand, touch)
        assert k.babbling_before_touch(hand, -1) == k.is_babbling(
            f, share, k.hand_amplitude(hand))  # no touch: the detector itself


@pytest.mark.parametrize("touch", [-1, 20, 120])
def test_before_touch_sees_no_babbling_where_there_is_none(touch):
    """Still paths of the synthetic set (rest, reach and hold, slow sweeps, small circles)
    stay not babbling whatever the touch's row; a babbling circle stays babbling."""
    from dart_reach.measures import babbling_synthetic as synthetic

    rng = np.random.default_rng(5)
    for family in ("rest", "reach and hold", "slow sweeps", "small circles", "drift"):
        for _ in range(20):
            assert not k.babbling_before_touch(synthetic.path(family, rng).hand, touch), family
    circles = [synthetic.path("circle", rng).hand for _ in range(40)]
    whole = sum(k.is_babbling(*k.hand_periodicity(h), k.hand_amplitude(h)) for h in circles)
    before = sum(k.babbling_before_touch(h, touch) for h in circles)
    assert whole >= 36
    # 5-40 cycles in 20 s keep 2.5-20 in the first 10 s: nearly all still babble there
    assert before == whole if touch < 0 else before >= 0.85 * whole
