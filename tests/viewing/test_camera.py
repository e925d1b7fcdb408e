"""The camera image of the scene (``viewing.camera``, ``viewing.episode``): a real DART world
drawn in numpy. The ball is red where the camera's projection puts it, and moves with it; the
image follows the arm; the same state gives the same image to the last bit; DART's other
primitives (capsule, cylinder) are drawn where they are."""

from __future__ import annotations

import math

import dartpy as dart
import numpy as np
import pytest

from dart_reach.model.icub import HAND_SEGMENTS
from dart_reach.model.task import TrialData
from dart_reach.model.world import World
from dart_reach.viewing.camera import TOUCH, SceneCamera
from dart_reach.viewing.episode import TrialRenderer


@pytest.fixture(scope="module")
def world():
    return World()


def red(image: np.ndarray) -> np.ndarray:
    r, g, b = (image[..., i].astype(int) for i in range(3))
    return (r > 40) & (r > 3 * g) & (r > 3 * b)  # lit or in shade


def centroid(mask: np.ndarray) -> np.ndarray:
    rows, cols = np.nonzero(mask)
    return np.array([cols.mean() + 0.5, rows.mean() + 0.5])  # pixel centres, as ``project``


def test_the_ball_is_red_where_the_camera_sees_it_and_moves_with_it(world):
    camera = SceneCamera(world)
    seen = []
    for sector in (0, 4, 8):
        world.reset(world.sector_point(sector, 0.5, 0.5))
        image = camera.image(world)
        assert image.shape == (240, 320, 3) and image.dtype == np.uint8
        mask = red(image)
        ball = world.ball_position()
        centre = camera.project(ball)[0]
        # its disc: where the pinhole puts it, and as large as its radius at its distance
        assert np.abs(centroid(mask) - centre).max() < 1.5, (sector, centroid(mask), centre)
        distance = np.linalg.norm(ball - camera.position)
        area = math.pi * (camera.focal * world.config.ball.radius / distance) ** 2
        assert 0.8 * area < mask.sum() < 1.2 * area, (mask.sum(), area)
        seen.append(centroid(mask))
    # the sectors run from upper-left to lower-right as the robot sees them: apart on screen
    assert np.linalg.norm(seen[0] - seen[1]) > 10 and np.linalg.norm(seen[1] - seen[2]) > 10
    # an image of another size is the same scene
    world.reset(world.sector_point(4, 0.5, 0.5))
    large = SceneCamera(world, width=640, height=480).image(world)
    assert large.shape == (480, 640, 3)
    assert np.abs(centroid(red(large)) / 2 - seen[1]).max() < 1.0


def test_the_image_follows_the_arm_and_the_same_state_gives_the_same_image(world):
    world.reset(world.sector_point(4, 0.5, 0.5))
    camera = SceneCamera(world)
    home = camera.image(world)
    assert np.array_equal(home, camera.image(world))
    # a second world and camera in the same state: the same image, bit for bit
    other = World()
    other.reset(world.sector_point(4, 0.5, 0.5))
    assert np.array_equal(home, SceneCamera(other).image(other))
    robot = world.robot
    q = robot.getPositions()
    elbow = robot.getJoint("r_elbow").getIndexInSkeleton(0)
    moved = q.copy()
    moved[elbow] += 0.6
    robot.setPositions(moved)
    bent = camera.image(world)
    changed = (bent != home).any(axis=2)
    assert changed.sum() > 200  # the forearm and the hand moved
    # where the hand is now, the image is no longer the background
    col, row = camera.project(world.hand_position())[0].astype(int)
    assert changed[max(row - 6, 0):row + 6, max(col - 6, 0):col + 6].any()
    robot.setPositions(q)
    assert np.array_equal(camera.image(world), home)


def test_touching_hand_segments_are_drawn_yellow(world):
    world.reset(world.sector_point(4, 0.5, 0.5))
    camera = SceneCamera(world)
    touch = np.asarray(TOUCH) * 255

    def yellow(image):
        return (np.abs(image.astype(float) - touch) < 80).all(axis=2).sum()

    assert yellow(camera.image(world)) == 0
    assert yellow(camera.image(world, np.ones(len(HAND_SEGMENTS), bool))) > 50
    renderer = TrialRenderer(160, 120)
    data = TrialData.empty(3, 0, world.ball_position(), world.robot.getNumDofs())
    data.contacts[0] = True
    assert renderer.frame(world, data.contacts[0]).shape == (120, 160, 3)
    assert yellow(renderer.frame(world, data.contacts[0])) > 5
    assert yellow(renderer.frame(world, data.contacts[1])) == 0
    assert yellow(renderer.frame(world)) == 0


@pytest.mark.parametrize("kind", ["capsule", "cylinder"])
def test_capsules_and_cylinders_are_drawn_where_they_are(kind):
    """A green capsule or cylinder added around the ball (radius 5 cm, 20 cm long, along
    world z): its pixels span what the pinhole makes of its ends."""
    world = World()
    world.reset(world.sector_point(4, 0.5, 0.5))
    radius, height = 0.05, 0.2
    shape = (dart.dynamics.CapsuleShape(radius, height) if kind == "capsule"
             else dart.dynamics.CylinderShape(radius, height))
    node = world.ball_body.createShapeNode(shape)
    node.createVisualAspect().setColor([0.0, 0.8, 0.0])
    camera = SceneCamera(world)
    assert [s.kind for s in camera.shapes][-1] == kind
    image = camera.image(world).astype(int)
    green = (image[..., 1] > 40) & (image[..., 1] > 3 * image[..., 0]) \
        & (image[..., 1] > 3 * image[..., 2])
    assert not red(image).any()  # the ball is inside it
    ball = world.ball_position()
    # its outline: the hull of its end spheres (capsule) or of its rims (cylinder), sampled
    a = np.linspace(0, 2 * np.pi, 721)
    ends = [ball + [0, 0, z] for z in (-height / 2, height / 2)]
    if kind == "capsule":
        u, v = np.meshgrid(a, np.linspace(0, np.pi, 361))
        sphere = np.stack([np.sin(v) * np.cos(u), np.sin(v) * np.sin(u), np.cos(v)], -1)
        points = np.concatenate([e + radius * sphere.reshape(-1, 3) for e in ends])
    else:
        rim = np.stack([np.cos(a), np.sin(a), np.zeros_like(a)], -1)
        points = np.concatenate([e + radius * rim for e in ends])
    pixels = camera.project(points)
    rows, cols = np.nonzero(green)
    # the silhouette spans the outline's projection, to the pixel
    for found, outline in ((rows, pixels[:, 1]), (cols, pixels[:, 0])):
        assert abs(found.min() + 0.5 - outline.min()) < 1.5, (kind, found.min(), outline.min())
        assert abs(found.max() + 0.5 - outline.max()) < 1.5, (kind, found.max(), outline.max())
    centre = camera.project(ball)[0]
    assert green[int(centre[1]), int(centre[0])]


def test_the_renderer_needs_no_graphics_stack():
    """The rgb_array path loads neither rerun nor a viewer (a vector environment's workers
    pay for what they import)."""
    import subprocess
    import sys

    code = ("import sys, dart_reach.viewing.episode as e; "
            "print(sorted(m for m in ('rerun', 'polars', 'PIL') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]"
