"""The robot's neural controller (paper section III-B, Fig. 3).

Layout of the layers (shared by sensors, task, genome and recording):

- 25 sensory neurons: 14 proprioceptors (motor order below), 6 touch (palm, then thumb, index,
  middle, ring and little fingertips), 3 sight (Eqs. 1-3), 2 sight-offset (Eq. 4).
- 8 internal neurons.
- 14 motor neurons: head (3), torso (3), right arm (7), right hand (1).
"""

from __future__ import annotations

import abc
from dataclasses import dataclass

import numpy as np

from .levers import REFLEX_EVOLVED_SCALE, ReflexInputs

N_SENSORS = 25
N_HIDDEN = 8
N_MOTORS = 14

# The sensor vector's layers (the network's 25 inputs, section III-B), used by every module
# that reads or writes it; the single sensors by index, for code that writes one value at a
# time (the compiled sensing, ``kernels.sensing.sense_posed``).
PROPRIO = slice(0, 14)  # 14 proprioceptors, in motor order (MOTOR_NAMES)
TOUCH = slice(14, 20)  # 6 touch sensors: palm, then the thumb, index, middle, ring, little tips
SIGHT = slice(20, 23)  # the ball's image coordinates c_x, c_y (Eqs. 1-2) and distance (Eq. 3)
OFFSET = slice(23, 25)  # the hand-ball offset, horizontal and vertical (Eq. 4)
SIGHT_X, SIGHT_Y, SIGHT_DISTANCE = range(SIGHT.start, SIGHT.stop)
OFFSET_X, OFFSET_Y = range(OFFSET.start, OFFSET.stop)

# The motor vector's groups (the 14 motor neurons and their targets, section III-B).
NECK = slice(0, 3)  # neck pitch, roll, yaw
TORSO = slice(3, 6)  # torso pitch, roll, yaw
ARM = slice(6, 13)  # right shoulder (3), elbow, wrist (3)
JOINT_MOTORS = slice(0, 13)  # the 13 motors that drive one joint each
HAND_MOTOR = 13  # the one motor every finger flexion joint follows

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


# ---------------------------------------------------------------------------------------------
# Parameters: shapes, validation, helpers
# ---------------------------------------------------------------------------------------------

#: Index of each motor neuron and each sensory neuron by name.
MOTOR_INDEX = {name: i for i, name in enumerate(MOTOR_NAMES)}
SENSOR_INDEX = {name: i for i, name in enumerate(SENSOR_NAMES)}

#: Expected shape of every field of ``NetworkParams``.
PARAM_SHAPES = {
    "w_sensor_motor": (N_MOTORS, N_SENSORS),
    "w_sensor_hidden": (N_HIDDEN, N_SENSORS),
    "w_hidden_motor": (N_MOTORS, N_HIDDEN),
    "bias_hidden": (N_HIDDEN,),
    "bias_motor": (N_MOTORS,),
    "tau_hidden": (N_HIDDEN,),
    "tau_motor": (N_MOTORS,),
    "gain_hidden": (N_HIDDEN,),
    "gain_offset": (2,),
}


def validate_params(params: NetworkParams) -> None:
    """Check a ``NetworkParams`` (section III-B): every field a real array of the shape in
    ``PARAM_SHAPES``, every value finite, every time constant in [0, 1].

    Raises ``ValueError`` naming the offending field (and the expected shape).
    """
    for name, shape in PARAM_SHAPES.items():
        value = getattr(params, name, None)
        if value is None:
            raise ValueError(f"NetworkParams.{name} is missing (expected shape {shape})")
        try:
            a = np.asarray(value)
        except Exception as exc:  # ragged sequences and the like
            raise ValueError(f"NetworkParams.{name} is not an array of shape {shape}: {exc}"
                             ) from None
        if a.shape != shape:
            raise ValueError(f"NetworkParams.{name} must have shape {shape}, got {a.shape}")
        if a.dtype.kind not in "biuf":
            raise ValueError(f"NetworkParams.{name} must hold real numbers, got dtype {a.dtype}")
        if not np.isfinite(a).all():
            raise ValueError(f"NetworkParams.{name} holds {int((~np.isfinite(a)).sum())} "
                             f"non-finite value(s)")
        if name.startswith("tau_") and ((a < 0.0).any() or (a > 1.0).any()):
            raise ValueError(f"NetworkParams.{name} must lie in [0, 1] (0 <= tau <= 1, "
                             f"section III-B), got values in [{a.min()}, {a.max()}]")


