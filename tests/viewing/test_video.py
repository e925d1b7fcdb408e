"""``dart-reach video``: a trial rendered frame by frame by the real Rerun viewer, headless,
and encoded with imageio-ffmpeg: the frames are real pictures that change with time."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from dart_reach.viewing.video import frame_times, render_video, video_missing
from dart_reach.viewing.watch import watch


def test_frame_times_cover_the_trial():
    assert frame_times(19.9, 10) == [k / 10 for k in range(200)]
    assert frame_times(2.0, 4)[-1] == 2.0 and len(frame_times(0.0, 10)) == 1


def test_bad_arguments_are_refused_before_rendering(tmp_path):
    w = watch(out=tmp_path / "w.rrd", viewer=False)
    with pytest.raises(ValueError, match="mp4"):
        render_video(w.recording, tmp_path / "v.avi")
    with pytest.raises(ValueError, match="size"):
        render_video(w.recording, tmp_path / "v.mp4", size="big")
    result = subprocess.run([sys.executable, "-m", "dart_reach.cli", "video", str(w.recording),
                             str(tmp_path / "missing" / "v.mp4")],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2 and "no such directory" in result.stderr
    assert result.stderr.count("\n") == 1


@pytest.mark.skipif(video_missing() is not None,
                    reason=f"cannot render a video here: {video_missing()}")
def test_a_few_frames_rendered_by_the_real_viewer(tmp_path):
    import imageio_ffmpeg

    w = watch(out=tmp_path / "w.rrd", viewer=False)
    result = render_video(w.recording, tmp_path / "v.mp4", fps=1, size="640x400",
                          max_frames=4, progress=False)
    assert result.frames == 4 and result.sim_seconds == 3.0
    reader = imageio_ffmpeg.read_frames(str(result.path))
    width, height = next(reader)["size"]
    frames = [np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in reader]
    assert len(frames) == 4 and frames[0].shape == (400, 640, 3)
    # real pictures (many colours), and the scene moves between 0 s and 3 s
    assert np.unique(frames[0].reshape(-1, 3)[::37], axis=0).shape[0] > 30
    assert np.abs(frames[0].astype(int) - frames[3].astype(int)).mean() > 0.2
