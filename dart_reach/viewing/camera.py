"""A camera image of the scene, drawn in numpy: the robot's and the ball's shapes as DART holds
them, seen through a fixed pinhole camera, without a GPU, a display or a graphics driver.

Each frame reads the world pose of every visual shape of the robot and the ball from the DART
world (``ShapeNode.getWorldTransform``: its cost in docs/results/benchmarks.md) and casts one
ray per pixel against it, in the shape's own frame: boxes (slabs), spheres, capsules and
cylinders (DART's primitives; meshes and other shapes are listed in ``SceneCamera.skipped`` and
not drawn). Only the pixels inside the screen rectangle that bounds a shape's projection are
tested, and a depth buffer keeps the nearest hit, whose normal gives flat Lambert shading under
one fixed light. The pendulum's string is drawn as a depth-tested line. Everything is float64
numpy with a fixed order of operations: the same state gives the same image to the last bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.icub import HAND_SEGMENTS
from ..model.world import World

#: Where the camera stands and what it looks at (m, the world frame: +x backward, +y the
#: robot's right, +z up): in front of the robot, to its right and above, on the sector area,
#: as the 3D view of the trial layout (``recording.layout.CAMERA``).
POSITION = (-0.85, 0.55, 0.45)
TARGET = (-0.18, 0.1, 0.12)
UP = (0.0, 0.0, 1.0)
#: deg, the camera's vertical field of view.
FIELD_OF_VIEW = 40.0
#: Direction towards the light (world frame; normalised), and the share of ambient light.
LIGHT = (-0.5, 0.6, 0.9)
AMBIENT = 0.35
#: Colours (0-1): the background's top and bottom, a hand segment that touches the ball, the
#: pendulum's string.
SKY, GROUND = (0.93, 0.94, 0.97), (0.72, 0.73, 0.76)
TOUCH = (1.0, 0.78, 0.0)
STRING = (0.3, 0.3, 0.3)


@dataclass(frozen=True)
class _Shape:
    node: object  # dart.dynamics.ShapeNode
    kind: str  # "box", "sphere", "capsule", "cylinder"
    size: tuple  # box: half sizes; sphere: (radius,); capsule, cylinder: (radius, half height)
    bound: float  # radius of a sphere around the shape's origin that holds it
    colour: np.ndarray
    segment: int  # index in icub.HAND_SEGMENTS, or -1


def _primitive(shape) -> tuple[str, tuple, float] | None:
    kind = type(shape).__name__
    if kind == "BoxShape":
        half = tuple(float(h) for h in np.asarray(shape.getSize()) / 2)
        return "box", half, math.sqrt(sum(h * h for h in half))
    if kind == "SphereShape":
        r = float(shape.getRadius())
        return "sphere", (r,), r
    if kind in ("CapsuleShape", "CylinderShape"):
        r, half = float(shape.getRadius()), float(shape.getHeight()) / 2
        return kind[:-5].lower(), (r, half), (half + r if kind == "CapsuleShape"
                                               else math.hypot(r, half))
    return None


class SceneCamera:
    """A fixed pinhole camera on a world's robot and ball: ``image(world)`` is its view of the
    world's current state, (height, width, 3) uint8. ``width``, ``height``: pixels;
    ``position``, ``target``, ``up`` (m, world frame) and ``fov`` (deg, vertical) place it.
    The shapes are listed once, from ``world`` (every shape node with a visual aspect of the
    robot and the ball, coloured as DART holds them); their poses are read at every image."""

    def __init__(self, world: World, width: int = 320, height: int = 240,
                 position=POSITION, target=TARGET, up=UP, fov: float = FIELD_OF_VIEW):
        if int(width) < 8 or int(height) < 8:
            raise ValueError(f"the image must be at least 8x8 pixels, got {width}x{height}")
        self.width, self.height = int(width), int(height)
        self.position = np.asarray(position, float)
        forward = np.asarray(target, float) - self.position
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, np.asarray(up, float))
        right /= np.linalg.norm(right)
        down = np.cross(forward, right)
        #: rows: the camera's right, down and forward axes in the world frame
        self.axes = np.stack([right, down, forward])
        self.focal = 0.5 * self.height / math.tan(math.radians(fov) / 2)  # pixels
        u = (np.arange(self.width) + 0.5 - 0.5 * self.width) / self.focal
        v = (np.arange(self.height) + 0.5 - 0.5 * self.height) / self.focal
        rays = (forward + u[None, :, None] * right + v[:, None, None] * down)
        self._rays = rays / np.linalg.norm(rays, axis=-1, keepdims=True)  # (H, W, 3), unit
        light = np.asarray(LIGHT, float)
        self._light = light / np.linalg.norm(light)
        shade = np.linspace(0.0, 1.0, self.height)[:, None, None]
        self._background = np.broadcast_to(
            (1 - shade) * np.asarray(SKY) + shade * np.asarray(GROUND),
            (self.height, self.width, 3)).copy()
        segment = {name: i for i, name in enumerate(HAND_SEGMENTS)}
        self.shapes: list[_Shape] = []
        #: shapes that cannot be drawn (meshes, ...): "body: ShapeType"
        self.skipped: list[str] = []
        for skeleton in (world.robot, world.ball_skeleton):
            for body in skeleton.getBodyNodes():
                for node in body.getShapeNodes():
                    if not node.hasVisualAspect():
                        continue
                    primitive = _primitive(node.getShape())
                    if primitive is None:
                        self.skipped.append(f"{body.getName()}: {type(node.getShape()).__name__}")
                        continue
                    colour = np.asarray(node.getVisualAspect().getColor(), float)[:3]
                    self.shapes.append(_Shape(node, *primitive, colour,
                                              segment.get(body.getName(), -1)))
        self._pivot = world.ball_body.getParentJoint()

    # ------------------------------------------------------------------ drawing
    def image(self, world: World | None = None, touching=None) -> np.ndarray:
        """The camera's view of the scene as the DART world holds it now, (H, W, 3) uint8.
        ``touching``: which hand segments (``icub.HAND_SEGMENTS`` order) touch the ball, drawn
        yellow (a trial's ``contacts`` row); None: none. ``world`` is the one the camera was
        built on (its shapes are read through their DART nodes); it is taken for clarity."""
        H, W = self.height, self.width
        depth = np.full((H, W), np.inf)
        normal = np.zeros((H, W, 3))
        colour = np.zeros((H, W, 3))
        for shape in self.shapes:
            pose = shape.node.getWorldTransform().matrix()
            if not np.isfinite(pose).all():
                continue  # a diverged world: nothing to draw of it
            box = self._window(pose[:3, 3], shape.bound)
            if box is None:
                continue
            r0, r1, c0, c1 = box
            rays = self._rays[r0:r1, c0:c1].reshape(-1, 3)
            t, n = _HIT[shape.kind](self.position, rays, pose, shape.size)
            here = depth[r0:r1, c0:c1]
            nearer = (t < here.reshape(-1)).reshape(here.shape)
            if not nearer.any():
                continue
            here[nearer] = t.reshape(here.shape)[nearer]
            normal[r0:r1, c0:c1][nearer] = n.reshape(*here.shape, 3)[nearer]
            paint = shape.colour
            if touching is not None and shape.segment >= 0 and touching[shape.segment]:
                paint = np.asarray(TOUCH)
            colour[r0:r1, c0:c1][nearer] = paint
        self._string(depth, colour, normal)
        hit = np.isfinite(depth)
        lambert = np.clip(normal @ self._light, 0.0, 1.0)
        light = AMBIENT + (1.0 - AMBIENT) * lambert
        out = np.where(hit[..., None], colour * light[..., None], self._background)
        return (np.clip(out, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)

    def project(self, points) -> np.ndarray:
        """Pixel coordinates (n, 2: column, row) of world points (n, 3) in front of the camera
        (NaN behind it)."""
        local = (np.asarray(points, float).reshape(-1, 3) - self.position) @ self.axes.T
        z = np.where(local[:, 2] > 1e-9, local[:, 2], np.nan)
        return np.stack([self.focal * local[:, 0] / z + 0.5 * self.width,
                         self.focal * local[:, 1] / z + 0.5 * self.height], axis=1)

    def _window(self, centre: np.ndarray, radius: float):
        """The pixel rectangle (r0, r1, c0, c1) that holds the projection of a sphere, or None
        when it is off the image or behind the camera (a shape through the image plane is
        tested everywhere)."""
        x, y, z = self.axes @ (centre - self.position)
        if z + radius <= 1e-6:
            return None
        if z - radius <= 1e-6:
            return 0, self.height, 0, self.width
        # the projection of the camera-aligned cube around the sphere holds the sphere's
        xs = [self.focal * (x + a) / (z + b) for a in (-radius, radius) for b in (-radius, radius)]
        ys = [self.focal * (y + a) / (z + b) for a in (-radius, radius) for b in (-radius, radius)]
        c0 = max(0, int(math.floor(min(xs) + 0.5 * self.width)))
        c1 = min(self.width, int(math.ceil(max(xs) + 0.5 * self.width)) + 1)
        r0 = max(0, int(math.floor(min(ys) + 0.5 * self.height)))
        r1 = min(self.height, int(math.ceil(max(ys) + 0.5 * self.height)) + 1)
        return None if c0 >= c1 or r0 >= r1 else (r0, r1, c0, c1)

    def _string(self, depth: np.ndarray, colour: np.ndarray, normal: np.ndarray) -> None:
        """The pendulum's string, pivot to ball centre, a depth-tested line a pixel wide."""
        pivot = self._pivot.getTransformFromParentBodyNode().translation()
        ball = self._pivot.getChildBodyNode().getWorldTransform().translation()
        n = 2 * (self.width + self.height)
        s = np.linspace(0.0, 1.0, n)[:, None]
        points = pivot + s * (ball - pivot)
        pixels = self.project(points)
        distance = np.linalg.norm(points - self.position, axis=1)
        ok = np.isfinite(pixels).all(axis=1)
        col = np.floor(pixels[ok, 0]).astype(int)
        row = np.floor(pixels[ok, 1]).astype(int)
        distance = distance[ok]
        inside = (col >= 0) & (col < self.width) & (row >= 0) & (row < self.height)
        row, col, distance = row[inside], col[inside], distance[inside]
        front = distance < depth[row, col]
        row, col = row[front], col[front]
        depth[row, col] = distance[front]
        colour[row, col] = STRING
        normal[row, col] = self._light  # lit: the string is drawn in its own colour


# ------------------------------------------------------------------------------ ray casting
# Each takes the rays' origin (3,), their unit directions (n, 3), the shape's world pose (4, 4)
# and its size, and returns the distance along each ray to its first hit (inf: none) and the
# world normal there (n, 3).

def _local(origin, rays, pose):
    rotation = pose[:3, :3]
    return rotation.T @ (origin - pose[:3, 3]), rays @ rotation, rotation


def _box(origin, rays, pose, half):
    o, d, rotation = _local(origin, rays, pose)
    half = np.asarray(half)
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = 1.0 / d
        t1 = (-half - o) * inverse
        t2 = (half - o) * inverse
    near = np.fmin(t1, t2)
    far = np.fmax(t1, t2)
    axis = np.argmax(near, axis=1)
    t_near = near[np.arange(len(near)), axis]
    t_far = far.min(axis=1)
    t = np.where((t_near <= t_far) & (t_near > 0.0), t_near, np.inf)
    n = np.zeros_like(d)
    n[np.arange(len(n)), axis] = -np.sign(d[np.arange(len(d)), axis])
    return t, n @ rotation.T


def _sphere_hit(o, d, centre, radius):
    """Ray-sphere in any frame: distance (inf: none) and the hit point."""
    oc = o - centre
    b = d @ oc
    disc = b * b - (oc @ oc - radius * radius)
    with np.errstate(invalid="ignore"):
        t = -b - np.sqrt(disc)
    t = np.where((disc >= 0.0) & (t > 0.0), t, np.inf)
    return t


def _sphere(origin, rays, pose, size):
    centre = pose[:3, 3]
    t = _sphere_hit(origin, rays, centre, size[0])
    with np.errstate(invalid="ignore"):
        n = (origin + t[:, None] * rays - centre) / size[0]
    return t, np.where(np.isfinite(t)[:, None], n, 0.0)


def _side(o, d, radius, half):
    """The side of a cylinder along local z: distance (inf: none) and local normals."""
    a = d[:, 0] ** 2 + d[:, 1] ** 2
    b = o[0] * d[:, 0] + o[1] * d[:, 1]
    c = o[0] ** 2 + o[1] ** 2 - radius * radius
    disc = b * b - a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (-b - np.sqrt(disc)) / a
    z = o[2] + t * d[:, 2]
    t = np.where((disc >= 0.0) & (a > 1e-12) & (t > 0.0) & (np.abs(z) <= half), t, np.inf)
    p = o + np.where(np.isfinite(t), t, 0.0)[:, None] * d
    n = np.stack([p[:, 0] / radius, p[:, 1] / radius, np.zeros(len(t))], axis=1)
    return t, n


def _nearest(candidates):
    """The nearest of several (t, n) hits, per ray."""
    ts = np.stack([t for t, _ in candidates])
    pick = np.argmin(ts, axis=0)
    ns = np.stack([n for _, n in candidates])
    rows = np.arange(ts.shape[1])
    return ts[pick, rows], ns[pick, rows]


def _capsule(origin, rays, pose, size):
    radius, half = size
    o, d, rotation = _local(origin, rays, pose)
    hits = [_side(o, d, radius, half)]
    for end in (-half, half):
        centre = np.array([0.0, 0.0, end])
        t = _sphere_hit(o, d, centre, radius)
        p = o + np.where(np.isfinite(t), t, 0.0)[:, None] * d
        hits.append((t, (p - centre) / radius))
    t, n = _nearest(hits)
    return t, n @ rotation.T


def _cylinder(origin, rays, pose, size):
    radius, half = size
    o, d, rotation = _local(origin, rays, pose)
    hits = [_side(o, d, radius, half)]
    for end in (-half, half):
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (end - o[2]) / d[:, 2]
        p = o + np.where(np.isfinite(t), t, 0.0)[:, None] * d
        inside = (t > 0.0) & (p[:, 0] ** 2 + p[:, 1] ** 2 <= radius * radius)
        n = np.zeros_like(d)
        n[:, 2] = math.copysign(1.0, end)
        hits.append((np.where(inside, t, np.inf), n))
    t, n = _nearest(hits)
    return t, n @ rotation.T


_HIT = {"box": _box, "sphere": _sphere, "capsule": _capsule, "cylinder": _cylinder}
