"""Touch from the kinematics, measured (not adopted in any model version).

The living model decides which hand segments touch the ball on their inner face (sections
III-B, III-C) from DART's contacts: per physics substep in contact it reads the contact list
through dartpy (each contact's objects and point) and turns the vector from the contact point
to the ball's centre into the segment's frame (``kernels.touch.inner_touches``, which the
servo's substeps call: ``servo.Servo.gather``). This module decides the same from the
kinematics alone: the segments' poses composed from the joint positions (``kernels.
kinematics.body_poses`` over the world's ``layout.KinematicTree``), their collision boxes,
and the ball's centre and radius, with no contact read. It is a measurement for a later model
version: it changes what the sensor computes, so no model version uses it.

``KinematicTouch`` is the decision: for each of the 16 hand segments (``icub.HAND_SEGMENTS``)
the ball's centre in the box's frame, the box's closest point to it, and

- a touch on any face when the centre is within the ball's radius of the box (as DART's
  sphere-box test: penetration r - |centre - closest point| >= 0);
- a touch on the inner face when, besides, the vector from the closest point to the centre
  lies in the face's cone (``icub.INNER_FACES``), the rule of ``kernels.touch.inner_touches``
  with the closest point for DART's contact point (a centre inside the box gives the zero
  vector, which the rule counts as inner, as it does for DART's contact there).

``measure`` runs trials of evolved robots under a model version's scene and numerics with
both decisions at every physics substep, the model's own (DART's contacts) driving the trial,
the kinematic one on the state after the step (``post``, only where DART reports contacts)
and on the state before it, the one DART's collision detection saw (``pre``,
``Comparison``), and reports their agreement and the time of each per decision (``python -m
dart_reach.studies.touch_geometry``; docs/results/benchmarks.md, "Touch from the kinematics,
measured (not adopted)").

Units: lengths in m, angles in rad, times in µs.
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np
from numba import njit

from ..evolution.genome import decode
from ..evolution.settings import seed_at
from ..model import icub
from ..model.kernels.kinematics import body_poses
from ..model.kernels.touch import inner_touches
from ..model.task import Trial, network_for, trial_positions
from ..model.world import World
from .scaling import late_generation


@njit(cache=True)
def kinematic_touches(positions, ball, radius, order, parent, dof, axis, before, after,
                      scratch, poses, segment_body, shape_rotation, shape_offset, half,
                      inner, cos_limit, touch, touch_any):
    """Mark in ``touch`` (inner face) and ``touch_any`` (any face) the hand segments whose
    collision box the ball (centre ``ball``, m; ``radius``, m) overlaps, from the skeleton's
    joint positions (rad): the poses of the bodies of ``order`` (the segments' bodies and
    their ancestors, parents first) by ``kernels.kinematics.body_poses``; per segment its body
    (``segment_body``), its box's rotation and offset in the body's frame
    (``shape_rotation`` (16, 3, 3), ``shape_offset`` (16, 3), m), half extents (``half``
    (16, 3), m), inner face's direction in the box's frame (``inner`` (16, 3)) and the cosine
    of its cone's half angle (``cos_limit`` (16,)). Both outputs are overwritten; returns
    the number of segments touched on any face."""
    body_poses(positions, order, parent, dof, axis, before, after, scratch, poses)
    n = 0
    for i in range(segment_body.shape[0]):
        pose = poses[segment_body[i]]
        d0, d1, d2 = ball[0] - pose[0, 3], ball[1] - pose[1, 3], ball[2] - pose[2, 3]
        # the centre in the body's frame, then in the box's
        b0 = pose[0, 0] * d0 + pose[1, 0] * d1 + pose[2, 0] * d2 - shape_offset[i, 0]
        b1 = pose[0, 1] * d0 + pose[1, 1] * d1 + pose[2, 1] * d2 - shape_offset[i, 1]
        b2 = pose[0, 2] * d0 + pose[1, 2] * d1 + pose[2, 2] * d2 - shape_offset[i, 2]
        r = shape_rotation[i]
        p0 = r[0, 0] * b0 + r[1, 0] * b1 + r[2, 0] * b2
        p1 = r[0, 1] * b0 + r[1, 1] * b1 + r[2, 1] * b2
        p2 = r[0, 2] * b0 + r[1, 2] * b1 + r[2, 2] * b2
        # the vector from the box's closest point to the centre
        o0 = p0 - min(max(p0, -half[i, 0]), half[i, 0])
        o1 = p1 - min(max(p1, -half[i, 1]), half[i, 1])
        o2 = p2 - min(max(p2, -half[i, 2]), half[i, 2])
        norm = math.sqrt(o0 * o0 + o1 * o1 + o2 * o2)
        hit = radius - norm >= 0.0
        touch_any[i] = hit
        along = o0 * inner[i, 0] + o1 * inner[i, 1] + o2 * inner[i, 2]
        touch[i] = hit and along >= cos_limit[i] * norm
        n += 1 if hit else 0
    return n


class KinematicTouch:
    """The touch decision from the kinematics for one built ``World`` (see the module
    docstring). Built once from the world's public layout and its collision shapes (each
    hand segment's box: size and placement in its body's frame; the ball's radius);
    ``decide(positions, ball)`` then overwrites ``touch`` and ``touch_any`` ((16,) bool, per
    ``icub.HAND_SEGMENTS``) from the joint positions (rad) and the ball's centre (m)."""

    def __init__(self, world: World):
        layout = world.layout
        n_seg = len(icub.HAND_SEGMENTS)
        rotation, offset = np.zeros((n_seg, 3, 3)), np.zeros((n_seg, 3))
        half, inner, cos_limit = np.zeros((n_seg, 3)), np.zeros((n_seg, 3)), np.zeros(n_seg)
        found = np.zeros(n_seg, bool)
        for shape, face in layout.touch_faces.items():
            box = shape.getShape()
            if type(box).__name__ != "BoxShape":
                raise ValueError(f"touch from the kinematics knows boxes only, segment "
                                 f"{icub.HAND_SEGMENTS[face.segment]} has a "
                                 f"{type(box).__name__}")
            if found[face.segment]:
                raise ValueError(f"segment {icub.HAND_SEGMENTS[face.segment]} has more than "
                                 "one collision shape")
            found[face.segment] = True
            placed = shape.getRelativeTransform().matrix()
            rotation[face.segment], offset[face.segment] = placed[:3, :3], placed[:3, 3]
            half[face.segment] = 0.5 * np.asarray(box.getSize())
            inner[face.segment], cos_limit[face.segment] = face.inner, face.cos_limit
        if not found.all():
            raise ValueError("a hand segment has no collision shape")
        radii = {float(s.getShape().getRadius()) for s in layout.ball_shapes}
        if len(radii) != 1:
            raise ValueError("the ball must be one sphere")
        #: the ball's radius (m)
        self.radius = radii.pop()
        parent, dof, axis, before, after = layout.tree.arrays
        n = len(parent)
        self._args = (layout.tree.chain(*layout.segment_body), parent, dof, axis, before,
                      after, np.zeros((3, 4, 4)), np.zeros((n, 4, 4)), layout.segment_body,
                      rotation, offset, half, inner, cos_limit)
        #: (16,) bool, the inner-face and any-face touches of the last ``decide``
        self.touch, self.touch_any = np.zeros(n_seg, bool), np.zeros(n_seg, bool)

    @property
    def poses(self) -> np.ndarray:
        """(n, 4, 4) the bodies' world poses (m) of the last ``decide`` (those of the hand
        segments and their ancestors; the others are stale)."""
        return self._args[7]

    def decide(self, positions: np.ndarray, ball: np.ndarray) -> int:
        """Overwrite ``touch`` and ``touch_any`` for joint positions ``positions`` (rad,
        skeleton order) and the ball's centre ``ball`` (m); the number touched on any face."""
        return kinematic_touches(positions, ball, self.radius, *self._args, self.touch,
                                 self.touch_any)


