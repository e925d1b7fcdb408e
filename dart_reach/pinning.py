"""Same seed, same bits on AVX2 and AVX-512 processors: the pin of numpy's and OpenBLAS's
kernels, and the refusal of model version 1 where the pin did not take.

numpy picks the code of its elementwise functions by the CPU (its dispatch), and OpenBLAS,
numpy's BLAS, picks its kernels by the CPU: on an AVX-512 processor both take code of their own
that can round differently from an AVX2 one's (float64 ``np.exp`` one ulp apart for some
inputs: docs/guides/runs.md, "Determinism", gives the measurement and its command; the trial
digests of tests/model/test_task.py differ between OpenBLAS's SkylakeX and Haswell kernels).
Model version 1 (``versions.Numerics.REFERENCE``) computes its network and sensors with them,
so its results depend on them.

``import dart_reach`` imports this module first, which, before numpy loads, keeps numpy's
dispatch at AVX2 at most (``NPY_DISABLE_CPU_FEATURES`` = ``ABOVE_AVX2``) and pins OpenBLAS's
Haswell kernels (``OPENBLAS_CORETYPE`` = ``PINNED_CORE``, on every x86_64 CPU with AVX2 and
FMA), unless the user has set the variable; worker processes inherit both. Neither can reach a
numpy loaded before ``dart_reach``: ``AT_IMPORT`` records whether numpy was (``ImportRecord``),
``kernel_pin`` decides from that record and the kernels a process runs whether the pin took
(``KernelPin``, a pure function of its inputs), and ``require_pinned_kernels`` raises
``KernelsNotPinned`` once the kernels differ from the pinned ones and the user did not choose
them (a reference-numerics trial calls it when it is built; ``dart-reach`` prints its one line
and exits with code 2). docs/guides/runs.md, "Determinism", says what holds.

This module imports nothing but the standard library at its top: it must run before numpy.
"""

from __future__ import annotations

import ctypes
import functools
import os
import platform
import sys
from collections.abc import Collection, Mapping, MutableMapping
from dataclasses import dataclass
from pathlib import Path

#: The environment variable that disables numpy's dispatch targets (numpy reads it when it loads).
NUMPY_VARIABLE = "NPY_DISABLE_CPU_FEATURES"
#: The environment variable that chooses OpenBLAS's kernels (read when OpenBLAS loads).
BLAS_VARIABLE = "OPENBLAS_CORETYPE"
#: numpy's dispatch targets above AVX2: numpy 2.4's groups (``numpy.show_runtime()``) and the
#: AVX-512 names of earlier 2.x releases; a name a release does not know is ignored. numpy
#: disables only the targets named (an AVX-512 CPU keeps AVX512_ICL when X86_V4 alone is).
ABOVE_AVX2 = ("X86_V4 AVX512_ICL AVX512_SPR AVX512F AVX512CD AVX512_KNL AVX512_KNM AVX512_SKX "
              "AVX512_CLX AVX512_CNL")
#: OpenBLAS's kernels the pin chooses: Haswell's, which every x86_64 CPU with AVX2 and FMA runs.
PINNED_CORE = "Haswell"


def cpu_flags(cpuinfo: str | None = None) -> frozenset[str]:
    """The processor's feature flags (``avx2``, ``fma``, ``avx512f``, ...) from ``cpuinfo``
    (default: /proc/cpuinfo's text; empty where there is none, e.g. off Linux)."""
    if cpuinfo is None:
        try:
            cpuinfo = Path("/proc/cpuinfo").read_text(encoding="utf-8", errors="replace")
        except OSError:
            return frozenset()
    line = next((x for x in cpuinfo.splitlines() if x.startswith("flags")), "")
    return frozenset(line.partition(":")[2].split())


@dataclass(frozen=True)
class ImportRecord:
    """What ``import dart_reach`` found: whether numpy was loaded before it (``numpy_first``;
    then neither variable it sets can take), the values the user had set of
    ``NPY_DISABLE_CPU_FEATURES`` and ``OPENBLAS_CORETYPE`` (None: not set; a value set is the
    user's choice, left as it is), and whether it set ``OPENBLAS_CORETYPE`` (``blas_set``: an
    x86_64 CPU with AVX2 and FMA, the variable not set)."""

    numpy_first: bool
    numpy_preset: str | None
    blas_preset: str | None
    blas_set: bool


