"""The inner-face touch of the living model (sections III-B, III-C), compiled: which of the 16
hand segments (the palm and the 15 phalanges, ``icub.HAND_SEGMENTS``) touch the ball on their
inner face, decided per contact DART reports in a physics substep; the touch sensors (section
III-B) and p_touch (Eq. 5) read the marks gathered over a control step's substeps.
``servo.Servo.advance``'s substeps call ``inner_touches`` (through ``servo.Servo.gather``)
after a substep whose contacts have a segment's inner face to decide, over one ``TouchState``
(``servo.Servo.touch_state``): the contacts' buffers, the kinematic tree (``layout.
KinematicTree``), the segments' bodies and inner faces (``layout.WorldLayout.face_direction``,
``face_cos_limit``: a unit direction in the body's frame and the cosine of the cone's half
angle) and the marks. Units: lengths in m, angles in rad."""

from __future__ import annotations

import math

from numba import njit
from numba.experimental import structref

from .kinematics import body_poses
from .structures import Structure, build


@structref.register
class _TouchStateType(Structure):
    pass


class TouchState(structref.StructRefProxy):
    """What ``inner_touches`` reads and writes besides the joint positions and the ball, in
    one object (built by ``touch_state``): the contacts' buffers, the skeleton's tree and
    poses, the segments' inner faces and the touches."""


_TOUCH_FIELDS = ("segments", "points", "need", "order", "parent", "dof", "axis", "before",
                 "after", "scratch", "poses", "segment_body", "direction", "cos_limit", "touch")
structref.define_proxy(TouchState, _TouchStateType, _TOUCH_FIELDS)


@njit(cache=True)
def _new_touch_state(*fields):
    return TouchState(*fields)


def touch_state(**fields) -> TouchState:
    """The ``TouchState`` of ``fields`` (by name, ``_TOUCH_FIELDS``)."""
    return build(_new_touch_state, _TOUCH_FIELDS, fields)


@njit(cache=True)
def inner_touches(positions, ball, n, s):
    """Mark in ``s.touch`` the hand segments whose contacts with the ball (the first ``n`` of
    ``s.segments``, ``s.points``: the segment's index, the contact point in m) touch it on
    their inner face: the vector from the contact point to the ball's centre, in the segment's
    body frame, lies within the face's cone (``s.direction`` in the body frame,
    ``s.cos_limit``), as version 1's ``reference.servo.inner_face_touch`` decides in the
    shape's frame (a rotation keeps the angle). Only the poses of those segments' bodies and
    their ancestors are computed (``s.need`` and ``s.order``: scratches of one bool and one
    index per body)."""
    need, order, parent, segment_body = s.need, s.order, s.parent, s.segment_body
    segments, points, touch = s.segments, s.points, s.touch
    need[:] = False
    for c in range(n):
        b = segment_body[segments[c]]
        while b >= 0 and not need[b]:
            need[b] = True
            b = parent[b]
    m = 0
    for b in range(need.shape[0]):  # parents first: a parent's index is below its child's
        if need[b]:
            order[m] = b
            m += 1
    body_poses(positions, order[:m], parent, s.dof, s.axis, s.before, s.after, s.scratch,
               s.poses)
    for c in range(n):
        i = segments[c]
        if touch[i]:
            continue
        rot = s.poses[segment_body[i]]
        v0, v1, v2 = ball[0] - points[c, 0], ball[1] - points[c, 1], ball[2] - points[c, 2]
        o0 = rot[0, 0] * v0 + rot[1, 0] * v1 + rot[2, 0] * v2
        o1 = rot[0, 1] * v0 + rot[1, 1] * v1 + rot[2, 1] * v2
        o2 = rot[0, 2] * v0 + rot[1, 2] * v1 + rot[2, 2] * v2
        along = o0 * s.direction[i, 0] + o1 * s.direction[i, 1] + o2 * s.direction[i, 2]
        if along >= s.cos_limit[i] * math.sqrt(o0 * o0 + o1 * o1 + o2 * o2):
            touch[i] = True
