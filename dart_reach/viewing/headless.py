"""The real Rerun viewer, headless: render a recording with its layout to a PNG and report each
view's state (``make screenshots``, and the test that every view of the layout has data and
no error).

The viewer draws with Vulkan; on a machine without a GPU, Mesa's software rasterizer
(lavapipe, Debian's ``mesa-vulkan-drivers``) does it. ``renderer_missing()`` says why
rendering cannot work here, or None.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import polars as pl
import rerun.experimental as rx
from PIL import Image

from ..postevaluation.systematic import BLUEPRINT, load_evaluation

#: Mesa's software Vulkan driver (lavapipe), where Debian installs it.
LAVAPIPE = Path("/usr/share/vulkan/icd.d/lvp_icd.x86_64.json")


def rerun_binary() -> str | None:
    """The viewer's executable: the binary the rerun-sdk wheel ships (``rerun_cli/rerun``),
    not the ``rerun`` console script, a Python wrapper whose termination leaves the viewer
    running; else whatever ``rerun`` is on the PATH."""
    spec = importlib.util.find_spec("rerun_cli")
    for folder in (spec.submodule_search_locations or []) if spec else []:
        binary = Path(folder) / ("rerun.exe" if sys.platform == "win32" else "rerun")
        if binary.is_file() and os.access(binary, os.X_OK):
            return str(binary)
    return shutil.which("rerun", path=os.path.dirname(sys.executable)) or shutil.which("rerun")


def renderer_missing() -> str | None:
    """Why the viewer cannot render headless here (None: it can)."""
    if rerun_binary() is None:
        return "the rerun viewer is not installed (pip install rerun-sdk)"
    named = [Path(f) for f in os.environ.get("VK_ICD_FILENAMES", "").split(os.pathsep) if f]
    if not (any(f.is_file() for f in named) if named else LAVAPIPE.is_file()):
        return (f"no Vulkan driver: install Mesa's software one (Debian: apt-get install "
                f"mesa-vulkan-drivers, which provides {LAVAPIPE})")
    return None


class HeadlessViewer:
    """A headless Rerun viewer on a free loopback port, driven through
    ``rerun.experimental.ViewerClient``. Use as a context manager."""

    def __init__(self, size: str = "1600x1000", timeout_s: float = 60.0):
        reason = renderer_missing()
        if reason:
            raise RuntimeError(reason)
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        env = dict(os.environ)
        if "VK_ICD_FILENAMES" not in env:
            env["VK_ICD_FILENAMES"] = str(LAVAPIPE)
        self._process = subprocess.Popen(
            [rerun_binary(), "--bind", "127.0.0.1", "--port", str(port), "--headless",
             "--hide-welcome-screen", "--window-size", size],
            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + timeout_s
        while True:
            try:
                self.client = rx.ViewerClient.connect(f"rerun+http://127.0.0.1:{port}/proxy")
                self.client.get_state()
                break
            except Exception:  # not listening yet
                if self._process.poll() is not None or time.monotonic() > deadline:
                    self.close()
                    raise RuntimeError("the headless rerun viewer did not start") from None
                time.sleep(0.2)

    def show(self, recording, layout=None, sim_time_s: float | None = None,
             settle_s: float = 2.0):
        """Open ``recording`` (an .rrd file) with ``layout`` (an .rbl file; default the one
        the recording carries), make it the active recording, put the time cursor at
        ``sim_time_s`` (paused) and let the viewer draw. Returns the viewer's state."""
        if layout:  # the layout first: a recording opened after it takes it
            self.client.open(str(layout), navigate=False)
        opened = self.client.open(str(recording))
        deadline = time.monotonic() + 60
        while True:
            state = self.client.get_state()
            if not state.loading or time.monotonic() > deadline:
                break
            time.sleep(0.2)
        mine = [r for r in state.recordings if r.store_id in opened.store_ids]
        self.client.set_location(mine[0].location)
        self.store_id = mine[0].store_id  # the recording shown, for set_time
        if sim_time_s is not None:
            self.client.set_time("sim_time", duration=sim_time_s, play_state="paused",
                                 recording=mine[0].store_id)
        time.sleep(settle_s)
        return self.client.get_state()

    def screenshot(self, path) -> Path:
        self.client.save_screenshot(str(path))
        return Path(path)

    def close(self) -> None:
        if self._process.poll() is None:
            self._process.terminate()
            try:
                self._process.wait(10)
            except subprocess.TimeoutExpired:
                self._process.kill()
                self._process.wait()

    def __enter__(self) -> "HeadlessViewer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _shrink(path: Path, width: int) -> None:
    """Downscale a PNG to ``width`` pixels (the README's pictures stay small)."""
    with Image.open(path) as image:
        height = round(image.height * width / image.width)
        small = image.convert("RGB").resize((width, height), Image.LANCZOS)
    small.save(path, optimize=True)


def readme_pictures(run_dir, out_dir, width: int = 1000) -> list[Path]:
    """The README's pictures of a post-evaluated run (``make screenshots``): a fine-reaching
    trial of the best robot in the centre sector with its layout, 9 s in, and the training
    curves. Returns the files written."""
    run_dir, out_dir = Path(run_dir), Path(out_dir)
    table = load_evaluation(run_dir).filter(pl.col("recording").is_not_null()
                                            & (pl.col("senses") == "normal"))
    if table.height == 0:
        raise ValueError(f"{run_dir}: no recorded post-evaluation trial to show")
    fine = table.filter(pl.col("notation") == "fine")
    rows = fine if fine.height else table
    centre = rows.filter(pl.col("trial") == 20)
    recording = run_dir / (centre if centre.height else rows)["recording"][0]
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    with HeadlessViewer(size="1600x1000") as viewer:
        viewer.show(recording, run_dir / BLUEPRINT, sim_time_s=9.0)
        written.append(viewer.screenshot(out_dir / "trial.png"))
    with HeadlessViewer(size="1600x1000") as viewer:  # a viewer keeps a layout per application
        viewer.show(run_dir / "training.rrd")
        written.append(viewer.screenshot(out_dir / "training.png"))
    for path in written:
        _shrink(path, width)
    return written


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: python -m dart_reach.screenshots RUN_DIR OUT_DIR")
    reason = renderer_missing()
    if reason:
        sys.exit(f"screenshots: {reason}")
    for p in readme_pictures(sys.argv[1], sys.argv[2]):
        print(f"wrote {p} ({p.stat().st_size // 1024} kB)")