def pin_kernels(environ: MutableMapping[str, str], loaded: Collection[str],
                flags: Collection[str], machine: str) -> ImportRecord:
    """Pin the kernels in ``environ`` (for a numpy not in ``loaded``, the modules already
    imported, to take them) on an x86_64 ``machine`` with CPU ``flags``: numpy's dispatch at
    AVX2 at most, OpenBLAS's Haswell kernels where the CPU has AVX2 and FMA; a variable the
    user has set is left alone. It changes nothing numpy computes on an AVX2 machine. Returns
    what it found (``ImportRecord``)."""
    record = ImportRecord(numpy_first="numpy" in loaded,
                          numpy_preset=environ.get(NUMPY_VARIABLE),
                          blas_preset=environ.get(BLAS_VARIABLE),
                          blas_set=(machine == "x86_64" and BLAS_VARIABLE not in environ
                                       and {"avx2", "fma"} <= set(flags)))
    if machine == "x86_64" and NUMPY_VARIABLE not in environ:
        environ[NUMPY_VARIABLE] = ABOVE_AVX2
    if record.blas_set:
        environ[BLAS_VARIABLE] = PINNED_CORE
    return record


#: This process's processor flags and what ``import dart_reach`` found and pinned, before numpy.
CPU_FLAGS = cpu_flags()
AT_IMPORT = pin_kernels(os.environ, sys.modules, CPU_FLAGS, platform.machine())


class KernelsNotPinned(RuntimeError):
    """Model version 1 asked to run where numpy's or OpenBLAS's kernels are not the pinned ones
    and the user did not choose them: its results would drift from the committed ones. The
    message is one line: what happened and how to fix it."""


@dataclass(frozen=True)
class KernelPin:
    """The kernels a process computes with, against the pin: ``numpy_first`` (numpy was loaded
    before ``dart_reach``), ``numpy_above_avx2`` (numpy's dispatch targets above AVX2 enabled
    in the process; empty when the pin took or the CPU has none), ``blas_core`` (OpenBLAS's
    kernels, read from the library or inferred from the environment numpy loaded with; None:
    the CPU's own choice, unknown), ``avx512`` (the CPU has AVX-512, where OpenBLAS's own
    choice is not Haswell's) and whether the user chose numpy's (``numpy_chosen``) and
    OpenBLAS's (``blas_chosen``) by setting their variables."""

    numpy_first: bool
    numpy_above_avx2: tuple[str, ...]
    blas_core: str | None
    avx512: bool
    numpy_chosen: bool
    blas_chosen: bool

    @property
    def numpy_pinned(self) -> bool:
        """numpy runs no dispatch target above AVX2."""
        return not self.numpy_above_avx2

    @property
    def blas_pinned(self) -> bool:
        """OpenBLAS runs the pinned kernels (or, unknown, the CPU has no AVX-512, where its own
        choice is the same)."""
        if self.blas_core is None:
            return not self.avx512
        return self.blas_core.lower() == PINNED_CORE.lower()

    @property
    def took(self) -> bool:
        """Both run the pinned kernels."""
        return self.numpy_pinned and self.blas_pinned

    def refusal(self) -> str | None:
        """Why model version 1 must not run here, in one line with the fix; None where it may:
        the kernels are the pinned ones, or the user chose the ones that differ."""
        differ = []
        if not self.numpy_pinned and not self.numpy_chosen:
            differ.append(f"numpy's code for {', '.join(self.numpy_above_avx2)}")
        if not self.blas_pinned and not self.blas_chosen:
            differ.append(f"OpenBLAS's {self.blas_core or 'own choice of'} kernels")
        if not differ:
            return None
        why = ("numpy was imported before dart_reach" if self.numpy_first
               else "the pin did not take when numpy loaded")
        return (f"model version 1 cannot run in this process: {why}, so it computes with "
                f"{' and '.join(differ)}, which round differently from the kernels its results "
                f"were made with; import dart_reach before numpy, or set "
                f"{NUMPY_VARIABLE}='{ABOVE_AVX2}' and {BLAS_VARIABLE}={PINNED_CORE} before "
                f"Python starts")


