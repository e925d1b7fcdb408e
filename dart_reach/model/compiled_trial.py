"""The steps of a trial under model version 2's compiled numerics (``versions.Numerics.
COMPILED``; the kernels: ``model.compiled``): ``task.Trial`` takes them in place of its own,
so that ``Trial(world, config)``, ``run``, ``fitness`` and the environment's ``control`` are
the same code under both versions."""

from __future__ import annotations

import math

import numpy as np

from . import icub
from .compiled import (PAY_CODES, CompiledNetwork, control_state, control_step, inner_touches,
                       motor_commands, network_targets, record_row, sense_posed,
                       spring_forces, targets_of_motor, touch_state)
from .ctrnn import N_MOTORS, Network
from .icub import HAND_SEGMENTS, INNER_FACES, PALM_POINT, TOUCH_BODIES, segment_kind
from .world import PALM_NORMAL, SkeletonError

#: Indices in ``HAND_SEGMENTS`` of the six touch-sensor bodies (palm, fingertips).
TOUCH_SEGMENTS = np.array([HAND_SEGMENTS.index(b) for b in TOUCH_BODIES], np.int64)


class CompiledSteps:
    """The steps of a ``task.Trial`` under ``Numerics.COMPILED`` (model version 2), which
    ``Trial`` takes in place of its own when ``config.numerics`` says so: its sensing
    (``sense_posed``), record (``record_row``), network update (``network_targets``),
    motor commands (``motor_commands``) and inner-face touches (``inner_touches``),
    compiled (``model.compiled``); and the genetic algorithm's trial (``fitness``) with
    each control step in one compiled call (``control_step``). It shares the trial's buffers
    and writes what the trial reads after a step (the positions, the ball, the hand's pose,
    the fitness terms). Per control step it asks DART for the joint positions and the ball's
    centre once each; the bodies' poses it needs come from them (``body_poses``), and per
    physics substep in contact the contacts' points."""

    def __init__(self, trial):
        self.trial = trial
        self.world = w = trial.world
        self.config = config = trial.config
        self._x, self._q, self._targets = trial._x, trial._q, trial._targets
        self._no_touch, self._no_sight = trial._no_touch, trial._no_sight
        self._offsets = trial._offsets
        # the world's own record of this control step's touches
        self._contacts = trial._contacts = w._touch
        self._p3 = np.zeros(3)
        self._palm = np.asarray(PALM_POINT, float)
        self._no_ball = trial._no_ball
        self._resolve_kinematics()
        self._substeps = self._substeps_of()
        #: the hand's pose as ``sense`` computed it last (a view of the poses)
        self._hand_view = self._kinematics[-1][self._hand_body]
        self._sense_args = (
            self._sensed_bodies, *self._kinematics, self._camera_body, self._hand_body,
            w._motor_dofs.astype(np.int64), w._finger_dofs.astype(np.int64),
            np.asarray(w.motor_limit_lower, float),
            np.asarray(w.motor_limit_upper - w.motor_limit_lower, float),
            TOUCH_SEGMENTS.astype(np.int64), float(config.acuity), self._no_touch,
            self._no_sight, self._offsets, PAY_CODES[config.touch_pay],
            self._palm, self._q, self._x, self._p3, np.zeros(9))
        self._q_cmd = np.zeros(N_MOTORS)
        self._forces = np.zeros(w.robot.getNumDofs())
        self._spring_args = (w._dof_motor.astype(np.int64), np.asarray(w.stiffness, float))
        self._command_args = (
            np.asarray(w._half_range), np.asarray(w._mid_range), np.asarray(w._lower_list),
            np.asarray(w._upper_list), float(w._max_move), *self._spring_args, self._q_cmd)

    # ---------------------------------------------------------------- kinematics and touch
    def _resolve_kinematics(self) -> None:
        """The skeleton's kinematic tree for ``body_poses`` (revolute and weld joints
        only) and the hand segments' inner faces in their bodies' frames (``icub.INNER_FACES``)."""
        r = self.world.robot
        bodies = [r.getBodyNode(i) for i in range(r.getNumBodyNodes())]
        index = {b.getName(): i for i, b in enumerate(bodies)}
        n = len(bodies)
        parent, dof = np.full(n, -1, np.int64), np.full(n, -1, np.int64)
        axis, before, after = np.zeros((n, 3)), np.zeros((n, 4, 4)), np.zeros((n, 4, 4))
        for i, body in enumerate(bodies):
            up, joint = body.getParentBodyNode(), body.getParentJoint()
            parent[i] = -1 if up is None else index[up.getName()]
            kind = type(joint).__name__
            if kind == "RevoluteJoint":
                dof[i], axis[i] = joint.getIndexInSkeleton(0), joint.getAxis()
            elif kind != "WeldJoint":
                raise SkeletonError(f"model version 2 computes the bodies' poses from revolute "
                                    f"and weld joints; joint {joint.getName()} is a {kind}")
            before[i] = joint.getTransformFromParentBodyNode().matrix()
            child = joint.getTransformFromChildBodyNode().matrix()
            after[i, :3, :3] = child[:3, :3].T
            after[i, :3, 3] = -child[:3, :3].T @ child[:3, 3]
            after[i, 3, 3] = 1.0
        m = len(HAND_SEGMENTS)
        self._segment_body = np.array([index[name] for name in HAND_SEGMENTS], np.int64)
        self._direction = np.array([INNER_FACES[segment_kind(name)][0] for name in HAND_SEGMENTS])
        self._cos_limit = np.array([math.cos(math.radians(INNER_FACES[segment_kind(name)][1]))
                                    for name in HAND_SEGMENTS])
        #: the tree, a scratch and the poses ``body_poses`` computes (n, 4, 4)
        self._kinematics = (parent, dof, axis, before, after, np.zeros((3, 4, 4)),
                            np.zeros((n, 4, 4)))
        self._camera_body, self._hand_body = index[icub.CAMERA], index[icub.HAND]
        self._shoulder_body = index[icub.SHOULDER]  # on the hand's chain

        if (parent >= np.arange(n)).any():
            raise SkeletonError("model version 2 needs the skeleton's bodies after their parents")

        def chain(*ends):  # the bodies from the root to ``ends``, parents first
            found = set()
            for b in ends:
                while b >= 0 and b not in found:
                    found.add(b)
                    b = parent[b]
            return np.array(sorted(found), np.int64)  # a parent's index is below its child's
        self._sensed_bodies = chain(self._camera_body, self._hand_body)
        # the bodies whose poses a touch decision needs, and their indices
        self._need, self._order = np.zeros(n, bool), np.zeros(n, np.int64)
        self._objects = {}  # a collision object -> (its hand segment or -1, is it the ball)
        self._hold_contacts(4 * m)

    def _hold_contacts(self, n: int) -> None:
        """Buffers for ``n`` contacts' hand segments and points, and the ``TouchState`` of
        ``inner_touches`` that holds them."""
        self._contact_segments, self._contact_points = np.zeros(n, np.int64), np.zeros((n, 3))
        self._touch_state = touch_state(
            self._contact_segments, self._contact_points, self._need, self._order,
            *self._kinematics, self._segment_body, self._direction, self._cos_limit,
            self.world._touch)

    def _object(self, obj) -> tuple[int, bool]:
        """What a collision object is to touch: (its hand segment's index or -1, the ball?);
        remembered (dartpy hands back the same Python object for it while one is held)."""
        frame = obj.getShapeFrame()
        face = self.world._touch_faces.get(frame)
        found = self._objects[obj] = (-1 if face is None else face[0],
                                      frame in self.world._ball_shapes)
        return found

    def advance(self) -> None:
        """``world.World.advance`` with the inner-face touches decided by compiled code
        (``inner_touches``) from the skeleton's joint positions and the contacts' points."""
        w = self.world
        w._touch[:] = False
        w._touch_any[:] = False
        self._substeps()

    def _substeps_of(self):
        """The physics substeps of one control period, the touches gathered into the world's
        (cleared) records; a closure over what it calls."""
        w = self.world
        step, last_collisions = w.world.step, w.world.getLastCollisionResult
        mark, gather = w.mark_colliding_segments, self._gather
        self_collision, substeps = w.config.self_collision, w.config.substeps

        def run_substeps() -> None:
            deciding = False  # the last substep had contacts to decide: likely this one has
            for _ in range(substeps):
                step(False)
                result = last_collisions()
                n = result.getNumContacts()
                if not n:
                    deciding = False
                elif self_collision or deciding or mark(result):
                    deciding = gather(result, n)
        return run_substeps

    def _gather(self, result, n: int) -> bool:
        """Mark the touches of one substep's ``n`` contacts (``touch_any``: any face;
        ``touch``: the inner face, ``inner_touches``); whether any contact had an inner face to
        decide."""
        if n > len(self._contact_segments):
            self._hold_contacts(2 * n)
        w, objects, lookup = self.world, self._objects, self._object
        self_collision = w.config.self_collision
        touch, touch_any = w._touch, w._touch_any
        segments, points = self._contact_segments, self._contact_points
        k = 0
        for contact in result.getContacts():
            o1 = contact.collisionObject1
            i, ball1 = objects.get(o1) or lookup(o1)
            if self_collision or ball1:  # else the other one is the ball: a touch if i >= 0
                o2 = contact.collisionObject2
                seg2, ball2 = objects.get(o2) or lookup(o2)
                if i >= 0 and not ball2:
                    i = -1
                if i < 0 and ball1:
                    i = seg2
            if i < 0:  # not a hand segment with the ball
                continue
            touch_any[i] = True
            if touch[i]:
                continue
            segments[k] = i
            points[k] = contact.point
            k += 1
        if k:
            inner_touches(w.robot.getPositions(), w.ball_body.getCOM(), k, self._touch_state)
        return k > 0

    def targets_of(self, motor: np.ndarray) -> bool:
        return targets_of_motor(motor, self._targets)

    def act(self, network: Network) -> bool:
        """``Trial._act``: the network's update and its targets in one compiled call."""
        if type(network) is not CompiledNetwork:  # a version 1 network: its own step
            return targets_of_motor(network.step(self._x), self._targets)
        return network_targets(self._x, *network._args, self._targets)

    def fitness(self, network: Network, p: np.ndarray) -> float | None:
        """``Trial.fitness``'s steps after the reset, to the last bit, with a control step's
        sensing, network and motor commands in one compiled call (``control_step``) and
        p_multimodal into ``p`` (one per step); None for a network of version 1, which the
        trial steps by its own loop."""
        if type(network) is not CompiledNetwork:
            return None
        w = self.world
        robot, ball = w.robot, w.ball_body
        positions, centre, gravity = robot.getPositions, ball.getCOM, robot.getGravityForces
        set_commands, substeps, forces = robot.setCommands, self._substeps, self._forces
        state = control_state(self._contacts, w._touch_any, *self._sense_args, *network._args,
                              self._targets, *self._command_args, p, forces)
        for t in range(self.config.steps):
            if not control_step(t, positions(), centre(), gravity(), state):
                return 0.0
            set_commands(forces)
            substeps()
        return float(p.mean())

    def observe(self, data, t: int) -> bool:
        """``Trial.observe``, compiled (``record_row``)."""
        finite = self.sense()
        trial = self.trial
        record_row(t, trial._positions, self._q,
                    trial._ball_at if self._no_ball else trial._ball, self._contacts,
                    self.world._touch_any, self._x, self._p3, self._kinematics[-1],
                    self._hand_body, self._shoulder_body, self._palm, PALM_NORMAL, data.dofs,
                    data.joints, data.hand, data.shoulder, data.ball, data.contacts,
                    data.contacts_any, data.palm_normal, data.sensors, data.p_sight,
                    data.p_touch, data.p_multimodal)
        return finite

    def after_reset(self) -> None:
        """After ``Trial._reset``: the springs' rest positions at 0 and their pull toward the
        home posture's commanded positions as forces (``spring_forces``)."""
        w = self.world
        for dof in w._dofs:
            dof.setRestPosition(0.0)
        self._q_cmd[:] = w.commanded
        spring_forces(self._q_cmd, *self._spring_args, w.robot.getGravityForces(),
                      self._forces)
        w.robot.setCommands(self._forces)

    def command(self, targets: np.ndarray) -> None:
        """The world's motors commanded toward 14 finite targets in [-1, 1]
        (``motor_commands``)."""
        robot = self.world.robot
        if not motor_commands(targets, *self._command_args, robot.getGravityForces(),
                              self._forces):
            raise ValueError(f"motor targets must be finite, got {targets}")
        robot.setCommands(self._forces)

    def sense(self) -> bool:
        """``Trial.sense``, compiled (``sense_posed``): the camera's and the hand's poses
        computed from the joint positions (``body_poses``), not asked of DART."""
        w, trial = self.world, self.trial
        positions = trial._positions = w.robot.getPositions()
        ball = trial._ball = w.ball_body.getCOM()
        finite = sense_posed(positions, ball, self._contacts, *self._sense_args)
        trial._hand_pose = self._hand_view
        trial._p_sight, trial._p_touch, trial._p_multimodal = self._p3.tolist()
        return finite
