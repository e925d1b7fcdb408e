"""Model version 1's servo (section III-B; the touch of III-B, III-C), frozen: the motors
driven toward 14 targets by the springs' rest positions and the physics substeps of one
control period, the hand's touches gathered on Python floats (``inner_face_touch``), as the
world did it itself when version 1 was trained (``World.set_targets``, ``advance``, the
touch gathering and ``world.inner_face_touch``, moved here unchanged).

Never edited (``model.reference``): a change to the model is a new model version
(docs/model/trial.md, "How to change the model").
"""

from __future__ import annotations

import math

import numpy as np

from ..ctrnn import N_MOTORS
from ..sensors import clip
from ..world import World


class ReferenceServo:
    """Version 1's servo over a ``World`` (read through its ``layout``; the touches into its
    records ``World.touched``, ``touched_any``): ``reset`` the motors' commanded positions at
    a trial's start (after ``World.reset``), ``set_targets`` (the springs' rest positions
    moved toward the targets at most at the speed cap, gravity compensation), ``advance``
    (the physics substeps, the touches gathered)."""

    def __init__(self, world: World):
        layout = world.layout
        self.robot, self.world, self.config = world.robot, world.world, world.config
        self.ball_body = world.ball_body
        self.touched, self.touched_any = world.touched, world.touched_any
        self._home_motor, self._home_targets = world.home_motor, world.home_targets
        self._segment_index = layout.segment_index
        self._touch_faces, self._ball_shapes = layout.touch_faces, layout.ball_shapes
        # Per motor, as Python floats for ``set_targets``.
        self._half_range, self._mid_range = layout.half_range.tolist(), layout.mid_range.tolist()
        self._lower_list = layout.motor_lower.tolist()
        self._upper_list = layout.motor_upper.tolist()
        dofs = [self.robot.getDof(i) for i in range(layout.n_dofs)]
        self._dof_motor_pairs = list(zip(dofs, layout.dof_motor.tolist()))
        self._q_cmd = [0.0] * N_MOTORS  # the springs' rest positions per motor (rad)
        self._max_move = layout.max_move
        self._substeps = self.config.substeps

    def reset(self) -> None:
        """The motors' commanded positions at a trial's start, after ``World.reset``: the
        home posture's, moved toward the targets that hold it."""
        self._q_cmd[:] = self._home_motor.tolist()
        self.set_targets(self._home_targets)

    def set_targets(self, targets) -> None:
        """Scale 14 targets in [-1, 1] into the joint limits and move the springs' rest
        positions toward them, by at most ``max_joint_speed * control_dt`` per motor; refresh
        the gravity compensation. Values outside [-1, 1] are clipped. Computed on Python
        floats: the same IEEE operations in the same order as on numpy arrays, for a third
        of the cost on 14 values."""
        t = targets if type(targets) is np.ndarray else np.asarray(targets, dtype=float)
        if t.shape != (N_MOTORS,):
            raise ValueError(f"expected {N_MOTORS} motor targets, got shape {t.shape}")
        q_des = [clip(v * h + m, lo, hi) for v, h, m, lo, hi in
                 zip(t.tolist(), self._half_range, self._mid_range, self._lower_list,
                     self._upper_list)]
        if not math.isfinite(sum(q_des)):
            raise ValueError(f"motor targets must be finite, got {t}")
        move = self._max_move
        q_cmd = self._q_cmd
        for i, q in enumerate(q_des):
            q_cmd[i] += clip(q - q_cmd[i], -move, move)
        for dof, motor in self._dof_motor_pairs:
            dof.setRestPosition(q_cmd[motor])
        self.robot.setCommands(self.robot.getGravityForces())

    def advance(self) -> None:
        """The physics substeps of one control step toward the targets set. The touches of
        every substep are gathered: on the inner faces (``hand_contacts``) and on any face
        (``hand_contacts_any``)."""
        touch = self.touched
        touch[:] = False
        self.touched_any[:] = False
        step, last_collisions = self.world.step, self.world.getLastCollisionResult
        self_collision = self.config.self_collision
        for _ in range(self._substeps):
            step(False)
            result = last_collisions()
            if not result.getNumContacts():
                continue
            if self_collision:
                self._gather_ball_touch(result)
            else:
                # Only the ball collides with the robot (self-collision is off), so a hand
                # segment among the colliding bodies touches the ball on some face. List the
                # contacts (costly) only when a segment not yet marked as touching on its inner
                # face collides.
                if self.mark_colliding_segments(result):
                    self._gather_touch(result, touch)

    def mark_colliding_segments(self, result) -> bool:
        """With self-collision off (only the ball collides with the robot): mark the hand
        segments among a substep's colliding bodies as touching on some face
        (``hand_contacts_any``); whether one of them is not yet marked as touching on its
        inner face, so that the contacts must be read."""
        touch, touch_any, segment = self.touched, self.touched_any, self._segment_index
        pending = False
        for body in result.getCollidingBodyNodes():
            i = segment.get(body)
            if i is not None:
                touch_any[i] = True
                pending = pending or not touch[i]
        return pending

    def _gather_ball_touch(self, result) -> None:
        """With self-collision on: mark the hand segments in one substep's contacts with the
        ball (any face, and inner face as ``_gather_touch``), ignoring the robot's contacts
        with itself."""
        faces, ball_shapes = self._touch_faces, self._ball_shapes
        touch, touch_any = self.touched, self.touched_any
        ball = None
        for contact in result.getContacts():
            frame1 = contact.collisionObject1.getShapeFrame()
            frame2 = contact.collisionObject2.getShapeFrame()
            frame = frame2 if frame1 in ball_shapes else frame1 if frame2 in ball_shapes else None
            face = None if frame is None else faces.get(frame)
            if face is None:  # not with the ball, or not a hand segment
                continue
            touch_any[face[0]] = True
            if touch[face[0]]:
                continue
            if ball is None:
                ball = self.ball_body.getCOM()
            if inner_face_touch(frame.getTransform().rotation(), ball - contact.point, face):
                touch[face[0]] = True

    def _gather_touch(self, result, touch: np.ndarray) -> None:
        """Mark the hand segments that touch the ball on their inner face in one substep's
        contacts: the direction from the contact point to the ball's centre (the outward
        normal of the segment's surface there), in the segment's shape frame, must lie within
        the face's cone (``inner_face_touch``)."""
        ball = None
        faces = self._touch_faces
        for contact in result.getContacts():
            frame = contact.collisionObject1.getShapeFrame()
            face = faces.get(frame)
            if face is None:  # the robot's shape is the other one of the pair
                frame = contact.collisionObject2.getShapeFrame()
                face = faces.get(frame)
            if face is None or touch[face[0]]:  # not a hand segment, or already touched
                continue
            if ball is None:
                ball = self.ball_body.getCOM()  # its centre: the body's origin, 10x cheaper
            # ``Frame.getTransform()`` of the world frame is ``getWorldTransform()``, cheaper
            if inner_face_touch(frame.getTransform().rotation(), ball - contact.point, face):
                touch[face[0]] = True


