"""Model version 1's sensor encodings and fitness terms (paper sections III-B and III-C),
frozen: Python floats and numpy arrays, the constants of ``model.sensors``.

Pure functions of the world's geometry: nothing here knows about DART. Every array-valued
encoding takes an optional ``out=`` buffer so the per-step loop allocates nothing; without it a
new array is returned. Scalar functions return Python floats. Units and the meaning of the
"nothing sensed" values: ``model.sensors``.

Never edited (``model.reference``): a change to the model is a new model version
(docs/model/trial.md, "How to change the model").
"""

from __future__ import annotations

import math

import numpy as np

from ..levers import TOUCH_CAP, TouchPay
from ..sensors import (HALF_FOV_X_DEG, HALF_FOV_Y_DEG, NO_SIGHT, NO_TOUCH, OFFSET_D_MAX_DEG,
                       OFFSET_SCALE, SIGHT_RANGE_M, TOUCHING, clip)

_TAN_HALF_FOV_X = math.tan(math.radians(HALF_FOV_X_DEG))
_TAN_HALF_FOV_Y = math.tan(math.radians(HALF_FOV_Y_DEG))


def _floats(a) -> list:
    """``a`` as a list of Python floats (a list is taken as it is)."""
    return a if type(a) is list else np.asarray(a, dtype=float).ravel().tolist()


def proprioception(q, lower, upper, out=None, *, span=None) -> np.ndarray:
    """Proprioceptors (section III-B): joint angles scaled linearly from [lower, upper] to
    [-1, 1], clipped to [-1, 1]: clip((q - lower) / (upper - lower) * 2 - 1).

    ``q``, ``lower``, ``upper``: joint angles and limits, rad (the hand: mean finger flexion and
    the flexion limits), arrays or lists of floats. ``span`` (optional) is ``upper - lower``
    precomputed. Returns ``out`` (a new array if None), dimensionless. Computed on Python
    floats (the same IEEE operations as numpy's, in the same order): for 14 joints that is a
    third of the cost of numpy's calls.
    """
    q = np.asarray(q, dtype=float)
    if out is None:
        out = np.empty(q.shape)
    lo = _floats(lower)
    span = [u - l for u, l in zip(_floats(upper), lo)] if span is None else _floats(span)
    values = [clip((v - l) / s * 2.0 - 1.0, -1.0, 1.0)
              for v, l, s in zip(q.ravel().tolist(), lo, span)]
    out[...] = values if q.ndim == 1 else np.reshape(values, q.shape)
    return out


def touch(contacts, out=None) -> np.ndarray:
    """Touch sensors (section III-B): +1.0 where ``contacts`` is True, -1.0 elsewhere.

    ``contacts``: booleans (palm, thumb, index, middle, ring, little fingertips). Returns
    ``out`` (a new float array if None).
    """
    flags = np.asarray(contacts, dtype=bool)
    if out is None:
        out = np.empty(flags.shape)
    values = [TOUCHING if c else NO_TOUCH for c in flags.ravel().tolist()]
    out[...] = values if flags.ndim == 1 else np.reshape(values, flags.shape)
    return out


def project(point_cam) -> tuple[float, float, bool]:
    """Normalised image coordinates of a point seen by the head camera (section III-B).

    ``point_cam``: (x, y, z) in metres in the camera frame (+z optical axis, +x right, +y down).
    Returns ``(c_x, c_y, in_view)`` with c_x = (x/z) / tan(56 deg) (+ = right of the image
    centre) and c_y = -(y/z) / tan(47 deg) (+ = above it), so the 112 deg x 94 deg field of view
    maps onto [-1, 1]^2; ``in_view`` is z > 0 and |c_x| <= 1 and |c_y| <= 1. A point on or behind
    the image plane (z <= 0) gives (0.0, 0.0, False): always read ``in_view`` before the
    coordinates. Points in front of the camera but outside the field of view keep their
    coordinates (|c| > 1).
    """
    x, y, z = float(point_cam[0]), float(point_cam[1]), float(point_cam[2])
    if not z > 0.0:
        return 0.0, 0.0, False
    cx = (x / z) / _TAN_HALF_FOV_X
    cy = -(y / z) / _TAN_HALF_FOV_Y
    return cx, cy, (abs(cx) <= 1.0 and abs(cy) <= 1.0)


def visual_angles(point_cam) -> tuple[float, float]:
    """Direction of a camera-frame point as visual angles, degrees (section III-B, Eq. 4).

    Returns ``(azimuth, elevation)`` = (atan2(x, z), atan2(-y, z)): + azimuth to the right of
    the optical axis, + elevation above it; both 0 on the axis, in [-180, 180].
    """
    x, y, z = float(point_cam[0]), float(point_cam[1]), float(point_cam[2])
    return math.degrees(math.atan2(x, z)), math.degrees(math.atan2(-y, z))


