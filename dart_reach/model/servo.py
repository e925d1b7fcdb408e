"""The living model's servo: the motors driven toward a controller's targets and the physics
substeps of one control period, the hand's touches gathered (section III-B; the touch of
III-B, III-C), over a ``world.World`` read through its public ``layout``.

Every 0.1 s a controller (the network, the scripted reach, a study's targets) gives 14 motor
targets in [-1, 1]; ``Servo.command`` scales each into its motor's range and moves the motor's
commanded position toward it by at most ``WorldConfig.max_joint_speed`` x ``control_dt``, then
commands every joint the force that pulls its spring toward its motor's commanded position
plus the gravity compensation (``kernels.motors.motor_commands``: joint forces k q_cmd with the
springs' rest positions held at 0, which DART integrates as the spring toward q_cmd).
``Servo.advance`` runs the physics substeps and marks, per hand segment, whether it touched
the ball on any face (``World.touched_any``) and on its inner face (``World.touched``,
decided by ``kernels.touch.inner_touches``) in any of them. ``Servo.step`` is both.

It is what the trials of the living model (model versions 2 and 3: ``compiled_trial.
CompiledSteps``, whose genetic algorithm's control step, ``compiled.control_step``, shares its
commanded positions and forces) and every controller outside a trial (the scripted reach of
``dart-reach reach``, ``validate`` and ``bench``, the physics-step study's targets, the touch
tests) step the world with. Version 1's servo is frozen in ``reference.servo``.

Units: angles in rad, forces in N m, lengths in m.
"""

from __future__ import annotations

import numpy as np

from .kernels.motors import motor_commands
from .kernels.touch import inner_touches, touch_state
from .ctrnn import N_MOTORS
from .icub import HAND_SEGMENTS
from .world import SkeletonError, World


