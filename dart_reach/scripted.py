"""A hand-written reach-and-grasp, for demos, benchmarks and tests (not part of the paper's model).

``grasp_posture`` solves, by bounded least squares on the skeleton's forward kinematics, for
joint angles within the limits that put the inner face of the palm against the ball, facing it.
``ScriptedReach`` then drives the world toward that posture with the fingers open and closes the
hand once any hand segment touches the ball.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from . import icub
from .world import World


@dataclass(frozen=True)
class ReachSolution:
    q: np.ndarray  # full joint vector (rad), skeleton order, fingers open
    palm_error: float  # m, distance between the ball centre and where the posture puts it


def grasp_posture(world: World, ball_position, standoff: float = 0.0,
                  x0: np.ndarray | None = None, look: bool = False) -> ReachSolution:
    """Joint angles that put the ball's centre ``radius + standoff`` in front of the palm's
    inner face, along its normal. The trunk and arm joints move; with ``look`` the neck turns
    the camera toward the ball, else the head stays at home; the fingers stay open. The robot's
    state is restored afterwards."""
    robot, hand = world.robot, world.hand
    ball = np.asarray(ball_position, float)
    idx = world._motor_dofs[3:]  # torso (3) and arm (7); the neck stays put
    lo, hi = world.lower[idx], world.upper[idx]
    saved = robot.getPositions()
    q = world.home.copy()
    reach = world.config.ball.radius + standoff
    normal = np.array([0.0, -1.0, 0.0])  # the palm's inner normal in the r_hand frame

    def residual(x):
        q[idx] = x
        robot.setPositions(q)
        T = hand.getWorldTransform()
        R = T.rotation()
        return R @ (icub.PALM_POINT + reach * normal) + T.translation() - ball

    start = world.home[idx] if x0 is None else x0
    best = None
    for guess in (start, (lo + hi) / 2):
        sol = least_squares(residual, np.clip(guess, lo, hi), bounds=(lo, hi), xtol=1e-10)
        if best is None or sol.cost < best.cost:
            best = sol
    q[idx] = best.x
    err = float(np.linalg.norm(residual(best.x)))
    if look:
        # Then the neck, so that the ball projects on the optical axis of the head camera.
        neck = world._motor_dofs[:3]
        camera = world.camera

        def off_axis(x):
            q[neck] = x
            robot.setPositions(q)
            T = camera.getWorldTransform()
            v = T.rotation().T @ (ball - T.translation())
            return v[:2] / v[2]

        q[neck] = least_squares(off_axis, world.home[neck], bounds=(world.lower[neck],
                                                                     world.upper[neck])).x
    robot.setPositions(saved)
    return ReachSolution(q=q.copy(), palm_error=err)


class ScriptedReach:
    """Targets for a reach with the open hand, then a grasp when the palm touches the ball."""

    def __init__(self, world: World, ball_position, look: bool = False):
        self.world = world
        self.solution = grasp_posture(world, ball_position, standoff=-0.01, look=look)
        self.open_targets = world.targets_for(self.solution.q)
        self.closed_targets = self.open_targets.copy()
        self.closed_targets[13] = 1.0
        self.grasping = False

    def targets(self, contacts: np.ndarray) -> np.ndarray:
        """Motor targets for the next control step given the current hand contacts."""
        if contacts.any():  # some hand segment touches the ball
            self.grasping = True
        return self.closed_targets if self.grasping else self.open_targets


class ScriptedController:
    """A hand-written controller with the interface of ``ctrnn.Network`` (``reset``, ``step``,
    ``hidden``): it looks at the ball, reaches for it and closes the hand once a touch sensor
    fires. It knows the ball's position from the world, which the evolved networks do not: it
    is a yardstick for the fitness function, not a model of the robot."""

    def __init__(self, world: World, ball_position):
        self._reach = ScriptedReach(world, ball_position, look=True)
        self.hidden = np.zeros(8)
        self.motor = np.zeros(14)

    def reset(self, motor=None) -> None:
        self._reach.grasping = False

    def step(self, sensors: np.ndarray) -> np.ndarray:
        touching = sensors[14:20] > 0  # touch sensors read +1 on contact
        self.motor[:] = (self._reach.targets(touching) + 1.0) / 2.0
        return self.motor
