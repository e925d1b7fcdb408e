"""Names of the skeleton's joints, bodies and frames (``skeletons/icub_upper_body.urdf``).

Every other module refers to the robot through these names, resolved to indices once when the
world is built. Names follow the official iCub model (robotology/icub-models).
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np

from .ctrnn import JOINT_MOTORS, MOTOR_NAMES

#: The 13 joints driven one motor each, in motor order (section III-B: head, torso, right arm).
ARM_HEAD_TORSO_JOINTS = MOTOR_NAMES[JOINT_MOTORS]
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

#: Inner (palmar) face of each kind of hand segment (sections III-B, III-C: touch sensors "in
#: the right hand palm and fingertips", p_touch counts "inner hand/fingers segments"): its
#: outward direction in the segment's body frame and the half-angle (deg) of the cone of
#: surface directions that count as that face. The palm's inner face is -y of ``r_hand`` (the
#: fingers close toward it); a phalanx flexes about its +z, so its pad faces +y. The thumb,
#: welded in a slight opposition, meets a held ball with its flexion side (+y) or its side
#: that faces the palm (+z): its cone is centred between the two and takes both faces.
INNER_FACES = {
    "palm": ((0.0, -1.0, 0.0), 45.0),
    "finger": ((0.0, 1.0, 0.0), 45.0),
    "thumb": ((0.0, 0.5 ** 0.5, 0.5 ** 0.5), 67.5),
}


def segment_kind(body: str) -> str:
    """The key of ``INNER_FACES`` for a hand segment's body name."""
    if body == HAND:
        return "palm"
    return "thumb" if body.startswith("r_hand_thumb") else "finger"


#: Rest posture at the start of every trial (rad; docs/model/world.md, III): the arm hangs at the
#: side, slightly abducted, the forearm a little forward (shoulder pitch 0, roll 20 deg, elbow
#: 34 deg), away from the ball (palm at least 10 cm from it in every sector); the trunk
#: straight; the head bent 32 deg down and turned 17 deg right, toward the sectors, so that the
#: ball is in the field of view wherever it starts; fingers open.
HOME_POSTURE = {
    "neck_pitch": -0.55,
    "neck_yaw": -0.30,
    "r_shoulder_pitch": 0.0,
    "r_shoulder_roll": 0.35,
    "r_elbow": 0.60,
}


def default_skeleton() -> Path:
    """Path of the skeleton shipped with the package."""
    return Path(str(resources.files("dart_reach.skeletons") / "icub_upper_body.urdf"))