class Servo:
    """The motors and the physics substeps of a ``World`` under the living model (see the
    module docstring). ``q_cmd`` (14,) holds the motors' commanded positions (rad) and
    ``forces`` (n_dofs,) the joint forces commanded (N m), both updated in place; the
    touches are the world's records (``World.touched``, ``touched_any``, read through
    ``World.hand_contacts`` and ``hand_contacts_any``).

    Per control step it asks DART for the gravity forces once; per physics substep in contact,
    for the colliding bodies and, when a segment may touch on its inner face, the contacts'
    points and the joint positions (the segments' poses come from them:
    ``kernels.kinematics.body_poses`` over the layout's kinematic tree)."""

    def __init__(self, world: World):
        self.world = world
        layout = self.layout = world.layout
        tree = layout.tree
        if tree.unsupported:
            raise SkeletonError("the living model computes the bodies' poses from revolute and "
                                "weld joints in parent order: " + "; ".join(tree.unsupported))
        self.q_cmd = np.zeros(N_MOTORS)
        self.forces = np.zeros(layout.n_dofs)
        robot = world.robot
        self._dofs = [robot.getDof(i) for i in range(layout.n_dofs)]
        n = len(tree.parent)
        parent, dof, axis, before, after = tree.arrays
        #: the tree, a scratch and the poses ``inner_touches`` computes (n, 4, 4)
        self._kinematics = dict(parent=parent, dof=dof, axis=axis, before=before, after=after,
                                scratch=np.zeros((3, 4, 4)), poses=np.zeros((n, 4, 4)))
        # the bodies whose poses a touch decision needs, and their indices
        self._need, self._order = np.zeros(n, bool), np.zeros(n, np.int64)
        self._objects = {}  # a collision object -> (its hand segment or -1, is it the ball)
        # a hand segment's body node -> its index, as a dict (a read per colliding body)
        self._segment_of = dict(layout.segment_index)
        self.hold_contacts(4 * len(HAND_SEGMENTS))
        #: the physics substeps of one control period, the touches gathered into the world's
        #: records (not cleared: ``advance`` clears them first): the model's own loop, or the
        #: one a study chose with ``use_substeps``
        self.substeps = self._model_substeps = self._substeps_of()

    # ---------------------------------------------------------------- commands
    def reset(self, ball_position) -> None:
        """A trial's start: the world reset (``World.reset``: home posture, the ball at rest
        at ``ball_position``, m), the springs' rest positions at 0, the motors' commanded
        positions at the home posture's (``World.home_motor``) and commanded once toward the
        targets that hold it (``World.home_targets``)."""
        w = self.world
        w.reset(ball_position)
        for dof in self._dofs:
            dof.setRestPosition(0.0)
        self.q_cmd[:] = w.home_motor
        self.command(w.home_targets)

    def command(self, targets) -> None:
        """The motors commanded toward 14 targets in [-1, 1] (values outside are clipped):
        the commanded positions moved at most at the speed cap, the joint forces that pull
        the springs toward them plus gravity compensation (``kernels.motors.motor_commands``); no
        physics yet. ``ValueError`` for another shape or a target that is not finite (the
        commanded positions are left as they were)."""
        if type(targets) is not np.ndarray or targets.shape != (N_MOTORS,) \
                or targets.dtype != np.float64:
            targets = np.asarray(targets, dtype=float)
            if targets.shape != (N_MOTORS,):
                raise ValueError(f"expected {N_MOTORS} motor targets, got shape "
                                 f"{targets.shape}")
        layout, robot = self.layout, self.world.robot
        if not motor_commands(targets, layout.half_range, layout.mid_range, layout.motor_lower,
                              layout.motor_upper, layout.max_move, layout.dof_motor,
                              layout.stiffness, self.q_cmd, robot.getGravityForces(),
                              self.forces):
            raise ValueError(f"motor targets must be finite, got {targets}")
        robot.setCommands(self.forces)

    def advance(self) -> None:
        """The physics substeps of one control period (``substeps``), the world's touch
        records cleared first and gathered in every substep."""
        w = self.world
        w.touched[:] = False
        w.touched_any[:] = False
        self.substeps()

    def step(self, targets) -> None:
        """One control step (0.1 s): ``command`` toward ``targets``, then ``advance``."""
        self.command(targets)
        self.advance()

    def use_substeps(self, loop=None) -> None:
        """Run each control period's physics substeps by ``loop`` from now on (``advance``
        and the genetic algorithm's trial, ``compiled_trial.CompiledSteps.fitness``, call
        ``substeps``): a callable of no argument that steps the world
        ``WorldConfig.substeps`` times and gathers the touches into the world's records, as
        the model's own loop does with ``mark_colliding_segments`` and ``gather`` (a study's
        instrumented copy of it: ``studies.touch_geometry``). ``None``: the model's own loop
        again."""
        if loop is not None and not callable(loop):
            raise TypeError(f"the substeps' loop must be callable, got {loop!r}")
        self.substeps = self._model_substeps if loop is None else loop

    # ---------------------------------------------------------------- touch
    def hold_contacts(self, n: int) -> None:
        """Buffers for ``n`` contacts' hand segments and points (``contact_segments``,
        ``contact_points``; they grow when a substep has more), and the ``TouchState`` of
        ``inner_touches`` that holds them."""
        self.contact_segments, self.contact_points = np.zeros(n, np.int64), np.zeros((n, 3))
        layout = self.layout
        #: what ``inner_touches`` reads and writes (``kernels.touch.TouchState``)
        self.touch_state = touch_state(
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

    def _substeps_of(self):
        """``substeps``: a closure over what it calls."""
        w = self.world
        step, last_collisions = w.world.step, w.world.getLastCollisionResult
        mark, gather = self.mark_colliding_segments, self.gather
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

    def mark_colliding_segments(self, result) -> bool:
        """With self-collision off (only the ball collides with the robot): mark the hand
        segments among a substep's colliding bodies (``result``, its collision result) as
        touching on some face (``World.touched_any``); whether one of them is not yet marked
        as touching on its inner face, so that the contacts must be read."""
        w = self.world
        touch, touch_any, segment = w.touched, w.touched_any, self._segment_of
        pending = False
        for body in result.getCollidingBodyNodes():
            i = segment.get(body)
            if i is not None:
                touch_any[i] = True
                pending = pending or not touch[i]
        return pending

    def gather(self, result, n: int) -> bool:
        """Mark the touches of one substep's ``n`` contacts (``result``, its collision
        result): ``World.touched_any`` any face, ``World.touched`` the inner face
        (``inner_touches``); whether any contact had an inner face to decide."""
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
            inner_touches(w.robot.getPositions(), w.ball_body.getCOM(), k, self.touch_state)
        return k > 0
