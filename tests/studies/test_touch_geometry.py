"""Touch from the kinematics (``studies.touch_geometry``) against DART's contacts: a ball far
from the hand, against the palm's inner face and against its back, and a scripted grasp under
model version 3's world and numerics, where both decisions must find the same touching faces."""

from __future__ import annotations

import numpy as np
import pytest

from dart_reach.evolution.settings import Settings
from dart_reach.model import icub
from dart_reach.model.scripted import ScriptedController
from dart_reach.model.task import Trial, TrialConfig
from dart_reach.model.versions import Numerics
from dart_reach.model.world import PALM_NORMAL, World, palm_point
from dart_reach.studies.touch_geometry import Comparison, KinematicTouch

PALM = icub.HAND_SEGMENTS.index("r_hand")


@pytest.fixture(scope="module")
def world():
    return World(Settings(model_version=3).world)


def test_a_ball_far_from_the_hand_touches_nothing(world):
    touch = KinematicTouch(world)
    q = world.robot.getPositions()
    hand = world.hand_transform()
    assert touch.decide(q, palm_point(hand) + np.array([0.0, 0.0, 0.5])) == 0
    assert not touch.touch.any() and not touch.touch_any.any()


def test_the_palm_is_touched_on_its_inner_face_only_from_the_inner_side(world):
    touch = KinematicTouch(world)
    q = world.robot.getPositions()
    hand = world.hand_transform()
    normal = hand[:3, :3] @ PALM_NORMAL  # the palm's inner normal in the world
    # the palm point is on the inner face: a ball 1 mm into it from that side touches it there
    touch.decide(q, palm_point(hand) + (touch.radius - 0.001) * normal)
    assert touch.touch[PALM] and touch.touch_any[PALM]
    # 1 mm short of it: no touch
    touch.decide(q, palm_point(hand) + (touch.radius + 0.001) * normal)
    assert not touch.touch_any[PALM]
    # from the back of the palm (the box is 2 cm thick): a touch, not on the inner face
    back = palm_point(hand) - (0.02 + touch.radius - 0.001) * normal
    touch.decide(q, back)
    assert touch.touch_any[PALM] and not touch.touch[PALM]


def test_a_scripted_grasp_touches_the_same_faces_both_ways(world):
    trial = Trial(world, TrialConfig(steps=60, numerics=Numerics.COMPILED))
    comparison = Comparison(world)
    comparison.instrument(trial.steps)
    p = world.sector_point(4, 0.5, 0.5)
    data = trial.run(ScriptedController(world, p), 4, p)
    c = comparison.figures()
    # the grasp touched the ball, palm and fingers on their inner faces
    assert data.contacts[:, PALM].any() and data.contacts[:, 1:].any()
    assert c["substeps_in_contact"] > 20
    # on the state DART's collision detection saw, the same segments on any face at every
    # substep (DART's sphere-box test, computed again), and the same inner faces at every
    # control step of the trial
    assert c["substeps_either_any_pre"] == c["substeps_same_any_pre"] > 20
    assert c["control_steps_either_pre"] == c["control_steps_same_pre"] > 5
    assert c["control_steps_sensors_differ_pre"] == 0
    # DART's own contact points, judged in that state, give the kinematics' inner faces
    assert c["substeps_either_pre_points"] == c["substeps_same_pre_points"] > 20
    # both paths were timed at every substep in contact
    assert len(comparison.dart_ns) == len(comparison.post_ns) == c["substeps_in_contact"]