@dataclass(frozen=True)
class ParamRanges:
    """Ranges (low, high) of the uniform draws of ``random_params``. The paper gives none
    (section III-C: 8-bit genes); these are ours: weights and thresholds in [-5, 5] (the reflex
    weights below lie inside it), time constants in their full range [0, 1], gains in [0, 1]."""

    weight: tuple[float, float] = (-5.0, 5.0)
    bias: tuple[float, float] = (-5.0, 5.0)
    tau: tuple[float, float] = (0.0, 1.0)
    gain: tuple[float, float] = (0.0, 1.0)

    def __post_init__(self):
        for name in ("weight", "bias", "tau", "gain"):
            lo, hi = getattr(self, name)
            if not (np.isfinite(lo) and np.isfinite(hi) and lo <= hi):
                raise ValueError(f"ParamRanges.{name} must be finite with low <= high, "
                                 f"got {(lo, hi)}")
        if self.tau[0] < 0.0 or self.tau[1] > 1.0:
            raise ValueError(f"ParamRanges.tau must lie within [0, 1], got {self.tau}")


def random_params(rng: np.random.Generator, ranges: ParamRanges = ParamRanges()) -> NetworkParams:
    """Parameters drawn uniformly within ``ranges`` from the generator ``rng``."""
    kind = {"w": ranges.weight, "b": ranges.bias, "t": ranges.tau, "g": ranges.gain}
    return NetworkParams(**{name: rng.uniform(*kind[name[0]], size=shape)
                            for name, shape in PARAM_SHAPES.items()})


def zero_params() -> NetworkParams:
    """Every weight and threshold 0, every time constant 0 (no memory), every gain 1."""
    return NetworkParams(**{
        name: (np.ones(shape) if name.startswith("gain_") else np.zeros(shape))
        for name, shape in PARAM_SHAPES.items()})


# ---------------------------------------------------------------------------------------------
# Reflexes (sections II-D, III-D 1; full arrows of Fig. 3)
# ---------------------------------------------------------------------------------------------
# With threshold 0, a motor neuron driven only by its reflex inputs settles at
# s = sigma(z) and its target is 2 s - 1 = tanh(z / 2) ~= z / 2 near z = 0.
#
# Orienting response (a proportional controller around the home posture): neck motor <- the
# ball's image coordinate with weight W and a hand-set threshold theta = -2 atanh(t_home), so that
# a centred ball (c = 0) holds the neck at its home target t_home and an off-centre one moves the
# target by ~ k c: the slope of tanh((W c - theta) / 2) at c = 0 is W (1 - t_home^2) / 2 = k, so
# W = 2 k / (1 - t_home^2). On this robot a target change of 1 turns the camera by 50 deg (yaw) or
# 31 deg (pitch), i.e. c by ~0.6 or ~0.5 near the centre: a loop gain of 0.6 k per step. k = 1
# (ORIENT_GAIN) was chosen by measurement (docs/model/controller.md, ``dart-reach validate``):
# stable (no oscillation at 10 Hz with the joints' speed bound), and it halves the image offset of a
# reflex-only head. With low acuity (a = 3) the drive is c^3: the reflex is weaker near the
# centre, as a blurrier orienting response would be. ORIENT_HOME_TARGETS are the neck's home
# targets of ``world.World`` (tested equal). ORIENT_*_SIGN say in which direction a positive
# neck target turns the camera relative to +c (a property of the world's joint axes, measured
# on ``world.World``: raising the neck_yaw target turns the camera left, raising the neck_pitch
# target turns it up).
#
# Grasp reflex: hand motor <- palm touch with GRASP_WEIGHT = 5 and threshold 0: palm touched (+1)
# -> sigma(5) = 0.993, target 0.987 (fingers closed); untouched (-1) -> target -0.987 (open).
#
# What else the three reflex motor neurons receive (docs/model/controller.md): while the
# reflexes are on, none of the evolved sensory connections (the reflex arcs are the full arrows
# of Fig. 3: all of their direct input is hand-set; with evolved direct inputs at full range as
# well, each of the 24 other sensors of a random network would reach them with a weight of up to
# 5 against the reflex arcs' 2.3-5, and could drown the reflexes: the ``evolved`` lever scales
# them down). From gross-reaching the internal neurons project to them like to every motor
# neuron: "the intervention of cortical centers in the mediation of sensory-motor reflexive
# behavior" (III-D 2). Their thresholds are hand-set; their time constants stay evolved (tau
# only sets how fast the reflex acts).

