"""Unit quaternions of rotation matrices, as rerun takes them (the recordings' poses)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit


def quaternions(R: np.ndarray) -> np.ndarray:
    """Unit quaternions (..., 4), xyzw as rerun takes them, of rotation matrices (..., 3, 3)
    (``quaternion_of``, one at a time, compiled)."""
    R = np.ascontiguousarray(R, dtype=float)
    out = np.empty(R.shape[:-2] + (4,))
    _quaternions(R.reshape(-1, 3, 3), out.reshape(-1, 4))
    return out


@njit(cache=True)
def _quaternions(R, out):
    for i in range(R.shape[0]):
        quaternion_of(R[i], out[i])


@njit(cache=True)
def quaternion_of(R, q):
    """Write into ``q`` (4,) the unit quaternion, xyzw, of the rotation matrix ``R`` (3, 3).

    Each component's magnitude comes from the diagonal and, relative to w, its sign from the
    off-diagonal differences. Near half-turns (w small) those differences vanish, and the
    components are taken relative to the largest of x, y, z instead."""
    m00, m11, m22 = R[0, 0], R[1, 1], R[2, 2]
    diffs = (R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1])
    q[0] = math.copysign(0.5 * math.sqrt(max(0.0, 1 + m00 - m11 - m22)), diffs[0])
    q[1] = math.copysign(0.5 * math.sqrt(max(0.0, 1 - m00 + m11 - m22)), diffs[1])
    q[2] = math.copysign(0.5 * math.sqrt(max(0.0, 1 - m00 - m11 + m22)), diffs[2])
    q[3] = 0.5 * math.sqrt(max(0.0, 1 + m00 + m11 + m22))
    if q[3] >= 0.25:
        return
    # 4 x y = m01 + m10, 4 x z = m02 + m20, 4 y z = m12 + m21, 4 w x_k = diff_k
    k = 0
    for j in (1, 2):
        if abs(q[j]) > abs(q[k]):
            k = j
    big = abs(q[k])
    for j in range(3):
        q[j] = 4 * big * big if j == k else R[k, j] + R[j, k]
        q[j] /= 4 * big
    q[3] = diffs[k] / (4 * big)
