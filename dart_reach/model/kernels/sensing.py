"""The sensors (section III-B, Eqs. 1-4) and the fitness terms (section III-C, Eq. 5),
compiled: one control step's 25 sensor values, the 14 motor-space angles and p_sight, p_touch,
p_multimodal, from the joint positions, the ball's centre and the hand segments' inner-face
touches; and a trial's record row of the same step.

The sensor vector is written through ``ctrnn``'s named layout only, never a literal index:
``PROPRIO`` (14 proprioceptors, in motor order, each joint angle scaled from its limits to
[-1, 1]), ``TOUCH`` (6 touch sensors, ``sensors.TOUCHING`` or ``NO_TOUCH``), ``SIGHT``
(``SIGHT_X``, ``SIGHT_Y``: the ball's image coordinates under the acuity, Eqs. 1-2;
``SIGHT_DISTANCE``: Eq. 3) and ``OFFSET`` (``OFFSET_X``, ``OFFSET_Y``: the hand-ball offset,
Eq. 4). The constants are ``model.sensors``' (the field of view, the values of "nothing
sensed", the distance sensor's range, the offset's clamp and scale). Units: joint angles in
rad, lengths in m, visual angles in degrees; camera points in the head camera's frame (+z the
optical axis, +x right, +y down)."""

from __future__ import annotations

import math

from numba import njit

from .. import sensors
from ..ctrnn import OFFSET_X, OFFSET_Y, PROPRIO, SIGHT_DISTANCE, SIGHT_X, SIGHT_Y, TOUCH
from ..levers import TOUCH_CAP, TouchPay
from .floats import clip
from .kinematics import body_poses

#: ``TouchPay`` as the small integers the sensing kernel takes.
PAY_CODES = {TouchPay.FACES: 0, TouchPay.BINARY: 1, TouchPay.CAPPED: 2}
_TAN_X = math.tan(math.radians(sensors.HALF_FOV_X_DEG))
_TAN_Y = math.tan(math.radians(sensors.HALF_FOV_Y_DEG))
_SQRT2 = math.sqrt(2.0)
_DEGREES = 180.0 / math.pi
_NO_TOUCH, _TOUCHING, _NO_SIGHT = sensors.NO_TOUCH, sensors.TOUCHING, sensors.NO_SIGHT
_SIGHT_RANGE, _OFFSET_D_MAX, _OFFSET_SCALE = (sensors.SIGHT_RANGE_M, sensors.OFFSET_D_MAX_DEG,
                                              sensors.OFFSET_SCALE)
#: The first index of the sensor vector's proprioceptors and touch sensors (``ctrnn.PROPRIO``,
#: ``ctrnn.TOUCH``), as the integers compiled code indexes with.
_PROPRIO0, _TOUCH0 = PROPRIO.start, TOUCH.start


@njit(cache=True)
def _in_camera(p, cam, out):
    """``out`` = R^T (p - o): the point ``p`` (m, world frame) in the frame of the 4x4 camera
    pose ``cam`` (rotation R, origin o, m)."""
    d0, d1, d2 = p[0] - cam[0, 3], p[1] - cam[1, 3], p[2] - cam[2, 3]
    for i in range(3):
        out[i] = d0 * cam[0, i] + d1 * cam[1, i] + d2 * cam[2, i]


@njit(cache=True)
def project(x, y, z):
    """Normalised image coordinates (c_x, c_y, in view) of a point (x, y, z) (m) in the head
    camera's frame (+z the optical axis, +x right, +y down; section III-B): c_x = (x / z) /
    tan(56 deg) (+ right), c_y = -(y / z) / tan(47 deg) (+ up), in view when z > 0 and both
    lie in [-1, 1]; (0.0, 0.0, False) on or behind the image plane."""
    if not z > 0.0:
        return 0.0, 0.0, False
    cx = (x / z) / _TAN_X
    cy = -(y / z) / _TAN_Y
    return cx, cy, abs(cx) <= 1.0 and abs(cy) <= 1.0


@njit(cache=True)
def touch_pay(n, n_segments, pay):
    """p_touch (section III-C, Eq. 5) of ``n`` of ``n_segments`` hand segments touching the
    ball on their inner face, in [0, 1], under the ``levers.TouchPay`` of code ``pay``
    (``PAY_CODES``): n / N (faces), 1 if any (binary), min(n, TOUCH_CAP) / TOUCH_CAP
    (capped)."""
    if pay == 0:
        return n / n_segments
    if pay == 1:
        return 1.0 if n > 0 else 0.0
    return min(n, TOUCH_CAP) / TOUCH_CAP


@njit(cache=True)
def _power(c, a):
    """sgn(c) |c|^a of Eqs. 1-2 (the acuity a, section III-B): a product for a = 1 and
    a = 3, the C library's pow else."""
    m = abs(c)
    if a == 3.0:
        m = m * m * m
    elif a != 1.0:
        m = m ** a
    return m if c >= 0.0 else -m


