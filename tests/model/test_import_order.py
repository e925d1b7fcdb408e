"""No result depends on what was imported first (``dart_reach.pinning``).

In fresh processes that load numpy before ``dart_reach``: model version 1 gives its committed
digests where numpy's and OpenBLAS's kernels are the pinned ones anyway (an AVX2 processor) and
refuses in one line where they are not (an AVX-512 one); version 2's compiled numerics give
their committed digests even where numpy runs other kernels (here: numpy's baseline dispatch and
OpenBLAS's Sandybridge kernels, the only others an AVX2 processor runs), where version 1's
drift. The digests are those of tests/model/test_task.py (version 1: the "pre/normal" panel)
and tests/model/test_compiled.py (version 2), computed by their own code."""

from __future__ import annotations

import importlib.util
import json
import os
import platform
import subprocess
import sys
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pytest

from dart_reach import pinning

HERE = Path(__file__).parent
#: Where the digests were recorded (machine, dartpy, numpy): tests/model/test_task.py's and
#: test_compiled.py's platform, numpy's dispatch level aside.
PLATFORM = ("x86_64", "6.20.0", "2.4.6")
#: What the fresh process loads before numpy: nothing (``pinned``), or numpy's baseline
#: dispatch and OpenBLAS's Sandybridge kernels, the variables gone before ``import dart_reach``
#: (``other kernels``: neither chosen by the user nor pinned).
OTHER_KERNELS = ("os.environ['OPENBLAS_CORETYPE'] = 'Sandybridge'; "
                 "os.environ['NPY_DISABLE_CPU_FEATURES'] = 'X86_V3 X86_V4 AVX512_ICL "
                 "AVX512_SPR'; ")
SCRIPT = """
import hashlib, importlib.util, json, os
{before}import numpy  # first, as a script or a notebook may
os.environ.pop('OPENBLAS_CORETYPE', None); os.environ.pop('NPY_DISABLE_CPU_FEATURES', None)
import dart_reach
from dart_reach import pinning


def load(name):
    spec = importlib.util.spec_from_file_location(name, {here!r} + '/' + name + '.py')
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


found = {{"refusal": pinning.this_process().refusal(), "blas": pinning.openblas_core()}}
if {version_1}:
    from dart_reach.model.scenes import load_scene
    from dart_reach.model.world import World

    t = load("test_task")
    try:
        near = World(load_scene("near").world())
        trials = t._panel_trials(near, "pre", "normal", pre=t._golden_pre())
        digests = [t._digest(*(getattr(d, f) for f in t.RECORDS)) for d in trials]
        found["version 1"] = hashlib.sha256("".join(digests).encode()).hexdigest()[:16]
    except pinning.KernelsNotPinned as exc:
        found["raised"] = str(exc)
if {version_2}:
    found["version 2"] = load("test_compiled").version_2_trials()
print(json.dumps(found))
"""


def _numpy_first(*, before: str = "", version_1: bool = True, version_2: bool = False) -> dict:
    """What a fresh Python that loads numpy first (after ``before``) computes, without
    either variable in its environment: the refusal it would get, OpenBLAS's kernels, version
    1's "pre/normal" digest or the refusal raised, version 2's trials."""
    env = {k: v for k, v in os.environ.items()
           if k not in (pinning.NUMPY_VARIABLE, pinning.BLAS_VARIABLE)}
    code = SCRIPT.format(before=before, here=str(HERE), version_1=version_1,
                         version_2=version_2)
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, timeout=1800, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _golden(name: str):
    """The test module ``name`` of this folder, loaded apart (for its golden digests)."""
    spec = importlib.util.spec_from_file_location(f"golden_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


ON_PLATFORM = (platform.machine(), version("dartpy"), np.__version__) == PLATFORM
AVX2 = pinning.CPU_FLAGS >= {"avx2", "fma"}


@pytest.mark.skipif(not ON_PLATFORM, reason=f"digests recorded on {PLATFORM}")
def test_numpy_imported_first_gives_version_1s_committed_digests_or_the_refusal():
    """On an AVX2 processor the digests (its kernels are the pinned ones whatever was
    imported first); on an AVX-512 one the refusal, in one line, raised before a trial ran
    (never a drift). Version 2's compiled numerics give their digests on either, with the
    processor's own numpy and OpenBLAS kernels loaded first."""
    found = _numpy_first(version_2=True)
    assert found.pop("version 2")["digests"] == _golden("test_compiled").GOLDEN_V2
    golden = _golden("test_task").GOLDEN_BY_SIMD["X86_V3"]["pre/normal"]
    if found["refusal"] is None:
        assert found == {"refusal": None, "blas": found["blas"], "version 1": golden}
    else:
        assert "\n" not in found["refusal"] and "import dart_reach before numpy" in \
            found["refusal"]
        assert found.get("raised") == found["refusal"] and "version 1" not in found


@pytest.mark.skipif(not (ON_PLATFORM and AVX2), reason=f"digests recorded on {PLATFORM}, "
                                                      "x86_64 with AVX2")
def test_the_compiled_numerics_take_nothing_from_numpys_kernels():
    """Version 2's digests, and its genetic algorithm's fitness equal to ``run``'s, where numpy
    runs its baseline code and OpenBLAS its Sandybridge kernels; version 1's drift there (or
    refuse): the process does run other kernels."""
    found = _numpy_first(before=OTHER_KERNELS, version_2=True)
    if found["blas"] is None:
        pytest.skip("numpy's OpenBLAS does not name its kernels here")
    assert found["blas"] == "Sandybridge" and "Sandybridge" in found["refusal"]
    assert "raised" in found or found["version 1"] != \
        _golden("test_task").GOLDEN_BY_SIMD["X86_V3"]["pre/normal"]
    trials = found["version 2"]
    assert trials["digests"] == _golden("test_compiled").GOLDEN_V2
    assert trials["fitness"] == trials["run"]


@pytest.mark.skipif(not AVX2, reason="x86_64 with AVX2")
def test_a_version_1_trial_refuses_where_numpy_runs_other_kernels():
    found = _numpy_first(before=OTHER_KERNELS)
    if found["blas"] is None:
        pytest.skip("numpy's OpenBLAS does not name its kernels here")
    assert found["raised"] == found["refusal"] and "Sandybridge" in found["raised"]
