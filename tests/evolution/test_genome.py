"""The genotype: 8 bits per parameter, linear decoding, parameter groups (sections III-C, III-D)."""

from __future__ import annotations

import numpy as np
import pytest

from dart_reach.evolution import genome as G
from dart_reach.model.ctrnn import N_HIDDEN, N_MOTORS, N_SENSORS, NetworkParams
from dart_reach.evolution.genome import ALL_GROUPS, ParamGroup

PRE = {ParamGroup.DIRECT}
GROSS = {ParamGroup.DIRECT, ParamGroup.HIDDEN}
FINE = set(ParamGroup)

HIDDEN_FIELDS = ("w_sensor_hidden", "w_hidden_motor", "bias_hidden", "tau_hidden")
DIRECT_FIELDS = ("w_sensor_motor", "bias_motor", "tau_motor")


def test_layout_covers_network_params_contiguously():
    assert G.n_genes() == G.N_GENES == 716  # 350 + 200 + 112 + 8 + 14 + 8 + 14 + 8 + 2
    start = 0
    for f in G.LAYOUT:
        assert f.start == start and f.size == int(np.prod(f.shape))
        start = f.stop
    assert start == G.N_GENES
    assert tuple(f.name for f in G.LAYOUT) == tuple(NetworkParams.__dataclass_fields__)
    assert G.field("w_sensor_motor").shape == (N_MOTORS, N_SENSORS)
    assert G.field("w_sensor_hidden").shape == (N_HIDDEN, N_SENSORS)
    assert G.field("gain_offset").shape == (2,)
    with pytest.raises(ValueError, match="unknown parameter field"):
        G.field("nope")


def test_ranges():
    for f in G.LAYOUT:
        if f.name.startswith(("w_", "bias_")):
            assert (f.lo, f.hi) == (-5.0, 5.0)
        else:
            assert (f.lo, f.hi) == (0.0, 1.0)


@pytest.mark.parametrize("code", [0, 255, 128])
def test_decode_hand_made_codes(code):
    p = G.decode(np.full(G.N_GENES, code, np.uint8), ALL_GROUPS)
    # by hand: weights/biases -5 + 10 k / 255, tau and gains k / 255
    wb = {0: -5.0, 255: 5.0, 128: 5.0 / 255.0}[code]
    unit = {0: 0.0, 255: 1.0, 128: 128.0 / 255.0}[code]
    for name in ("w_sensor_motor", "w_sensor_hidden", "w_hidden_motor", "bias_hidden",
                 "bias_motor"):
        v = getattr(p, name)
        assert v.dtype == np.float64
        np.testing.assert_allclose(v, wb, rtol=0, atol=1e-15)
    for name in ("tau_hidden", "tau_motor", "gain_hidden", "gain_offset"):
        np.testing.assert_allclose(getattr(p, name), unit, rtol=0, atol=1e-15)
    if code in (0, 255):  # the ends of the ranges are exact
        assert np.all(p.w_sensor_motor == wb) and np.all(p.tau_motor == unit)


def test_decode_places_each_gene_in_c_order():
    g = np.zeros(G.N_GENES, np.uint8)
    sl = G.field_slice("w_sensor_motor")
    g[sl.start + 2 * N_SENSORS + 3] = 200  # [post=2, pre=3]
    g[G.field_slice("tau_hidden").start + 5] = 51
    p = G.decode(g, ALL_GROUPS)
    assert p.w_sensor_motor[2, 3] == pytest.approx(-5 + 10 * 200 / 255, abs=1e-14)
    assert np.count_nonzero(p.w_sensor_motor != -5.0) == 1
    assert p.tau_hidden[5] == pytest.approx(0.2, abs=1e-15)


def test_encode_decode_round_trip_is_exact_on_the_grid():
    rng = np.random.default_rng(3)
    for _ in range(5):
        codes = G.random_genome(rng)
        params = G.decode(codes, ALL_GROUPS)
        back = G.encode(params)
        np.testing.assert_array_equal(back, codes)
        again = G.decode(back, ALL_GROUPS)
        for name in NetworkParams.__dataclass_fields__:
            assert np.array_equal(getattr(again, name), getattr(params, name))


