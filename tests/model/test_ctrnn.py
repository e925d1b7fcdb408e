"""The controller (paper section III-B, Fig. 3; reflexes: sections II-D, III-D).

Update pinned here: within one step, sensors (t) -> internal neurons -> motor neurons, each a
leaky integrator x(t) = tau x(t-1) + (1 - tau) g sigma(sum_j w_ij x_j(t) - theta).
"""

import dataclasses
import math

import numpy as np
import pytest

from dart_reach.model import ctrnn
from dart_reach.model.kernels.network import CompiledNetwork
from dart_reach.model.ctrnn import (MOTOR_INDEX, N_HIDDEN, N_MOTORS, N_SENSORS, SENSOR_INDEX,
                                    NetworkParams)
from dart_reach.model.reference.network import ReferenceNetwork, sigmoid


def with_(params: NetworkParams, **changes) -> NetworkParams:
    return dataclasses.replace(params, **changes)


def sig(z: float) -> float:
    return 1.0 / (1.0 + math.exp(-z))


# ------------------------------------------------------------------ single neurons, closed form
def test_motor_neuron_follows_the_closed_form_under_constant_input():
    # One motor neuron (index 4) with input w * x = 1.5 * 0.8 = 1.2 and threshold -0.4:
    # s = sigma(1.2 + 0.4) = sigma(1.6) at every step; x(t) = tau^t x0 + s (1 - tau^t).
    tau, x0 = 0.7, 0.2
    w = np.zeros((N_MOTORS, N_SENSORS))
    w[4, 3] = 1.5
    p = with_(ctrnn.zero_params(), w_sensor_motor=w,
              bias_motor=np.where(np.arange(N_MOTORS) == 4, -0.4, 0.0),
              tau_motor=np.full(N_MOTORS, tau))
    net = ReferenceNetwork(p)
    start = np.full(N_MOTORS, 0.5)
    start[4] = x0
    net.reset(motor=start)
    sensors = np.zeros(N_SENSORS)
    sensors[3] = 0.8
    s_inf = sig(1.6)
    for t in range(1, 31):
        net.step(sensors)
        assert net.motor[4] == pytest.approx(tau**t * x0 + s_inf * (1 - tau**t), abs=1e-14)
    # and the first step against the number by hand: 0.7 * 0.2 + 0.3 * sigma(1.6)
    net.reset(motor=start)
    net.step(sensors)
    assert net.motor[4] == pytest.approx(0.14 + 0.3 * 0.8320183851339245, abs=1e-14)


def test_hidden_neuron_follows_the_closed_form_with_gain():
    # Internal neuron 2: input 2.0 * (-0.5) = -1, threshold 0.5, gain 0.6, tau 0.3, from 0:
    # x(t) = 0.6 sigma(-1.5) (1 - 0.3^t)
    w = np.zeros((N_HIDDEN, N_SENSORS))
    w[2, 10] = 2.0
    p = with_(ctrnn.zero_params(), w_sensor_hidden=w, bias_hidden=np.full(N_HIDDEN, 0.5),
              gain_hidden=np.full(N_HIDDEN, 0.6), tau_hidden=np.full(N_HIDDEN, 0.3))
    net = ReferenceNetwork(p)
    net.reset()
    sensors = np.zeros(N_SENSORS)
    sensors[10] = -0.5
    for t in range(1, 20):
        net.step(sensors)
        assert net.hidden[2] == pytest.approx(0.6 * sig(-1.5) * (1 - 0.3**t), abs=1e-14)


def test_tau_zero_follows_input_at_once_and_tau_one_holds_its_state():
    p = with_(ctrnn.zero_params(), bias_motor=np.full(N_MOTORS, -1.0),
              tau_motor=np.where(np.arange(N_MOTORS) < 7, 0.0, 1.0))
    net = ReferenceNetwork(p)
    net.reset(motor=np.full(N_MOTORS, 0.2))
    for _ in range(3):
        m = net.step(np.zeros(N_SENSORS))
        # tau = 0: x = s = sigma(0 - (-1)) = sigma(1) = 0.731059 every step
        np.testing.assert_allclose(m[:7], 0.7310585786300049, rtol=0, atol=1e-15)
        # tau = 1: x stays at its reset value
        np.testing.assert_array_equal(m[7:], 0.2)


