"""The pin of numpy's and OpenBLAS's kernels (``dart_reach.pinning``): what ``import
dart_reach`` sets and records, the decision whether model version 1 may run, as a pure function
of given processors, features and kernels (an AVX-512 processor's refusal included, which this
suite's machines may not have), this process's answer, and the command line's one line."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from dart_reach import pinning
from dart_reach.pinning import (ABOVE_AVX2, BLAS_VARIABLE, NUMPY_VARIABLE, ImportRecord,
                                KernelsNotPinned, kernel_pin, pin_kernels,
                                require_pinned_kernels)

AVX2 = frozenset({"sse4_2", "avx", "avx2", "fma"})
AVX512 = AVX2 | {"avx512f", "avx512cd", "avx512bw", "avx512dq", "avx512vl"}
#: numpy 2.4's runtime features of an AVX2 processor, and of an AVX-512 one with and without
#: the pin (``NPY_DISABLE_CPU_FEATURES`` sets a disabled target False)
AVX2_FEATURES = {"AVX2": True, "FMA3": True, "X86_V3": True, "X86_V4": False,
                 "AVX512F": False, "AVX512_ICL": False, "AVX512_SPR": False}
AVX512_FEATURES = {**AVX2_FEATURES, "X86_V4": True, "AVX512F": True, "AVX512_ICL": True,
                   "AVX512_SKX": True}
AVX512_PINNED = {**AVX512_FEATURES, "X86_V4": False, "AVX512F": False, "AVX512_ICL": False,
                 "AVX512_SKX": False}


def test_the_pin_sets_both_variables_before_numpy_and_leaves_a_users_choice():
    environ = {}
    record = pin_kernels(environ, {"os", "sys"}, AVX512, "x86_64")
    assert environ == {NUMPY_VARIABLE: ABOVE_AVX2, BLAS_VARIABLE: "Haswell"}
    assert record == ImportRecord(numpy_first=False, numpy_preset=None, blas_preset=None,
                                  blas_set=True)
    chosen = {NUMPY_VARIABLE: "", BLAS_VARIABLE: "SkylakeX"}
    record = pin_kernels(chosen, {"numpy"}, AVX512, "x86_64")
    assert chosen == {NUMPY_VARIABLE: "", BLAS_VARIABLE: "SkylakeX"}
    assert record == ImportRecord(True, "", "SkylakeX", False)
    elsewhere = {}
    assert not pin_kernels(elsewhere, set(), set(), "aarch64").blas_set and elsewhere == {}
    no_fma = {}
    pin_kernels(no_fma, set(), {"avx"}, "x86_64")
    assert no_fma == {NUMPY_VARIABLE: ABOVE_AVX2}


def test_an_avx2_machine_runs_the_pinned_kernels_whatever_was_imported_first():
    """On an AVX2 processor numpy has no target above AVX2 and OpenBLAS picks Haswell's
    kernels itself: numpy first changes nothing, version 1 runs."""
    for numpy_first in (False, True):
        record = ImportRecord(numpy_first, None, None, True)
        for core in ("Haswell", None):
            pin = kernel_pin(record, AVX2_FEATURES, core, AVX2)
            assert pin.took and pin.refusal() is None, (numpy_first, core)


def test_an_avx512_machine_with_numpy_first_refuses_version_1_in_one_line():
    record = ImportRecord(numpy_first=True, numpy_preset=None, blas_preset=None, blas_set=True)
    pin = kernel_pin(record, AVX512_FEATURES, "SkylakeX", AVX512)
    assert not pin.took and pin.numpy_above_avx2 == ("X86_V4", "AVX512_ICL", "AVX512F",
                                                     "AVX512_SKX")
    line = pin.refusal()
    assert "\n" not in line and line.startswith("model version 1 cannot run")
    for said in ("numpy was imported before dart_reach", "X86_V4", "SkylakeX",
                 "import dart_reach before numpy", f"{NUMPY_VARIABLE}='{ABOVE_AVX2}'",
                 f"{BLAS_VARIABLE}=Haswell", "before Python starts"):
        assert said in line, said
    with pytest.raises(KernelsNotPinned) as raised:
        require_pinned_kernels(pin)
    assert str(raised.value) == line
    # OpenBLAS's kernels not read: numpy loaded with neither variable, so the CPU chose
    unread = kernel_pin(record, AVX512_FEATURES, None, AVX512)
    assert unread.blas_core is None and "OpenBLAS's own choice of kernels" in unread.refusal()


def test_an_avx512_machine_where_the_pin_took_or_the_user_chose_runs_version_1():
    first = ImportRecord(numpy_first=False, numpy_preset=None, blas_preset=None, blas_set=True)
    assert kernel_pin(first, AVX512_PINNED, "Haswell", AVX512).refusal() is None
    assert kernel_pin(first, AVX512_PINNED, None, AVX512).blas_core == "Haswell"  # inferred
    # numpy first, but the variables set before Python started: they took
    preset = ImportRecord(True, ABOVE_AVX2, "Haswell", False)
    assert kernel_pin(preset, AVX512_PINNED, None, AVX512).took
    # the user's own choice of numpy's AVX-512 code (e.g. to check the X86_V4 digests)
    chosen = ImportRecord(False, "", None, True)
    pin = kernel_pin(chosen, AVX512_FEATURES, "Haswell", AVX512)
    assert not pin.took and pin.refusal() is None
    require_pinned_kernels(pin)
    # one variable set, the other not: the other one's kernels refuse
    half = ImportRecord(True, None, "Haswell", False)
    line = kernel_pin(half, AVX512_FEATURES, "Haswell", AVX512).refusal()
    assert "numpy's code for X86_V4" in line and "OpenBLAS" not in line.split(";")[0]


def _fresh(code: str) -> dict:
    """``code``'s last line of output as JSON, run by a fresh Python without either variable."""
    env = {k: v for k, v in os.environ.items()
           if k not in (NUMPY_VARIABLE, BLAS_VARIABLE)}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, timeout=300, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


