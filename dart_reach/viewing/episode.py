"""Frames of a trial in progress, drawn by the real Rerun viewer, headless
(``viewing.headless``; it needs a Vulkan driver, Mesa's software one on a machine without a
GPU): the frames of the Gymnasium environment's ``render_mode="rgb_array"``. It takes a
trial's record and the world it runs in, not the environment (``envs`` imports it, never the
other way).
"""

from __future__ import annotations

import dataclasses
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

from ..model.task import TrialData
from ..model.world import World
from ..recording.rrd import RobotModel, TrialInfo, trial_rrd, write_rrd
from .headless import HeadlessViewer, renderer_missing


class TrialRenderer:
    """A trial so far, recorded (``recording.trial_rrd``, the trial layout), opened in a
    headless Rerun viewer (started on the first frame) with the time cursor at its last
    observed step, and its screenshot: 5 s for the first frame (the viewer starts), 1 s for
    each after (software Vulkan, a loaded 2-core machine, 2026-11-26): for looking at a
    policy, not for training with pixels. RuntimeError where the viewer cannot draw (no
    Vulkan driver), with the reason."""

    def __init__(self, size: str = "960x600"):
        reason = renderer_missing()
        if reason:
            raise RuntimeError(f"render_mode='rgb_array' draws with the Rerun viewer, "
                               f"headless, which cannot run here: {reason}")
        self._size = size
        self._folder = tempfile.TemporaryDirectory(prefix="dart-reach-render-")
        self._viewer: HeadlessViewer | None = None
        self._model: RobotModel | None = None

    def frame(self, world: World, data: TrialData, info: TrialInfo) -> np.ndarray:
        """The frame (H, W, 3) uint8 of the trial ``data`` (run in ``world``) at the state it
        observed last; ``info``: what the trial is about (the recording's properties)."""
        if self._viewer is None:
            self._viewer = HeadlessViewer(size=self._size)
            self._model = RobotModel(world)
        seen = min(data.steps_run + 1, data.p_multimodal.shape[0])  # the state observed last
        folder = Path(self._folder.name)
        recording = folder / "episode.rrd"
        dt = world.config.control_dt
        write_rrd(recording, trial_rrd(dataclasses.replace(data, steps_run=seen), info,
                                       self._model, dt))
        self._viewer.show(recording, sim_time_s=(seen - 1) * dt, settle_s=0.5)
        with Image.open(self._viewer.screenshot(folder / "frame.png")) as image:
            return np.asarray(image.convert("RGB"))

    def close(self) -> None:
        if self._viewer is not None:
            self._viewer.close()
            self._viewer = None
        self._folder.cleanup()
