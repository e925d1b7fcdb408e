"""Names of the skeleton's joints, bodies and frames (``skeletons/icub_upper_body.urdf``).

Every other module refers to the robot through these names, resolved to indices once when the
world is built. Names follow the official iCub model (robotology/icub-models).
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np

from .ctrnn import MOTOR_NAMES

#: The 13 joints driven one motor each, in motor order (section III-B: head, torso, right arm).
ARM_HEAD_TORSO_JOINTS = MOTOR_NAMES[:13]
FINGERS = ("thumb", "index", "middle", "ring", "little")
#: The 15 finger flexion joints that all follow the single hand motor (motor 13).
FINGER_JOINTS = tuple(f"r_hand_{f}_{k}_joint" for f in FINGERS for k in (1, 2, 3))
#: Hand segments, in the order of the per-segment contact arrays: the palm, then the three
#: phalanges of each finger (proximal to distal).
HAND_SEGMENTS = ("r_hand",) + tuple(f"r_hand_{f}_{k}" for f in FINGERS for k in (1, 2, 3))
#: Bodies that carry the six touch sensors of Fig. 4 (palm and the five fingertips).
TOUCH_BODIES = ("r_hand",) + tuple(f"r_hand_{f}_3" for f in FINGERS)
CAMERA = "head_camera"
HAND = "r_hand"
#: The shoulder body whose origin (the shoulder pitch axis) is used for hand–shoulder distances.
SHOULDER = "r_shoulder_1"
NECK = "neck_1"
#: Centre of the inner face of the palm in the ``r_hand`` frame (m). The fingers close toward
#: -y of that frame; the palm box is 2 cm thick and centred at y = +0.006 m.
PALM_POINT = np.array([-0.041, -0.004, 0.018])

#: Posture at the start of every trial (rad), the iCub's usual "home" for the arm (shoulder
#: pitch -30 deg, roll 30 deg, elbow 45 deg), trunk and head straight, fingers open.
HOME_POSTURE = {
    "r_shoulder_pitch": -0.5236,
    "r_shoulder_roll": 0.5236,
    "r_elbow": 0.7854,
}


def default_skeleton() -> Path:
    """Path of the skeleton shipped with the package."""
    return Path(str(resources.files("dart_reach.skeletons") / "icub_upper_body.urdf"))