#: Sign of the neck yaw target change that turns the camera toward a ball at +c_x (right).
ORIENT_YAW_SIGN = -1.0
#: Sign of the neck pitch target change that turns the camera toward a ball at +c_y (up).
ORIENT_PITCH_SIGN = 1.0
#: Neck targets of the home posture (``world.World.home_targets``; icub.HOME_POSTURE).
ORIENT_HOME_TARGETS = {"neck_yaw": -0.3508, "neck_pitch": -0.7410}
ORIENT_GAIN = 1.0
GRASP_WEIGHT = 5.0
GRASP_BIAS = 0.0

_REFLEX_MOTORS = ("neck_yaw", "neck_pitch", "r_hand_fingers")


def reflex_weights() -> tuple[np.ndarray, np.ndarray]:
    """The hand-set sensor-to-motor weights of the orienting and grasp reflexes (sections II-D,
    III-D 1, full arrows of Fig. 3).

    Returns ``(mask, weights)``, both (N_MOTORS, N_SENSORS) indexed [motor, sensor]: where
    ``mask`` is True, ``weights`` replaces the evolved ``w_sensor_motor`` when reflexes are on.
    neck_yaw <- sight/x and proprio/neck_yaw; neck_pitch <- sight/y and proprio/neck_pitch;
    r_hand_fingers <- touch/palm. Reads the module constants at call time.
    """
    mask = np.zeros((N_MOTORS, N_SENSORS), dtype=bool)
    weights = np.zeros((N_MOTORS, N_SENSORS))
    m, s = MOTOR_INDEX, SENSOR_INDEX
    for motor, image_axis, sign in (("neck_yaw", "sight/x", ORIENT_YAW_SIGN),
                                    ("neck_pitch", "sight/y", ORIENT_PITCH_SIGN)):
        home = ORIENT_HOME_TARGETS[motor]
        weights[m[motor], s[image_axis]] = sign * 2.0 * ORIENT_GAIN / (1.0 - home * home)
    weights[m["r_hand_fingers"], s["touch/palm"]] = GRASP_WEIGHT
    mask[[m[name] for name in _REFLEX_MOTORS], :] = True
    return mask, weights


def reflex_biases() -> tuple[np.ndarray, np.ndarray]:
    """The hand-set thresholds of the three reflex motor neurons (neck_yaw, neck_pitch,
    r_hand_fingers): ``(mask (N_MOTORS,) bool, biases (N_MOTORS,))``; where ``mask`` is True
    ``biases`` replaces the evolved ``bias_motor`` when reflexes are on. The neck's hold its
    home target with the ball centred (theta = -2 atanh(t_home)); the hand's is 0."""
    mask = np.zeros(N_MOTORS, dtype=bool)
    biases = np.zeros(N_MOTORS)
    for name, home in ORIENT_HOME_TARGETS.items():
        biases[MOTOR_INDEX[name]] = -2.0 * np.arctanh(home)
    biases[MOTOR_INDEX["r_hand_fingers"]] = GRASP_BIAS
    mask[[MOTOR_INDEX[n] for n in _REFLEX_MOTORS]] = True
    return mask, biases


# ---------------------------------------------------------------------------------------------
# The network
# ---------------------------------------------------------------------------------------------

#: Motor neuron state after ``Network.reset()``: target 0, the middle of every joint's range.
RESET_MOTOR_STATE = 0.5


def motor_targets(motor_state, out=None) -> np.ndarray:
    """Joint targets in [-1, 1] for the world from motor neuron states in [0, 1]: 2 x - 1
    (section III-B: the motor neurons set the desired angle scaled within the joint limits)."""
    out = np.empty(np.shape(motor_state)) if out is None else out
    np.multiply(motor_state, 2.0, out=out)
    out -= 1.0
    return out


