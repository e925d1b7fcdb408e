"""The package as a user installs it: the wheel holds the code's licence, the robot model's
CC BY-SA licence text beside the URDF, py.typed and the shipped robots; its metadata has an
SPDX licence, authors, classifiers and the supported Pythons; setuptools builds it without a
deprecation or package-discovery warning. CITATION.cff cites the paper."""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_the_wheel_ships_both_licences_typing_and_the_robots(tmp_path):
    result = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-v", "-w",
                             str(tmp_path), str(ROOT)], capture_output=True, text=True,
                            timeout=600)
    assert result.returncode == 0, result.stderr
    assert "Deprecat" not in result.stdout + result.stderr
    # every package and data directory declared: no "Package would be ignored" warnings
    assert "absent from the `packages` configuration" not in result.stdout + result.stderr
    assert "Warning" not in result.stdout + result.stderr
    wheel = next(tmp_path.glob("dart_reach-*.whl"))
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
        meta = z.read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
    for path in ("dart_reach/skeletons/icub_upper_body.urdf",
                 "dart_reach/skeletons/LICENSE-icub-models", "dart_reach/py.typed",
                 "dart_reach/analysis/templates/report.html"):
        assert path in names, path
    package = ROOT / "dart_reach"
    for pattern in ("*.py", "*.json", "*.toml"):  # every module, shipped robot, condition, scene
        for f in package.rglob(pattern):
            assert f"dart_reach/{f.relative_to(package).as_posix()}" in names, f
    assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names)
    assert "License-Expression: MIT AND CC-BY-SA-4.0" in meta
    assert "Requires-Python: <3.14,>=3.11" in meta or "Requires-Python: >=3.11,<3.14" in meta
    for version in ("3.11", "3.12", "3.13"):
        assert f"Programming Language :: Python :: {version}" in meta
    assert "Author: The dart_reach maintainers" in meta
    assert "Attribution-ShareAlike 4.0" in (ROOT / "skeletons/LICENSE-icub-models").read_text()


def test_licence_and_citation_files():
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")
    citation = (ROOT / "CITATION.cff").read_text()
    for needle in ("cff-version: 1.2.0", "preferred-citation:", "Savastano", "Nolfi",
                   "A robotic model of reaching and grasping development", "doi:"):
        assert needle in citation, needle


def test_numpy_blas_kernels_are_pinned_for_bit_identical_results():
    """OpenBLAS picks its kernels by the CPU and they round differently (the trial digests of
    tests/model/test_task.py differ between SkylakeX's and Haswell's): importing dart_reach
    pins Haswell's on every x86_64 CPU that runs them, unless the user chose."""
    import os
    import platform

    flags = ""
    if Path("/proc/cpuinfo").exists():
        flags = next((line for line in Path("/proc/cpuinfo").read_text().splitlines()
                      if line.startswith("flags")), "")
    if platform.machine() != "x86_64" or not {"avx2", "fma"} <= set(flags.split()):
        import pytest
        pytest.skip("the pin is for x86_64 CPUs with AVX2 and FMA")
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    code = "import dart_reach, numpy; numpy.ones((3, 3)) @ numpy.ones(3)"
    out = subprocess.run([sys.executable, "-c", code], env={**env, "OPENBLAS_VERBOSE": "2"},
                         capture_output=True, text=True, timeout=120)
    assert "Core: Haswell" in out.stdout + out.stderr
    chosen = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            env={**env, "OPENBLAS_VERBOSE": "2",
                                 "OPENBLAS_CORETYPE": "Sandybridge"},
                            timeout=120)
    assert "Core: Sandybridge" in chosen.stdout + chosen.stderr


def test_numpy_dispatch_is_kept_at_avx2_and_recorded():
    """numpy's elementwise functions take other code on AVX-512 CPUs: importing dart_reach keeps
    its dispatch at AVX2 at most, unless the user chose, and ``provenance.simd`` says the level
    that took effect (here: the user's choice of the baseline shows). numpy disables only the
    groups named: an AVX-512 CPU keeps AVX512_ICL when X86_V3 and X86_V4 are disabled (measured
    on an AMD EPYC with AVX-512), so the choice names every group above the baseline."""
    import os
    import platform

    from dart_reach import pinning

    if platform.machine() != "x86_64":
        import pytest
        pytest.skip("the pin is for x86_64 CPUs")
    env = {k: v for k, v in os.environ.items() if k != "NPY_DISABLE_CPU_FEATURES"}
    code = ("import os, dart_reach; from dart_reach.evolution.provenance import simd; "
            "print(os.environ.get('NPY_DISABLE_CPU_FEATURES'), simd(), sep='|')")
    pinned = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                            text=True, timeout=120)
    disabled, level = pinned.stdout.strip().split("|")
    assert disabled == pinning.ABOVE_AVX2 and level not in {"X86_V4", "AVX512_ICL",
                                                            "AVX512_SPR"}
    baseline_only = "X86_V3 X86_V4 AVX512_ICL AVX512_SPR"
    chosen = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            env={**env, "NPY_DISABLE_CPU_FEATURES": baseline_only}, timeout=120)
    assert chosen.stdout.strip().split("|") == [baseline_only, "X86_V2"]


def test_the_names_users_import_are_on_the_package():
    """The README's and the notebooks' names come from ``dart_reach`` itself, whatever module
    holds them, and resolve to the objects of those modules."""
    import dart_reach
    from dart_reach.analysis import figures, tables
    from dart_reach.evolution import trainer

    for name in dart_reach.__all__:
        assert getattr(dart_reach, name) is not None, name
    assert dart_reach.train is trainer.train and dart_reach.load_runs is tables.load_runs
    assert dart_reach.figures is figures
    import pytest
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        dart_reach.nothing  # noqa: B018
