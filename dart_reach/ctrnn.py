"""The robot's neural controller (paper section III-B, Fig. 3).

Layout of the layers (shared by sensors, task, genome and recording):

- 25 sensory neurons: 14 proprioceptors (motor order below), 6 touch (palm, then thumb, index,
  middle, ring and little fingertips), 3 sight (Eqs. 1-3), 2 sight-offset (Eq. 4).
- 8 internal neurons.
- 14 motor neurons: head (3), torso (3), right arm (7), right hand (1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

N_SENSORS = 25
N_HIDDEN = 8
N_MOTORS = 14

PROPRIO = slice(0, 14)
TOUCH = slice(14, 20)
SIGHT = slice(20, 23)
OFFSET = slice(23, 25)

MOTOR_NAMES = (
    "neck_pitch", "neck_roll", "neck_yaw",
    "torso_pitch", "torso_roll", "torso_yaw",
    "r_shoulder_pitch", "r_shoulder_roll", "r_shoulder_yaw", "r_elbow",
    "r_wrist_prosup", "r_wrist_pitch", "r_wrist_yaw",
    "r_hand_fingers",
)
TOUCH_NAMES = ("palm", "thumb", "index", "middle", "ring", "little")
SENSOR_NAMES = (
    tuple(f"proprio/{n}" for n in MOTOR_NAMES)
    + tuple(f"touch/{n}" for n in TOUCH_NAMES)
    + ("sight/x", "sight/y", "sight/distance", "offset/x", "offset/y")
)


@dataclass(frozen=True)
class NetworkParams:
    """Every parameter of the controller as plain numpy float64 arrays.

    Weights are indexed [post, pre]. ``bias_*`` is the threshold theta of the update equation
    (subtracted from the net input), ``tau_*`` the time constant in [0, 1], ``gain_*`` g.
    Sensory, and motor neurons have gain 1.0 (section III-B); only the internal neurons and the
    two sight-offset sensors carry a gain.
    """

    w_sensor_motor: np.ndarray  # (N_MOTORS, N_SENSORS)
    w_sensor_hidden: np.ndarray  # (N_HIDDEN, N_SENSORS)
    w_hidden_motor: np.ndarray  # (N_MOTORS, N_HIDDEN)
    bias_hidden: np.ndarray  # (N_HIDDEN,)
    bias_motor: np.ndarray  # (N_MOTORS,)
    tau_hidden: np.ndarray  # (N_HIDDEN,)
    tau_motor: np.ndarray  # (N_MOTORS,)
    gain_hidden: np.ndarray  # (N_HIDDEN,)
    gain_offset: np.ndarray  # (2,)
