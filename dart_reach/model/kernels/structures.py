"""The Numba structures the trial's compiled step functions read and write their arrays
through (a trial's ``compiled.StepState``, a network's ``network.NetworkState``, the touch
decisions' ``touch.TouchState``): a compiled call pays for each array it is passed, and the
sensing, the network and the motor commands read about fifty (docs/results/benchmarks.md
has what that cost). Each structure is registered
(``numba.experimental.structref``) in the module of the kernels that read it, when that
module is imported, before any structure of it is built or passed."""

from __future__ import annotations

from types import SimpleNamespace

from numba.core import config as numba_config
from numba.core import types


class Structure(types.StructRef):
    """A Numba structure of arrays and scalars, each field typed as the value it is built
    with."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(kind)) for name, kind in fields)


def build(new, names: tuple[str, ...], fields: dict):
    """The structure of ``fields`` (every name of ``names``; arrays shared, not copied), built
    by compiled code (``new``) so that its constructor is compiled once and cached, not in
    every process; uncompiled (``NUMBA_DISABLE_JIT=1``), a plain object with the same
    fields, which the uncompiled step functions read alike."""
    if set(fields) != set(names):
        raise TypeError(f"fields missing {sorted(set(names) - set(fields))}, "
                        f"unknown {sorted(set(fields) - set(names))}")
    if numba_config.DISABLE_JIT:
        return SimpleNamespace(**fields)
    return new(*(fields[name] for name in names))