def test_encode_rejects_out_of_range_and_nearest_code():
    p = G.decode(np.zeros(G.N_GENES, np.uint8), ALL_GROUPS)
    bad = NetworkParams(**{**p.__dict__, "tau_motor": np.full(N_MOTORS, 1.5)})
    with pytest.raises(ValueError, match="tau_motor"):
        G.encode(bad)
    assert G.encode_values(0.0, -5, 5) == 128  # halfway between 127 and 128: the even code
    assert G.encode_values(0.9 / 255, 0, 1) == 1


@pytest.mark.parametrize("free", [PRE, GROSS, FINE, {ParamGroup.HIDDEN}])
def test_frozen_groups_decode_to_fixed_values_whatever_their_bits(free):
    rng = np.random.default_rng(11)
    for _ in range(3):
        g = G.random_genome(rng)
        p = G.decode(g, free)
        full = G.decode(g, ALL_GROUPS)
        for f in G.LAYOUT:
            v = getattr(p, f.name)
            if f.group in free:
                assert np.array_equal(v, getattr(full, f.name)), f.name
            else:
                assert np.all(v == f.fixed), f.name
    p = G.decode(G.random_genome(rng), PRE)
    for name in HIDDEN_FIELDS:
        assert np.all(getattr(p, name) == 0.0)
    assert np.all(p.gain_hidden == 1.0) and np.all(p.gain_offset == 1.0)


def test_group_names_are_accepted():
    g = G.random_genome(np.random.default_rng(0))
    a, b = G.decode(g, ["direct", "hidden"]), G.decode(g, GROSS)
    assert np.array_equal(a.w_hidden_motor, b.w_hidden_motor)
    with pytest.raises(ValueError, match="unknown parameter group 'hiden'"):
        G.free_mask(["hiden"])


def test_free_mask_sizes_per_phase():
    assert G.free_mask(PRE).sum() == 350 + 14 + 14
    assert G.free_mask(GROSS).sum() == 378 + 200 + 112 + 8 + 8
    assert G.free_mask(FINE).sum() == G.N_GENES
    m = G.free_mask(PRE)
    for name in DIRECT_FIELDS:
        assert m[G.field_slice(name)].all()
    for name in HIDDEN_FIELDS + ("gain_hidden", "gain_offset"):
        assert not m[G.field_slice(name)].any()


def test_release_sets_freed_genes_near_their_fixed_value():
    rng = np.random.default_rng(5)
    pop = G.random_genome(rng, 4)
    out = G.release(pop, {ParamGroup.HIDDEN})
    assert out.shape == pop.shape and pop is not out
    hidden = G.free_mask({ParamGroup.HIDDEN})
    assert np.array_equal(out[:, ~hidden], pop[:, ~hidden])  # everything else untouched
    p = G.decode(out[0], GROSS)
    step = 10.0 / 255.0
    for name in ("w_sensor_hidden", "w_hidden_motor", "bias_hidden"):
        v = getattr(p, name)
        assert np.all(np.abs(v) <= step / 2 + 1e-15), name  # residual 5/255
        assert np.all(v == p.w_sensor_hidden.flat[0])
    assert np.all(p.tau_hidden == 0.0)
    p = G.decode(G.release(out[1], {ParamGroup.HIDDEN_GAIN, ParamGroup.OFFSET_GAIN}), FINE)
    assert np.all(p.gain_hidden == 1.0) and np.all(p.gain_offset == 1.0)
    # releasing then decoding with the group free gives (nearly) what the frozen decode gave
    q = G.decode(out[2], PRE)
    r = G.decode(out[2], GROSS)
    np.testing.assert_allclose(r.w_hidden_motor, q.w_hidden_motor, atol=5 / 255 + 1e-15)


def test_random_genome_and_checks():
    a = G.random_genome(np.random.default_rng(1), 3)
    b = G.random_genome(np.random.default_rng(1), 3)
    assert a.dtype == np.uint8 and a.shape == (3, G.N_GENES) and np.array_equal(a, b)
    assert G.random_genome(np.random.default_rng(1)).shape == (G.N_GENES,)
    with pytest.raises(TypeError, match="Generator"):
        G.random_genome(np.random.RandomState(0))
    with pytest.raises(TypeError, match="uint8"):
        G.decode(np.zeros(G.N_GENES), PRE)
    with pytest.raises(ValueError, match="shape"):
        G.decode(np.zeros(10, np.uint8), PRE)
