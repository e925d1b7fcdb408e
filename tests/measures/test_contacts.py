"""The touch measures (``contacts.py``; sections IV-A-2, IV-A-3, Table I) on constructed trials
where each must fire and where it must not."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dart_reach.measures import contacts as c

T = 40


def touches(*rows, segments=(0,)) -> np.ndarray:
    a = np.zeros((T, 16), bool)
    for r in rows:
        a[r, list(segments)] = True
    return a


def test_reach_and_grasp_follow_the_papers_definitions():
    finger = touches(8, segments=(4,))
    assert c.reached(finger) and c.first_touch(finger) == 8 and not c.grasped(finger)
    grasp = touches(8, 9, segments=(0, 5))
    assert c.grasped(grasp) and c.first_grasp(grasp) == 8
    palm_then_finger = touches(8, segments=(0,)) | touches(9, segments=(5,))
    assert not c.grasped(palm_then_finger)  # never together at one step
    assert not c.reached(touches())


def test_touch_onsets_are_the_starts_of_touches():
    a = touches(0, 1, 5, 6, 7, 20)
    assert c.touch_onsets(a).tolist() == [0, 5, 20]
    assert c.touch_onsets(touches()).tolist() == []


def flexion_closing(start_row: int, rows: int, rise: float) -> np.ndarray:
    """Mean finger flexion (rad): open (0.05) then closing by ``rise`` over ``rows`` rows from
    ``start_row`` on, held after."""
    f = np.full(T, 0.05)
    f[start_row:start_row + rows] += np.linspace(0, rise, rows)
    f[start_row + rows:] = 0.05 + rise
    return f


def test_fingers_closing_before_the_palm_touch_is_anticipation():
    palm = touches(20, 21, 22, segments=(0,))
    ant, lead = c.anticipatory_grasp(flexion_closing(15, 6, 0.3), palm)  # 15 .. 20
    assert ant == 1.0 and lead == pytest.approx(0.5)


def test_closing_after_the_touch_or_a_hand_held_closed_is_not_anticipation():
    palm = touches(20, 21, 22, segments=(0,))
    reflex = flexion_closing(21, 5, 0.6)  # the grasp reflex closes after the touch
    assert c.anticipatory_grasp(reflex, palm)[0] == 0.0
    closed = np.full(T, 0.8)  # held half closed all along: no closing at the touch
    ant, lead = c.anticipatory_grasp(closed, palm)
    assert ant == 0.0 and math.isnan(lead)
    early = flexion_closing(2, 5, 0.5)  # closed long before the window: not anticipation
    assert c.anticipatory_grasp(early, palm)[0] == 0.0
    small = flexion_closing(15, 6, 0.05)  # a twitch of 0.05 rad < FLEXION_RISE
    assert c.anticipatory_grasp(small, palm)[0] == 0.0
    assert all(math.isnan(v) for v in c.anticipatory_grasp(flexion_closing(15, 6, 0.3),
                                                             touches(20, segments=(4,))))


def swipe_trial(vz: float, normal_z: float, below: bool, rows=(20,)):
    """The hand rising at ``vz`` m/s toward a ball 10 cm above (or below) it, palm normal with
    vertical component ``normal_z``, touching at ``rows``."""
    t = np.arange(T)
    hand = np.column_stack([np.zeros(T), np.zeros(T), vz * 0.1 * t])
    ball = hand + [0.0, 0.0, 0.05 if below else -0.05]  # where the hand touches it
    side = math.sqrt(max(1 - normal_z ** 2, 0))
    normal = np.tile([side, 0.0, normal_z], (T, 1))
    return hand, ball, normal, touches(*rows, segments=(3,))


def test_a_palm_up_upward_touch_from_below_is_a_swipe():
    first, count = c.upward_swipes(*swipe_trial(0.3, 0.9, True))
    assert first == 1.0 and count == 1
    first, count = c.upward_swipes(*swipe_trial(0.3, 0.9, True, rows=(20, 21, 30)))
    assert first == 1.0 and count == 2  # two touch onsets, both swipes


@pytest.mark.parametrize("vz, normal_z, below", [
    (-0.3, 0.9, True),  # moving down
    (0.01, 0.9, True),  # rising too slowly
    (0.3, -0.9, True),  # palm down
    (0.3, 0.5, True),  # palm tilted 60 deg from up
    (0.3, 0.9, False),  # hand above the ball
])
def test_other_touches_are_no_swipes(vz, normal_z, below):
    first, count = c.upward_swipes(*swipe_trial(vz, normal_z, below))
    assert first == 0.0 and count == 0


def test_swipe_is_undefined_without_a_touch_or_a_palm_normal():
    hand, ball, normal, _ = swipe_trial(0.3, 0.9, True)
    first, count = c.upward_swipes(hand, ball, normal, touches())
    assert math.isnan(first) and count == 0
    assert all(math.isnan(v) for v in c.upward_swipes(hand, ball, None, touches(20)))
