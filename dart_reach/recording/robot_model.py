"""The robot's kinematic tree and visual shapes, for drawing a trial from its joint record
(``RobotModel``; no rerun here: ``viewing`` uses it without loading the recorder)."""

from __future__ import annotations

import numpy as np
from numba import njit

from ..model.icub import HAND_SEGMENTS
from .quaternion import quaternion_of


class RobotModel:
    """The robot's kinematic tree and visual shapes, for drawing a trial from its joint record.

    Body poses are computed for all steps at once (vectorised forward kinematics) from
    ``TrialData.dofs``: asking DART for 28 body transforms per step would cost more than the
    recording itself. Only revolute and weld joints occur in the skeleton; others are refused.
    """

    def __init__(self, world):
        robot = world.robot
        bodies = list(robot.getBodyNodes())
        index = {b.getName(): i for i, b in enumerate(bodies)}
        # A revolute joint's transform from its parent body is before @ R(q) @ after, and
        # R(q) = I + sin q K + (1 - cos q) K^2 (Rodrigues, K the axis' cross-product matrix):
        # so it is terms[0] + sin q terms[1] + (1 - cos q) terms[2], three constant matrices.
        self.parent, self.dof, self.terms = [], [], []
        for b in bodies:
            j = b.getParentJoint()
            kind = type(j).__name__
            if kind not in ("RevoluteJoint", "WeldJoint"):
                raise ValueError(f"cannot draw joint {j.getName()} of type {kind}")
            p = b.getParentBodyNode()
            self.parent.append(-1 if p is None else index[p.getName()])
            before = np.asarray(j.getTransformFromParentBodyNode().matrix())
            after = np.linalg.inv(np.asarray(j.getTransformFromChildBodyNode().matrix()))
            K = np.zeros((4, 4))
            if kind == "RevoluteJoint":
                x, y, z = np.asarray(j.getAxis(), float)
                K[:3, :3] = [[0, -z, y], [z, 0, -x], [-y, x, 0]]
            self.dof.append(j.getIndexInSkeleton(0) if kind == "RevoluteJoint" else -1)
            self.terms.append(np.stack([before @ after, before @ K @ after,
                                        before @ K @ K @ after]))
        self.parent, self.dof = np.array(self.parent), np.array(self.dof)
        self.terms = np.stack(self.terms)
        self.names = [b.getName() for b in bodies]
        segment = {name: i for i, name in enumerate(HAND_SEGMENTS)}
        boxes, spheres = [], []
        for i, b in enumerate(bodies):
            for s in b.getShapeNodes():
                if not s.hasVisualAspect():
                    continue
                shape, local = s.getShape(), np.asarray(s.getRelativeTransform().matrix())
                kind = type(shape).__name__
                if kind == "BoxShape":
                    boxes.append((i, local, np.asarray(shape.getSize()) / 2,
                                  segment.get(b.getName(), -1)))
                elif kind == "SphereShape":
                    spheres.append((i, local, shape.getRadius()))
        self.box_body = np.array([b[0] for b in boxes])
        self.box_local = np.stack([b[1] for b in boxes])
        self.box_half = np.stack([b[2] for b in boxes])
        self.box_segment = np.array([b[3] for b in boxes])
        self.sphere_body = np.array([s[0] for s in spheres], int)
        self.sphere_local = np.stack([s[1] for s in spheres]) if spheres else np.zeros((0, 4, 4))
        self.sphere_radius = np.array([s[2] for s in spheres])
        self.ball_radius = world.config.ball.radius
        self.string_length = world.config.ball.string_length

    def body_transforms(self, dofs: np.ndarray) -> np.ndarray:
        """World transforms (T, B, 4, 4) of every body for joint positions ``dofs`` (T, ndof)."""
        dofs = np.asarray(dofs, float)
        # (T, ndof, 3): the coefficients 1, sin q, 1 - cos q of each joint's three terms
        coefficients = np.stack([np.ones_like(dofs), np.sin(dofs), 1.0 - np.cos(dofs)], axis=-1)
        out = np.empty((len(dofs), len(self.names), 4, 4))
        _body_transforms(coefficients, self.parent, self.dof, self.terms, out)
        return out

    def shape_poses(self, dofs: np.ndarray):
        """Centres (T, n, 3) and xyzw quaternions (T, n, 4) of the boxes, and the sphere centres
        (T, m, 3)."""
        bodies = self.body_transforms(dofs)
        T = len(bodies)
        centres, quats = np.empty((T, len(self.box_body), 3)), np.empty((T, len(self.box_body), 4))
        spheres = np.empty((T, len(self.sphere_body), 3))
        _shape_poses(bodies, self.box_body, self.box_local, self.sphere_body, self.sphere_local,
                     centres, quats, spheres)
        return centres, quats, spheres


@njit(cache=True)
def _compose(a, b, out):
    """``out = a @ b`` for 4 x 4 rigid transforms (each sum in index order)."""
    for r in range(4):
        for c in range(4):
            out[r, c] = (a[r, 0] * b[0, c] + a[r, 1] * b[1, c] + a[r, 2] * b[2, c]
                         + a[r, 3] * b[3, c])


@njit(cache=True)
def _body_transforms(coefficients, parent, dof, terms, out):
    local = np.empty((4, 4))
    for t in range(out.shape[0]):
        for i in range(out.shape[1]):
            d = dof[i]
            for r in range(4):
                for c in range(4):
                    local[r, c] = terms[i, 0, r, c] if d < 0 else (
                        coefficients[t, d, 0] * terms[i, 0, r, c]
                        + coefficients[t, d, 1] * terms[i, 1, r, c]
                        + coefficients[t, d, 2] * terms[i, 2, r, c])
            if parent[i] < 0:
                out[t, i] = local
            else:
                _compose(out[t, parent[i]], local, out[t, i])


@njit(cache=True)
def _shape_poses(bodies, box_body, box_local, sphere_body, sphere_local, centres, quats, spheres):
    pose = np.empty((4, 4))
    for t in range(bodies.shape[0]):
        for k in range(box_body.shape[0]):
            _compose(bodies[t, box_body[k]], box_local[k], pose)
            centres[t, k] = pose[:3, 3]
            quaternion_of(pose[:3, :3], quats[t, k])
        for k in range(sphere_body.shape[0]):
            _compose(bodies[t, sphere_body[k]], sphere_local[k], pose)
            spheres[t, k] = pose[:3, 3]
