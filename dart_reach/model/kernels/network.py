"""The network of Fig. 3 (section III-B), compiled: the update equation of one 0.1 s control
step, its logistic and the motor targets, over the network's parameters and states in one
structure (``NetworkState``); ``CompiledNetwork`` is ``ctrnn.Network`` stepped by them.

The vectors are laid out by ``ctrnn``'s names: ``N_SENSORS`` = 25 inputs, ``N_HIDDEN`` = 8
internal neurons, ``N_MOTORS`` = 14 motor neurons in ``ctrnn.MOTOR_NAMES``' order. The
parameters (weights, biases, gains; the time constants tau in [0, 1], the fraction of a
neuron's state kept per 0.1 s step) are ``ctrnn.Network``'s arrays, shared, not copied. Every
sum is taken in index order (``model.compiled``: the rounding rules)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numba.experimental import structref

from ..ctrnn import N_HIDDEN, N_MOTORS, N_SENSORS, Network, NetworkParams
from ..levers import ReflexInputs
from .floats import exp_nonpositive
from .structures import Structure, build


@njit(cache=True)
def logistic(z: float) -> float:
    """sigma(z) = 1 / (1 + exp(-z)) of the update equation (section III-B), from
    ``exp_nonpositive`` of -|z| (no overflow): 1 / (1 + e) for z >= 0, e / (1 + e) below."""
    if z >= 0.0:
        return 1.0 / (1.0 + exp_nonpositive(-z))
    e = exp_nonpositive(z)
    return e / (1.0 + e)


@njit(cache=True)
def _network_step(sensors_in, in_scale, w_sm, w_sh, w_hm, bias_h, bias_m, gain_h, tau_h, tau_m,
                  hidden_frozen, x, hidden, motor):
    """One 0.1 s update of the network (``ctrnn.Network``'s update equation, section III-B),
    in place on ``hidden`` (8) and ``motor`` (14) from the 25 sensor values ``sensors_in``
    scaled by ``in_scale`` into ``x``; every sum in index order: the sensors', then the
    internal neurons'."""
    for j in range(N_SENSORS):
        x[j] = sensors_in[j] * in_scale[j]
    if not hidden_frozen:
        for i in range(N_HIDDEN):
            s = 0.0
            for j in range(N_SENSORS):
                s += w_sh[i, j] * x[j]
            s = gain_h[i] * logistic(s - bias_h[i])
            hidden[i] = tau_h[i] * hidden[i] + (1.0 - tau_h[i]) * s
    for i in range(N_MOTORS):
        s = 0.0
        for j in range(N_SENSORS):
            s += w_sm[i, j] * x[j]
        if not hidden_frozen:
            for j in range(N_HIDDEN):
                s += w_hm[i, j] * hidden[j]
        motor[i] = tau_m[i] * motor[i] + (1.0 - tau_m[i]) * logistic(s - bias_m[i])


@njit(cache=True)
def targets_of_motor(motor, targets):
    """Motor targets 2 s - 1 in [-1, 1] of the 14 motor states s in [0, 1]
    (``ctrnn.motor_targets``, section III-B); whether all are finite."""
    finite = True
    for i in range(N_MOTORS):
        targets[i] = motor[i] * 2.0 - 1.0
        finite = finite and math.isfinite(targets[i])
    return finite


# ------------------------------------------------------------------------------ the structure
@structref.register
class _NetworkStateType(Structure):
    pass


class NetworkState(structref.StructRefProxy):
    """A network's parameters and states as ``_network_step`` takes them (built by
    ``network_state``; ``CompiledNetwork.state``)."""


_NETWORK_FIELDS = ("in_scale", "w_sm", "w_sh", "w_hm", "bias_h", "bias_m", "gain_h", "tau_h",
                   "tau_m", "hidden_frozen", "x", "hidden", "motor")
structref.define_proxy(NetworkState, _NetworkStateType, _NETWORK_FIELDS)


@njit(cache=True)
def _new_network_state(*fields):
    return NetworkState(*fields)


def network_state(**fields) -> NetworkState:
    """The ``NetworkState`` of ``fields`` (by name, ``_NETWORK_FIELDS``)."""
    return build(_new_network_state, _NETWORK_FIELDS, fields)


@njit(cache=True)
def network_step(sensors_in, n):
    """One 0.1 s update of the network of ``NetworkState`` ``n`` from 25 sensor values
    (``_network_step``), in place on ``n.hidden`` and ``n.motor``."""
    _network_step(sensors_in, n.in_scale, n.w_sm, n.w_sh, n.w_hm, n.bias_h, n.bias_m,
                  n.gain_h, n.tau_h, n.tau_m, n.hidden_frozen, n.x, n.hidden, n.motor)


class CompiledNetwork(Network):
    """``ctrnn.Network`` (section III-B, Fig. 3) stepped by compiled code (the living model,
    model versions 2 and 3); ``step`` allocates nothing."""

    def __init__(self, params: NetworkParams, *, reflexes: bool = False,
                 hidden_frozen: bool = False, reflex_inputs: ReflexInputs = ReflexInputs.HAND_SET):
        super().__init__(params, reflexes=reflexes, hidden_frozen=hidden_frozen,
                         reflex_inputs=reflex_inputs)
        #: the network's parameters and states as ``network_step`` and ``act_step`` read
        #: them (``NetworkState``; arrays shared with the network, updated in place)
        self.state = network_state(
            in_scale=self._in_scale, w_sm=self._w_sm, w_sh=self._w_sh, w_hm=self._w_hm,
            bias_h=self._bias_h, bias_m=self._bias_m, gain_h=self._gain_h, tau_h=self._tau_h,
            tau_m=self._tau_m, hidden_frozen=self.hidden_frozen, x=self._x,
            hidden=self.hidden, motor=self.motor)

    def step(self, sensors: np.ndarray) -> np.ndarray:
        """One 0.1 s update from the 25 sensor values; returns ``self.motor``."""
        if type(sensors) is not np.ndarray or sensors.shape != (N_SENSORS,) \
                or sensors.dtype != np.float64:
            sensors = np.asarray(sensors, dtype=float)
            if sensors.shape != (N_SENSORS,):
                raise ValueError(f"expected {N_SENSORS} sensor values, got shape {sensors.shape}")
        network_step(sensors, self.state)
        return self.motor