def test_gains():
    # hidden gain 0: the internal neurons' s is 0, so they stay at 0 whatever their input
    rng = np.random.default_rng(3)
    p = with_(ctrnn.random_params(rng), gain_hidden=np.zeros(N_HIDDEN))
    net = ReferenceNetwork(p)
    for _ in range(5):
        net.step(rng.uniform(-1, 1, N_SENSORS))
        np.testing.assert_array_equal(net.hidden, 0.0)
    # the offset gain multiplies the two offset sensor values: 2.5 * 0.4 = 1.0 into motor 5
    w = np.zeros((N_MOTORS, N_SENSORS))
    w[5, 23] = 1.0
    w[6, 24] = 1.0
    net = ReferenceNetwork(with_(ctrnn.zero_params(), w_sensor_motor=w,
                                 gain_offset=np.array([2.5, 0.0])))
    x = np.zeros(N_SENSORS)
    x[23] = x[24] = 0.4
    m = net.step(x)
    assert m[5] == pytest.approx(sig(1.0), abs=1e-15)
    assert m[6] == 0.5  # 0 * 0.4: sigma(0)


# ------------------------------------------------------------------ switches
def test_hidden_frozen_keeps_internal_neurons_at_zero_and_cuts_their_weights():
    rng = np.random.default_rng(11)
    p = ctrnn.random_params(rng)
    q = with_(p, w_sensor_hidden=rng.uniform(-5, 5, (N_HIDDEN, N_SENSORS)),
              w_hidden_motor=rng.uniform(-5, 5, (N_MOTORS, N_HIDDEN)),
              bias_hidden=rng.uniform(-5, 5, N_HIDDEN))
    frozen_p, frozen_q = (ReferenceNetwork(x, hidden_frozen=True) for x in (p, q))
    live_p, live_q = ReferenceNetwork(p), ReferenceNetwork(q)
    for _ in range(20):
        s = rng.uniform(-1, 1, N_SENSORS)
        a, b = frozen_p.step(s), frozen_q.step(s)
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(frozen_p.hidden, 0.0)
        live_p.step(s)
        live_q.step(s)
    # unfrozen, the hidden weights matter (this test could fail)
    assert not np.allclose(live_p.motor, live_q.motor)
    assert np.abs(live_p.hidden).max() > 0


def test_reflex_weights_layout():
    mask, w = ctrnn.reflex_weights()
    assert mask.shape == w.shape == (N_MOTORS, N_SENSORS) and mask.dtype == bool
    m, s = MOTOR_INDEX, SENSOR_INDEX
    reflex_motors = {m["neck_yaw"], m["neck_pitch"], m["r_hand_fingers"]}
    # every direct input of the three reflex motors is hand-set, nothing else is
    assert {i for i, _ in zip(*np.nonzero(mask))} == reflex_motors
    assert mask[sorted(reflex_motors)].all()
    nonzero = {(int(i), int(j)) for i, j in zip(*np.nonzero(w))}
    assert nonzero == {(m["neck_yaw"], s["sight/x"]), (m["neck_pitch"], s["sight/y"]),
                       (m["r_hand_fingers"], s["touch/palm"])}
    for motor, sight, sign in (("neck_yaw", "sight/x", ctrnn.ORIENT_YAW_SIGN),
                               ("neck_pitch", "sight/y", ctrnn.ORIENT_PITCH_SIGN)):
        home = ctrnn.ORIENT_HOME_TARGETS[motor]
        assert w[m[motor], s[sight]] == sign * 2 * ctrnn.ORIENT_GAIN / (1 - home ** 2)
    assert w[m["r_hand_fingers"], s["touch/palm"]] == ctrnn.GRASP_WEIGHT > 0
    assert abs(ctrnn.ORIENT_YAW_SIGN) == abs(ctrnn.ORIENT_PITCH_SIGN) == 1.0
    bmask, b = ctrnn.reflex_biases()
    assert set(np.nonzero(bmask)[0]) == reflex_motors
    assert b[m["r_hand_fingers"]] == ctrnn.GRASP_BIAS


