"""A trial seen again by the numpy camera (``camera.SceneCamera``): no GPU, display or graphics
driver. The world is put in the state of a recorded step (the robot's joints, the ball on its
string) and drawn; ``write_pictures`` makes a strip of a few instants and an animated image of
the whole trial (``dart-reach watch`` where no viewer opens), ``frame`` the frames of
``dart-reach video`` where the Rerun viewer cannot render.

A trial comes from this process (``Poses.of_trial``: its ``TrialData``, every joint as the
physics held it) or from its recording (``Poses.of_recording``: the recording holds the 13
joints and the hand's mean finger flexion, so every finger is drawn at that mean; the ball
hangs from the default string, ``world.BallConfig``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from .. import integrity
from ..model.ctrnn import MOTOR_NAMES
from ..model.icub import HAND_SEGMENTS
from ..model.task import TrialData
from ..model.world import World
from .camera import SceneCamera

#: Pixels of each picture of ``write_pictures``: the strip's panels and the animation's frames.
PICTURE_SIZE = (320, 240)
#: How many instants the strip shows, evenly spread from the first step to the last.
STRIP_INSTANTS = 5


@dataclass(frozen=True)
class Poses:
    """What the camera needs of a trial, per control step: every degree of freedom of the
    robot (T, ndof; rad), the ball's centre (T, 3; m, world frame), which hand segments touch
    the ball (T, 16; ``icub.HAND_SEGMENTS``), and the control step ``dt`` (s)."""

    dofs: np.ndarray
    ball: np.ndarray
    contacts: np.ndarray
    dt: float

    @property
    def steps(self) -> int:
        return len(self.ball)

    @classmethod
    def of_trial(cls, data: TrialData, dt: float) -> "Poses":
        """A trial run in this process (its rows up to the last step run)."""
        n = data.steps_run or len(data.ball)
        return cls(data.dofs[:n], data.ball[:n], data.contacts[:n], float(dt))

    @classmethod
    def of_recording(cls, table, world: World) -> "Poses":
        """A trial's recording read back (``recording.rrd.read_rrd``'s table): the 14 motor
        angles give every degree of freedom of ``world``'s robot (each finger joint the hand's
        mean flexion)."""
        groups = ("robot/joints/head_torso", "robot/joints/arm_hand")
        motors = [next(f"{g}/{name}" for g in groups if f"{g}/{name}" in table.columns)
                  for name in MOTOR_NAMES]
        angles = table.select(motors).to_numpy()
        ball = table.select([f"robot/positions/ball/{a}" for a in "xyz"]).to_numpy()
        contacts = table.select([f"robot/contacts/{s}" for s in HAND_SEGMENTS]).to_numpy() > 0.5
        times = table["sim_time"].to_numpy()
        dt = float(np.median(np.diff(times))) if len(times) > 1 else 0.1
        return cls(angles[:, world.layout.dof_motor], ball, contacts, dt)


class Replay:
    """The camera (``width`` x ``height`` pixels) on ``world``, which ``frame(k)`` puts in the
    state of step ``k`` of ``poses``. The ball's pivot is where the trial hung it: its string
    length above the ball's first position (a trial starts with the ball at rest)."""

    def __init__(self, world: World, poses: Poses, width: int = PICTURE_SIZE[0],
                 height: int = PICTURE_SIZE[1]):
        if poses.steps == 0:
            raise ValueError("a trial of no step has nothing to draw")
        self.world, self.poses = world, poses
        world.reset(poses.ball[0])  # the pivot above the first position, time 0
        self.pivot = poses.ball[0] + [0.0, 0.0, world.config.ball.string_length]
        self.camera = SceneCamera(world, width, height)

    def frame(self, k: int) -> np.ndarray:
        """The camera's view of step ``k``, (height, width, 3) uint8."""
        p = self.poses
        self.world.robot.setPositions(p.dofs[k])
        self.world.ball_skeleton.setPositions(pendulum_angles(p.ball[k] - self.pivot))
        return self.camera.image(self.world, p.contacts[k])

    def at(self, seconds: float) -> int:
        """The step shown at ``seconds`` of simulated time: the last one at or before it."""
        return int(np.clip(np.floor(seconds / self.poses.dt + 1e-9), 0, self.poses.steps - 1))


def pendulum_angles(offset) -> np.ndarray:
    """The angles (rad) of the ball's universal joint (about x, then about y;
    ``bodies.make_ball``) that hang the ball in the direction of ``offset`` (ball centre less
    pivot) from its pivot."""
    d = np.asarray(offset, float)
    length = np.linalg.norm(d)
    if not length > 0:  # at the pivot (not a state a trial reaches): hanging straight down
        return np.zeros(2)
    d = d / length
    # R_x(a) R_y(b) (0, 0, -1) = (-sin b, cos b sin a, -cos b cos a)
    return np.array([np.arctan2(d[1], -d[2]), np.arcsin(np.clip(-d[0], -1.0, 1.0))])


def strip(replay: Replay, instants: int = STRIP_INSTANTS):
    """A PIL image: ``instants`` frames side by side, evenly spread over the trial, each
    labelled with its simulated time."""
    last = replay.poses.steps - 1
    steps = sorted({round(last * i / max(instants - 1, 1)) for i in range(instants)})
    width, height = replay.camera.width, replay.camera.height
    image = Image.new("RGB", (width * len(steps) + len(steps) - 1, height), "white")
    draw = ImageDraw.Draw(image)
    for i, k in enumerate(steps):
        x = i * (width + 1)
        image.paste(Image.fromarray(replay.frame(k)), (x, 0))
        draw.text((x + 6, 4), f"{k * replay.poses.dt:.1f} s", fill=(20, 20, 20))
    return image


def write_pictures(world: World, poses: Poses, recording: Path) -> tuple[Path, Path]:
    """Beside ``recording`` (``X.rrd``): ``X.png``, a strip of the trial at a few instants,
    and ``X.gif``, the whole trial animated at real time (one frame per control step), both
    drawn by the camera at ``PICTURE_SIZE``. Returns their paths."""
    replay = Replay(world, poses)
    png, gif = Path(recording).with_suffix(".png"), Path(recording).with_suffix(".gif")
    picture = strip(replay)
    integrity.write(png, lambda p: picture.save(p, format="PNG", optimize=True))
    # GIF's 256 colours per frame by a fast octree, no dithering: a quarter of the time and
    # half the bytes of Pillow's default (the scene's flat shades lose nothing to see)
    frames = [Image.fromarray(replay.frame(k)).quantize(
        255, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE)
        for k in range(poses.steps)]
    integrity.write(gif, lambda p: frames[0].save(
        p, format="GIF", save_all=True, append_images=frames[1:], loop=0,
        duration=round(1000 * poses.dt)))
    return png, gif
