"""A trial seen again by the numpy camera (``viewing.replay``): a real trial's recording puts a
real DART world back in each recorded state (the hand and the ball where the trial had them),
and ``watch`` without a viewer draws it beside the recording: a strip of instants that differ,
an animated GIF of every control step at real time."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from dart_reach.model.world import World
from dart_reach.recording.rrd import read_rrd
from dart_reach.viewing.replay import PICTURE_SIZE, STRIP_INSTANTS, Poses, Replay
from dart_reach.viewing.watch import watch


@pytest.fixture(scope="module")
def watched(tmp_path_factory):
    """A shipped robot's trial, written with no viewer: the recording and the pictures."""
    return watch("pre", shipped="arm-length-shoulder", viewer=False,
                 out=tmp_path_factory.mktemp("replay") / "w.rrd")


def test_a_recording_puts_the_world_back_in_each_recorded_state(watched):
    table = read_rrd(watched.recording)
    world = World()
    poses = Poses.of_recording(table, world)
    assert poses.steps == table.height == 200 and poses.dt == pytest.approx(0.1)
    replay = Replay(world, poses, 160, 120)
    hand = table.select([f"robot/positions/hand/{a}" for a in "xyz"]).to_numpy()
    ball = table.select([f"robot/positions/ball/{a}" for a in "xyz"]).to_numpy()
    assert np.ptp(hand, axis=0).max() > 0.05  # the hand moves: the check means something
    images = {}
    for k in range(0, 200, 9):
        images[k] = replay.frame(k)
        # the palm is not moved by the fingers (drawn at their mean flexion): exact
        assert np.abs(world.hand_position() - hand[k]).max() < 1e-9, k
        assert np.abs(world.ball_position() - ball[k]).max() < 1e-9, k
        assert images[k].shape == (120, 160, 3)
    assert not np.array_equal(images[0], images[99])  # the camera sees the robot move
    assert replay.at(0.0) == 0 and replay.at(0.35) == 3 and replay.at(99.0) == 199
    assert np.array_equal(replay.frame(0), images[0])  # the same state, the same image


def test_watch_without_a_viewer_draws_a_strip_and_an_animation(watched):
    assert watched.viewer_pid is None
    strip, animation = watched.pictures
    assert (strip, animation) == (watched.recording.with_suffix(".png"),
                                  watched.recording.with_suffix(".gif"))
    width, height = PICTURE_SIZE
    with Image.open(strip) as image:
        assert image.format == "PNG"
        assert image.size == (STRIP_INSTANTS * width + STRIP_INSTANTS - 1, height)
        panels = [np.asarray(image.convert("RGB"))[:, i * (width + 1):i * (width + 1) + width]
                  for i in range(STRIP_INSTANTS)]
    # the red ball in every panel, and the first and last instants differ
    assert all(((p[..., 0] > 120) & (p[..., 1] < 60)).sum() > 50 for p in panels)
    assert np.abs(panels[0].astype(int) - panels[-1].astype(int)).mean() > 0.5
    with Image.open(animation) as gif:
        assert gif.format == "GIF" and gif.size == PICTURE_SIZE and gif.n_frames > 100
        durations = []
        for k in range(gif.n_frames):  # a still step is merged into the frame before it
            gif.seek(k)
            durations.append(gif.info["duration"])
    assert sum(durations) == 200 * 100 and min(durations) == 100  # real time: 0.1 s a step
