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
                  x0: np.ndarray | None = None) -> ReachSolution:
    """Joint angles that put the ball's centre ``radius + standoff`` in front of the palm's
    inner face, along its normal. Only the trunk and arm joints move; the head and fingers stay
    at home. The robot's state is restored afterwards."""
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
    robot.setPositions(saved)
    return ReachSolution(q=q.copy(), palm_error=err)


class ScriptedReach:
    """Targets for a reach with the open hand, then a grasp when the palm touches the ball."""

    def __init__(self, world: World, ball_position):
        self.world = world
        self.solution = grasp_posture(world, ball_position, standoff=-0.01)
        self.open_targets = world.targets_for(self.solution.q)
        self.closed_targets = self.open_targets.copy()
        self.closed_targets[13] = 1.0
        self.grasping = False

    def targets(self, contacts: np.ndarray) -> np.ndarray:
        """Motor targets for the next control step given the current hand contacts."""
        if contacts.any():  # some hand segment touches the ball
            self.grasping = True
        return self.closed_targets if self.grasping else self.open_targets