def test_reflexes_override_evolved_weights_on_masked_connections_only():
    rng = np.random.default_rng(5)
    p = ctrnn.random_params(rng)
    mask, w = ctrnn.reflex_weights()
    bmask, b = ctrnn.reflex_biases()
    on, off = ReferenceNetwork(p, reflexes=True), ReferenceNetwork(p, reflexes=False)
    np.testing.assert_array_equal(on.effective_w_sensor_motor[mask], w[mask])
    np.testing.assert_array_equal(on.effective_w_sensor_motor[~mask], p.w_sensor_motor[~mask])
    np.testing.assert_array_equal(off.effective_w_sensor_motor, p.w_sensor_motor)
    np.testing.assert_array_equal(on.effective_bias_motor[bmask], b[bmask])
    np.testing.assert_array_equal(on.effective_bias_motor[~bmask], p.bias_motor[~bmask])
    # only the reflex motors behave differently
    others = ~mask.any(axis=1)
    for _ in range(10):
        s = rng.uniform(-1, 1, N_SENSORS)
        a, c = on.step(s), off.step(s)
        np.testing.assert_array_equal(a[others], c[others])
    assert not np.allclose(a[~others], c[~others])
    np.testing.assert_array_equal(on.params.w_sensor_motor, p.w_sensor_motor)  # not mutated


def test_grasp_reflex_closes_the_hand_on_palm_touch():
    net = ReferenceNetwork(ctrnn.zero_params(), reflexes=True)  # tau = 0, no other input
    hand = MOTOR_INDEX["r_hand_fingers"]
    x = np.zeros(N_SENSORS)
    x[14:20] = -1.0
    x[SENSOR_INDEX["touch/palm"]] = 1.0
    target = ctrnn.motor_targets(net.step(x))[hand]
    assert target == pytest.approx(2 * sig(ctrnn.GRASP_WEIGHT) - 1) and target > 0.98  # closed
    x[SENSOR_INDEX["touch/palm"]] = -1.0
    x[SENSOR_INDEX["touch/thumb"]] = 1.0  # a fingertip alone does not trigger it
    assert ctrnn.motor_targets(net.step(x))[hand] < -0.98  # open


def test_orienting_reflex_holds_home_and_moves_the_neck_target_by_k_c():
    net = ReferenceNetwork(ctrnn.zero_params(), reflexes=True)  # tau = 0
    k = ctrnn.ORIENT_GAIN
    for motor, sight, sign in (("neck_yaw", "sight/x", ctrnn.ORIENT_YAW_SIGN),
                               ("neck_pitch", "sight/y", ctrnn.ORIENT_PITCH_SIGN)):
        home = ctrnn.ORIENT_HOME_TARGETS[motor]
        x = np.zeros(N_SENSORS)
        x[SENSOR_INDEX[f"proprio/{motor}"]] = 0.5  # proprioception plays no part
        # ball centred or not in sight (0): the target is the home posture's
        t = ctrnn.motor_targets(net.step(x))[MOTOR_INDEX[motor]]
        assert t == pytest.approx(home, abs=1e-12)
        # off centre by c: the target moves by ~ sign k c (the slope of tanh at home)
        x[SENSOR_INDEX[sight]] = 0.01
        t = ctrnn.motor_targets(net.step(x))[MOTOR_INDEX[motor]]
        assert (t - home) / 0.01 == pytest.approx(sign * k, rel=0.02)


def test_orienting_home_targets_are_the_worlds():
    from dart_reach.model.world import World
    world = World()
    for motor, home in ctrnn.ORIENT_HOME_TARGETS.items():
        assert world.home_targets[MOTOR_INDEX[motor]] == pytest.approx(home, abs=1e-4)