#: Relative margin of ``inner_face_touch``'s Python-float decision; a case nearer the cone's
#: edge than this is decided again with numpy's operations (rounding differs by ~1e-15).
TOUCH_DECISION_MARGIN = 1e-9


def inner_face_touch(rotation: np.ndarray, to_ball: np.ndarray, face: tuple) -> bool:
    """Whether a contact touches a segment on its inner face (III-B, III-C): ``to_ball``, the
    world vector from the contact point to the ball's centre, turned into the shape's frame
    (``rotation``: the shape frame's world rotation) as o = R^T v, lies within the face's
    cone: o . inner >= cos(half angle) |o|; ``face`` = (segment, inner, cos_limit, inner as
    a tuple of floats).

    The decision is numpy's (``R.T @ v``, then ``@`` products) to the last bit: it is first
    taken on Python floats (a fifth of the cost) and, where that falls within
    ``TOUCH_DECISION_MARGIN`` of the cone's edge, where the two roundings could disagree,
    taken again with numpy's operations."""
    _, inner, cos_limit, (n0, n1, n2) = face
    (r0, r1, r2), (v0, v1, v2) = rotation.tolist(), to_ball.tolist()
    o = [r0[i] * v0 + r1[i] * v1 + r2[i] * v2 for i in range(3)]
    along = o[0] * n0 + o[1] * n1 + o[2] * n2
    edge = cos_limit * math.sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2])
    if abs(along - edge) > TOUCH_DECISION_MARGIN * (abs(v0) + abs(v1) + abs(v2)):
        return along >= edge
    outward = rotation.T @ to_ball
    return bool(outward @ inner >= cos_limit * math.sqrt(outward @ outward))