class Network(abc.ABC):
    """The controller of Fig. 3 (section III-B), stepped once per 0.1 s: its parameters and
    states; its ``step`` is a model version's numerics (``task.network_for`` builds the one of
    a trial: ``compiled.CompiledNetwork``, the living model, or version 1's frozen
    ``reference.network.ReferenceNetwork``).

    25 sensory neurons (the sensor values; the two sight-offset values are multiplied by
    ``gain_offset``) project to 8 internal and 14 motor neurons; the internal neurons project to
    the motor neurons. Internal and motor neurons are leaky integrators:

        x_i(t) = tau_i x_i(t-1) + (1 - tau_i) s_i(t),   s_i(t) = g_i sigma(sum_j w_ij x_j(t) - theta_i)

    with g = ``gain_hidden`` for the internal neurons and 1 for the motor neurons. Within a step:
    sensors (t) -> internal neurons (from the sensors at t) -> motor neurons (from the sensors
    at t and the internal states at t just computed). No lateral connections: an internal
    neuron's only memory is its own tau.

    ``reflexes``: the hand-set weights of ``reflex_weights`` and thresholds of ``reflex_biases``
    replace the evolved ones on their connections (``reflex_inputs``: on every connection of the
    three reflex motors, or, ``ReflexInputs.EVOLVED``, on the reflex arcs only, the others
    evolved and scaled by ``REFLEX_EVOLVED_SCALE``). ``hidden_frozen``: the internal neurons are
    held at 0 (pre-reaching, section III-D 1), so neither ``w_sensor_hidden`` nor
    ``w_hidden_motor`` has any effect.

    Attributes ``hidden`` (8,) and ``motor`` (14,) are the current states (updated in place);
    ``step`` returns ``motor`` itself. The parameters are copied at construction.
    """

    def __init__(self, params: NetworkParams, *, reflexes: bool = False,
                 hidden_frozen: bool = False, reflex_inputs: ReflexInputs = ReflexInputs.HAND_SET):
        validate_params(params)
        self.params = params
        self.reflexes = bool(reflexes)
        self.hidden_frozen = bool(hidden_frozen)
        self.reflex_inputs = ReflexInputs(reflex_inputs)
        f = lambda a: np.array(a, dtype=float, order="C")  # noqa: E731  (private copies)
        self._w_sm = f(params.w_sensor_motor)
        self._bias_m = f(params.bias_motor)
        if self.reflexes:
            mask, w = reflex_weights()
            if self.reflex_inputs is ReflexInputs.EVOLVED:
                # Fig. 3's caption: the evolved direct inputs reach the reflex motors too,
                # scaled down so that the reflex arcs still act (levers.ReflexInputs)
                self._w_sm[mask] *= REFLEX_EVOLVED_SCALE
                mask = w != 0.0
            self._w_sm[mask] = w[mask]
            bmask, b = reflex_biases()
            self._bias_m[bmask] = b[bmask]
        self._w_sh = f(params.w_sensor_hidden)
        self._w_hm = f(params.w_hidden_motor)
        self._bias_h = f(params.bias_hidden)
        self._gain_h = f(params.gain_hidden)
        self._tau_h = f(params.tau_hidden)
        self._tau_m = f(params.tau_motor)
        self._in_scale = np.ones(N_SENSORS)
        self._in_scale[OFFSET] = params.gain_offset
        self._x = np.zeros(N_SENSORS)  # the sensor values times their gains, of the last step
        self.hidden = np.zeros(N_HIDDEN)
        self.motor = np.full(N_MOTORS, RESET_MOTOR_STATE)

    @property
    def effective_w_sensor_motor(self) -> np.ndarray:
        """The sensor-to-motor weights in use (evolved, with the reflex weights if on); a copy."""
        return self._w_sm.copy()

    @property
    def effective_bias_motor(self) -> np.ndarray:
        """The motor thresholds in use (evolved, with the reflex thresholds if on); a copy."""
        return self._bias_m.copy()

    def reset(self, motor=None) -> None:
        """Start of a trial: internal states 0; motor states ``motor`` (14 values in [0, 1]) or,
        by default, RESET_MOTOR_STATE = 0.5 (target 0, mid-range; a state of 0 would mean
        target -1, every joint at its lower limit). Pass ``(home_targets + 1) / 2`` to start
        from the robot's posture."""
        self.hidden[:] = 0.0
        if motor is None:
            self.motor[:] = RESET_MOTOR_STATE
            return
        m = np.asarray(motor, dtype=float)
        if m.shape != (N_MOTORS,):
            raise ValueError(f"motor reset state must have shape ({N_MOTORS},), got {m.shape}")
        if not (np.isfinite(m).all() and (m >= 0.0).all() and (m <= 1.0).all()):
            raise ValueError(f"motor reset state must lie in [0, 1], got {m}")
        self.motor[:] = m

    @abc.abstractmethod
    def step(self, sensors: np.ndarray) -> np.ndarray:
        """One 0.1 s update from the 25 sensor values at time t; returns ``self.motor`` (14,)
        in [0, 1] (the same array every call, updated in place)."""