def contact_touches(world: World, result, touch: np.ndarray, touch_any: np.ndarray,
                    before=None) -> None:
    """One substep's touches from DART's contacts (``result``: its collision result), not
    gathered with the control step's earlier substeps: the hand segments in contact with the
    ball on any face (``touch_any``) and on the inner face (``touch``: per contact, the
    vector from its point to the ball's centre in the segment's body frame within the face's
    cone, the rule of ``kernels.touch.inner_touches``, in the state after the step, as the model
    decides). With ``before`` = (the ball's centre (m), the bodies' world poses (n, 4, 4))
    of the state before the step, the one DART's collision detection saw
    (``KinematicTouch.poses`` of that state), the contact points are judged in that state
    instead: the ball's centre and the segment's rotation of the same instant as the points.
    Both (16,) outputs are overwritten."""
    touch[:] = False
    touch_any[:] = False
    layout = world.layout
    faces, ball_shapes = layout.touch_faces, layout.ball_shapes
    centre, poses = (world.ball_body.getCOM(), None) if before is None else before
    for contact in result.getContacts():
        f1, f2 = contact.collisionObject1.getShapeFrame(), contact.collisionObject2.getShapeFrame()
        frame = f2 if f1 in ball_shapes else f1 if f2 in ball_shapes else None
        face = None if frame is None else faces.get(frame)
        if face is None:
            continue
        i = face.segment
        touch_any[i] = True
        if touch[i]:
            continue
        body = int(layout.segment_body[i])
        rot = (world.robot.getBodyNode(body).getTransform().rotation() if poses is None
               else poses[body][:3, :3])
        o = rot.T @ (centre - contact.point)
        touch[i] = o @ layout.face_direction[i] >= layout.face_cos_limit[i] * math.sqrt(o @ o)


