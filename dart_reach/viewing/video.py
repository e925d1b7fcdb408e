"""A trial as a video (``dart-reach video TRIAL.rrd OUT.mp4``): the real Rerun viewer, headless
(``screenshots.HeadlessViewer``), draws the recording with its layout at each frame's time,
and the frames are encoded with imageio's ffmpeg plugin (the ``video`` extra:
``imageio-ffmpeg`` ships its own ffmpeg binary, so no system ffmpeg is needed).

What it costs (docs/results/benchmarks.md, "Watch and video"): the viewer renders in software (Mesa's lavapipe)
on a machine without a GPU, so a frame takes a sizeable fraction of a second.
"""

from __future__ import annotations

import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from ..errors import UsageError
from ..progress import ProgressBar
from ..recording.rrd import read_rrd, write_blueprint
from .headless import HeadlessViewer, renderer_missing


#: The viewer's commands that hide its side panels (sources and layout, selection).
SIDE_PANELS = ("ui.toggle_blueprint_panel", "ui.toggle_selection_panel")


@dataclass(frozen=True)
class VideoResult:
    """A video written: its path, frames, the simulated seconds they show (s) and the wall
    time of the rendering and encoding (s)."""

    path: Path
    frames: int
    sim_seconds: float
    wall_seconds: float


@dataclass(frozen=True)
class FrameProgress:
    """What the progress bar is told after each frame (times in s)."""

    done: int
    total: int
    elapsed_s: float

    @property
    def eta_s(self) -> float:
        return self.elapsed_s / self.done * (self.total - self.done)


class CannotRender(RuntimeError):
    """This machine cannot make a video (the headless viewer's renderer or the encoder is
    missing; ``str(exc)`` says which). ``render_video`` raises it only once its arguments and
    the recording have passed their checks: a mistake in them is told first, on any machine."""


def video_missing() -> str | None:
    """Why a video cannot be made here (None: it can): the headless viewer's renderer or the
    encoder is missing."""
    reason = renderer_missing()
    if reason:
        return reason
    try:
        import imageio_ffmpeg  # noqa: F401  (the encoder's binary)
        import imageio.v2  # noqa: F401
    except ImportError:
        return "imageio and imageio-ffmpeg are not installed: pip install 'dart_reach[video]'"
    return None


def frame_times(sim_seconds: float, fps: int) -> list[float]:
    """The simulated times (s) of the frames of a recording lasting ``sim_seconds``:
    0, 1/fps, ... up to its last instant."""
    n = int(sim_seconds * fps + 1e-9) + 1
    return [k / fps for k in range(n)]


def render_video(recording, out, layout=None, fps: int = 10, size: str = "1280x720",
                 progress: bool = True, max_frames: int | None = None) -> VideoResult:
    """Render ``recording`` (a trial's .rrd) with ``layout`` (.rbl; default the trial
    layout; the viewer's side panels are hidden) at ``fps`` frames per simulated second (10:
    one per control step, so the video plays at real time) into ``out`` (a new .mp4 file) at
    ``size`` pixels ("WIDTHxHEIGHT"). ``max_frames``: only the first frames (a preview).
    ``progress`` shows a progress bar (plain lines where the output is not a terminal).
    Every argument and the recording are checked before the machine: ``CannotRender`` (a
    RuntimeError) comes only after them.
    Cost: 0.27-0.36 s of wall time per frame on a 2-core machine without a GPU
    (docs/results/benchmarks.md, "Watch and video")."""
    recording, out = Path(recording), Path(out)
    if out.suffix.lower() != ".mp4":
        raise UsageError(f"out must be an .mp4 file, got {out}",
                         cli=f"OUT.mp4 must end in .mp4, got {out}")
    if out.exists():
        raise FileExistsError(f"{out} exists; choose another file")
    if not out.parent.is_dir():
        raise FileNotFoundError(f"{out.parent}: no such directory")
    if fps < 1:
        raise UsageError(f"fps must be at least 1, got {fps}", cli=f"--fps must be at least 1, "
                                                                   f"got {fps}")
    try:
        width, height = (int(v) for v in size.lower().split("x"))
    except ValueError:
        width = height = 0
    if width < 64 or height < 64:
        raise UsageError(f"size must be WIDTHxHEIGHT in pixels (each >= 64), got {size!r}",
                         cli=f"--size must be WIDTHxHEIGHT in pixels (each >= 64), got {size!r}")
    if layout is not None and not Path(layout).is_file():
        raise FileNotFoundError(f"{layout}: no such layout file")
    table = read_rrd(recording)  # also a clear error for a missing or damaged file
    if "sim_time" not in table.columns or table.height == 0:
        raise ValueError(f"{recording}: not a trial recording (no sim_time timeline)")
    reason = video_missing()  # the machine, once the arguments are known to be right
    if reason:
        raise CannotRender(reason)
    import imageio.v2 as imageio
    import imageio.v3 as iio

    sim_seconds = float(table["sim_time"].max())
    times = frame_times(sim_seconds, fps)[:max_frames]
    t0 = time.monotonic()
    bar = ProgressBar(lambda p: (p.done, p.total, "frame", f"video {out.name}"),
                      bar=None if progress else False)
    partial = out.with_name(out.name + ".part.mp4")
    scratch = tempfile.TemporaryDirectory(prefix="dart_reach-video-")
    if layout is None:
        layout = write_blueprint(Path(scratch.name) / "trial.rbl")
    try:
        with HeadlessViewer(size=f"{width}x{height}") as viewer:
            viewer.show(recording, layout, sim_time_s=0.0, settle_s=0.5)
            for panel in SIDE_PANELS:  # the views only, and the time line
                viewer.client.run_command(panel)
            with imageio.get_writer(partial, format="FFMPEG", fps=fps, codec="libx264",
                                    quality=8, macro_block_size=2,
                                    ffmpeg_log_level="error") as writer:
                for k, t in enumerate(times, start=1):
                    viewer.client.set_time("sim_time", duration=t, play_state="paused",
                                           recording=viewer.store_id)
                    writer.append_data(iio.imread(viewer.client.take_screenshot())[..., :3])
                    if progress:
                        bar(FrameProgress(k, len(times), time.monotonic() - t0))
        partial.replace(out)
    finally:
        bar.close()
        partial.unlink(missing_ok=True)
        scratch.cleanup()
    return VideoResult(out, len(times), times[-1] if times else 0.0, time.monotonic() - t0)
