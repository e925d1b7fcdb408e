"""A hand-written reach-and-grasp, for demos, benchmarks, tests and ``dart-reach validate``
(not part of the paper's model: it knows the ball's position, which the robots do not).

``grasp_posture`` solves, by bounded least squares on the skeleton's forward kinematics, for
joint angles within the limits that put the inner face of the palm against the ball from below
and from the robot's side (palm normal between straight up and the shoulder-to-ball direction,
fingers pointing away from the shoulder), like the robots' palm-up swipes of section IV-A-2.
``ScriptedReach`` drives the world through postures 8 and 4 cm back along the palm's normal
(fingers open), slowly onto the ball (it hangs free and swings away if hit), and closes the hand
as soon as an inner face touches the ball, or once the hand has arrived; a closed hand that has
not grasped (palm and a finger at once) within ``RETRY_STEPS`` opens and approaches again.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from . import icub
from .ctrnn import ARM, HAND_MOTOR, NECK, TORSO
from .world import World

#: The motors of the torso (3) and the arm (7), which the scripted reach moves.
TRUNK_AND_ARM = slice(TORSO.start, ARM.stop)

#: The palm's inner normal in the ``r_hand`` frame (``icub.INNER_FACES``).
PALM_NORMAL = np.array(icub.INNER_FACES["palm"][0])
#: Metres of palm-normal alignment error that weigh as much as one metre of position error.
ORIENTATION_WEIGHT = 0.03
#: The palm's normal is this blend of straight up and the shoulder-to-ball direction.
UP_BLEND = 0.6
#: Where the ball is put against the palm (``r_hand`` frame, m): the inner face, 3 cm from its
#: centre toward the fingers, so that they close around the ball.
GRASP_POINT = icub.PALM_POINT + np.array([-0.03, 0.0, 0.0])
#: The fingers' direction in the ``r_hand`` frame, and the weight (m per unit) of its
#: alignment with the direction from the shoulder to the ball.
FINGER_AXIS = np.array([-1.0, 0.0, 0.0])
FINGER_WEIGHT = 0.01
#: Stand-offs of the approach postures (m, along the palm's normal), one after the other.
APPROACH_STANDOFFS = (0.08, 0.04)
#: Stand-off of the grasp posture (m): the palm's face on the ball's surface.
GRASP_STANDOFF = 0.0
#: Control steps per stage: at each approach posture, on the way (linearly) from the last one
#: onto the ball, and at the grasp posture; then the hand closes even if it felt nothing.
STAGE_STEPS = 10
#: Control steps a closing hand waits for a grasp before it opens and approaches again (a ball
#: touched at the rim of the reachable space can roll off the palm).
RETRY_STEPS = 2 * STAGE_STEPS


def _unit(v):
    return v / np.linalg.norm(v)


@dataclass(frozen=True)
class ReachSolution:
    q: np.ndarray  # full joint vector (rad), skeleton order, fingers open
    palm_error: float  # m, distance between the ball centre and where the posture puts it


def grasp_posture(world: World, ball_position, standoff: float = 0.0,
                  x0: np.ndarray | None = None, look: bool = False) -> ReachSolution:
    """Joint angles that put the ball's centre ``radius + standoff`` in front of the palm's
    inner face (at ``GRASP_POINT``), along its normal, oriented as the module says. The trunk
    and arm joints move; with ``look`` the neck turns
    the camera toward the ball, else the head stays at home; the fingers stay open. The result
    does not depend on the robot's current state, which is restored afterwards."""
    robot, hand = world.robot, world.hand
    ball = np.asarray(ball_position, float)
    idx = world.layout.motor_dofs[TRUNK_AND_ARM]  # the neck stays put
    lo, hi = world.lower[idx], world.upper[idx]
    saved = robot.getPositions()
    q = world.home.copy()
    robot.setPositions(q)  # directions from the shoulder where it starts a trial, at home
    reach = world.config.ball.radius + standoff
    approach = _unit(UP_BLEND * np.array([0.0, 0.0, 1.0])
                     + (1.0 - UP_BLEND) * _unit(ball - world.shoulder_position()))

    def palm_residual(x):
        q[idx] = x
        robot.setPositions(q)
        T = hand.getWorldTransform()
        R = T.rotation()
        return R @ (GRASP_POINT + reach * PALM_NORMAL) + T.translation() - ball, R

    forward = ball - world.shoulder_position()
    forward = _unit(forward - (forward @ approach) * approach)

    def residual(x):
        position, R = palm_residual(x)
        return np.concatenate([position, ORIENTATION_WEIGHT * (R @ PALM_NORMAL - approach),
                               FINGER_WEIGHT * (R @ FINGER_AXIS - forward)])

    start = world.home[idx] if x0 is None else x0
    best = None
    for guess in (start, (lo + hi) / 2):
        sol = least_squares(residual, np.clip(guess, lo, hi), bounds=(lo, hi), xtol=1e-10)
        if best is None or sol.cost < best.cost:
            best = sol
    q[idx] = best.x
    err = float(np.linalg.norm(palm_residual(best.x)[0]))
    if look:
        # Then the neck, so that the ball projects on the optical axis of the head camera.
        neck = world.layout.motor_dofs[NECK]
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
    """Targets for an approach with the open hand along the palm's normal (through
    ``APPROACH_STANDOFFS``), then a grasp: the hand closes as soon as the palm touches the ball,
    or once the hand has arrived; without a grasp ``RETRY_STEPS`` later it starts again."""

    def __init__(self, world: World, ball_position, look: bool = False):
        self.world = world
        self.solution = grasp_posture(world, ball_position, standoff=GRASP_STANDOFF, look=look)
        x0 = self.solution.q[world.layout.motor_dofs[TRUNK_AND_ARM]]
        self.waypoints = [world.targets_for(grasp_posture(world, ball_position, standoff=s,
                                                          x0=x0, look=look).q)
                          for s in APPROACH_STANDOFFS]
        self.open_targets = world.targets_for(self.solution.q)
        self.waypoints.append(self.open_targets)
        self.closed_targets = self.open_targets.copy()
        self.closed_targets[HAND_MOTOR] = 1.0
        self.reset()

    def reset(self) -> None:
        self.steps = 0
        self.grasping = False
        self.closing_steps = 0
        self.held = False

    def targets(self, contacts: np.ndarray) -> np.ndarray:
        """Motor targets for the next control step given the current inner-face touches
        (``World.hand_contacts``, palm first)."""
        if self.grasping:
            self.closing_steps += 1
            self.held |= bool(contacts[0] and contacts[1:].any())
            if self.closing_steps > RETRY_STEPS and not self.held:
                self.reset()
        stage = self.steps // STAGE_STEPS
        self.steps += 1
        if contacts.any() or stage > len(self.waypoints):
            self.grasping = True
        if self.grasping:
            return self.closed_targets
        last = len(self.waypoints) - 1
        if stage < last - 1:
            return self.waypoints[stage]
        if stage == last - 1:  # the last stretch, slowly: the ball hangs free
            f = (self.steps % STAGE_STEPS) / STAGE_STEPS
            return (1 - f) * self.waypoints[last - 1] + f * self.waypoints[last]
        return self.waypoints[last]


class ScriptedController:
    """A hand-written controller with the interface of ``ctrnn.Network`` (``reset``, ``step``,
    ``hidden``): it looks at the ball, reaches for it and closes the hand once the palm's
    touch sensor fires. It knows the ball's position from the world, which the evolved
    networks do not: it is a yardstick for the fitness function, not a model of the robot."""

    def __init__(self, world: World, ball_position):
        self._reach = ScriptedReach(world, ball_position, look=True)
        self.hidden = np.zeros(8)
        self.motor = np.zeros(14)

    def reset(self, motor=None) -> None:
        self._reach.reset()

    def step(self, sensors: np.ndarray) -> np.ndarray:
        touching = sensors[14:20] > 0  # touch sensors read +1 on contact, palm first
        self.motor[:] = (self._reach.targets(touching) + 1.0) / 2.0
        return self.motor