class Comparison:
    """Counts of the decisions' agreement and their CPU times, gathered by ``instrument``'d
    substeps (see ``measure``). Two kinematic variants beside DART's contacts:

    - ``post``: on the state after the physics step, the one the model reads its joint
      positions from (``servo.Servo.gather``), taken only in the substeps
      where DART reports contacts (its count comes with the step, no contact is read);
    - ``pre``: on the state before the step, the one DART's collision detection saw (a
      world's step detects the collisions before it integrates the positions), taken in
      every substep (the state must be read before the step, whether or not it collides).
    """

    VARIANTS = ("post", "pre")

    def __init__(self, world: World):
        self.world = world
        self.kin = {v: KinematicTouch(world) for v in self.VARIANTS}
        n_seg = len(icub.HAND_SEGMENTS)
        self.dart, self.dart_any = np.zeros(n_seg, bool), np.zeros(n_seg, bool)
        #: DART's contact points judged in the state before the step (``contact_touches``'
        #: ``before``), and that state's ball centre
        self.dart_before, self._scratch = np.zeros(n_seg, bool), np.zeros(n_seg, bool)
        self.ball_before = np.zeros(3)
        #: the kinematic inner-face touches gathered in a control step, per variant
        self.gathered = {v: np.zeros(n_seg, bool) for v in self.VARIANTS}
        self.reset()

    def reset(self) -> None:
        """Zero the counts and the times (after a warm-up)."""
        c = self.counts = dict(substeps=0, substeps_in_contact=0, control_steps=0,
                               substeps_either_pre_points=0, substeps_same_pre_points=0)
        for v in self.VARIANTS:
            for key in ("substeps_either", "substeps_same", "substeps_either_any",
                        "substeps_same_any", "control_steps_either", "control_steps_same",
                        "control_steps_sensors_differ", "control_steps_count_differ"):
                c[f"{key}_{v}"] = 0
        #: CPU ns per substep in contact: the model's contact path and ``post``'s decision
        #: (interleaved, the order alternating); per substep: ``pre``'s read and decision
        self.dart_ns, self.post_ns, self.pre_ns = [], [], []
        #: CPU ns per control step: the model's contact path, ``post``, ``pre``
        self.step_ns = []

    def instrument(self, steps) -> None:
        """Run the physics substeps of ``steps`` (a ``compiled_trial.CompiledSteps``: its
        servo's substeps of one control period) by a copy of the model's loop with the
        decisions compared and timed (``servo.Servo.use_substeps``; CPU time of
        this thread, so that the other processes' load does not count). The trial's touches
        stay the model's own (the servo's ``mark_colliding_segments`` and ``gather``), so the
        robots move as they do in training."""
        w = self.world
        world, robot, ball_body = w.world, w.robot, w.ball_body
        step, last = world.step, world.getLastCollisionResult
        servo = steps.servo
        mark, gather = servo.mark_colliding_segments, servo.gather
        self_collision, n_sub = w.config.self_collision, w.config.substeps
        post, pre, c = self.kin["post"], self.kin["pre"], self.counts
        gathered = self.gathered
        touch_segments = w.layout.touch_segments
        clock = time.thread_time_ns

        def run_substeps() -> None:
            c = self.counts
            deciding = False
            for g in gathered.values():
                g[:] = False
            dart_sum = post_sum = pre_sum = 0
            for k in range(n_sub):
                t0 = clock()
                pre.decide(robot.getPositions(), ball_body.getCOM())
                t1 = clock()
                self.ball_before[:] = ball_body.getCOM()  # untimed: for ``dart_before``
                self.pre_ns.append(t1 - t0)
                pre_sum += t1 - t0
                step(False)
                result = last()
                n = result.getNumContacts()
                if n:
                    # the model's decision and ours, timed in turn (the order alternating)
                    if k % 2:
                        t0 = clock()
                        post.decide(robot.getPositions(), ball_body.getCOM())
                        t1 = clock()
                        if self_collision or deciding or mark(result):
                            deciding = gather(result, n)
                        t2 = clock()
                        dt_post, dt_dart = t1 - t0, t2 - t1
                    else:
                        t0 = clock()
                        if self_collision or deciding or mark(result):
                            deciding = gather(result, n)
                        t1 = clock()
                        post.decide(robot.getPositions(), ball_body.getCOM())
                        t2 = clock()
                        dt_dart, dt_post = t1 - t0, t2 - t1
                    self.dart_ns.append(dt_dart)
                    self.post_ns.append(dt_post)
                    dart_sum += dt_dart
                    post_sum += dt_post
                    c["substeps_in_contact"] += 1
                    contact_touches(w, result, self.dart, self.dart_any)
                    contact_touches(w, result, self.dart_before, self._scratch,
                                    (self.ball_before, pre.poses))
                    if self.dart_before.any() or pre.touch.any():
                        c["substeps_either_pre_points"] += 1
                        c["substeps_same_pre_points"] += bool(
                            (self.dart_before == pre.touch).all())
                else:
                    if pre.touch.any():
                        c["substeps_either_pre_points"] += 1
                    deciding = False
                    post.touch[:] = False  # no contact reported: the gated variant decides none
                    post.touch_any[:] = False
                    self.dart[:] = False
                    self.dart_any[:] = False
                c["substeps"] += 1
                for v in self.VARIANTS:
                    kin = self.kin[v]
                    gathered[v] |= kin.touch
                    for key, a, b in (("", self.dart, kin.touch),
                                      ("_any", self.dart_any, kin.touch_any)):
                        if a.any() or b.any():
                            c[f"substeps_either{key}_{v}"] += 1
                            c[f"substeps_same{key}_{v}"] += bool((a == b).all())
            self.step_ns.append((dart_sum, post_sum, pre_sum))
            model = w.touched  # the model's touches of the control step
            c["control_steps"] += 1
            for v, g in gathered.items():
                if model.any() or g.any():
                    c[f"control_steps_either_{v}"] += 1
                    c[f"control_steps_same_{v}"] += bool((model == g).all())
                c[f"control_steps_sensors_differ_{v}"] += bool(
                    (model[touch_segments] != g[touch_segments]).any())
                c[f"control_steps_count_differ_{v}"] += int(model.sum() != g.sum())

        servo.use_substeps(run_substeps)

    def figures(self) -> dict:
        """The counts, the agreement shares (of the substeps or control steps where either
        decision has a touch: the same touching segments; of all control steps: the six
        touch sensors' readings differ, the number of touching segments (p_touch) differs)
        and the CPU times (µs): per substep in contact, the model's contact path
        (``dart_us``) and ``post``'s decision; per substep, ``pre``'s; per control step,
        each path's sum; the ratios the model's over ours."""
        c = self.counts
        share = lambda a, b: c[a] / c[b] if c[b] else float("nan")  # noqa: E731
        out = dict(c)
        out["substep_agreement_pre_points"] = share("substeps_same_pre_points",
                                                    "substeps_either_pre_points")
        for v in self.VARIANTS:
            out[f"substep_agreement_{v}"] = share(f"substeps_same_{v}", f"substeps_either_{v}")
            out[f"substep_agreement_any_face_{v}"] = share(f"substeps_same_any_{v}",
                                                           f"substeps_either_any_{v}")
            out[f"control_step_agreement_{v}"] = share(f"control_steps_same_{v}",
                                                       f"control_steps_either_{v}")
            out[f"control_steps_sensors_differ_share_{v}"] = share(
                f"control_steps_sensors_differ_{v}", "control_steps")
            out[f"control_steps_count_differ_share_{v}"] = share(
                f"control_steps_count_differ_{v}", "control_steps")
        us = lambda ns: np.asarray(ns, float) / 1e3  # noqa: E731
        dart, post, pre = us(self.dart_ns), us(self.post_ns), us(self.pre_ns)
        if len(dart):
            out.update(dart_us_median=float(np.median(dart)), dart_us_mean=float(dart.mean()),
                       post_us_median=float(np.median(post)), post_us_mean=float(post.mean()),
                       in_contact_ratio_median=float(np.median(dart) / np.median(post)))
        if len(pre):
            out.update(pre_us_median=float(np.median(pre)), pre_us_mean=float(pre.mean()))
        if self.step_ns:
            per_step = us(self.step_ns).mean(axis=0)
            out.update(dart_us_per_control_step=float(per_step[0]),
                       post_us_per_control_step=float(per_step[1]),
                       pre_us_per_control_step=float(per_step[2]),
                       control_step_ratio_post=float(per_step[0] / per_step[1]),
                       control_step_ratio_pre=float(per_step[0] / per_step[2]))
        return out


