"""Seeing an episode of ``ReachGraspEnv``: a Rerun recording like a trial's (the trial's own
``recording.trial_rrd``, so the trial layout and ``dart-reach`` readers work on it), and the
frames of ``render_mode="rgb_array"``, drawn by the real Rerun viewer, headless
(``viewing.headless``: it needs a Vulkan driver, Mesa's software one on a machine without a GPU).
"""

from __future__ import annotations

import dataclasses
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

from ..recording.rrd import RobotModel, TrialInfo, trial_rrd, write_rrd
from ..viewing.headless import HeadlessViewer, renderer_missing
from .reach_grasp import ReachGraspEnv

#: The ``condition`` an episode's recording names (its ``phase`` is the environment's).
CONDITION = "gymnasium"


def _unwrapped(env) -> ReachGraspEnv:
    env = getattr(env, "unwrapped", env)
    if not isinstance(env, ReachGraspEnv):
        raise TypeError(f"expected a ReachGraspEnv (or a wrapper of one), got "
                        f"{type(env).__name__}")
    if env.trial_data is None:
        raise ValueError("no episode to record: call reset() first")
    return env


def episode_rrd(env, blueprint: bool = True) -> bytes:
    """The .rrd bytes of the current episode of ``env`` (its steps so far), written as
    ``Trial.run``'s trials are (``recording.trial_rrd``): the scene, every sensor, motor and
    fitness term over time. The internal neurons read 0 (a policy's state is not known)."""
    env = _unwrapped(env)
    return trial_rrd(env.trial_data, _info(env), RobotModel(env.world),
                     env.world.config.control_dt, blueprint=blueprint)


def _info(env: ReachGraspEnv) -> TrialInfo:
    """What the recording is about: the phase, the sector, the reset's seed ("drawn": the
    environment's generator went on)."""
    seed = "drawn" if env.episode_seed is None else str(env.episode_seed)
    return TrialInfo(CONDITION, env.phase.name, 0, 0, env.trial_data.sector, 0, seed,
                     senses=env.config.senses.value)


def record_episode(env, path) -> Path:
    """Write the current episode of ``env`` to the .rrd file ``path`` (``rerun PATH`` shows
    it); returns the path."""
    return write_rrd(Path(path), episode_rrd(env))


class Renderer:
    """The frames of ``render_mode="rgb_array"``: the episode so far, recorded, opened in a
    headless Rerun viewer (started on the first frame, one per environment) with the time
    cursor at the current step, and its screenshot: 5 s for the first frame (the viewer
    starts), 1 s for each after (software Vulkan, a loaded 2-core machine, 2026-11-26): for
    looking at a policy, not for training with pixels. RuntimeError where the viewer cannot
    draw (no Vulkan driver), with the reason."""

    def __init__(self, size: str = "960x600"):
        reason = renderer_missing()
        if reason:
            raise RuntimeError(f"render_mode='rgb_array' draws with the Rerun viewer, "
                               f"headless, which cannot run here: {reason}")
        self._size = size
        self._folder = tempfile.TemporaryDirectory(prefix="dart-reach-render-")
        self._viewer: HeadlessViewer | None = None
        self._model: RobotModel | None = None

    def frame(self, env: ReachGraspEnv) -> np.ndarray:
        """The frame (H, W, 3) uint8 of ``env`` at its current step."""
        if self._viewer is None:
            self._viewer = HeadlessViewer(size=self._size)
            self._model = RobotModel(env.world)
        data = env.trial_data
        seen = min(data.steps_run + 1, data.p_multimodal.shape[0])  # the state observed last
        folder = Path(self._folder.name)
        recording = folder / "episode.rrd"
        write_rrd(recording, trial_rrd(dataclasses.replace(data, steps_run=seen), _info(env),
                                       self._model, env.world.config.control_dt))
        self._viewer.show(recording, sim_time_s=(seen - 1) * env.world.config.control_dt,
                          settle_s=0.5)
        with Image.open(self._viewer.screenshot(folder / "frame.png")) as image:
            return np.asarray(image.convert("RGB"))

    def close(self) -> None:
        if self._viewer is not None:
            self._viewer.close()
            self._viewer = None
        self._folder.cleanup()