# ------------------------------------------------------------------ reference trajectory
def reference_trajectory(p: NetworkParams, inputs, reflexes: bool, hidden_frozen: bool,
                         motor0=None):
    """A deliberately plain per-neuron loop over Python floats (no numpy arithmetic)."""
    w_sm = p.w_sensor_motor.tolist()
    b_m = p.bias_motor.tolist()
    if reflexes:
        mask, w = ctrnn.reflex_weights()
        bmask, b = ctrnn.reflex_biases()
        for i in range(N_MOTORS):
            for j in range(N_SENSORS):
                if mask[i, j]:
                    w_sm[i][j] = float(w[i, j])
            if bmask[i]:
                b_m[i] = float(b[i])
    h = [0.0] * N_HIDDEN
    m = [0.5] * N_MOTORS if motor0 is None else list(motor0)
    rows = []
    for s in inputs:
        x = [float(v) for v in s]
        x[23] *= float(p.gain_offset[0])
        x[24] *= float(p.gain_offset[1])
        if not hidden_frozen:
            new_h = []
            for i in range(N_HIDDEN):
                a = sum(float(p.w_sensor_hidden[i, j]) * x[j] for j in range(N_SENSORS))
                si = float(p.gain_hidden[i]) * sig(a - float(p.bias_hidden[i]))
                ti = float(p.tau_hidden[i])
                new_h.append(ti * h[i] + (1.0 - ti) * si)
            h = new_h
        new_m = []
        for i in range(N_MOTORS):
            a = sum(w_sm[i][j] * x[j] for j in range(N_SENSORS))
            a += sum(float(p.w_hidden_motor[i, k]) * h[k] for k in range(N_HIDDEN))
            si = sig(a - b_m[i])
            ti = float(p.tau_motor[i])
            new_m.append(ti * m[i] + (1.0 - ti) * si)
        m = new_m
        rows.append((list(h), list(m)))
    return rows


@pytest.mark.parametrize("kind", [ReferenceNetwork, CompiledNetwork])
@pytest.mark.parametrize("reflexes,hidden_frozen", [(True, False), (False, False), (True, True)])
def test_network_matches_an_independent_per_neuron_loop(reflexes, hidden_frozen, kind):
    """Both numerics: the living model's (compiled) and version 1's frozen one."""
    rng = np.random.default_rng(2013)
    p = ctrnn.random_params(rng)
    # weights small enough that the trajectory is not saturated and every term matters
    p = with_(p, w_sensor_motor=p.w_sensor_motor / 3, w_sensor_hidden=p.w_sensor_hidden / 3,
              gain_offset=np.array([0.7, 1.3]))
    inputs = rng.uniform(-1.0, 1.0, (15, N_SENSORS))
    motor0 = rng.uniform(0.0, 1.0, N_MOTORS)
    net = kind(p, reflexes=reflexes, hidden_frozen=hidden_frozen)
    net.reset(motor=motor0)
    ref = reference_trajectory(p, inputs, reflexes, hidden_frozen, motor0.tolist())
    for s, (h, m) in zip(inputs, ref):
        net.step(s)
        np.testing.assert_allclose(net.hidden, h, rtol=0, atol=1e-12)
        np.testing.assert_allclose(net.motor, m, rtol=0, atol=1e-12)
    assert np.ptp(np.array([m for _, m in ref]), axis=0).max() > 0.05  # it moved


# ------------------------------------------------------------------ buffers, reset, targets
def test_step_reuses_its_buffers():
    net = ReferenceNetwork(ctrnn.random_params(np.random.default_rng(1)), reflexes=True)
    hidden, motor = net.hidden, net.motor
    s = np.random.default_rng(2).uniform(-1, 1, N_SENSORS)
    out1 = net.step(s)
    out2 = net.step(s)
    net.reset()
    out3 = net.step(s)
    assert out1 is out2 is out3 is motor is net.motor
    assert net.hidden is hidden
    # the caller's sensor array is never written to
    s_copy = s.copy()
    net.step(s)
    np.testing.assert_array_equal(s, s_copy)


def test_reset_states():
    net = ReferenceNetwork(ctrnn.random_params(np.random.default_rng(4)))
    net.step(np.ones(N_SENSORS))
    net.reset()
    np.testing.assert_array_equal(net.hidden, 0.0)
    np.testing.assert_array_equal(net.motor, ctrnn.RESET_MOTOR_STATE)
    np.testing.assert_array_equal(ctrnn.motor_targets(net.motor), 0.0)  # mid-range
    home = np.linspace(0.1, 0.9, N_MOTORS)
    net.reset(motor=home)
    np.testing.assert_array_equal(net.motor, home)
    with pytest.raises(ValueError, match="shape"):
        net.reset(motor=np.zeros(3))
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        net.reset(motor=np.full(N_MOTORS, 1.5))


