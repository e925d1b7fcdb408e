"""A trial streamed to a live Rerun viewer a step at a time: the Gymnasium environment's
``render_mode="human"``. Each step goes out as a row of the trial layout
(``recording.rrd.send_live_step``: the scene, every sensor, motor and fitness term), once its
action is taken, so the viewer shows what ``dart-reach watch`` shows of a recorded trial, as
it happens. Episodes follow one another on the stream's timelines. It takes a trial's world
and record, not the environment. Where the stream goes: ``recording.rrd.live_stream``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..model.task import TrialData
from ..model.world import World
from ..recording.rrd import RobotModel, TrialInfo, live_stream, send_live_step
from .watch import display_available


class LiveViewer:
    """Streams trials to a Rerun viewer (``target``: a viewer's gRPC URL, an .rrd path, or None:
    a viewer spawned here, or a gRPC server where there is no display, its URL printed to stderr
    once); the stream opens at the first step sent. ``send(world, data, info)`` after each step
    sends the rows the trial completed since the last call; a new trial (a new ``data``) follows
    the last one on the timelines."""

    def __init__(self, target: str | Path | None = None, name: str = "gymnasium episodes"):
        self.target, self.name = target, name
        self.where: str | None = None  # where the stream goes, once it is open
        self._rec = None
        self._model: RobotModel | None = None
        self._data: TrialData | None = None
        self._sent = 0  # rows of the current trial sent
        self._first = 0  # the step at which the current trial begins on the timelines

    def send(self, world: World, data: TrialData, info: TrialInfo) -> None:
        """Send the rows of ``data`` whose action has been taken (``steps_run`` rows) and not
        yet sent."""
        if data is not self._data:
            if self._data is not None:
                self._first += self._sent
            self._data, self._sent = data, 0
        if self._rec is None:
            if data.steps_run == 0:
                return  # opened at the first row: a reset alone starts no viewer
            self._rec, self.where = live_stream(self.name, self.target,
                                                   spawn=display_available())
            self._model = RobotModel(world)
            if self.target is None:
                print(f"dart_reach: render_mode='human' streams to {self.where}",
                      file=sys.stderr)
        for row in range(self._sent, data.steps_run):
            send_live_step(self._rec, data, info, self._model, world.config.control_dt, row,
                           self._first)
        self._sent = data.steps_run

    def close(self) -> None:
        """Flush the stream and end it (a saved file gets its footer)."""
        if self._rec is not None:
            self._rec.flush()
            self._rec.disconnect()
            self._rec = None
