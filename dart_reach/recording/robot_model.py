"""The robot's kinematic tree and visual shapes, for drawing a trial from its joint record
(``RobotModel``; no rerun here: ``viewing`` uses it without loading the recorder)."""

from __future__ import annotations

import numpy as np

from ..model.icub import HAND_SEGMENTS
from .quaternion import quaternions


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
        n = dofs.shape[0]
        out = np.empty((n, len(self.names), 4, 4))
        # (T, ndof, 3): the coefficients 1, sin q, 1 - cos q of each joint's three terms
        coefficients = np.stack([np.ones_like(dofs), np.sin(dofs), 1.0 - np.cos(dofs)], axis=-1)
        for i, (p, d, terms) in enumerate(zip(self.parent, self.dof, self.terms)):
            if d >= 0:
                local = (coefficients[:, d] @ terms.reshape(3, 16)).reshape(n, 4, 4)
            else:
                local = np.broadcast_to(terms[0], (n, 4, 4))
            if p < 0:
                out[:, i] = local
            else:
                np.matmul(out[:, p], local, out=out[:, i])
        return out

    def shape_poses(self, dofs: np.ndarray):
        """Centres (T, n, 3) and xyzw quaternions (T, n, 4) of the boxes, and the sphere centres
        (T, m, 3)."""
        bodies = self.body_transforms(dofs)
        box = bodies[:, self.box_body] @ self.box_local
        sphere = bodies[:, self.sphere_body] @ self.sphere_local
        return box[..., :3, 3], quaternions(box[..., :3, :3]), sphere[..., :3, 3]
