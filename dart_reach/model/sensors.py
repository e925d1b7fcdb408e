"""What the controller's sensors read and what the fitness pays (paper sections III-B and
III-C): the constants both numerics compute with (the living model's ``model.kernels.
sensing``, model version 1's frozen ``model.reference.sensors``), and ``clip``.

Units: joint angles in radians, lengths in metres, visual angles in degrees. Camera points are
in the head camera frame (OpenCV convention): +z along the optical axis, +x to the right of the
image, +y down.

Values that mean "nothing sensed" (used for the sensory deprivations of Fig. 9, section IV-B):
``NO_TOUCH`` for the touch sensors, ``NO_SIGHT`` for the sight and offset sensors. The sight
encodings read ``NO_SIGHT`` when the ball (or, for the offset, the hand or the ball) is out of
view. This is ambiguous by construction: 0 on sight/x or sight/y also means "centred", 0 on
sight/distance also means "50 cm or farther", 0 on the offset also means "hand on the ball".
"""

from __future__ import annotations


#: Half field of view of the head camera (section III-B: 112 deg x 94 deg), degrees.
HALF_FOV_X_DEG = 56.0
HALF_FOV_Y_DEG = 47.0

#: Touch sensor value of a segment that touches nothing (section III-B: binary -1 / 1).
NO_TOUCH = -1.0
#: Touch sensor value of a segment in contact.
TOUCHING = 1.0
#: Sight and offset sensor value when nothing is seen (see the module docstring).
NO_SIGHT = 0.0

#: Distance (m) from which the distance sensor reads 0 (Eq. 3: "ball distance up to 50 cm").
SIGHT_RANGE_M = 0.5
#: Clamp of the hand-ball offset, degrees of visual angle (Eq. 4; the paper leaves it open:
#: chosen so that OFFSET_SCALE * OFFSET_D_MAX_DEG = 1 and the sensor spans [-1, 1]).
OFFSET_D_MAX_DEG = 10.0
#: Scale factor z of Eq. 4 (paper: 0.1), per degree.
OFFSET_SCALE = 0.1


def clip(v: float, lo: float, hi: float) -> float:
    """``np.clip`` of one float, to the last bit: NaN stays NaN, else min(max(v, lo), hi)."""
    if v != v:
        return v
    v = v if v > lo else lo
    return v if v < hi else hi
