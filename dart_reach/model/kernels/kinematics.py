"""The robot's forward kinematics, compiled: the world poses of the skeleton's bodies from
its joint positions, as DART composes them, over the world's kinematic tree
(``layout.KinematicTree``). The sensing reads the head camera's and the hand's poses from it
(section III-B: the image, the offset, the records' palm point and normal), the inner-face
touch the hand segments' (sections III-B, III-C), so that a control step asks DART only for
the joint positions. Poses are 4x4 homogeneous transforms, translations in m, angles in
rad."""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True)
def body_poses(positions, order, parent, dof, axis, before, after, scratch, out):
    """World poses (4x4, m) of every body of a skeleton of revolute and weld joints from its
    joint positions (rad), as DART composes them: a body's pose is its parent's, times its
    joint's fixed transform from the parent (``before``), the rotation by the joint's angle
    about its ``axis`` (Rodrigues's formula; none where ``dof`` < 0, a weld) and the inverse
    of the joint's fixed transform from the body (``after``). Only the bodies of ``order``
    (indices, each after its parent; every body: ``arange``); ``scratch`` is (3, 4, 4)."""
    joint, local, tmp = scratch[0], scratch[1], scratch[2]
    for i in range(4):
        for k in range(4):
            joint[i, k] = 1.0 if i == k else 0.0
    for b in order:
        if dof[b] >= 0:
            q = positions[dof[b]]
            c, s = math.cos(q), math.sin(q)
            a0, a1, a2 = axis[b, 0], axis[b, 1], axis[b, 2]
            v = 1.0 - c
            joint[0, 0], joint[0, 1], joint[0, 2] = c + v * a0 * a0, v * a0 * a1 - s * a2, \
                v * a0 * a2 + s * a1
            joint[1, 0], joint[1, 1], joint[1, 2] = v * a1 * a0 + s * a2, c + v * a1 * a1, \
                v * a1 * a2 - s * a0
            joint[2, 0], joint[2, 1], joint[2, 2] = v * a2 * a0 - s * a1, v * a2 * a1 + s * a0, \
                c + v * a2 * a2
            _compose(before[b], joint, tmp)
            _compose(tmp, after[b], local)
        else:
            _compose(before[b], after[b], local)
        if parent[b] >= 0:
            _compose(out[parent[b]], local, out[b])
        else:
            out[b, :, :] = local


@njit(cache=True)
def _compose(a, b, out):
    """``out`` = a b for rigid 4x4 transforms (rotation products and a t_b + t_a)."""
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]
        out[i, 3] = (a[i, 0] * b[0, 3] + a[i, 1] * b[1, 3] + a[i, 2] * b[2, 3]) + a[i, 3]
    out[3, 0], out[3, 1], out[3, 2], out[3, 3] = 0.0, 0.0, 0.0, 1.0