def sight(c_x: float, c_y: float, distance_m: float, in_view: bool, acuity_a: float,
          out=None) -> np.ndarray:
    """The three sight sensors (section III-B, Eqs. 1-3).

    x1 = sgn(c_x) |c_x|^a, x2 = sgn(c_y) |c_y|^a (``c_x``, ``c_y`` from ``project``, a =
    ``acuity_a``: 3 = low acuity, 1 = full acuity); x3 = 1 - 2 l if l < 0.5 else 0 with l =
    ``distance_m`` the camera-ball distance in metres. Out of view (``in_view`` False) all three
    read ``NO_SIGHT`` (0.0). Returns ``out`` of shape (3,) (a new array if None), each in [-1, 1]
    for in-view coordinates and l >= 0.
    """
    if out is None:
        out = np.empty(3)
    if not in_view:
        out[:] = NO_SIGHT
        return out
    out[0] = math.copysign(abs(c_x) ** acuity_a, c_x) if c_x != 0.0 else 0.0
    out[1] = math.copysign(abs(c_y) ** acuity_a, c_y) if c_y != 0.0 else 0.0
    out[2] = 1.0 - 2.0 * distance_m if distance_m < SIGHT_RANGE_M else 0.0
    return out


def offset(ball_angles_deg, hand_angles_deg, both_in_view: bool, d_max: float = OFFSET_D_MAX_DEG,
           z: float = OFFSET_SCALE, out=None) -> np.ndarray:
    """The two sight-offset sensors (section III-B, Eq. 4).

    d = ball - hand visual angle on each axis (``(azimuth, elevation)`` pairs in degrees from
    ``visual_angles``; + when the ball is right of / above the hand), clamped to
    [-``d_max``, ``d_max``] degrees and multiplied by ``z`` (per degree). With the defaults
    (d_max = 10 deg, z = 0.1) the sensors span [-1, 1]. Read ``NO_SIGHT`` (0.0) unless
    ``both_in_view`` (hand and ball in the field of view). Returns ``out`` of shape (2,).
    """
    if out is None:
        out = np.empty(2)
    if not both_in_view:
        out[:] = NO_SIGHT
        return out
    for i in range(2):
        d = float(ball_angles_deg[i]) - float(hand_angles_deg[i])
        out[i] = z * min(max(d, -d_max), d_max)
    return out


def p_sight(c_x: float, c_y: float, in_view: bool) -> float:
    """Fitness term p_sight (section III-C, Eq. 5): closeness of the ball's image to the
    centre of the visual field, in [0, 1].

    max(0, 1 - hypot(c_x, c_y) / sqrt(2)) in view (1 at the centre, 0 at the corners of the
    field of view), 0.0 out of view. Uses the raw coordinates, whatever the acuity.
    """
    if not in_view:
        return 0.0
    return max(0.0, 1.0 - math.hypot(c_x, c_y) / math.sqrt(2.0))


def p_touch(n_segments_touching: int, n_segments: int) -> float:
    """Fitness term p_touch (section III-C, Eq. 5): the fraction n / N of the inner hand and
    finger segments touching the ball, in [0, 1]."""
    if n_segments <= 0:
        raise ValueError(f"n_segments must be positive, got {n_segments}")
    if not 0 <= n_segments_touching <= n_segments:
        raise ValueError(f"n_segments_touching must be in [0, {n_segments}], "
                         f"got {n_segments_touching}")
    return n_segments_touching / n_segments


def p_touch_binary(n_segments_touching: int, n_segments: int) -> float:
    """p_touch under ``levers.TouchPay.BINARY``: 1.0 when any of the ``n_segments`` touches,
    else 0.0."""
    p_touch(n_segments_touching, n_segments)  # checks the counts
    return 1.0 if n_segments_touching > 0 else 0.0


def p_touch_capped(n_segments_touching: int, n_segments: int, cap: int) -> float:
    """p_touch under ``levers.TouchPay.CAPPED``: min(n, cap) / cap, in [0, 1]."""
    if not 1 <= cap <= n_segments:
        raise ValueError(f"cap must be in [1, {n_segments}], got {cap}")
    p_touch(n_segments_touching, n_segments)  # checks the counts
    return min(n_segments_touching, cap) / cap


def p_touch_of(pay: TouchPay):
    """The p_touch function (n touching, N segments) -> [0, 1] of a ``levers.TouchPay``."""
    return {TouchPay.FACES: p_touch, TouchPay.BINARY: p_touch_binary,
            TouchPay.CAPPED: lambda n, m: p_touch_capped(n, m, TOUCH_CAP)}[TouchPay(pay)]


def p_multimodal(p_sight: float, p_touch: float) -> float:  # noqa: F811 (names as in Eq. 5)
    """Performance of one step (section III-C, Eq. 5): min(p_sight, p_touch), in [0, 1]."""
    return min(p_sight, p_touch)
