"""A trial as a video (``dart-reach video TRIAL.rrd OUT.mp4``): the real Rerun viewer, headless
(``headless.HeadlessViewer``), draws the recording with its layout at each frame's time; where
it cannot render (no Vulkan driver), the numpy camera (``replay.Replay``) draws the 3D scene
alone. The frames are encoded with imageio's ffmpeg plugin (the ``video`` extra:
``imageio-ffmpeg`` ships its own ffmpeg binary, so no system ffmpeg is needed).

What it costs (docs/results/benchmarks.md, "Watch and video"): the viewer renders in software
(Mesa's lavapipe) on a machine without a GPU, so a frame takes a sizeable fraction of a second;
the camera draws a 1280 x 720 frame in about a tenth of a second.
"""

from __future__ import annotations

import contextlib
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from ..errors import UsageError
from ..progress import ProgressBar
from ..model.world import World
from ..recording.rrd import read_rrd, write_blueprint
from .headless import HeadlessViewer, renderer_missing
from .replay import Poses, Replay

#: Who draws the frames: the Rerun viewer (the trial layout: scene and time series) or the
#: numpy camera (the 3D scene alone, any machine).
RENDERERS = ("viewer", "camera")


#: The viewer's commands that hide its side panels (sources and layout, selection).
SIDE_PANELS = ("ui.toggle_blueprint_panel", "ui.toggle_selection_panel")


@dataclass(frozen=True)
class VideoResult:
    """A video written: its path, frames, the simulated seconds they show (s), the wall
    time of the rendering and encoding (s), and who drew it (``RENDERERS``)."""

    path: Path
    frames: int
    sim_seconds: float
    wall_seconds: float
    renderer: str


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
    """This machine cannot make a video (the encoder, or the headless viewer's renderer where
    the viewer is asked for, is missing; ``str(exc)`` says which). ``render_video`` raises it
    only once its arguments and the recording have passed their checks: a mistake in them is
    told first, on any machine."""


def video_missing(renderer: str = "camera") -> str | None:
    """Why a video cannot be made here with ``renderer`` (None: it can): the encoder is
    missing, or for the viewer its headless renderer."""
    reason = renderer_missing() if renderer == "viewer" else None
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
                 progress: bool = True, max_frames: int | None = None,
                 renderer: str | None = None) -> VideoResult:
    """Render ``recording`` (a trial's .rrd) at ``fps`` frames per simulated second (10:
    one per control step, so the video plays at real time) into ``out`` (a new .mp4 file) at
    ``size`` pixels ("WIDTHxHEIGHT"). ``renderer``: "viewer", the Rerun viewer with
    ``layout`` (.rbl; default the trial layout; its side panels hidden); "camera", the numpy
    camera's view of the 3D scene (``layout`` unused); None (default): the viewer where it
    can render headless here, else the camera. ``max_frames``: only the first frames (a
    preview). ``progress`` shows a progress bar (plain lines where the output is not a
    terminal). Every argument and the recording are checked before the machine:
    ``CannotRender`` (a RuntimeError) comes only after them.
    Cost: 0.27-0.36 s of wall time per frame with the viewer on a 2-core machine without a
    GPU (docs/results/benchmarks.md, "Watch and video")."""
    recording, out = Path(recording), Path(out)
    if renderer is not None and renderer not in RENDERERS:
        raise UsageError(f"renderer must be one of {', '.join(RENDERERS)}, got {renderer!r}",
                         cli=f"--renderer must be one of {', '.join(RENDERERS)}, got "
                             f"{renderer!r}")
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
    if layout is not None and Path(layout).read_bytes()[:3] != b"RRF":  # Rerun's files begin so
        raise ValueError(f"{layout}: not a Rerun layout file (.rbl; 'dart-reach watch' writes "
                         f"one beside its recording)")
    table = read_rrd(recording)  # also a clear error for a missing or damaged file
    if "sim_time" not in table.columns or table.height == 0:
        raise ValueError(f"{recording}: not a trial recording (no sim_time timeline)")
    # the machine, once the arguments are known to be right
    renderer = renderer or ("viewer" if renderer_missing() is None else "camera")
    reason = video_missing(renderer)
    if reason:
        raise CannotRender(reason)
    import imageio.v2 as imageio

    sim_seconds = float(table["sim_time"].max())
    times = frame_times(sim_seconds, fps)[:max_frames]
    t0 = time.monotonic()
    bar = ProgressBar(lambda p: (p.done, p.total, "frame", f"video {out.name}"),
                      bar=None if progress else False)
    partial = out.with_name(out.name + ".part.mp4")
    try:
        with imageio.get_writer(partial, format="FFMPEG", fps=fps, codec="libx264",
                                quality=8, macro_block_size=2,
                                ffmpeg_log_level="error") as writer:
            draw = _viewer_frames if renderer == "viewer" else _camera_frames
            with contextlib.closing(draw(recording, table, layout, times, width,
                                         height)) as frames:
                for k, frame in enumerate(frames, start=1):
                    writer.append_data(frame)
                    if progress:
                        bar(FrameProgress(k, len(times), time.monotonic() - t0))
        partial.replace(out)
    finally:
        bar.close()
        partial.unlink(missing_ok=True)
    return VideoResult(out, len(times), times[-1] if times else 0.0, time.monotonic() - t0,
                       renderer)


def _viewer_frames(recording, table, layout, times, width, height):
    """The headless Rerun viewer's screenshots at ``times`` (s), (H, W, 3) uint8 each."""
    import imageio.v3 as iio

    with tempfile.TemporaryDirectory(prefix="dart_reach-video-") as scratch:
        if layout is None:
            layout = write_blueprint(Path(scratch) / "trial.rbl")
        with HeadlessViewer(size=f"{width}x{height}") as viewer:
            viewer.show(recording, layout, sim_time_s=0.0, settle_s=0.5)
            for panel in SIDE_PANELS:  # the views only, and the time line
                viewer.client.run_command(panel)
            for t in times:
                viewer.client.set_time("sim_time", duration=t, play_state="paused",
                                       recording=viewer.store_id)
                yield iio.imread(viewer.client.take_screenshot())[..., :3]


def _camera_frames(recording, table, layout, times, width, height):
    """The numpy camera's views of the recorded trial at ``times`` (s)."""
    world = World()
    replay = Replay(world, Poses.of_recording(table, world), width, height)
    for t in times:
        yield replay.frame(replay.at(t))