@njit(cache=True)
def _sense(positions, ball, cam, hand, touching, motor_dofs, finger_dofs, lower, span,
           touch_segments, acuity, no_touch, no_sight, offsets, pay, palm, q, x, p, scratch):
    """The sensor vector ``x`` (25), the motor-space angles ``q`` (14) and the fitness terms
    ``p`` = (p_sight, p_touch, p_multimodal) (Eq. 5) of one step, from the skeleton's joint
    positions, the ball's centre, the camera's and (with ``offsets``) the hand's 4x4 poses and
    the 16 hand segments' inner-face touches; as ``task.Trial.sense`` (sections III-B, III-C).
    Returns whether the joint positions and the ball are finite."""
    finite = True
    for i in range(positions.shape[0]):
        finite = finite and math.isfinite(positions[i])
    for i in range(3):
        finite = finite and math.isfinite(ball[i])
    n_motor = motor_dofs.shape[0]
    for i in range(n_motor):
        q[i] = positions[motor_dofs[i]]
    s = 0.0
    for i in range(finger_dofs.shape[0]):
        s += positions[finger_dofs[i]]
    q[n_motor] = s / finger_dofs.shape[0]
    for i in range(n_motor + 1):  # proprioception
        x[_PROPRIO0 + i] = clip((q[i] - lower[i]) / span[i] * 2.0 - 1.0, -1.0, 1.0)
    n_touch = touch_segments.shape[0]
    for i in range(n_touch):
        x[_TOUCH0 + i] = _NO_TOUCH if no_touch or not touching[touch_segments[i]] else _TOUCHING
    ball_cam = scratch[0:3]
    _in_camera(ball, cam, ball_cam)
    cx, cy, visible = project(ball_cam[0], ball_cam[1], ball_cam[2])
    if no_sight or not visible:
        x[SIGHT_X] = x[SIGHT_Y] = x[SIGHT_DISTANCE] = _NO_SIGHT
    else:
        x[SIGHT_X] = _power(cx, acuity)
        x[SIGHT_Y] = _power(cy, acuity)
        distance = math.sqrt(ball_cam[0] * ball_cam[0] + ball_cam[1] * ball_cam[1]
                             + ball_cam[2] * ball_cam[2])
        x[SIGHT_DISTANCE] = 1.0 - 2.0 * distance if distance < _SIGHT_RANGE else 0.0
    x[OFFSET_X] = x[OFFSET_Y] = _NO_SIGHT
    if offsets and not no_sight and visible:
        palm_world, hand_cam = scratch[3:6], scratch[6:9]
        for i in range(3):
            palm_world[i] = (hand[i, 0] * palm[0] + hand[i, 1] * palm[1] + hand[i, 2] * palm[2]
                             ) + hand[i, 3]
        _in_camera(palm_world, cam, hand_cam)
        if project(hand_cam[0], hand_cam[1], hand_cam[2])[2]:
            d = (math.atan2(ball_cam[0], ball_cam[2]) * _DEGREES
                 - math.atan2(hand_cam[0], hand_cam[2]) * _DEGREES)
            x[OFFSET_X] = _OFFSET_SCALE * min(max(d, -_OFFSET_D_MAX), _OFFSET_D_MAX)
            d = (math.atan2(-ball_cam[1], ball_cam[2]) * _DEGREES
                 - math.atan2(-hand_cam[1], hand_cam[2]) * _DEGREES)
            x[OFFSET_Y] = _OFFSET_SCALE * min(max(d, -_OFFSET_D_MAX), _OFFSET_D_MAX)
    p_sight = 0.0
    if visible:
        p_sight = max(0.0, 1.0 - math.sqrt(cx * cx + cy * cy) / _SQRT2)
    n = 0
    for i in range(touching.shape[0]):
        n += 1 if touching[i] else 0
    p_touch = touch_pay(n, touching.shape[0], pay)
    p[0], p[1], p[2] = p_sight, p_touch, min(p_sight, p_touch)
    return finite


@njit(cache=True)
def sense_posed(positions, ball, touching, order, parent, dof, axis, before, after, scratch,
                poses, camera_body, hand_body, motor_dofs, finger_dofs, lower, span,
                touch_segments, acuity, no_touch, no_sight, offsets, pay, palm, q, x, p,
                sense_scratch):
    """``_sense`` with the camera's and the hand's poses from the joint positions
    (``body_poses`` of the bodies of ``order`` into ``poses``)."""
    body_poses(positions, order, parent, dof, axis, before, after, scratch, poses)
    return _sense(positions, ball, poses[camera_body], poses[hand_body], touching, motor_dofs,
                  finger_dofs, lower, span, touch_segments, acuity, no_touch, no_sight, offsets,
                  pay, palm, q, x, p, sense_scratch)


@njit(cache=True)
def record_row(t, positions, q, ball, touch, touch_any, x, p, poses, hand_body, shoulder_body,
                palm, palm_normal, dofs, joints, hand, shoulder, ball_rec, contacts,
                contacts_any, normal, sensors_rec, p_sight, p_touch, p_multimodal):
    """Row ``t`` of a trial's record (``task.Trial.observe``) from what ``sense_posed`` read
    and computed: the hand's palm point (m, ``palm`` in the hand's frame), its inner normal
    (``palm_normal`` in the hand's frame: the swipes of section IV-A-2) and the shoulder (m)
    from the bodies' poses."""
    dofs[t, :] = positions
    joints[t, :] = q
    h = poses[hand_body]
    for i in range(3):
        hand[t, i] = (h[i, 0] * palm[0] + h[i, 1] * palm[1] + h[i, 2] * palm[2]) + h[i, 3]
        normal[t, i] = h[i, 0] * palm_normal[0] + h[i, 1] * palm_normal[1] \
            + h[i, 2] * palm_normal[2]
        shoulder[t, i] = poses[shoulder_body, i, 3]
        ball_rec[t, i] = ball[i]
    contacts[t, :] = touch
    contacts_any[t, :] = touch_any
    sensors_rec[t, :] = x
    p_sight[t], p_touch[t], p_multimodal[t] = p[0], p[1], p[2]