REPORT = ("import json; from dart_reach import pinning; p = pinning.this_process(); "
          "print(json.dumps([pinning.AT_IMPORT.numpy_first, p.numpy_first, p.refusal()]))")


@pytest.mark.skipif(not pinning.CPU_FLAGS >= {"avx2", "fma"}, reason="x86_64 with AVX2")
def test_dart_reach_imported_first_runs_the_pinned_kernels_here():
    """A real process, neither variable set before: numpy loads pinned, version 1 may run. On
    an AVX-512 processor too, where numpy 2.4 still reports features it no longer dispatches
    on (``AVX512F``, ``AVX512_CLX``), which once refused this process wrongly."""
    assert _fresh("import dart_reach; " + REPORT) == [False, False, None]


@pytest.mark.skipif(not pinning.CPU_FLAGS >= {"avx2", "fma"} or "avx512f" in pinning.CPU_FLAGS,
                    reason="an AVX2 processor without AVX-512")
def test_this_avx2_machine_runs_version_1_whatever_was_imported_first():
    assert _fresh("import numpy, dart_reach; " + REPORT) == [True, True, None]


#: numpy loaded with OpenBLAS's Sandybridge kernels and numpy's baseline dispatch, by variables
#: gone when ``dart_reach`` is imported
OTHER_KERNELS_FIRST = (
    "import os; os.environ['OPENBLAS_CORETYPE'] = 'Sandybridge'; "
    "os.environ['NPY_DISABLE_CPU_FEATURES'] = 'X86_V3 X86_V4 AVX512_ICL AVX512_SPR'; "
    "import numpy; del os.environ['OPENBLAS_CORETYPE'], os.environ['NPY_DISABLE_CPU_FEATURES']; ")


@pytest.mark.skipif(not pinning.CPU_FLAGS >= {"avx2", "fma"}, reason="x86_64 with AVX2")
def test_numpy_loaded_with_other_kernels_before_dart_reach_is_refused_here():
    """A real refusal on this machine: numpy loaded with OpenBLAS's Sandybridge kernels (and
    numpy's baseline dispatch) by variables gone when ``dart_reach`` is imported, as where a
    notebook's environment differs; OpenBLAS names the kernels it runs."""
    first, also, line = _fresh(OTHER_KERNELS_FIRST + "import dart_reach; " + REPORT)
    if pinning.openblas_core() is None:
        pytest.skip("numpy's OpenBLAS does not name its kernels here")
    assert first and also and "OpenBLAS's Sandybridge kernels" in line and "\n" not in line


@pytest.mark.skipif(not pinning.CPU_FLAGS >= {"avx2", "fma"}, reason="x86_64 with AVX2")
def test_the_command_line_says_the_refusal_in_one_line_with_exit_code_2(tmp_path):
    """A real refusal through the command: numpy loaded with other kernels first, then a
    training of version 1 asked for; nothing is written, so the same command can run again
    once the kernels are pinned."""
    if pinning.openblas_core() is None:
        pytest.skip("numpy's OpenBLAS does not name its kernels here")
    run = tmp_path / "refused"
    code = (OTHER_KERNELS_FIRST + "import sys; from dart_reach.cli import main; "
            "sys.exit(main(['train', 'standard', '--model-version', '1', '--generations', '1', "
            f"'--replications', '1', '--workers', '1', '--yes', '--out', {str(run)!r}]))")
    env = {k: v for k, v in os.environ.items() if k not in (NUMPY_VARIABLE, BLAS_VARIABLE)}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 2 and out.stdout == "", out.stderr
    assert out.stderr.startswith("dart-reach: error: ") and out.stderr.count("\n") == 1
    assert "OpenBLAS's Sandybridge kernels" in out.stderr
    assert not list(tmp_path.iterdir())
