"""Frames of a trial in progress: the Gymnasium environment's ``render_mode="rgb_array"``. A
camera image of the scene (``viewing.camera``, drawn in numpy: no GPU, display or graphics
driver), with the hand segments that touch the ball drawn yellow. It takes a trial's world and
record, not the environment (``envs`` imports it, never the other way), and loads neither
rerun nor polars, so a vector environment's workers stay light.
"""

from __future__ import annotations

import numpy as np

from ..model.world import World
from .camera import SceneCamera


class TrialRenderer:
    """The camera's view (``camera.SceneCamera``) of a trial's world at the state it holds now,
    the state the trial observed last: ``frame(world, touching)``, (height, width, 3) uint8.
    Its frame rate: ``dart-reach bench``'s ``env_render_fps`` (docs/guides/gymnasium.md,
    "Frame rate")."""

    def __init__(self, width: int = 320, height: int = 240):
        self.width, self.height = int(width), int(height)
        self._camera: SceneCamera | None = None
        self._world: World | None = None

    def frame(self, world: World, touching=None) -> np.ndarray:
        """The frame of ``world`` now; ``touching``: which hand segments touch the ball in
        that state (a row of a trial's ``contacts``, ``TrialData``), drawn yellow; None: no
        contacts drawn."""
        if self._camera is None or world is not self._world:
            self._camera = SceneCamera(world, self.width, self.height)
            self._world = world
        return self._camera.image(world, touching)

    def close(self) -> None:
        self._camera = None
        self._world = None
