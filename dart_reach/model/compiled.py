"""The living model's numerics (model versions 2 and 3, ``versions.Numerics.COMPILED``): the
trial's Python around DART's step (the sensors, the network, the fitness terms and the motor
commands of one 0.1 s control step) compiled with Numba, so that a trial costs little more than
its physics.

Version 2 computes what version 1 computes (its frozen code: ``model.reference``; sections
III-B, III-C): the same equations, the same physics, the same DART step. Only the rounding may
differ, and it is the same on every processor, by construction:

- every sum is taken in index order, every product and quotient as written: compiled without
  ``fastmath``, LLVM may neither reorder nor fuse (no FMA) floating-point operations, so the
  vector width of the processor (SSE, AVX2, AVX-512) cannot change a result (tested: the same
  trials to the last bit compiled for the host and for a generic x86-64);
- the logistic's exponential (``exp_nonpositive``) is written here from +, -, * and exact
  scaling by powers of 2, not taken from the C library, whose implementations differ between
  processors (glibc picks an FMA variant where the CPU has one) and between libraries;
- distances use ``sqrt`` (correctly rounded by IEEE 754), not ``hypot``; the acuity's power
  is a product for the paper's exponents 1 and 3 (section III-B), the C library's ``pow``
  only for other exponents a user may set; the offset sensors' visual angles (fine-reaching,
  Eq. 4) take the C library's ``atan2``, as version 1 does (Python's ``math.atan2``).

What stays numpy's in both versions (the scene's geometry: the sectors' points; the records'
hand point and palm normal) rounds alike on every processor under the dispatch level that
``import dart_reach`` pins, as in version 1.

One thing is commanded differently, to the same effect: the springs that drive the joints
are pulled toward the motors' commanded positions by joint forces k q_cmd, their rest
positions held at 0 (``spring_forces``): the same force, and DART does not prepare its world
again at every control step, as it does after a new rest position.

Version 1 keeps its own code, frozen in ``model.reference``, and its digests: every run trained
under it reproduces bit for bit.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from numba import njit
from numba.core import config as numba_config
from numba.core import types
from numba.experimental import structref

from . import sensors
from .ctrnn import (N_HIDDEN, N_MOTORS, N_SENSORS, OFFSET_X, OFFSET_Y, PROPRIO, SIGHT_DISTANCE,
                    SIGHT_X, SIGHT_Y, TOUCH, Network, NetworkParams)
from .levers import TOUCH_CAP, ReflexInputs, TouchPay

# ------------------------------------------------------------------------------ exponential
#: ln 2 split in two (fdlibm's constants): k * _LN2_HI is exact for |k| < 2^11.
_LN2_HI = 6.93147180369123816490e-01
_LN2_LO = 1.90821492927058770002e-10
_INV_LN2 = 1.44269504088896338700e+00
#: Below this exp(x) is 0 in float64 (the smallest subnormal is 4.9e-324 = exp(-744.4)).
_EXP_UNDERFLOW = -745.2
#: 1 / n! for n = 2..13: the Taylor series of exp(r) - 1 - r on |r| <= ln(2) / 2, whose
#: truncation error (<= 0.347^14 / 14! = 4e-18) lies far below float64's half ulp.
_INV_FACTORIALS = (1.0 / 2, 1.0 / 6, 1.0 / 24, 1.0 / 120, 1.0 / 720, 1.0 / 5040, 1.0 / 40320,
                   1.0 / 362880, 1.0 / 3628800, 1.0 / 39916800, 1.0 / 479001600,
                   1.0 / 6227020800)


@njit(cache=True)
def exp_nonpositive(x: float) -> float:
    """exp(x) for x <= 0 from +, -, * and ``ldexp`` only (the same bits on every processor):
    x = k ln 2 + r with |r| <= ln(2) / 2 (Cody and Waite's two-part ln 2), exp(r) by its
    Taylor series to r^13 in Horner's form, times 2^k. Within 2 ulp of the correctly rounded
    value (tested against ``math.exp``); 0.0 below -745.2; NaN for NaN."""
    if x != x:
        return x
    if x < _EXP_UNDERFLOW:
        return 0.0
    k = math.floor(x * _INV_LN2 + 0.5)
    r = (x - k * _LN2_HI) - k * _LN2_LO
    c = _INV_FACTORIALS
    p = c[11]
    for i in range(10, -1, -1):
        p = p * r + c[i]
    return math.ldexp(1.0 + (r + r * r * p), int(k))


@njit(cache=True)
def logistic(z: float) -> float:
    """sigma(z) = 1 / (1 + exp(-z)) of the update equation (section III-B), from
    ``exp_nonpositive`` of -|z| (no overflow): 1 / (1 + e) for z >= 0, e / (1 + e) below."""
    if z >= 0.0:
        return 1.0 / (1.0 + exp_nonpositive(-z))
    e = exp_nonpositive(z)
    return e / (1.0 + e)


# ------------------------------------------------------------------------------ the network
@njit(cache=True)
def _network_step(sensors_in, in_scale, w_sm, w_sh, w_hm, bias_h, bias_m, gain_h, tau_h, tau_m,
                  hidden_frozen, x, hidden, motor):
    """One 0.1 s update of the network (``ctrnn.Network``'s update equation), in place on
    ``hidden`` and ``motor``; every sum in index order: the sensors', then the internal
    neurons'."""
    for j in range(N_SENSORS):
        x[j] = sensors_in[j] * in_scale[j]
    if not hidden_frozen:
        for i in range(N_HIDDEN):
            s = 0.0
            for j in range(N_SENSORS):
                s += w_sh[i, j] * x[j]
            s = gain_h[i] * logistic(s - bias_h[i])
            hidden[i] = tau_h[i] * hidden[i] + (1.0 - tau_h[i]) * s
    for i in range(N_MOTORS):
        s = 0.0
        for j in range(N_SENSORS):
            s += w_sm[i, j] * x[j]
        if not hidden_frozen:
            for j in range(N_HIDDEN):
                s += w_hm[i, j] * hidden[j]
        motor[i] = tau_m[i] * motor[i] + (1.0 - tau_m[i]) * logistic(s - bias_m[i])


@njit(cache=True)
def targets_of_motor(motor, targets):
    """Motor targets 2 s - 1 (``ctrnn.motor_targets``); whether all are finite."""
    finite = True
    for i in range(N_MOTORS):
        targets[i] = motor[i] * 2.0 - 1.0
        finite = finite and math.isfinite(targets[i])
    return finite


class CompiledNetwork(Network):
    """``ctrnn.Network`` (section III-B, Fig. 3) stepped by compiled code (the living model,
    model versions 2 and 3); ``step`` allocates nothing."""

    def __init__(self, params: NetworkParams, *, reflexes: bool = False,
                 hidden_frozen: bool = False, reflex_inputs: ReflexInputs = ReflexInputs.HAND_SET):
        super().__init__(params, reflexes=reflexes, hidden_frozen=hidden_frozen,
                         reflex_inputs=reflex_inputs)
        #: the network's parameters and states as ``network_step`` and ``act_step`` read
        #: them (``NetworkState``; arrays shared with the network, updated in place)
        self.state = network_state(
            in_scale=self._in_scale, w_sm=self._w_sm, w_sh=self._w_sh, w_hm=self._w_hm,
            bias_h=self._bias_h, bias_m=self._bias_m, gain_h=self._gain_h, tau_h=self._tau_h,
            tau_m=self._tau_m, hidden_frozen=self.hidden_frozen, x=self._x,
            hidden=self.hidden, motor=self.motor)

    def step(self, sensors: np.ndarray) -> np.ndarray:
        """One 0.1 s update from the 25 sensor values; returns ``self.motor``."""
        if type(sensors) is not np.ndarray or sensors.shape != (N_SENSORS,) \
                or sensors.dtype != np.float64:
            sensors = np.asarray(sensors, dtype=float)
            if sensors.shape != (N_SENSORS,):
                raise ValueError(f"expected {N_SENSORS} sensor values, got shape {sensors.shape}")
        network_step(sensors, self.state)
        return self.motor


# ------------------------------------------------------------------------------ sensing
#: ``TouchPay`` as the small integers the sensing kernel takes.
PAY_CODES = {TouchPay.FACES: 0, TouchPay.BINARY: 1, TouchPay.CAPPED: 2}
_TAN_X = math.tan(math.radians(sensors.HALF_FOV_X_DEG))
_TAN_Y = math.tan(math.radians(sensors.HALF_FOV_Y_DEG))
_SQRT2 = math.sqrt(2.0)
_DEGREES = 180.0 / math.pi
_NO_TOUCH, _TOUCHING, _NO_SIGHT = sensors.NO_TOUCH, sensors.TOUCHING, sensors.NO_SIGHT
_SIGHT_RANGE, _OFFSET_D_MAX, _OFFSET_SCALE = (sensors.SIGHT_RANGE_M, sensors.OFFSET_D_MAX_DEG,
                                              sensors.OFFSET_SCALE)
#: The first index of the sensor vector's proprioceptors and touch sensors (``ctrnn.PROPRIO``,
#: ``ctrnn.TOUCH``), as the integers compiled code indexes with.
_PROPRIO0, _TOUCH0 = PROPRIO.start, TOUCH.start


@njit(cache=True)
def _clip(v, lo, hi):
    if v != v:
        return v
    v = v if v > lo else lo
    return v if v < hi else hi


@njit(cache=True)
def _in_camera(p, cam, out):
    """``out`` = R^T (p - o) of the 4x4 camera pose ``cam`` (rotation R, origin o)."""
    d0, d1, d2 = p[0] - cam[0, 3], p[1] - cam[1, 3], p[2] - cam[2, 3]
    for i in range(3):
        out[i] = d0 * cam[0, i] + d1 * cam[1, i] + d2 * cam[2, i]


@njit(cache=True)
def project(x, y, z):
    """Normalised image coordinates (c_x, c_y, in view) of a point (x, y, z) (m) in the head
    camera's frame (+z the optical axis, +x right, +y down; section III-B): c_x = (x / z) /
    tan(56 deg) (+ right), c_y = -(y / z) / tan(47 deg) (+ up), in view when z > 0 and both
    lie in [-1, 1]; (0.0, 0.0, False) on or behind the image plane."""
    if not z > 0.0:
        return 0.0, 0.0, False
    cx = (x / z) / _TAN_X
    cy = -(y / z) / _TAN_Y
    return cx, cy, abs(cx) <= 1.0 and abs(cy) <= 1.0


@njit(cache=True)
def touch_pay(n, n_segments, pay):
    """p_touch (section III-C, Eq. 5) of ``n`` of ``n_segments`` hand segments touching the
    ball on their inner face, in [0, 1], under the ``levers.TouchPay`` of code ``pay``
    (``PAY_CODES``): n / N (faces), 1 if any (binary), min(n, TOUCH_CAP) / TOUCH_CAP
    (capped)."""
    if pay == 0:
        return n / n_segments
    if pay == 1:
        return 1.0 if n > 0 else 0.0
    return min(n, TOUCH_CAP) / TOUCH_CAP


@njit(cache=True)
def _power(c, a):
    """sgn(c) |c|^a of Eqs. 1-2: a product for a = 1 and a = 3, the C library's pow else."""
    m = abs(c)
    if a == 3.0:
        m = m * m * m
    elif a != 1.0:
        m = m ** a
    return m if c >= 0.0 else -m


@njit(cache=True)
def _sense(positions, ball, cam, hand, touching, motor_dofs, finger_dofs, lower, span,
           touch_segments, acuity, no_touch, no_sight, offsets, pay, palm, q, x, p, scratch):
    """The sensor vector ``x`` (25), the motor-space angles ``q`` (14) and the fitness terms
    ``p`` = (p_sight, p_touch, p_multimodal) (Eq. 5) of one step, from the skeleton's joint
    positions, the ball's centre, the camera's and (with ``offsets``) the hand's 4x4 poses and
    the 16 hand segments' inner-face touches; as ``task.Trial.sense`` (sections III-B, III-C).
    Returns whether the joint positions and the ball are finite."""
    finite = True
    for i in range(positions.shape[0]):
        finite = finite and math.isfinite(positions[i])
    for i in range(3):
        finite = finite and math.isfinite(ball[i])
    n_motor = motor_dofs.shape[0]
    for i in range(n_motor):
        q[i] = positions[motor_dofs[i]]
    s = 0.0
    for i in range(finger_dofs.shape[0]):
        s += positions[finger_dofs[i]]
    q[n_motor] = s / finger_dofs.shape[0]
    for i in range(n_motor + 1):  # proprioception
        x[_PROPRIO0 + i] = _clip((q[i] - lower[i]) / span[i] * 2.0 - 1.0, -1.0, 1.0)
    n_touch = touch_segments.shape[0]
    for i in range(n_touch):
        x[_TOUCH0 + i] = _NO_TOUCH if no_touch or not touching[touch_segments[i]] else _TOUCHING
    ball_cam = scratch[0:3]
    _in_camera(ball, cam, ball_cam)
    cx, cy, visible = project(ball_cam[0], ball_cam[1], ball_cam[2])
    if no_sight or not visible:
        x[SIGHT_X] = x[SIGHT_Y] = x[SIGHT_DISTANCE] = _NO_SIGHT
    else:
        x[SIGHT_X] = _power(cx, acuity)
        x[SIGHT_Y] = _power(cy, acuity)
        distance = math.sqrt(ball_cam[0] * ball_cam[0] + ball_cam[1] * ball_cam[1]
                             + ball_cam[2] * ball_cam[2])
        x[SIGHT_DISTANCE] = 1.0 - 2.0 * distance if distance < _SIGHT_RANGE else 0.0
    x[OFFSET_X] = x[OFFSET_Y] = _NO_SIGHT
    if offsets and not no_sight and visible:
        palm_world, hand_cam = scratch[3:6], scratch[6:9]
        for i in range(3):
            palm_world[i] = (hand[i, 0] * palm[0] + hand[i, 1] * palm[1] + hand[i, 2] * palm[2]
                             ) + hand[i, 3]
        _in_camera(palm_world, cam, hand_cam)
        if project(hand_cam[0], hand_cam[1], hand_cam[2])[2]:
            d = (math.atan2(ball_cam[0], ball_cam[2]) * _DEGREES
                 - math.atan2(hand_cam[0], hand_cam[2]) * _DEGREES)
            x[OFFSET_X] = _OFFSET_SCALE * min(max(d, -_OFFSET_D_MAX), _OFFSET_D_MAX)
            d = (math.atan2(-ball_cam[1], ball_cam[2]) * _DEGREES
                 - math.atan2(-hand_cam[1], hand_cam[2]) * _DEGREES)
            x[OFFSET_Y] = _OFFSET_SCALE * min(max(d, -_OFFSET_D_MAX), _OFFSET_D_MAX)
    p_sight = 0.0
    if visible:
        p_sight = max(0.0, 1.0 - math.sqrt(cx * cx + cy * cy) / _SQRT2)
    n = 0
    for i in range(touching.shape[0]):
        n += 1 if touching[i] else 0
    p_touch = touch_pay(n, touching.shape[0], pay)
    p[0], p[1], p[2] = p_sight, p_touch, min(p_sight, p_touch)
    return finite



@njit(cache=True)
def sense_posed(positions, ball, touching, order, parent, dof, axis, before, after, scratch,
                poses, camera_body, hand_body, motor_dofs, finger_dofs, lower, span,
                touch_segments, acuity, no_touch, no_sight, offsets, pay, palm, q, x, p,
                sense_scratch):
    """``_sense`` with the camera's and the hand's poses from the joint positions
    (``body_poses`` of the bodies of ``order`` into ``poses``)."""
    body_poses(positions, order, parent, dof, axis, before, after, scratch, poses)
    return _sense(positions, ball, poses[camera_body], poses[hand_body], touching, motor_dofs,
                  finger_dofs, lower, span, touch_segments, acuity, no_touch, no_sight, offsets,
                  pay, palm, q, x, p, sense_scratch)


@njit(cache=True)
def record_row(t, positions, q, ball, touch, touch_any, x, p, poses, hand_body, shoulder_body,
                palm, palm_normal, dofs, joints, hand, shoulder, ball_rec, contacts,
                contacts_any, normal, sensors_rec, p_sight, p_touch, p_multimodal):
    """Row ``t`` of a trial's record (``task.Trial.observe``) from what ``sense_posed`` read
    and computed: the hand's palm point and normal and the shoulder from the bodies' poses."""
    dofs[t, :] = positions
    joints[t, :] = q
    h = poses[hand_body]
    for i in range(3):
        hand[t, i] = (h[i, 0] * palm[0] + h[i, 1] * palm[1] + h[i, 2] * palm[2]) + h[i, 3]
        normal[t, i] = h[i, 0] * palm_normal[0] + h[i, 1] * palm_normal[1] \
            + h[i, 2] * palm_normal[2]
        shoulder[t, i] = poses[shoulder_body, i, 3]
        ball_rec[t, i] = ball[i]
    contacts[t, :] = touch
    contacts_any[t, :] = touch_any
    sensors_rec[t, :] = x
    p_sight[t], p_touch[t], p_multimodal[t] = p[0], p[1], p[2]


# ------------------------------------------------------------------------------ motor commands

@njit(cache=True)
def motor_commands(targets, half_range, mid_range, lower, upper, max_move, dof_motor, stiffness,
                   q_cmd, gravity, forces):
    """The joint forces (N m, per degree of freedom, ``forces``) that drive the springs toward
    14 motor targets in [-1, 1]: each target scaled into its motor's range and the motor's
    commanded position ``q_cmd`` (rad) moved toward it by at most ``max_move``, as version
    1's ``reference.servo.ReferenceServo.set_targets`` does (the same operations in the same
    order); then ``spring_forces``. Returns whether the targets are finite (``q_cmd`` is
    left as it was when not)."""
    for i in range(N_MOTORS):
        if not math.isfinite(targets[i]):
            return False
    for i in range(N_MOTORS):
        q = _clip(targets[i] * half_range[i] + mid_range[i], lower[i], upper[i])
        q_cmd[i] += _clip(q - q_cmd[i], -max_move, max_move)
    spring_forces(q_cmd, dof_motor, stiffness, gravity, forces)
    return True


@njit(cache=True)
def spring_forces(q_cmd, dof_motor, stiffness, gravity, forces):
    """Each degree of freedom's command: the gravity compensation plus its spring's pull
    toward its motor's commanded position, k q_cmd (the springs' rest positions held at 0).
    DART integrates a spring's force -k (q - q_rest + h v) implicitly; q_rest enters it only
    through k q_rest, so k q_cmd as a force with q_rest = 0 is the same force, rounded
    apart, and changing a command, unlike a rest position, does not make DART prepare the
    world again at the next substep (docs/results/benchmarks.md)."""
    for i in range(dof_motor.shape[0]):
        forces[i] = gravity[i] + stiffness[i] * q_cmd[dof_motor[i]]



# ------------------------------------------------------------------------------ the step functions
# A trial's compiled steps read and write their arrays through two structures, a trial's
# (``StepState``) and a network's (``NetworkState``): a compiled call costs ~40 ns for each
# array it is passed, and the sensing, the network and the motor commands read ~50.
class _State(types.StructRef):
    """A Numba structure of arrays and scalars, each field typed as the value it is built
    with."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(kind)) for name, kind in fields)


@structref.register
class _StepStateType(_State):
    pass


class StepState(structref.StructRefProxy):
    """What a trial's steps read and write besides DART's state and the network (built by
    ``step_state``): ``sense_posed``'s arrays (the inner-face touches ``touching`` first, the
    sensor vector ``x``, the motor-space angles ``q``, the fitness terms ``p``), the touches on
    any face ``touching_any``, the motor targets ``targets`` and ``motor_commands``' arrays
    (the commanded positions ``q_cmd``, the joint forces out ``forces``)."""


_STEP_FIELDS = (
    "touching", "order", "parent", "dof", "axis", "before", "after", "scratch", "poses",
    "camera_body", "hand_body", "motor_dofs", "finger_dofs", "lower", "span", "touch_segments",
    "acuity", "no_touch", "no_sight", "offsets", "pay", "palm", "q", "x", "p", "sense_scratch",
    "touching_any", "targets", "half_range", "mid_range", "motor_lower", "motor_upper",
    "max_move", "dof_motor", "stiffness", "q_cmd", "forces")
structref.define_proxy(StepState, _StepStateType, _STEP_FIELDS)


@structref.register
class _NetworkStateType(_State):
    pass


class NetworkState(structref.StructRefProxy):
    """A network's parameters and states as ``_network_step`` takes them (built by
    ``network_state``; ``CompiledNetwork.state``)."""


_NETWORK_FIELDS = ("in_scale", "w_sm", "w_sh", "w_hm", "bias_h", "bias_m", "gain_h", "tau_h",
                   "tau_m", "hidden_frozen", "x", "hidden", "motor")
structref.define_proxy(NetworkState, _NetworkStateType, _NETWORK_FIELDS)


@njit(cache=True)
def _new_step_state(*fields):
    return StepState(*fields)


@njit(cache=True)
def _new_network_state(*fields):
    return NetworkState(*fields)


def _build(new, names: tuple[str, ...], fields: dict):
    """The structure of ``fields`` (every name of ``names``; arrays shared, not copied), built
    by compiled code (``new``) so that its constructor is compiled once and cached, not in
    every process; uncompiled (``NUMBA_DISABLE_JIT=1``), a plain object with the same
    fields, which the uncompiled step functions read alike."""
    if set(fields) != set(names):
        raise TypeError(f"fields missing {sorted(set(names) - set(fields))}, "
                        f"unknown {sorted(set(fields) - set(names))}")
    if numba_config.DISABLE_JIT:
        return SimpleNamespace(**fields)
    return new(*(fields[name] for name in names))


def step_state(**fields) -> StepState:
    """The ``StepState`` of ``fields`` (by name, ``_STEP_FIELDS``)."""
    return _build(_new_step_state, _STEP_FIELDS, fields)


def network_state(**fields) -> NetworkState:
    """The ``NetworkState`` of ``fields`` (by name, ``_NETWORK_FIELDS``)."""
    return _build(_new_network_state, _NETWORK_FIELDS, fields)


@njit(cache=True)
def sense_step(positions, ball, s):
    """Sense (``sense_posed``): the sensor vector ``s.x``, the motor-space angles ``s.q`` and
    the fitness terms ``s.p`` = (p_sight, p_touch, p_multimodal) (Eqs. 1-5) of the state DART
    reached (the joint positions, rad; the ball's centre, m). Whether it is finite."""
    return sense_posed(positions, ball, s.touching, s.order, s.parent, s.dof, s.axis, s.before,
                       s.after, s.scratch, s.poses, s.camera_body, s.hand_body, s.motor_dofs,
                       s.finger_dofs, s.lower, s.span, s.touch_segments, s.acuity, s.no_touch,
                       s.no_sight, s.offsets, s.pay, s.palm, s.q, s.x, s.p, s.sense_scratch)


@njit(cache=True)
def network_step(sensors_in, n):
    """One 0.1 s update of the network of ``NetworkState`` ``n`` from 25 sensor values
    (``_network_step``), in place on ``n.hidden`` and ``n.motor``."""
    _network_step(sensors_in, n.in_scale, n.w_sm, n.w_sh, n.w_hm, n.bias_h, n.bias_m,
                  n.gain_h, n.tau_h, n.tau_m, n.hidden_frozen, n.x, n.hidden, n.motor)


@njit(cache=True)
def act_step(s, n):
    """Act: the network ``n``'s update from the sensors ``s.x`` (``network_step``) and its
    motor targets 2 m - 1 into ``s.targets`` (``targets_of_motor``); whether finite."""
    network_step(s.x, n)
    return targets_of_motor(n.motor, s.targets)


@njit(cache=True)
def command_step(targets, gravity, s):
    """Command: the joint forces ``s.forces`` (N m) that drive the motors toward 14 targets in
    [-1, 1] under the servo's speed cap, from the gravity forces DART gives
    (``motor_commands``); whether the targets are finite."""
    return motor_commands(targets, s.half_range, s.mid_range, s.motor_lower, s.motor_upper,
                          s.max_move, s.dof_motor, s.stiffness, s.q_cmd, gravity, s.forces)


@njit(cache=True)
def control_step(t, positions, ball, gravity, s, n, p_series):
    """One control step of the genetic algorithm's trial in one call, from what DART gives
    after the last (the joint positions, the ball's centre, the gravity forces): the steps the
    recorded trial and the environment take one by one, in their order: ``sense_step``, step
    ``t``'s p_multimodal into ``p_series[t]``, ``act_step``, the touches cleared for the next
    period's substeps to gather (as ``servo.Servo.advance`` does before them), ``command_step``.
    Whether the state read and the targets are finite (the trial's fitness is 0 when not)."""
    if not sense_step(positions, ball, s):
        return False
    p_series[t] = s.p[2]
    if not act_step(s, n):
        return False
    s.touching[:] = False
    s.touching_any[:] = False
    return command_step(s.targets, gravity, s)


# ------------------------------------------------------------------------------ touch
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


@structref.register
class _TouchStateType(_State):
    pass


class TouchState(structref.StructRefProxy):
    """What ``inner_touches`` reads and writes besides the joint positions and the ball, in
    one object (built by ``touch_state``): the contacts' buffers, the skeleton's tree and
    poses, the segments' inner faces and the touches."""


_TOUCH_FIELDS = ("segments", "points", "need", "order", "parent", "dof", "axis", "before",
                 "after", "scratch", "poses", "segment_body", "direction", "cos_limit", "touch")
structref.define_proxy(TouchState, _TouchStateType, _TOUCH_FIELDS)


@njit(cache=True)
def _new_touch_state(*fields):
    return TouchState(*fields)


def touch_state(**fields) -> TouchState:
    """The ``TouchState`` of ``fields`` (by name, ``_TOUCH_FIELDS``)."""
    return _build(_new_touch_state, _TOUCH_FIELDS, fields)


@njit(cache=True)
def inner_touches(positions, ball, n, s):
    """Mark in ``s.touch`` the hand segments whose contacts with the ball (the first ``n`` of
    ``s.segments``, ``s.points``: the segment's index, the contact point in m) touch it on
    their inner face: the vector from the contact point to the ball's centre, in the segment's
    body frame, lies within the face's cone (``s.direction`` in the body frame,
    ``s.cos_limit``), as version 1's ``reference.servo.inner_face_touch`` decides in the
    shape's frame (a rotation keeps the angle). Only the poses of those segments' bodies and
    their ancestors are computed (``s.need`` and ``s.order``: scratches of one bool and one
    index per body)."""
    need, order, parent, segment_body = s.need, s.order, s.parent, s.segment_body
    segments, points, touch = s.segments, s.points, s.touch
    need[:] = False
    for c in range(n):
        b = segment_body[segments[c]]
        while b >= 0 and not need[b]:
            need[b] = True
            b = parent[b]
    m = 0
    for b in range(need.shape[0]):  # parents first: a parent's index is below its child's
        if need[b]:
            order[m] = b
            m += 1
    body_poses(positions, order[:m], parent, s.dof, s.axis, s.before, s.after, s.scratch,
               s.poses)
    for c in range(n):
        i = segments[c]
        if touch[i]:
            continue
        rot = s.poses[segment_body[i]]
        v0, v1, v2 = ball[0] - points[c, 0], ball[1] - points[c, 1], ball[2] - points[c, 2]
        o0 = rot[0, 0] * v0 + rot[1, 0] * v1 + rot[2, 0] * v2
        o1 = rot[0, 1] * v0 + rot[1, 1] * v1 + rot[2, 1] * v2
        o2 = rot[0, 2] * v0 + rot[1, 2] * v1 + rot[2, 2] * v2
        along = o0 * s.direction[i, 0] + o1 * s.direction[i, 1] + o2 * s.direction[i, 2]
        if along >= s.cos_limit[i] * math.sqrt(o0 * o0 + o1 * o1 + o2 * o2):
            touch[i] = True
