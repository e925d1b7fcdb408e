"""Unit quaternions of rotation matrices, as rerun takes them (the recordings' poses)."""

from __future__ import annotations

import numpy as np


def quaternions(R: np.ndarray) -> np.ndarray:
    """Unit quaternions (..., 4), xyzw as rerun takes them, of rotation matrices (..., 3, 3).

    Each component's magnitude comes from the diagonal and, relative to w, its sign from the
    off-diagonal differences. Near half-turns (w small) those differences vanish, and the
    signs are taken relative to the largest component instead."""
    R = np.asarray(R, float)
    m00, m11, m22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    q = np.empty(R.shape[:-2] + (4,))
    q[..., 0] = np.sqrt(np.maximum(0.0, 1 + m00 - m11 - m22))
    q[..., 1] = np.sqrt(np.maximum(0.0, 1 - m00 + m11 - m22))
    q[..., 2] = np.sqrt(np.maximum(0.0, 1 - m00 - m11 + m22))
    q[..., 3] = np.sqrt(np.maximum(0.0, 1 + m00 + m11 + m22))
    q *= 0.5
    diffs = (R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1])
    for i, d in enumerate(diffs):
        q[..., i] = np.copysign(q[..., i], d)
    small = q[..., 3] < 0.25
    if small.any():
        # sums: 4 x y = m01 + m10, 4 x z = m02 + m20, 4 y z = m12 + m21, 4 w x_i = diff_i
        Rs, qs = R[small], q[small]
        k = np.argmax(np.abs(qs[:, :3]), axis=1)
        rows = np.arange(len(k))
        big = np.abs(qs[rows, k])
        sums = {(0, 1): Rs[:, 0, 1] + Rs[:, 1, 0], (0, 2): Rs[:, 0, 2] + Rs[:, 2, 0],
                (1, 2): Rs[:, 1, 2] + Rs[:, 2, 1]}
        out = np.empty_like(qs)
        for j in range(3):
            other = np.select([k == i for i in range(3)],
                              [sums[tuple(sorted((i, j)))] if i != j else 4 * big ** 2
                               for i in range(3)])
            out[:, j] = other / (4 * big)
        out[:, 3] = np.select([k == i for i in range(3)],
                              [Rs[:, 2, 1] - Rs[:, 1, 2], Rs[:, 0, 2] - Rs[:, 2, 0],
                               Rs[:, 1, 0] - Rs[:, 0, 1]]) / (4 * big)
        q[small] = out
    return q
