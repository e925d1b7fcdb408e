"""The steps of a trial under the living model's compiled numerics (model versions 2 and 3,
``versions.Numerics.COMPILED``; the step functions: ``model.compiled``, over the kernels of
``model.kernels``), behind the interface of ``steps.TrialSteps``: ``Trial(world, config)``,
``run``, ``fitness`` and the environment's ``control`` are the same code under every
version. The motors and the physics substeps are the living model's servo (``servo.Servo``);
the world is read through its public layout (``world.layout``, ``layout.WorldLayout``) and
its touch records (``World.touched``, ``touched_any``)."""

from __future__ import annotations

import numpy as np
from numba import typeof

from .compiled import act_step, control_step, sense_step, step_state
from .ctrnn import N_MOTORS, N_SENSORS, Network
from .icub import PALM_POINT
from .kernels.network import CompiledNetwork, targets_of_motor
from .kernels.sensing import PAY_CODES, record_row
from .servo import Servo
from .steps import home_motor
from .world import BALL_PARKED, PALM_NORMAL, World


def entry_point(function, *args):
    """``function``, a compiled step function (``model.compiled``), as its compiled entry
    point for the types of ``args`` (compiled or loaded from the cache if need be): the same
    machine code, called without the dispatcher typing every argument on every call (what
    that saves: ``studies.scaling.loop_parts``, docs/results/benchmarks.md). The caller passes
    arguments of those types only (DART's readings are fresh float64 arrays). ``function``
    itself when it is not compiled (``NUMBA_DISABLE_JIT=1``, for debugging)."""
    compile_for = getattr(function, "compile", None)
    if compile_for is None:
        return function
    return compile_for(tuple(typeof(a) for a in args))


class CompiledSteps:
    """The steps of a ``task.Trial`` under ``Numerics.COMPILED`` (model versions 2 and 3),
    each a compiled step function of ``model.compiled`` over one ``StepState`` (``state``):
    ``sense`` (``sense_step``), ``act`` (``act_step``), the record's row (``record_row``);
    ``reset``, ``command`` and ``advance`` are the living model's servo's (``servo``: the
    motor commands, ``kernels.motors.motor_commands``, and the inner-face touches,
    ``kernels.touch.inner_touches``). The genetic algorithm's trial (``fitness``) takes
    sense, act and command in one compiled call per control step (``control_step``, over the
    servo's commanded positions and forces).
    Per control step it asks DART for the joint positions and the ball's centre once each;
    the bodies' poses it needs come from them (``kernels.kinematics.body_poses`` over the
    layout's kinematic tree)."""

    def __init__(self, world: World, config):
        self.world, self.config = world, config
        #: the motors and the physics substeps (``servo.Servo``)
        self.servo = servo = Servo(world)
        layout = self.layout = world.layout
        tree = layout.tree
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
        #: the poses ``body_poses`` computes of the sensed bodies (n, 4, 4)
        self.poses = np.zeros((len(tree.parent), 4, 4))
        parent, dof, axis, before, after = tree.arrays
        #: what the step functions read and write besides DART's state and the network
        self.state = step_state(
            touching=self.contacts, order=layout.sensed_bodies, parent=parent, dof=dof,
            axis=axis, before=before, after=after, scratch=np.zeros((3, 4, 4)),
            poses=self.poses, camera_body=layout.camera_body, hand_body=layout.hand_body,
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
            q_cmd=servo.q_cmd, forces=servo.forces)
        #: the world's motors commanded toward 14 finite targets in [-1, 1], no physics yet
        self.command = servo.command
        #: the physics substeps of one control period, the touches gathered
        self.advance = servo.advance

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
        step functions, called through its ``entry_point``), p_multimodal
        into ``p`` (one per step), then ``advance``'s substeps; None for another controller,
        which the trial steps by its own loop."""
        if type(network) is not CompiledNetwork:
            return None
        w = self.world
        robot, ball = w.robot, w.ball_body
        positions, centre, gravity = robot.getPositions, ball.getCOM, robot.getGravityForces
        servo = self.servo
        set_commands, substeps, forces = robot.setCommands, servo.substeps, servo.forces
        state, network_state = self.state, network.state
        n_dofs = self.layout.n_dofs
        step = entry_point(control_step, 0, np.zeros(n_dofs), np.zeros(3), np.zeros(n_dofs),
                           state, network_state, p)
        for t in range(self.config.steps):
            if not step(t, positions(), centre(), gravity(), state, network_state, p):
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
        """The world and the motors at a trial's start (``servo.Servo.reset``), the ball at
        ``ball_position`` (m; parked away when it is absent)."""
        self.ball_at[:] = ball_position
        self.servo.reset(BALL_PARKED if self._no_ball else ball_position)

    def sense(self) -> bool:
        """The sensors and the fitness terms (``sense_step``): the camera's and the hand's
        poses computed from the joint positions (``body_poses``), not asked of DART."""
        w = self.world
        positions = self.positions = w.robot.getPositions()
        ball = self.ball = w.ball_body.getCOM()
        finite = sense_step(positions, ball, self.state)
        self.p_sight, self.p_touch, self.p_multimodal = self._p3.tolist()
        return finite
