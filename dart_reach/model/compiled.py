"""The living model's numerics (model versions 2 and 3, ``versions.Numerics.COMPILED``): the
trial's step functions around DART's step (the sensors, the network, the fitness terms and the
motor commands of one 0.1 s control step), composed of the compiled kernels of
``model.kernels``, so that a trial costs little more than its physics. The kernels, one
module per concept of section III: the network (``kernels.network``, section III-B, Fig. 3),
the sensors and the fitness terms (``kernels.sensing``, Eqs. 1-5), the motor commands and the
servo's springs (``kernels.motors``), the inner-face touch (``kernels.touch``); what they
share: ``kernels.floats``, ``kernels.kinematics``, ``kernels.structures``. A change to the
model's equations edits them (docs/model/trial.md, "How to change the model").

Version 2 computes what version 1 computes (its frozen code: ``model.reference``; sections
III-B, III-C): the same equations, the same physics, the same DART step. Only the rounding may
differ, and it is the same on every processor, by construction:

- every sum is taken in index order, every product and quotient as written: compiled without
  ``fastmath``, LLVM may neither reorder nor fuse (no FMA) floating-point operations, so the
  vector width of the processor (SSE, AVX2, AVX-512) cannot change a result (tested: the same
  trials to the last bit compiled for the host and for a generic x86-64);
- the logistic's exponential (``kernels.floats.exp_nonpositive``) is written out from +, -, *
  and exact scaling by powers of 2, not taken from the C library, whose implementations differ
  between processors (glibc picks an FMA variant where the CPU has one) and between libraries;
- distances use ``sqrt`` (correctly rounded by IEEE 754), not ``hypot``; the acuity's power
  is a product for the paper's exponents 1 and 3 (section III-B), the C library's ``pow``
  only for other exponents a user may set; the offset sensors' visual angles (fine-reaching,
  Eq. 4) take the C library's ``atan2``, as version 1 does (Python's ``math.atan2``).

What stays numpy's in both versions (the scene's geometry: the sectors' points; the records'
hand point and palm normal) rounds alike on every processor under the dispatch level that
``import dart_reach`` pins, as in version 1.

One thing is commanded differently, to the same effect: the springs that drive the joints
are pulled toward the motors' commanded positions by joint forces k q_cmd, their rest
positions held at 0 (``kernels.motors.spring_forces``): the same force, and DART does not
prepare its world again at every control step, as it does after a new rest position.

Version 1 keeps its own code, frozen in ``model.reference``, and its digests: every run trained
under it reproduces bit for bit.
"""

from __future__ import annotations

from numba import njit
from numba.experimental import structref

from .kernels.motors import motor_commands
from .kernels.network import network_step, targets_of_motor
from .kernels.sensing import sense_posed
from .kernels.structures import Structure, build

# ------------------------------------------------------------------------------ the trial's steps
# One structure of the trial's arrays (``StepState``; why one: ``kernels.structures``) and
# the step functions over it and the network's ``kernels.network.NetworkState``.
@structref.register
class _StepStateType(Structure):
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


@njit(cache=True)
def _new_step_state(*fields):
    return StepState(*fields)


def step_state(**fields) -> StepState:
    """The ``StepState`` of ``fields`` (by name, ``_STEP_FIELDS``)."""
    return build(_new_step_state, _STEP_FIELDS, fields)


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
