"""The motor commands of the living model's servo (section III-B), compiled: every 0.1 s the
network's (or another controller's) 14 motor targets in [-1, 1], in ``ctrnn.MOTOR_NAMES``'
order (``ctrnn.NECK``, ``TORSO``, ``ARM``, ``HAND_MOTOR``), are scaled into their motors'
ranges, each motor's commanded position moves toward its target at most at the speed cap
(``WorldConfig.max_joint_speed`` x ``control_dt``), and every degree of freedom is commanded
the joint force that pulls its spring toward its motor's commanded position, plus the gravity
compensation. ``servo.Servo.command`` calls them; the arrays are the world's layout's
(``layout.WorldLayout``: the ranges, the limits, the speed cap, the springs' stiffness, which
motor drives each degree of freedom). Units: angles in rad, forces in N m, stiffness in
N m / rad."""

from __future__ import annotations

import math

from numba import njit

from ..ctrnn import N_MOTORS
from .floats import clip


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
        q = clip(targets[i] * half_range[i] + mid_range[i], lower[i], upper[i])
        q_cmd[i] += clip(q - q_cmd[i], -max_move, max_move)
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
