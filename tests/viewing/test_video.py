"""``dart-reach video``: a trial rendered frame by frame by the real Rerun viewer, headless, or
by the numpy camera where the viewer cannot render, and encoded with imageio-ffmpeg: the
frames are real pictures that change with time. Bad arguments are told before anything about
the machine, also on one without a Vulkan driver (made here by hiding this machine's)."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from dart_reach.viewing import headless
from dart_reach.viewing.video import CannotRender, frame_times, render_video, video_missing
from dart_reach.viewing.watch import watch

#: The real command line on a machine without a Vulkan driver: no VK_ICD_FILENAMES, and
#: Mesa's driver file (``headless.LAVAPIPE``, which ``renderer_missing`` looks for) moved to
#: a path that does not exist (argv[1]).
WITHOUT_DRIVER = """
import sys
from pathlib import Path
from dart_reach.viewing import headless
headless.LAVAPIPE = Path(sys.argv[1])
from dart_reach.cli import main
sys.exit(main(sys.argv[2:]))
"""


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """A trial recording of a shipped robot (no viewer, no renderer needed)."""
    return watch(out=tmp_path_factory.mktemp("watch") / "w.rrd", viewer=False).recording


def _video(*args, driver: bool = True, tmp_path=None):
    """``dart-reach video ARGS``, on this machine or, ``driver=False``, as on one without a
    Vulkan driver."""
    if driver:
        command, env = [sys.executable, "-m", "dart_reach.cli"], None
    else:
        command = [sys.executable, "-c", WITHOUT_DRIVER, str(tmp_path / "no-driver.json")]
        env = {k: v for k, v in os.environ.items() if k != "VK_ICD_FILENAMES"}
    return subprocess.run([*command, "video", *map(str, args)], capture_output=True, text=True,
                          timeout=120, env=env)


def _one_line_exit_2(result, fragment):
    assert result.returncode == 2, (result.returncode, result.stdout, result.stderr)
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr, result.stderr
    assert result.stderr.startswith("dart-reach: error: ") and fragment in result.stderr, \
        (fragment, result.stderr)


def test_frame_times_cover_the_trial():
    assert frame_times(19.9, 10) == [k / 10 for k in range(200)]
    assert frame_times(2.0, 4)[-1] == 2.0 and len(frame_times(0.0, 10)) == 1


def test_bad_arguments_are_refused_before_rendering(recording, tmp_path):
    with pytest.raises(ValueError, match="mp4"):
        render_video(recording, tmp_path / "v.avi")
    with pytest.raises(ValueError, match="size"):
        render_video(recording, tmp_path / "v.mp4", size="big")
    _one_line_exit_2(_video(recording, tmp_path / "missing" / "v.mp4"), "no such directory")


def test_without_a_vulkan_driver_arguments_are_checked_first(recording, tmp_path, monkeypatch,
                                                            in_process):
    """Where no Vulkan driver is installed, every mistake in the arguments is still named
    (not hidden behind the machine's problem); with right arguments and the viewer asked for,
    the missing driver is one line and exit code 2, and nothing is written. The mistakes are
    tried in this process (the same code, without a process's imports), the missing driver in
    a process of its own."""
    out = tmp_path / "v.mp4"
    notes = tmp_path / "layouts" / "notes.rbl"
    notes.parent.mkdir()
    notes.write_text("not a layout")
    monkeypatch.setattr(headless, "LAVAPIPE", tmp_path / "no-driver.json")
    monkeypatch.delenv("VK_ICD_FILENAMES", raising=False)
    for args, fragment in (
            ((recording, tmp_path / "missing" / "v.mp4"), "no such directory"),
            ((recording, tmp_path / "v.avi"), "OUT.mp4 must end in .mp4"),
            ((recording, out, "--size", "big"), "--size must be WIDTHxHEIGHT"),
            ((tmp_path / "none.rrd", out), "no such recording"),
            ((recording, out, "--layout", tmp_path / "none.rbl"), "no such layout file"),
            ((recording, out, "--layout", notes), "not a Rerun layout file"),
            ((recording, out, "--renderer", "gpu"), "--renderer must be one of viewer, camera")):
        _one_line_exit_2(in_process("video", *args), fragment)
    _one_line_exit_2(_video(recording, out, "--renderer", "viewer", driver=False,
                            tmp_path=tmp_path), "cannot render a video here: no Vulkan driver")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["layouts"]  # no video, no partial
    # the library in the same order: the arguments, then CannotRender (a RuntimeError)
    with pytest.raises(FileNotFoundError, match="no such directory"):
        render_video(recording, tmp_path / "missing" / "v.mp4")
    with pytest.raises(CannotRender, match="no Vulkan driver") as missing:
        render_video(recording, out, renderer="viewer")
    assert isinstance(missing.value, RuntimeError) and not out.exists()


@pytest.mark.skipif(video_missing("camera") is not None,
                    reason=f"cannot encode a video here: {video_missing('camera')}")
def test_without_a_vulkan_driver_the_numpy_camera_draws_the_video(recording, tmp_path):
    """The real command line on a machine without a Vulkan driver: the video is drawn by the
    numpy camera, and the output says so and why; its frames are real pictures that move."""
    import imageio_ffmpeg

    out = tmp_path / "v.mp4"
    result = _video(recording, out, "--fps", "1", "--size", "320x240", driver=False,
                    tmp_path=tmp_path)
    assert result.returncode == 0, result.stderr
    assert f"wrote {out}: 20 frames" in result.stdout
    assert "drawn by the numpy camera" in result.stdout and "no Vulkan driver" in result.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["v.mp4"]  # no partial file left
    reader = imageio_ffmpeg.read_frames(str(out))
    width, height = next(reader)["size"]
    frames = [np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in reader]
    assert len(frames) == 20 and frames[0].shape == (240, 320, 3)
    assert np.unique(frames[0].reshape(-1, 3)[::7], axis=0).shape[0] > 30
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).mean() > 0.5


@pytest.mark.skipif(video_missing("viewer") is not None,
                    reason=f"cannot render a video here: {video_missing('viewer')}")
def test_a_few_frames_rendered_by_the_real_viewer(recording, tmp_path):
    import imageio_ffmpeg

    result = render_video(recording, tmp_path / "v.mp4", fps=1, size="640x400",
                          max_frames=4, progress=False, renderer="viewer")
    assert result.frames == 4 and result.sim_seconds == 3.0 and result.renderer == "viewer"
    reader = imageio_ffmpeg.read_frames(str(result.path))
    width, height = next(reader)["size"]
    frames = [np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in reader]
    assert len(frames) == 4 and frames[0].shape == (400, 640, 3)
    # real pictures (many colours), and the scene moves between 0 s and 3 s
    assert np.unique(frames[0].reshape(-1, 3)[::37], axis=0).shape[0] > 30
    assert np.abs(frames[0].astype(int) - frames[3].astype(int)).mean() > 0.2
