"""The world's layout: which skeleton indices the model's quantities live at (section III-B).

``WorldLayout`` is the one public description of a built ``world.World`` that the trial's
step functions and the servo read, under either numerics (the living model's
``compiled_trial.CompiledSteps`` and ``servo.Servo``; version 1's ``reference.steps.
ReferenceSteps`` and ``reference.servo.ReferenceServo``): the degrees of freedom of the 14
motors, the motors' ranges and speed cap, the springs' stiffness, the bodies of the camera,
the hand, the shoulder and the 16 hand segments, the segments' inner faces
(``icub.INNER_FACES``), the kinematic tree the compiled numerics compute the bodies' poses
from, and which collision shapes and bodies are a hand segment or the ball. It is built once
by ``World`` from its skeleton and never changes: a frozen dataclass whose arrays are
read-only.

Units: angles in rad, lengths in m, stiffness in N m / rad, ``max_move`` in rad per control
step (``WorldConfig.max_joint_speed`` x ``control_dt``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import NamedTuple

import numpy as np

from . import icub

#: Indices in ``icub.HAND_SEGMENTS`` of the six touch-sensor bodies (palm, fingertips; Fig. 4).
TOUCH_SEGMENTS = np.array([icub.HAND_SEGMENTS.index(b) for b in icub.TOUCH_BODIES], np.int64)
TOUCH_SEGMENTS.flags.writeable = False


def _freeze(obj) -> None:
    """Make every array field of the dataclass ``obj`` read-only."""
    for f in fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, np.ndarray):
            value.flags.writeable = False


@dataclass(frozen=True, eq=False)
class KinematicTree:
    """The skeleton's bodies as a tree of revolute and weld joints, in DART's body order (a
    parent before its children), from which ``kernels.kinematics.body_poses`` composes the
    bodies' world poses: per body its ``parent`` (-1: the root), the degree of freedom of its joint
    (``dof``, -1: a weld), the joint's unit ``axis`` (in the joint frame), its fixed
    transform from the parent body (``before``, 4x4) and the inverse of its fixed transform
    from the child body (``after``, 4x4). ``unsupported`` names the joints of another kind
    (model version 2's numerics cannot compute a skeleton that has any)."""

    parent: np.ndarray  # (n,) int64
    dof: np.ndarray  # (n,) int64
    axis: np.ndarray  # (n, 3)
    before: np.ndarray  # (n, 4, 4)
    after: np.ndarray  # (n, 4, 4)
    unsupported: tuple[str, ...] = ()

    def __post_init__(self):
        _freeze(self)

    @property
    def arrays(self) -> tuple[np.ndarray, ...]:
        """(parent, dof, axis, before, after): the tree as ``kernels.kinematics.body_poses``
        takes it."""
        return self.parent, self.dof, self.axis, self.before, self.after

    def chain(self, *ends: int) -> np.ndarray:
        """The bodies from the root to each of ``ends`` (body indices), parents first."""
        found = set()
        for b in ends:
            while b >= 0 and b not in found:
                found.add(b)
                b = int(self.parent[b])
        chain = np.array(sorted(found), np.int64)  # a parent's index is below its child's
        chain.flags.writeable = False
        return chain


def kinematic_tree(robot) -> KinematicTree:
    """The ``KinematicTree`` of a DART skeleton ``robot``."""
    bodies = [robot.getBodyNode(i) for i in range(robot.getNumBodyNodes())]
    index = {b.getName(): i for i, b in enumerate(bodies)}
    n = len(bodies)
    parent, dof = np.full(n, -1, np.int64), np.full(n, -1, np.int64)
    axis, before, after = np.zeros((n, 3)), np.zeros((n, 4, 4)), np.zeros((n, 4, 4))
    unsupported = []
    for i, body in enumerate(bodies):
        up, joint = body.getParentBodyNode(), body.getParentJoint()
        parent[i] = -1 if up is None else index[up.getName()]
        kind = type(joint).__name__
        if kind == "RevoluteJoint":
            dof[i], axis[i] = joint.getIndexInSkeleton(0), joint.getAxis()
        elif kind != "WeldJoint":
            unsupported.append(f"joint {joint.getName()} is a {kind}")
        before[i] = joint.getTransformFromParentBodyNode().matrix()
        child = joint.getTransformFromChildBodyNode().matrix()
        after[i, :3, :3] = child[:3, :3].T
        after[i, :3, 3] = -child[:3, :3].T @ child[:3, 3]
        after[i, 3, 3] = 1.0
    if (parent >= np.arange(n)).any():
        unsupported.append("the skeleton lists a body before its parent")
    return KinematicTree(parent, dof, axis, before, after, tuple(unsupported))


class TouchFace(NamedTuple):
    """A hand segment's collision shape as touch sees it (sections III-B, III-C): the
    segment's index in ``icub.HAND_SEGMENTS``, the outward direction of its inner face in the
    shape's frame (a read-only unit vector), the cosine of the face's cone's half angle
    (``icub.INNER_FACES``) and the direction again as a tuple of floats."""

    segment: int
    inner: np.ndarray  # (3,)
    cos_limit: float
    inner_floats: tuple[float, float, float]


@dataclass(frozen=True, eq=False)
class WorldLayout:
    """Where the model's quantities live in a built world's skeleton (see the module
    docstring). Motor order is ``ctrnn.MOTOR_NAMES`` (the 13 joints, then the hand, whose
    commanded position every finger flexion joint takes)."""

    n_dofs: int
    #: (13,) int64, the skeleton degree of freedom of each joint motor
    motor_dofs: np.ndarray
    #: (15,) int64, the finger flexion degrees of freedom the hand motor drives
    finger_dofs: np.ndarray
    #: (n_dofs,) int64, the motor that drives each degree of freedom (13: the hand)
    dof_motor: np.ndarray
    #: (14,) rad, the joint limits per motor (what the proprioceptors span, Eq. of III-B)
    motor_limit_lower: np.ndarray
    motor_limit_span: np.ndarray
    #: (14,) rad, the motors' target ranges (the limits less ``world.LIMIT_MARGIN``), their
    #: half widths and middles: a target v in [-1, 1] means v * half_range + mid_range
    motor_lower: np.ndarray
    motor_upper: np.ndarray
    half_range: np.ndarray
    mid_range: np.ndarray
    #: rad per control step, the most a motor's commanded position moves (the speed cap)
    max_move: float
    #: (n_dofs,) N m / rad, each joint spring's stiffness
    stiffness: np.ndarray
    #: (6,) int64, ``TOUCH_SEGMENTS``: the touch sensors' segments (palm, fingertips)
    touch_segments: np.ndarray
    #: body indices of the head camera, the hand (``r_hand``) and the shoulder
    camera_body: int
    hand_body: int
    shoulder_body: int
    #: (16,) int64, the body of each hand segment (``icub.HAND_SEGMENTS``)
    segment_body: np.ndarray
    #: (16, 3) and (16,), each segment's inner face in its body's frame: the outward
    #: direction and the cosine of the cone's half angle
    face_direction: np.ndarray
    face_cos_limit: np.ndarray
    #: the bodies from the root to the camera and the hand, parents first
    sensed_bodies: np.ndarray
    tree: KinematicTree
    #: each hand segment's collision shape node -> its ``TouchFace``
    touch_faces: Mapping
    #: each hand segment's body node -> its index in ``icub.HAND_SEGMENTS`` (the segments
    #: among a substep's colliding bodies)
    segment_index: Mapping
    #: the ball's shape nodes
    ball_shapes: frozenset

    def __post_init__(self):
        _freeze(self)


def segment_faces(segments: tuple[str, ...] = icub.HAND_SEGMENTS
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The inner face of each of ``segments`` (body names) in its body's frame
    (``icub.INNER_FACES``): (directions (m, 3), cosines of the cones' half angles (m,))."""
    direction = np.array([icub.INNER_FACES[icub.segment_kind(name)][0] for name in segments])
    cos_limit = np.array([math.cos(math.radians(icub.INNER_FACES[icub.segment_kind(name)][1]))
                          for name in segments])
    return direction, cos_limit
