"""The steps of a trial under model version 2's compiled numerics (``versions.Numerics.
COMPILED``; the kernels: ``model.compiled``), behind the interface of ``steps.TrialSteps``:
``Trial(world, config)``, ``run``, ``fitness`` and the environment's ``control`` are the same
code under both versions. The world is read through its public layout (``world.layout``,
``layout.WorldLayout``) and its touch records (``World.touched``, ``touched_any``)."""

from __future__ import annotations

import numpy as np

from .compiled import (PAY_CODES, CompiledNetwork, act_step, command_step, control_step,
                       inner_touches, record_row, sense_step, spring_forces, step_state,
                       targets_of_motor, touch_state)
from .ctrnn import N_MOTORS, N_SENSORS, Network
from .icub import HAND_SEGMENTS, PALM_POINT
from .steps import home_motor
from .world import BALL_PARKED, PALM_NORMAL, SkeletonError, World


class CompiledSteps:
    """The steps of a ``task.Trial`` under ``Numerics.COMPILED`` (model version 2), each a
    compiled step function of ``model.compiled`` over one ``StepState`` (``state``): ``sense``
    (``sense_step``), ``act`` (``act_step``), ``command`` (``command_step``), the record's row
    (``record_row``) and, in ``advance``, the inner-face touches (``inner_touches``). The
    genetic algorithm's trial (``fitness``) takes the same three steps in one compiled call
    per control step (``control_step``). Per control step it asks DART for the joint
    positions and the ball's centre once each; the bodies' poses it needs come from them
    (``body_poses`` over the layout's kinematic tree), and per physics substep in contact the
    contacts' points."""

    def __init__(self, world: World, config):
        self.world, self.config = world, config
        layout = self.layout = world.layout
        tree = layout.tree
        if tree.unsupported:
            raise SkeletonError("model version 2 computes the bodies' poses from revolute and "
                                "weld joints in parent order: " + "; ".join(tree.unsupported))
        self.x, self.q = np.zeros(N_SENSORS), np.zeros(N_MOTORS)
        self.targets = np.zeros(N_MOTORS)
        self.home_motor = home_motor(world, config)
        self.ball_at = np.zeros(3)  # where the ball hangs (or would hang) in this trial
        self._no_ball = config.ball_absent
        #: the inner-face touches the sensing reads: the world's own record
        self.contacts = world.touched
        self.p_sight = self.p_touch = self.p_multimodal = 0.0
        self.positions = self.ball = None  # what ``sense`` read last
        self._p3 = np.zeros(3)
        self._palm = np.asarray(PALM_POINT, float)
        n = len(tree.parent)
        #: the tree, a scratch and the poses ``body_poses`` computes (n, 4, 4)
        parent, dof, axis, before, after = tree.arrays
        self._kinematics = dict(parent=parent, dof=dof, axis=axis, before=before, after=after,
                                scratch=np.zeros((3, 4, 4)), poses=np.zeros((n, 4, 4)))
        self.poses = self._kinematics["poses"]
        # the bodies whose poses a touch decision needs, and their indices
        self._need, self._order = np.zeros(n, bool), np.zeros(n, np.int64)
        self._objects = {}  # a collision object -> (its hand segment or -1, is it the ball)
        self.hold_contacts(4 * len(HAND_SEGMENTS))
        self.substeps = self._substeps_of()
        self._q_cmd = np.zeros(N_MOTORS)  # the motors' commanded positions (rad)
        self._forces = np.zeros(layout.n_dofs)  # the joint forces commanded (N m)
        #: what the step functions read and write besides DART's state and the network
        self.state = step_state(
            touching=self.contacts, order=layout.sensed_bodies, **self._kinematics,
            camera_body=layout.camera_body, hand_body=layout.hand_body,
            motor_dofs=layout.motor_dofs, finger_dofs=layout.finger_dofs,
            lower=layout.motor_limit_lower, span=layout.motor_limit_span,
            touch_segments=layout.touch_segments, acuity=float(config.acuity),
            no_touch=config.touch_deprived, no_sight=config.sight_deprived,
            offsets=config.offsets_sensed, pay=PAY_CODES[config.touch_pay], palm=self._palm,
            q=self.q, x=self.x, p=self._p3, sense_scratch=np.zeros(9),
            touching_any=world.touched_any, targets=self.targets,
            half_range=layout.half_range, mid_range=layout.mid_range,
            motor_lower=layout.motor_lower, motor_upper=layout.motor_upper,
            max_move=layout.max_move, dof_motor=layout.dof_motor, stiffness=layout.stiffness,
            q_cmd=self._q_cmd, forces=self._forces)

    # ---------------------------------------------------------------- touch
    def hold_contacts(self, n: int) -> None:
        """Buffers for ``n`` contacts' hand segments and points (``contact_segments``,
        ``contact_points``; they grow when a substep has more), and the ``TouchState`` of
        ``inner_touches`` that holds them."""
        self.contact_segments, self.contact_points = np.zeros(n, np.int64), np.zeros((n, 3))
        layout = self.layout
        self._touch_state = touch_state(
            segments=self.contact_segments, points=self.contact_points, need=self._need,
            order=self._order, **self._kinematics, segment_body=layout.segment_body,
            direction=layout.face_direction, cos_limit=layout.face_cos_limit,
            touch=self.world.touched)

    def _object(self, obj) -> tuple[int, bool]:
        """What a collision object is to touch: (its hand segment's index or -1, the ball?);
        remembered (dartpy hands back the same Python object for it while one is held)."""
        frame = obj.getShapeFrame()
        layout = self.layout
        face = layout.touch_faces.get(frame)
        found = self._objects[obj] = (-1 if face is None else face.segment,
                                      frame in layout.ball_shapes)
        return found

    def advance(self) -> None:
        """``world.World.advance`` with the inner-face touches decided by compiled code
        (``inner_touches``) from the skeleton's joint positions and the contacts' points."""
        w = self.world
        w.touched[:] = False
        w.touched_any[:] = False
        self.substeps()

    def _substeps_of(self):
        """The physics substeps of one control period, the touches gathered into the world's
        (cleared) records (``substeps``); a closure over what it calls."""
        w = self.world
        step, last_collisions = w.world.step, w.world.getLastCollisionResult
        mark, gather = w.mark_colliding_segments, self.gather
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

    def gather(self, result, n: int) -> bool:
        """Mark the touches of one substep's ``n`` contacts (``touch_any``: any face;
        ``touch``: the inner face, ``inner_touches``); whether any contact had an inner face to
        decide."""
        if n > len(self.contact_segments):
            self.hold_contacts(2 * n)
        w, objects, lookup = self.world, self._objects, self._object
        self_collision = w.config.self_collision
        touch, touch_any = w.touched, w.touched_any
        segments, points = self.contact_segments, self.contact_points
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

    # ---------------------------------------------------------------- the steps
    def targets_of(self, motor: np.ndarray) -> bool:
        """The motor targets ``targets`` of the motor states (``targets_of_motor``)."""
        return targets_of_motor(motor, self.targets)

    def act(self, network: Network) -> bool:
        """The network's update from ``x`` and its targets into ``targets`` (``act_step``)."""
        if type(network) is not CompiledNetwork:  # another controller: its own step
            return targets_of_motor(network.step(self.x), self.targets)
        return act_step(self.state, network.state)

    def fitness(self, network: Network, p: np.ndarray) -> float | None:
        """``Trial.fitness``'s loop after the reset, to the last bit: per control step
        ``sense``, ``act`` and ``command`` in one compiled call (``control_step``, the same
        step functions), p_multimodal into ``p`` (one per step), then ``advance``'s substeps;
        None for another controller, which the trial steps by its own loop."""
        if type(network) is not CompiledNetwork:
            return None
        w = self.world
        robot, ball = w.robot, w.ball_body
        positions, centre, gravity = robot.getPositions, ball.getCOM, robot.getGravityForces
        set_commands, substeps, forces = robot.setCommands, self.substeps, self._forces
        state, network_state = self.state, network.state
        for t in range(self.config.steps):
            if not control_step(t, positions(), centre(), gravity(), state, network_state, p):
                return 0.0
            set_commands(forces)
            substeps()
        return float(p.mean())

    def observe(self, data, t: int) -> bool:
        """``sense``, and row ``t`` of the record, compiled (``record_row``)."""
        finite = self.sense()
        layout = self.layout
        record_row(t, self.positions, self.q, self.ball_at if self._no_ball else self.ball,
                   self.contacts, self.world.touched_any, self.x, self._p3, self.poses,
                   layout.hand_body, layout.shoulder_body, self._palm, PALM_NORMAL, data.dofs,
                   data.joints, data.hand, data.shoulder, data.ball, data.contacts,
                   data.contacts_any, data.palm_normal, data.sensors, data.p_sight,
                   data.p_touch, data.p_multimodal)
        return finite

    def reset(self, ball_position) -> None:
        """The world at a trial's start (``World.reset``), then the springs' rest positions
        at 0 and their pull toward the home posture's commanded positions as forces
        (``spring_forces``)."""
        w = self.world
        self.ball_at[:] = ball_position
        w.reset(BALL_PARKED if self._no_ball else ball_position)
        w.set_spring_rest_positions(0.0)
        self._q_cmd[:] = w.commanded
        spring_forces(self._q_cmd, self.layout.dof_motor, self.layout.stiffness,
                      w.robot.getGravityForces(), self._forces)
        w.robot.setCommands(self._forces)

    def command(self, targets: np.ndarray) -> None:
        """The world's motors commanded toward 14 finite targets in [-1, 1]
        (``command_step``)."""
        robot = self.world.robot
        if not command_step(targets, robot.getGravityForces(), self.state):
            raise ValueError(f"motor targets must be finite, got {targets}")
        robot.setCommands(self._forces)

    def sense(self) -> bool:
        """The sensors and the fitness terms (``sense_step``): the camera's and the hand's
        poses computed from the joint positions (``body_poses``), not asked of DART."""
        w = self.world
        positions = self.positions = w.robot.getPositions()
        ball = self.ball = w.ball_body.getCOM()
        finite = sense_step(positions, ball, self.state)
        self.p_sight, self.p_touch, self.p_multimodal = self._p3.tolist()
        return finite