def _rng(job) -> np.random.Generator:
    """The generator of a job's trial positions, as the genetic algorithm draws them."""
    return np.random.default_rng(seed_at(job.seed))


def measure(robots: int = 10, trials: int = 3, steps: int = 200, model_version: int = 3,
            seed: int = 0) -> dict:
    """Trials of the late population (``scaling.late_robots``: the shipped standard-condition
    pre-reachers that trained longest) under ``model_version``'s scene and numerics, at the
    genetic algorithm's positions of ``seed``: ``robots`` robots (the first of the file) x
    ``trials`` trials of ``steps`` control steps, each physics substep decided both ways
    (``Comparison.instrument``). The agreement and the times (``Comparison.figures``), and
    the work done (``robots``, ``trials``, ``steps``, ``cpu_s``)."""
    jobs = late_generation(model_version, seed=seed, trials=trials, steps=steps)[:robots]
    world = World(jobs[0].world)
    trial = Trial(world, jobs[0].trial)
    comparison = Comparison(world)
    comparison.instrument(trial.steps)
    # compile and warm both paths (the model's contact decision loaded with no contact; a
    # whole trial), not counted
    inner_touches(world.robot.getPositions(), world.ball_body.getCOM(), 0,
                  trial.steps.servo.touch_state)
    warm = jobs[0]
    trial.fitness(network_for(decode(warm.genome, warm.free_groups), warm.trial),
                  trial_positions(world, _rng(warm), warm.trial.trials)[0][1])
    comparison.reset()
    fitness = []
    t0 = time.process_time()
    for job in jobs:
        network = network_for(decode(job.genome, job.free_groups), job.trial)
        for _, position in trial_positions(world, _rng(job), job.trial.trials):
            fitness.append(trial.fitness(network, position))
    out = comparison.figures()
    out.update(robots=len(jobs), trials=trials, steps=steps, model_version=model_version,
               cpu_s=time.process_time() - t0, mean_fitness=float(np.mean(fitness)))
    return out


def main(argv=None) -> None:
    """``python -m dart_reach.studies.touch_geometry [--robots N --trials N --steps N]``:
    ``measure``'s figures as JSON."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, default=10)
    parser.add_argument("--trials", type=int, default=3)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--model-version", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    a = parser.parse_args(argv)
    print(json.dumps(measure(a.robots, a.trials, a.steps, a.model_version, a.seed), indent=1))


if __name__ == "__main__":
    main()
