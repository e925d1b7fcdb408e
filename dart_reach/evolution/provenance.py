"""Where a run comes from, for its manifest: the state of the source tree (``git_state``), the
machine (``machine``) and the versions of the package and its main dependencies
(``versions``)."""

from __future__ import annotations

import hashlib
import os
import platform
import subprocess
from importlib import metadata
from pathlib import Path

from .. import __version__
from ..pinning import numpy_dispatch, numpy_targets


def _git(directory: Path, *args: str) -> bytes | None:
    try:
        out = subprocess.run(["git", *args], capture_output=True, cwd=directory, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout if out.returncode == 0 else None


def git_state(directory=None) -> dict:
    """The state of the git working tree holding ``directory`` (default: this package's
    source), for a run's manifest: ``git_revision`` (the commit), ``git_dirty`` (True when
    tracked files differ from it or files git does not ignore are untracked) and
    ``git_diff_sha256`` (SHA-256 of ``git diff HEAD --binary`` followed by each untracked
    file's path and content: two runs with the same revision and the same hash ran the same
    code). Run directories under ``recordings/`` are not source: left out of both. All None
    outside a git working tree."""
    directory = Path(directory) if directory is not None else Path(__file__).parent
    head = _git(directory, "rev-parse", "HEAD")
    if not head:
        return {"git_revision": None, "git_dirty": None, "git_diff_sha256": None}
    root = Path((_git(directory, "rev-parse", "--show-toplevel") or b".").decode().strip())
    outside = ("--", ".", ":(exclude)recordings")
    diff = _git(root, "diff", "HEAD", "--binary", *outside) or b""
    untracked = (_git(root, "ls-files", "--others", "--exclude-standard", "-z", *outside)
                 or b"")
    digest = hashlib.sha256(diff)
    for name in sorted(n for n in untracked.split(b"\0") if n):
        digest.update(b"\0untracked\0" + name + b"\0")
        try:
            digest.update((root / name.decode()).read_bytes())
        except OSError:
            pass
    return {"git_revision": head.decode().strip(), "git_dirty": bool(diff or untracked),
            "git_diff_sha256": digest.hexdigest()}


def simd() -> str:
    """numpy's dispatch level in this process: the highest of its dispatch groups (numpy 2.4:
    X86_V3 = AVX2, X86_V4 = AVX-512, ...) the CPU has and the environment did not disable, else
    its baseline; a float64 ``np.exp`` may round differently at different levels, so results
    are bit-identical only between processes at the same level."""
    found = [name for name, enabled in numpy_targets().items() if enabled]
    return (found or list(numpy_dispatch()[1]) or ["none"])[-1]


#: /proc/cpuinfo flags of the vector extensions, widest first, as ``cpu`` names them.
_VECTOR_FLAGS = (("avx512f", "AVX-512"), ("avx2", "AVX2"), ("avx", "AVX"), ("sse4_2", "SSE4.2"))


def cpu(cpuinfo: str | None = None) -> dict:
    """The processor a session ran on, for the manifest's ``sessions``: its ``model``,
    ``mhz`` (the first core's clock, MHz) and widest ``vector`` extension (the CPU's, not the
    level numpy is let use: that is ``simd``), from ``cpuinfo`` (default: /proc/cpuinfo's
    text; each None where that says nothing, e.g. off Linux). A run's wall times depend on
    it (docs/results/benchmarks.md, "What a run costs")."""
    if cpuinfo is None:
        try:
            cpuinfo = Path("/proc/cpuinfo").read_text(encoding="utf-8", errors="replace")
        except OSError:
            cpuinfo = ""
    fields: dict[str, str] = {}
    for line in cpuinfo.splitlines():
        key, sep, value = line.partition(":")
        if sep:
            fields.setdefault(key.strip(), value.strip())
    flags = set(fields.get("flags", "").split())
    try:
        mhz = float(fields["cpu MHz"])
    except (KeyError, ValueError):
        mhz = None
    return {"model": fields.get("model name") or platform.processor() or None, "mhz": mhz,
            "vector": next((name for flag, name in _VECTOR_FLAGS if flag in flags), None)}


def machine() -> dict:
    """Where a run was created (its speed figures depend on it; its bits on ``simd``)."""
    return {"platform": platform.platform(), "processor": platform.machine(),
            "cores": os.cpu_count(), "simd": simd()}


def versions() -> dict:
    """The versions of dart_reach, Python and the packages a run's result depends on (None for
    one not installed)."""
    found = {"dart_reach": __version__, "python": platform.python_version()}
    for pkg in ("dartpy", "numpy", "scipy", "polars", "rerun-sdk"):
        try:
            found[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            found[pkg] = None
    return found