def kernel_pin(record: ImportRecord, numpy_targets: Mapping[str, bool],
               blas_core: str | None, flags: Collection[str]) -> KernelPin:
    """The ``KernelPin`` of a process from what ``import dart_reach`` found (``record``),
    numpy's dispatch targets (name -> enabled: ``numpy_targets``, where a target the
    environment disabled is False), OpenBLAS's kernels as the library names them
    (None: not known) and the CPU's ``flags`` (/proc/cpuinfo's). A pure function."""
    above = tuple(name for name in ABOVE_AVX2.split() if numpy_targets.get(name))
    if blas_core is None:  # not read: the environment numpy loaded with decides
        if record.blas_preset is not None:
            blas_core = record.blas_preset
        elif record.blas_set and not record.numpy_first:
            blas_core = PINNED_CORE
    return KernelPin(numpy_first=record.numpy_first, numpy_above_avx2=above,
                     blas_core=blas_core, avx512="avx512f" in flags or bool(above),
                     numpy_chosen=record.numpy_preset is not None,
                     blas_chosen=record.blas_preset is not None)


def openblas_core() -> str | None:
    """The kernels numpy's OpenBLAS runs in this process (``Haswell``, ``SkylakeX``, ...), asked
    of the library that numpy's wheel bundles (``numpy.libs``); None where numpy has another
    BLAS or another layout. Loads numpy."""
    import numpy

    for path in sorted((Path(numpy.__file__).parent.parent / "numpy.libs").glob("*openblas*")):
        try:
            library = ctypes.CDLL(str(path))
        except OSError:
            continue
        for name in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename",
                     "openblas_get_corename64_", "openblas_get_corename"):
            corename = getattr(library, name, None)
            if corename is not None:
                corename.restype = ctypes.c_char_p
                found = corename()
                return found.decode().strip() if found else None
    return None


def numpy_targets() -> dict[str, bool]:
    """numpy's dispatch targets in this process, in numpy's order, name -> enabled (False:
    disabled by ``NPY_DISABLE_CPU_FEATURES``). A CPU feature numpy does not dispatch on is not
    one, even where the processor has it: numpy 2.4 dispatches on the groups ``X86_V4``,
    ``AVX512_ICL`` and ``AVX512_SPR``, and still reports ``AVX512F`` or ``AVX512_CLX`` among
    its features. Loads numpy."""
    import numpy

    features = numpy._core._multiarray_umath.__cpu_features__
    return {name: bool(features.get(name)) for name in numpy_dispatch()[0]}


def numpy_dispatch() -> tuple[tuple[str, ...], tuple[str, ...]]:
    """numpy's dispatch targets and its baseline features, each in numpy's order (its
    ``__cpu_dispatch__`` and ``__cpu_baseline__``; this module is the one that reads numpy's
    internals). Loads numpy."""
    import numpy

    umath = numpy._core._multiarray_umath
    return tuple(umath.__cpu_dispatch__), tuple(umath.__cpu_baseline__)


def this_process() -> KernelPin:
    """The ``KernelPin`` of this process (loads numpy)."""
    return kernel_pin(AT_IMPORT, numpy_targets(), openblas_core(), CPU_FLAGS)


@functools.cache
def _refusal_here() -> str | None:
    return this_process().refusal()


def require_pinned_kernels(pin: KernelPin | None = None) -> None:
    """``KernelsNotPinned`` (one line: what happened, how to fix it) where this process's
    kernels (or ``pin``'s) are not the pinned ones and the user did not choose them
    (``KernelPin.refusal``); nothing otherwise. This process's are decided once (about a
    millisecond), then the answer is cached: call it where a model version 1 trial is built,
    not per step."""
    refusal = _refusal_here() if pin is None else pin.refusal()
    if refusal is not None:
        raise KernelsNotPinned(refusal)
