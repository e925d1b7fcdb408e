"""Model version 1's steps of a trial (sections III-B, III-C), frozen: the sensors of
``reference.sensors`` on numpy arrays and Python floats, the network's own ``step``
(``reference.network.ReferenceNetwork``), the servo's ``set_targets`` and ``advance``
(``reference.servo.ReferenceServo``), behind the interface of ``steps.TrialSteps``; the palm's
normal of its records (``palm_normal``).

Never edited (``model.reference``): a change to the model is a new model version
(docs/model/trial.md, "How to change the model").
"""

from __future__ import annotations

import math

import numpy as np

from ..ctrnn import N_MOTORS, N_SENSORS, OFFSET, PROPRIO, SIGHT, TOUCH, Network, motor_targets
from ..icub import HAND_SEGMENTS
from ..steps import home_motor
from ..world import BALL_PARKED, PALM_NORMAL, World, palm_point
from . import sensors
from .servo import ReferenceServo

N_SEGMENTS = len(HAND_SEGMENTS)


def palm_normal(hand_pose: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """Unit world direction the palm's inner face looks toward (+z = palm up) for a 4x4
    world pose of the hand (``World.hand_transform``): the records' palm normal (the swipes
    of IV-A-2)."""
    return np.matmul(hand_pose[:3, :3], PALM_NORMAL, out=out)


class ReferenceSteps:
    """Model version 1's steps (``versions.Numerics.REFERENCE``): the sensors of ``sensors``
    on numpy arrays and Python floats, the network's own ``step`` (``ReferenceNetwork``), the
    servo's ``set_targets`` and ``advance`` (``ReferenceServo``). Every run trained under
    version 1 reproduces with them bit for bit (tests/model/test_task.py). ``config`` is the
    trial's ``task.TrialConfig``.
    """

    def __init__(self, world: World, config):
        self.world, self.config = world, config
        layout = world.layout
        self.x = x = np.zeros(N_SENSORS)
        # views of the sensor vector's layers (a slice costs as much as a small operation)
        self._x_proprio, self._x_touch = x[PROPRIO], x[TOUCH]
        self._x_sight, self._x_offset = x[SIGHT], x[OFFSET]
        self.q = np.zeros(N_MOTORS)  # the 14 motor-space angles (rad) read last
        self.contacts = np.zeros(N_SEGMENTS, bool)  # the inner-face touches read last
        self.ball_at = np.zeros(3)  # where the ball hangs (or would hang) in this trial
        self.targets = np.zeros(N_MOTORS)
        self.home_motor = home_motor(world, config)
        self._proprio_lower = layout.motor_limit_lower.tolist()
        self._proprio_span = layout.motor_limit_span.tolist()
        self._touch_segments = layout.touch_segments.tolist()
        self._pay_touch = sensors.p_touch_of(config.touch_pay)  # levers.TouchPay
        #: version 1's servo over the world
        self.servo = servo = ReferenceServo(world)
        #: the world's motors commanded toward 14 targets in [-1, 1], no physics yet
        self.command = servo.set_targets
        #: the physics substeps of one control period, the touches gathered
        self.advance = servo.advance
        self._no_touch, self._no_sight = config.touch_deprived, config.sight_deprived
        self._offsets = config.offsets_sensed
        self._no_ball = config.ball_absent
        # What ``sense`` read last: the skeleton's positions, the ball's centre, the hand's
        # pose (None when the step did not need it) and the fitness terms of the step.
        self.positions = self.ball = self._hand_pose = None
        self.p_sight = self.p_touch = self.p_multimodal = 0.0

    def reset(self, ball_position) -> None:
        self.ball_at[:] = ball_position
        self.world.reset(BALL_PARKED if self._no_ball else ball_position)
        self.servo.reset()

    def sense(self) -> bool:
        """Read the world into the sensor vector (the network's input) and the fitness terms
        of this step (Eq. 5); False when the state read is not finite (the simulation has
        exploded). Reads the hand's pose only when the offset sensors need it."""
        w = self.world
        positions = self.positions = w.joint_positions()
        q = w.motor_positions(self.q, positions)
        contacts = w.hand_contacts(self.contacts)
        ball = self.ball = w.ball_position()
        cam = w.camera_pose()
        R, origin = cam[:3, :3], cam[:3, 3]
        ball_cam = (ball - origin) @ R  # R^T (p - o)
        sensors.proprioception(q, self._proprio_lower, w.motor_limit_upper, out=self._x_proprio,
                               span=self._proprio_span)
        touching = contacts.tolist()
        if self._no_touch:
            self._x_touch[:] = sensors.NO_TOUCH
        else:
            sensors.touch([touching[i] for i in self._touch_segments], out=self._x_touch)
        cx, cy, ball_visible = sensors.project(ball_cam)
        if self._no_sight:
            self._x_sight[:] = sensors.NO_SIGHT
        else:
            sensors.sight(cx, cy, math.sqrt(ball_cam.dot(ball_cam)), ball_visible,
                          self.config.acuity, out=self._x_sight)
        if self._offsets:
            hand_pose = self._hand_pose = w.hand_transform()
            hand_cam = (palm_point(hand_pose) - origin) @ R
            hand_visible = sensors.project(hand_cam)[2]
            sensors.offset(sensors.visual_angles(ball_cam), sensors.visual_angles(hand_cam),
                           ball_visible and hand_visible, out=self._x_offset)
        else:
            self._hand_pose = None
            self._x_offset[:] = sensors.NO_SIGHT
        # The fitness is about the world, whatever the robot is deprived of (Eq. 5).
        p_s = self.p_sight = sensors.p_sight(cx, cy, ball_visible)
        p_t = self.p_touch = self._pay_touch(sum(touching), N_SEGMENTS)
        self.p_multimodal = sensors.p_multimodal(p_s, p_t)
        return math.isfinite(positions.sum() + ball.sum())

    def observe(self, data, t: int) -> bool:
        """``sense``, and the world and the sensors into the record's (``task.TrialData``)
        row t; False when the state read is not finite."""
        finite = self.sense()
        w = self.world
        hand_pose = w.hand_transform() if self._hand_pose is None else self._hand_pose
        data.joints[t] = self.q
        data.dofs[t] = self.positions
        data.hand[t] = palm_point(hand_pose)
        data.shoulder[t] = w.shoulder_position()
        data.ball[t] = self.ball_at if self._no_ball else self.ball
        data.contacts[t] = self.contacts
        w.hand_contacts_any(data.contacts_any[t])
        palm_normal(hand_pose, out=data.palm_normal[t])
        data.sensors[t] = self.x
        data.p_sight[t] = self.p_sight
        data.p_touch[t] = self.p_touch
        data.p_multimodal[t] = self.p_multimodal
        return finite

    def act(self, network: Network) -> bool:
        """The network's update from the sensors read last and its motor targets
        (``targets``); whether they are finite."""
        return self.targets_of(network.step(self.x))

    def targets_of(self, motor: np.ndarray) -> bool:
        """The motor targets (``targets``) of the network's motor states (``ctrnn.
        motor_targets``); whether they are finite (they lie in [-1, 1] when they are)."""
        motor_targets(motor, out=self.targets)
        return math.isfinite(self.targets.sum())

    def fitness(self, network: Network, p: np.ndarray) -> None:
        """None: version 1's fitness is the trial's own loop over these steps."""
        return None