def test_step_rejects_wrong_sensor_count():
    net = ReferenceNetwork(ctrnn.zero_params())
    with pytest.raises(ValueError, match="25"):
        net.step(np.zeros(24))
    net.step([0.0] * N_SENSORS)  # any sequence of 25 numbers is fine


def test_motor_targets():
    out = np.zeros(3)
    assert ctrnn.motor_targets(np.array([0.0, 0.5, 1.0]), out=out) is out
    np.testing.assert_array_equal(out, [-1.0, 0.0, 1.0])


def test_sigmoid_is_finite_and_exact_at_extremes():
    z = np.array([-1e6, -40.0, 0.0, 40.0, 1e6])
    with np.errstate(all="raise"):
        s = sigmoid(z)
    assert s[0] >= 0.0 and s[-1] == 1.0 and s[2] == 0.5
    assert s[1] == pytest.approx(sig(-40.0), rel=1e-12)


# ------------------------------------------------------------------ parameters
def test_zero_and_random_params():
    z = ctrnn.zero_params()
    ctrnn.validate_params(z)
    for name in ctrnn.PARAM_SHAPES:
        expected = 1.0 if name.startswith("gain_") else 0.0
        np.testing.assert_array_equal(getattr(z, name), expected)
    a = ctrnn.random_params(np.random.default_rng(9))
    b = ctrnn.random_params(np.random.default_rng(9))
    c = ctrnn.random_params(np.random.default_rng(10))
    ctrnn.validate_params(a)
    r = ctrnn.ParamRanges()
    for name, shape in ctrnn.PARAM_SHAPES.items():
        v = getattr(a, name)
        assert v.shape == shape and v.dtype == np.float64
        np.testing.assert_array_equal(v, getattr(b, name))
        lo, hi = {"w": r.weight, "b": r.bias, "t": r.tau, "g": r.gain}[name[0]]
        assert lo <= v.min() and v.max() <= hi
    assert not np.array_equal(a.w_sensor_motor, c.w_sensor_motor)
    with pytest.raises(ValueError, match="tau"):
        ctrnn.ParamRanges(tau=(0.0, 2.0))


@pytest.mark.parametrize("field", list(ctrnn.PARAM_SHAPES))
def test_validate_params_names_field_and_shape(field):
    shape = ctrnn.PARAM_SHAPES[field]
    bad = with_(ctrnn.zero_params(), **{field: np.zeros(shape[:-1] + (shape[-1] + 1,))})
    with pytest.raises(ValueError, match=rf"{field}.*{re_shape(shape)}"):
        ctrnn.validate_params(bad)
    with pytest.raises(ValueError, match=field):
        ReferenceNetwork(bad)
    nan = np.zeros(shape)
    nan.flat[0] = np.nan
    with pytest.raises(ValueError, match=rf"{field}.*non-finite"):
        ctrnn.validate_params(with_(ctrnn.zero_params(), **{field: nan}))
    inf = np.zeros(shape)
    inf.flat[-1] = -np.inf
    with pytest.raises(ValueError, match=rf"{field}.*non-finite"):
        ctrnn.validate_params(with_(ctrnn.zero_params(), **{field: inf}))


def re_shape(shape) -> str:
    return str(shape).replace("(", r"\(").replace(")", r"\)")


def test_validate_params_other_errors():
    with pytest.raises(ValueError, match=r"tau_motor.*\[0, 1\]"):
        ctrnn.validate_params(with_(ctrnn.zero_params(), tau_motor=np.full(N_MOTORS, 1.2)))
    with pytest.raises(ValueError, match=r"tau_hidden.*\[0, 1\]"):
        ctrnn.validate_params(with_(ctrnn.zero_params(), tau_hidden=np.full(N_HIDDEN, -0.1)))
    with pytest.raises(ValueError, match="gain_offset.*real"):
        ctrnn.validate_params(with_(ctrnn.zero_params(), gain_offset=np.array(["a", "b"])))
    with pytest.raises(ValueError, match=r"bias_motor.*\(14,\)"):
        ctrnn.validate_params(with_(ctrnn.zero_params(), bias_motor=None))
