"""Model version 1's network update (section III-B, Fig. 3), frozen: numpy's kernels on the
parameters and states of ``ctrnn.Network``.

Never edited (``model.reference``): a change to the model is a new model version
(docs/model/trial.md, "How to change the model").
"""

from __future__ import annotations

import numpy as np

from ..ctrnn import N_HIDDEN, N_MOTORS, N_SENSORS, Network

#: Inputs of the logistic are clipped to +-this (sigma(500) == 1.0 in float64; avoids overflow
#: warnings in exp without changing any representable result that matters).
_SIGMOID_CLIP = 500.0


def sigmoid(z, out=None) -> np.ndarray:
    """The logistic sigma(z) = 1 / (1 + exp(-z)) of the update equation (section III-B),
    elementwise; ``out`` may be ``z`` itself (in place)."""
    out = np.array(z, dtype=float) if out is None else out
    if out is not z:
        out[...] = z
    out.clip(-_SIGMOID_CLIP, _SIGMOID_CLIP, out=out)  # np.clip without its wrapper
    np.negative(out, out=out)
    np.exp(out, out=out)
    out += 1.0
    np.reciprocal(out, out=out)
    return out


class ReferenceNetwork(Network):
    """``ctrnn.Network`` stepped by version 1's numerics: numpy's ``matmul`` and ``exp`` on
    preallocated buffers (the rounding of numpy's kernels at the dispatch level that
    ``import dart_reach`` pins)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._one_minus_tau_h = 1.0 - self._tau_h
        self._one_minus_tau_m = 1.0 - self._tau_m
        # Preallocated buffers of the step.
        self._s_h = np.zeros(N_HIDDEN)
        self._s_m = np.zeros(N_MOTORS)
        self._from_hidden = np.zeros(N_MOTORS)

    def step(self, sensors: np.ndarray) -> np.ndarray:
        """One 0.1 s update from the 25 sensor values at time t; returns ``self.motor`` (14,)
        in [0, 1] (the same array every call, updated in place). Allocates nothing."""
        if type(sensors) is not np.ndarray or sensors.shape != (N_SENSORS,):
            sensors = np.asarray(sensors, dtype=float)
            if sensors.shape != (N_SENSORS,):
                raise ValueError(f"expected {N_SENSORS} sensor values, got shape {sensors.shape}")
        x = self._x
        np.multiply(sensors, self._in_scale, out=x)
        s_m = self._s_m
        np.matmul(self._w_sm, x, out=s_m)
        if not self.hidden_frozen:
            h, s_h = self.hidden, self._s_h
            np.matmul(self._w_sh, x, out=s_h)
            s_h -= self._bias_h
            sigmoid(s_h, out=s_h)
            s_h *= self._gain_h
            h *= self._tau_h
            s_h *= self._one_minus_tau_h
            h += s_h
            np.matmul(self._w_hm, h, out=self._from_hidden)
            s_m += self._from_hidden
        s_m -= self._bias_m
        sigmoid(s_m, out=s_m)
        m = self.motor
        m *= self._tau_m
        s_m *= self._one_minus_tau_m
        m += s_m
        return m
