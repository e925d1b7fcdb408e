"""The bodies of the scene as DART skeletons (section III, Fig. 1): the robot loaded from its
URDF file and the ball hung on its pendulum. ``world.World`` builds its world from them."""

from __future__ import annotations

import math
from pathlib import Path

import dartpy as dart


class SkeletonError(ValueError):
    """The robot model file is missing or cannot be used."""


def load_skeleton(path) -> dart.dynamics.Skeleton:
    """The robot's skeleton from its URDF file at ``path``, its root welded to the world (the
    iCub "suspended vertically over a stick attached to the pelvis", section III);
    ``SkeletonError`` when the file is missing or not a robot model."""
    path = Path(path)
    if not path.is_file():
        raise SkeletonError(f"skeleton file not found: {path}")
    text = path.read_text(errors="replace")
    if "<robot" not in text:
        raise SkeletonError(f"skeleton file {path} is not a URDF (no <robot> element)")
    loader = dart.utils.DartLoader()
    options = dart.utils.DartLoaderOptions()
    options.mDefaultRootJointType = dart.utils.DartLoaderRootJointType.FIXED
    loader.setOptions(options)
    skeleton = loader.parseSkeleton(dart.common.Uri.createFromPath(str(path.resolve())))
    if skeleton is None or skeleton.getNumDofs() == 0:
        raise SkeletonError(f"skeleton file {path} could not be parsed as a robot model")
    return skeleton


def make_ball(config):
    """The ball of ``config`` (a ``world.BallConfig``): a sphere hung from a fixed pivot
    ``string_length`` above its centre on a universal joint (two perpendicular horizontal
    axes): a spherical pendulum with a massless string. Each axis's swing is limited to
    ``max_swing`` by the constraint solver, so the ball can never rise to its pivot, whatever
    hits it (a taut string); damping brings a swing to rest."""
    skel = dart.dynamics.Skeleton("ball")
    joint_props = dart.dynamics.UniversalJointProperties()
    joint_props.mName = "pendulum_pivot"
    joint, body = skel.createUniversalJointAndBodyNodePair(None, joint_props)
    joint.setAxis1([1.0, 0.0, 0.0])
    joint.setAxis2([0.0, 1.0, 0.0])
    body.setName("ball")
    T = dart.math.Isometry3()
    T.set_translation([0.0, 0.0, config.string_length])
    joint.setTransformFromChildBodyNode(T)
    swing = math.radians(config.max_swing)
    for i in range(2):
        joint.setDampingCoefficient(i, config.damping)
        joint.setPositionLowerLimit(i, -swing)
        joint.setPositionUpperLimit(i, swing)
    joint.setLimitEnforcement(True)
    body.setMass(config.mass)
    i = 0.4 * config.mass * config.radius ** 2
    body.setMomentOfInertia(i, i, i, 0.0, 0.0, 0.0)
    shape = body.createShapeNode(dart.dynamics.SphereShape(config.radius))
    shape.createVisualAspect().setColor(list(config.color))
    shape.createCollisionAspect()
    shape.createDynamicsAspect().setFrictionCoeff(config.friction)
    return skel, joint, body
