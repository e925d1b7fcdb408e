"""The DART world of the experiment (paper sections III and III-A, Figs. 1-2).

An iCub upper body welded at the pelvis ("suspended vertically over a stick attached to the
pelvis"), gravity on, and a red ball hanging from a fixed pivot on a pendulum, placed in one of 9
sectors of a sphere centred on the robot's neck.

Frames: the world frame is the iCub ``root_link`` frame (pelvis): +x backward, +y to the robot's
right, +z up. Lengths in metres, angles in radians, time in seconds.

Control (section III-B): every ``control_dt`` = 0.1 s a controller gives 14 desired joint
positions in [-1, 1] (3 neck, 3 torso, 7 arm, 1 hand), scaled linearly into each motor's range
(the joint's limits less 1 % at each end, ``layout``), and the physics runs its substeps. Each
joint carries an implicit spring-damper (DART's joint spring, integrated implicitly, stable at
any stiffness) whose gains the world sets here; what drives the springs toward the targets, at
``max_joint_speed`` at most, with gravity compensation, and gathers the hand's touches in the
substeps is the model's servo, not the world's (the living model's ``servo.Servo``; version
1's frozen ``reference.servo.ReferenceServo``). Targets lie inside the limits, limits are
enforced by the constraint solver, and no actuator holds a joint at a limit, so no joint can
stay stuck there (the SERVO actuator can: DART issues #1683, #2422). The 15 finger flexion
joints all take the hand motor's target: the five fingers follow one motor, as in the paper;
each finger stops on its own when it meets the ball, like the iCub's tendon-driven fingers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import dartpy as dart
import numpy as np

from . import icub
from .bodies import SkeletonError, load_skeleton, make_ball
from .ctrnn import HAND_MOTOR, JOINT_MOTORS, N_MOTORS
from .layout import TOUCH_SEGMENTS, TouchFace, WorldLayout, kinematic_tree, segment_faces
from .sectors import (N_SECTORS, POINTS_PER_SECTOR, SYSTEMATIC_FRACTIONS, SectorConfig,
                      check_sector, sector_angles, sphere_point)

#: Fraction of each joint's range kept free of targets at both ends (see ``World``).
LIMIT_MARGIN = 0.01
#: Where the ball-absent test (``task.Senses.NO_BALL``, section IV-A-1) hangs the ball (m, world
#: frame): 50 m behind the robot, out of its reach and behind its camera whatever its posture.
BALL_PARKED = np.array([50.0, 0.0, 0.0])


@dataclass(frozen=True)
class BallConfig:
    """The target object (sections III, III-A). The paper gives no size: a 7 cm ball of 50 g is
    the size of the toy balls of the infant studies it replicates (Fig. 1) and fits the iCub hand
    (palm 8 cm, fingers 6-7 cm)."""

    radius: float = 0.035  # m
    mass: float = 0.05  # kg
    string_length: float = 0.40  # m, pivot to ball centre (period 2*pi*sqrt(L/g) = 1.27 s)
    damping: float = 0.004  # N m s / rad on the pendulum joint: amplitude decays as exp(-t / 4 s)
    #: deg, the largest swing about each of the pendulum's two axes (enforced limits): the ball
    #: stays at least 90 - acos(cos^2 75) = 4 deg below its pivot, as on a string.
    max_swing: float = 75.0
    friction: float = 1.0  # Coulomb coefficient of the ball's surface
    color: tuple[float, float, float] = (0.9, 0.05, 0.05)


@dataclass(frozen=True)
class WorldConfig:
    """Everything that defines the physics of a trial."""

    skeleton: Path | None = None  # None: the skeleton shipped with the package
    physics_dt: float = 0.02  # s per physics substep (5 per control step; see docs/model/world.md)
    control_dt: float = 0.1  # s per control step (section III-B)
    natural_frequency: float = 20.0  # rad/s of each joint's spring at the home posture
    damping_ratio: float = 1.0  # of each joint's spring-damper
    #: rad/s, the fastest a motor's commanded position may move (docs/model/world.md, III-B): the
    #: servo steps it toward the controller's targets by at most this times ``control_dt`` per
    #: control step (``layout.max_move``).
    max_joint_speed: float = 2.0
    gravity: float = 9.81  # m/s^2
    ball: BallConfig = field(default_factory=BallConfig)
    sectors: SectorConfig = field(default_factory=SectorConfig)
    #: A lever (docs/model/levers.md; the paper does not say): the right arm's bodies (shoulder
    #: to fingertips) collide with the rest of the body (pelvis, torso, chest, neck, head), so
    #: that a flexed arm cannot pass through the chest; the arm's own bodies never collide with
    #: each other (the primitive shapes of the hand, wrist and fingers overlap by construction).
    #: Off in model version 1: only the ball collides with the robot.
    self_collision: bool = False

    def __post_init__(self):
        if not isinstance(self.self_collision, bool):
            raise ValueError(f"self_collision must be true or false, got {self.self_collision!r}")
        for key in ("physics_dt", "control_dt"):
            if not 0 < getattr(self, key) < math.inf:
                raise ValueError(f"{key} must be a positive number of seconds, got "
                                 f"{getattr(self, key)!r}")
        ratio = self.control_dt / self.physics_dt
        if ratio < 1 or abs(ratio - round(ratio)) > 1e-9:
            raise ValueError(
                f"control_dt ({self.control_dt}) must be a whole multiple of physics_dt "
                f"({self.physics_dt})")
        if not self.max_joint_speed > 0:
            raise ValueError(f"max_joint_speed must be positive, got {self.max_joint_speed}")

    @property
    def substeps(self) -> int:
        return round(self.control_dt / self.physics_dt)




class World:
    """The robot, the ball on its pendulum and the physics: the skeletons, their ``layout``,
    ``reset`` and the readings, shared by every model version. No model equation: the motors
    are driven and the touches gathered by a servo over this world (the living model's
    ``servo.Servo``, which the trials of versions 2 and 3, the scripted reach and the studies
    step with; version 1's frozen ``reference.servo.ReferenceServo``; docs/model/world.md).

    Built once per process (DART objects cannot be pickled: send a ``WorldConfig`` to workers).
    """

    def __init__(self, config: WorldConfig | None = None):
        self.config = config = config or WorldConfig()
        self.robot = load_skeleton(config.skeleton or icub.default_skeleton())
        self.world = dart.simulation.World()
        self.world.setTimeStep(config.physics_dt)
        self.world.setGravity([0.0, 0.0, -config.gravity])
        self.world.getConstraintSolver().setCollisionDetector(
            dart.collision.DARTCollisionDetector())
        # Nothing here ever comes to rest long enough to sleep (the springs hold the robot, the
        # ball waits on its string): DART's deactivation test would only cost time.
        options = self.world.getDeactivationOptions()
        options.mEnabled = False
        self.world.setDeactivationOptions(options)
        self.world.addSkeleton(self.robot)
        self._resolve_robot()
        if config.self_collision:
            self._collide_arm_with_body()
        self.ball_skeleton, self._ball_joint, self.ball_body = make_ball(config.ball)
        self.world.addSkeleton(self.ball_skeleton)
        self._resolve_contacts()
        self._ball_shapes = set(self.ball_body.getShapeNodes())
        self._set_home()
        #: what the trial's step functions read of this world (``layout.WorldLayout``)
        self.layout = self._describe()
        self.neck_centre = self.robot.getBodyNode(icub.NECK).getWorldTransform().translation()
        self.reset(self.sector_point(4, 0.5, 0.5))

    # ------------------------------------------------------------------ construction helpers
    def _resolve_robot(self) -> None:
        r = self.robot
        try:
            motor_dofs = [r.getJoint(n).getIndexInSkeleton(0) for n in icub.ARM_HEAD_TORSO_JOINTS]
            finger_dofs = [r.getJoint(n).getIndexInSkeleton(0) for n in icub.FINGER_JOINTS]
            self._segments = [r.getBodyNode(n) for n in icub.HAND_SEGMENTS]
            self.hand = r.getBodyNode(icub.HAND)
            self.shoulder = r.getBodyNode(icub.SHOULDER)
            self.camera = r.getBodyNode(icub.CAMERA)
        except AttributeError as exc:  # dartpy returns None for an unknown name
            raise SkeletonError(
                f"skeleton {self.config.skeleton or icub.default_skeleton()} lacks a joint or "
                f"body the model needs ({exc})") from None
        if None in self._segments or None in (self.hand, self.shoulder, self.camera):
            raise SkeletonError("skeleton lacks a hand segment, the shoulder or the camera frame")
        n = r.getNumDofs()
        # dof_motor[i]: which of the 14 motors drives dof i (13 = the hand), -1 if none.
        self._dof_motor = np.full(n, -1)
        self._dof_motor[motor_dofs] = np.arange(JOINT_MOTORS.stop)
        self._dof_motor[finger_dofs] = HAND_MOTOR
        if (self._dof_motor < 0).any():
            raise SkeletonError("skeleton has joints that no motor drives")
        self._motor_dofs = np.array(motor_dofs)
        self._finger_dofs = np.array(finger_dofs)
        self._finger_q = np.zeros(len(finger_dofs))
        self.lower = np.asarray(r.getPositionLowerLimits())
        self.upper = np.asarray(r.getPositionUpperLimits())
        if not (np.isfinite(self.lower).all() and np.isfinite(self.upper).all()
                and (self.upper > self.lower).all()):
            raise SkeletonError("every joint of the skeleton needs finite limits, lower < upper")
        # Per-motor target ranges (the hand motor: finger flexion [0, pi/2]): the joint limits
        # shrunk by LIMIT_MARGIN of the range at each end, so that no joint at rest sits on its
        # limit (an active limit constraint doubles the cost of a physics step).
        # ``motor_limit_*`` are the joint limits per motor (what the proprioceptors span).
        lo = np.append(self.lower[self._motor_dofs], self.lower[finger_dofs].max())
        hi = np.append(self.upper[self._motor_dofs], self.upper[finger_dofs].min())
        self.motor_limit_lower, self.motor_limit_upper = lo, hi
        self.motor_lower = lo + LIMIT_MARGIN * (hi - lo)
        self.motor_upper = hi - LIMIT_MARGIN * (hi - lo)
        self._dofs = [r.getDof(i) for i in range(n)]
        for j in r.getJoints()[1:]:
            j.setActuatorType(dart.dynamics.ActuatorType.FORCE)
            j.setLimitEnforcement(True)

    def _describe(self) -> WorldLayout:
        """The world's ``WorldLayout``: copies of what the construction resolved, frozen."""
        r = self.robot
        tree = kinematic_tree(r)
        index = {r.getBodyNode(i).getName(): i for i in range(r.getNumBodyNodes())}
        camera, hand = index[icub.CAMERA], index[icub.HAND]
        direction, cos_limit = segment_faces(icub.HAND_SEGMENTS)
        ints = lambda a: np.array(a, np.int64)  # noqa: E731
        floats = lambda a: np.array(a, float)  # noqa: E731
        return WorldLayout(
            n_dofs=r.getNumDofs(), motor_dofs=ints(self._motor_dofs),
            finger_dofs=ints(self._finger_dofs), dof_motor=ints(self._dof_motor),
            motor_limit_lower=floats(self.motor_limit_lower),
            motor_limit_span=floats(self.motor_limit_upper - self.motor_limit_lower),
            motor_lower=floats(self.motor_lower), motor_upper=floats(self.motor_upper),
            half_range=floats(0.5 * (self.motor_upper - self.motor_lower)),
            mid_range=floats(0.5 * (self.motor_upper + self.motor_lower)),
            max_move=float(self.config.max_joint_speed * self.config.control_dt),
            stiffness=floats(self.stiffness),
            touch_segments=TOUCH_SEGMENTS, camera_body=camera, hand_body=hand,
            shoulder_body=index[icub.SHOULDER],
            segment_body=ints([index[name] for name in icub.HAND_SEGMENTS]),
            face_direction=direction, face_cos_limit=cos_limit,
            sensed_bodies=tree.chain(camera, hand), tree=tree,
            touch_faces=MappingProxyType(self._touch_faces),
            segment_index=MappingProxyType(self._segment_index),
            ball_shapes=frozenset(self._ball_shapes))

    def _collide_arm_with_body(self) -> None:
        """Self-collision on (``WorldConfig.self_collision``) for the arm against the body only:
        every pair of bodies inside the right arm's subtree, and inside the body, is left out
        by the constraint solver's collision filter."""
        r = self.robot
        r.setSelfCollisionCheck(True)
        r.setAdjacentBodyCheck(False)
        bodies = [r.getBodyNode(i) for i in range(r.getNumBodyNodes())]
        arm = arm_body_names(r)
        ignore = self.world.getConstraintSolver().getCollisionOption().collisionFilter
        for i, a in enumerate(bodies):
            for b in bodies[i + 1:]:
                if (a.getName() in arm) == (b.getName() in arm):
                    ignore.addBodyNodePairToBlackList(a, b)

    def _resolve_contacts(self) -> None:
        """Touch (III-B, III-C): for the collision shape of each hand segment, its index and the
        direction of its inner (palmar) face in the shape's frame (``icub.INNER_FACES``)."""
        # Keyed by the shape node itself: dartpy hands back the same Python object for a shape
        # node it has wrapped before, so a contact's shape frame is found without asking DART
        # for its name (a contact read per substep must cost little: docs/model/world.md).
        self._touch_faces = {}
        for i, body in enumerate(self._segments):
            direction, half_angle = icub.INNER_FACES[icub.segment_kind(body.getName())]
            cos_limit = math.cos(math.radians(half_angle))
            for shape in body.getShapeNodes():
                if shape.getCollisionAspect() is not None:
                    inner = shape.getRelativeTransform().rotation().T @ np.asarray(direction)
                    inner.flags.writeable = False
                    self._touch_faces[shape] = TouchFace(i, inner, cos_limit,
                                                         tuple(inner.tolist()))
        #: (16,) bool per hand segment (``icub.HAND_SEGMENTS``), the touches of the last
        #: control step, gathered by its physics substeps: on the segment's inner face
        #: (``touched``, III-B, III-C) and on any face (``touched_any``, the reach of IV-A-1).
        #: Written by the servo's substeps (``servo.Servo``; version 1's ``reference.servo``),
        #: cleared by ``reset``.
        self.touched = np.zeros(len(self._segments), bool)
        self.touched_any = np.zeros(len(self._segments), bool)
        self._segment_index = {body: i for i, body in enumerate(self._segments)}

    def _set_home(self) -> None:
        """Home posture and the per-joint spring gains (from the joint-space inertia there)."""
        r = self.robot
        home = np.zeros(r.getNumDofs())
        for name, value in icub.HOME_POSTURE.items():
            home[r.getJoint(name).getIndexInSkeleton(0)] = value
        margin = LIMIT_MARGIN * (self.upper - self.lower)
        self.home = np.clip(home, self.lower + margin, self.upper - margin)
        r.setPositions(self.home)
        inertia = np.diag(r.getMassMatrix())
        w, zeta = self.config.natural_frequency, self.config.damping_ratio
        self.stiffness = inertia * w * w
        self.damping = 2.0 * zeta * inertia * w
        for dof, k, c in zip(self._dofs, self.stiffness, self.damping):
            dof.setSpringStiffness(k)
            dof.setDampingCoefficient(c)
        self.home_motor = self._motor_angles(self.home)
        self.home_targets = self.targets_for(self.home)

    # ------------------------------------------------------------------ sectors
    def sector_point(self, sector: int, u: float, v: float) -> np.ndarray:
        """World position (m) of the point at fractions (u, v) of a sector (Fig. 2)."""
        az, el = sector_angles(self.config.sectors, sector, u, v)
        return sphere_point(self.neck_centre, self.config.sectors.radius, az, el)

    def random_sector_point(self, sector: int, rng: np.random.Generator) -> np.ndarray:
        """A point drawn uniformly in a sector's azimuth and elevation (training trials)."""
        check_sector(sector)
        u, v = rng.random(2)
        return self.sector_point(sector, u, v)

    def systematic_points(self) -> np.ndarray:
        """The 45 post-evaluation positions (9 sectors x 5 points), shape (45, 3)."""
        return np.array([self.sector_point(k, u, v) for k in range(N_SECTORS)
                         for u, v in SYSTEMATIC_FRACTIONS])

    # ------------------------------------------------------------------ trial control
    def reset(self, ball_position) -> None:
        """Start a trial: home posture, every velocity, force and command zero, the ball at
        rest at ``ball_position`` (its pivot ``string_length`` straight above), time 0, no
        touch. The motors are commanded by the servo's reset after it (``servo.Servo.reset``;
        version 1's ``reference.servo.ReferenceServo.reset``)."""
        p = np.asarray(ball_position, dtype=float)
        if p.shape != (3,) or not np.isfinite(p).all():
            raise ValueError(f"ball position must be 3 finite numbers, got {ball_position!r}")
        r = self.robot
        r.setPositions(self.home)
        r.resetVelocities()
        r.resetAccelerations()
        r.resetCommands()
        r.clearExternalForces()
        r.clearConstraintImpulses()
        T = dart.math.Isometry3()
        T.set_translation(p + [0.0, 0.0, self.config.ball.string_length])
        self._ball_joint.setTransformFromParentBodyNode(T)
        self.ball_skeleton.resetPositions()
        self.ball_skeleton.resetVelocities()
        self.ball_skeleton.resetAccelerations()
        self.ball_skeleton.clearConstraintImpulses()
        self.world.setTime(0.0)
        self.touched[:] = False
        self.touched_any[:] = False

    def _motor_angles(self, q: np.ndarray) -> np.ndarray:
        """The 14 motor-space angles (rad) of a full joint vector: 13 joints, then the mean
        finger flexion."""
        return np.append(q[self._motor_dofs], q[self._finger_dofs].mean())

    def targets_for(self, q: np.ndarray) -> np.ndarray:
        """The 14 motor targets in [-1, 1] that hold the robot at joint positions ``q``."""
        motor_q = self._motor_angles(np.asarray(q, float))
        return 2.0 * (motor_q - self.motor_lower) / (self.motor_upper - self.motor_lower) - 1.0

    @property
    def time(self) -> float:
        return self.world.getTime()

    # ------------------------------------------------------------------ observations
    # Read once per control step: every ``Frame.getTransform()``, ``getCOM()`` and
    # ``getWorldTransform()`` is a call into dartpy (their costs: docs/results/benchmarks.md).
    def joint_positions(self) -> np.ndarray:
        """All joint angles (rad), skeleton order."""
        return self.robot.getPositions()

    def motor_positions(self, out: np.ndarray | None = None,
                        positions: np.ndarray | None = None) -> np.ndarray:
        """The 14 motor-space joint angles (rad): the 13 joints, then the mean finger flexion;
        of the skeleton's ``positions`` when given (``joint_positions()``, read once)."""
        q = self.robot.getPositions() if positions is None else positions
        out = np.empty(N_MOTORS) if out is None else out
        q.take(self._motor_dofs, out=out[JOINT_MOTORS])
        # the mean as ``ndarray.mean`` computes it (the sum divided by the count), without
        # its wrapper
        out[HAND_MOTOR] = np.add.reduce(q.take(self._finger_dofs, out=self._finger_q)
                                ) / len(self._finger_dofs)
        return out

    def ball_position(self) -> np.ndarray:
        """World position (m) of the ball's centre (its body's centre of mass)."""
        return self.ball_body.getCOM()

    def hand_position(self) -> np.ndarray:
        """World position (m) of the centre of the inner face of the palm."""
        return palm_point(self.hand_transform())

    def hand_transform(self) -> np.ndarray:
        """4x4 world pose of the hand (``r_hand``): the palm point (``palm_point``) and the
        palm's normal (its rotation times ``PALM_NORMAL``) from one read."""
        return self.hand.getTransform().matrix()

    def shoulder_position(self) -> np.ndarray:
        return self.shoulder.getTransform().matrix()[:3, 3]

    def camera_pose(self) -> np.ndarray:
        """4x4 world pose of the head camera (+z optical axis, +x right, +y down)."""
        return self.camera.getTransform().matrix()

    def hand_contacts_any(self, out: np.ndarray | None = None) -> np.ndarray:
        """Which hand segments touched the ball on any face (inner, back or side) in any
        physics substep of the last control step: the touch of the paper's reach ("touch the
        object at least once with the hand", IV-A-1). A superset of ``hand_contacts``."""
        if out is None:
            return self.touched_any.copy()
        out[:] = self.touched_any
        return out

    def hand_contacts(self, out: np.ndarray | None = None) -> np.ndarray:
        """Which hand segments (``icub.HAND_SEGMENTS``) touched the ball on their inner face
        in any physics substep of the last control step, as booleans (III-B, III-C)."""
        if out is None:
            return self.touched.copy()
        out[:] = self.touched
        return out

    def is_finite(self) -> bool:
        """False once the simulation has exploded (NaN or infinite state)."""
        return bool(np.isfinite(self.robot.getPositions()).all()
                    and np.isfinite(self.robot.getVelocities()).all()
                    and np.isfinite(self.ball_skeleton.getPositions()).all())


def arm_body_names(robot) -> set[str]:
    """The names of the right arm's bodies: the shoulder's first link (``icub.SHOULDER``) and
    every body below it, to the fingertips."""
    arm: set[str] = set()
    for i in range(robot.getNumBodyNodes()):  # parents come before their children
        body = robot.getBodyNode(i)
        parent = body.getParentBodyNode()
        if body.getName() == icub.SHOULDER or (parent is not None and parent.getName() in arm):
            arm.add(body.getName())
    return arm


def palm_point(hand_pose: np.ndarray) -> np.ndarray:
    """World position (m) of the centre of the palm's inner face (``icub.PALM_POINT``) for a
    4x4 world pose of the hand (``World.hand_transform``)."""
    return hand_pose[:3, :3] @ icub.PALM_POINT + hand_pose[:3, 3]


#: The palm's inner face normal in the ``r_hand`` frame (``icub.INNER_FACES``): the records'
#: palm normal (``TrialData.palm_normal``, the swipes of IV-A-2) is the hand's rotation times
#: it, computed by each numerics' own code (``kernels.sensing.record_row``; version 1's
#: ``reference.steps.palm_normal``).
PALM_NORMAL = np.asarray(icub.INNER_FACES["palm"][0])
