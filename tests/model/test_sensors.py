"""Sensor encodings and fitness terms (paper section III-B, Eqs. 1-4; III-C, Eq. 5): version
1's frozen ones (``model.reference.sensors``), and the living model's image and touch pay
(``kernels.sensing.project``, ``kernels.sensing.touch_pay``) against them.

Expected values are worked out by hand in the comments; tan(56 deg) = 1.482561, tan(47 deg) =
1.072369.
"""

import math

import numpy as np
import pytest

from dart_reach.model.reference import sensors

TAN56 = 1.4825609685127403
TAN47 = 1.0723687100246826


# ------------------------------------------------------------------------------- proprioception
def test_proprioception_scales_limits_to_unit_range():
    lower = np.array([-1.0, 0.0, -0.6, -1.0, -1.0])
    upper = np.array([1.0, 1.0, 0.2, 1.0, 1.0])
    q = np.array([0.0, 0.25, 0.0, 1.0, -1.0])
    # 2 (q - lo) / (hi - lo) - 1:
    # [0 -> 2*1/2-1 = 0, 0.25 -> 2*0.25/1-1 = -0.5, 0 -> 2*0.6/0.8-1 = 0.5, hi -> 1, lo -> -1]
    np.testing.assert_allclose(sensors.proprioception(q, lower, upper),
                               [0.0, -0.5, 0.5, 1.0, -1.0], atol=1e-15)


def test_proprioception_clips_beyond_limits_and_fills_out():
    lower, upper = np.array([-1.0, -1.0]), np.array([1.0, 1.0])
    buf = np.full(5, 7.0)
    out = sensors.proprioception([2.0, -3.0], lower, upper, out=buf[1:3])
    assert out.base is buf
    np.testing.assert_array_equal(buf, [7.0, 1.0, -1.0, 7.0, 7.0])
    # the precomputed span gives the same answer
    np.testing.assert_array_equal(
        sensors.proprioception([0.5, -0.5], lower, upper, span=upper - lower), [0.5, -0.5])


# ------------------------------------------------------------------------------------- touch
def test_touch_is_plus_one_when_touching_minus_one_otherwise():
    out = np.zeros(6)
    r = sensors.touch(np.array([True, False, False, True, False, False]), out=out)
    assert r is out
    np.testing.assert_array_equal(out, [1.0, -1.0, -1.0, 1.0, -1.0, -1.0])
    assert sensors.NO_TOUCH == -1.0
    np.testing.assert_array_equal(sensors.touch(np.zeros(6, bool)), np.full(6, sensors.NO_TOUCH))


# ------------------------------------------------------------------------------------ camera
def test_project_centre_and_a_point_by_hand():
    assert sensors.project([0.0, 0.0, 1.0]) == (0.0, 0.0, True)
    # (0.5, 0.5, 2): x/z = 0.25 -> c_x = 0.25 / 1.482561 = 0.168627;
    # y/z = 0.25 (down) -> c_y = -0.25 / 1.072369 = -0.233129
    cx, cy, vis = sensors.project(np.array([0.5, 0.5, 2.0]))
    assert cx == pytest.approx(0.1686271292, rel=1e-9)
    assert cy == pytest.approx(-0.2331287715, rel=1e-9)
    assert vis is True


def test_project_field_of_view_edges():
    # just inside the right / top edges: x/z = 0.999 tan 56 -> c_x = 0.999; -y/z = 0.999 tan 47
    cx, cy, vis = sensors.project([0.999 * TAN56, -0.999 * TAN47, 1.0])
    assert (cx, cy) == (pytest.approx(0.999), pytest.approx(0.999)) and vis
    # just outside: 1.001 -> not in view, coordinates kept
    cx, _, vis = sensors.project([1.001 * TAN56, 0.0, 1.0])
    assert cx == pytest.approx(1.001) and not vis
    _, cy, vis = sensors.project([0.0, 1.001 * TAN47, 1.0])  # below the bottom edge
    assert cy == pytest.approx(-1.001) and not vis
    # the FOV is 112 x 94 deg: a point 55 deg to the left is in view, 57 deg is not
    assert sensors.project([-math.tan(math.radians(55.0)), 0.0, 1.0])[2]
    assert not sensors.project([-math.tan(math.radians(57.0)), 0.0, 1.0])[2]
    assert sensors.project([0.0, -math.tan(math.radians(46.0)), 1.0])[2]
    assert not sensors.project([0.0, -math.tan(math.radians(48.0)), 1.0])[2]


def test_project_behind_or_on_the_image_plane_is_out_of_view():
    assert sensors.project([0.0, 0.0, -1.0]) == (0.0, 0.0, False)
    assert sensors.project([0.1, 0.1, -0.5]) == (0.0, 0.0, False)
    assert sensors.project([0.1, 0.0, 0.0]) == (0.0, 0.0, False)


def test_visual_angles_by_hand():
    # (1, 0, 1): atan2(1, 1) = 45 deg to the right, on the horizon
    assert sensors.visual_angles([1.0, 0.0, 1.0]) == (pytest.approx(45.0), pytest.approx(0.0))
    # (0, -1, 1): y up is negative -> elevation atan2(1, 1) = +45
    assert sensors.visual_angles([0.0, -1.0, 1.0]) == (pytest.approx(0.0), pytest.approx(45.0))
    # (-sqrt 3, 1, 1): azimuth atan2(-sqrt 3, 1) = -60, elevation atan2(-1, 1) = -45
    az, el = sensors.visual_angles([-math.sqrt(3.0), 1.0, 1.0])
    assert (az, el) == (pytest.approx(-60.0), pytest.approx(-45.0))
    # behind the camera: azimuth beyond 90
    assert sensors.visual_angles([1.0, 0.0, -1.0])[0] == pytest.approx(135.0)


# ------------------------------------------------------------------------------------- sight
def test_sight_full_acuity_by_hand():
    # a = 1: x1 = c_x = 0.5, x2 = c_y = -0.25; l = 0.2 m -> x3 = 1 - 0.4 = 0.6
    out = np.zeros(3)
    assert sensors.sight(0.5, -0.25, 0.2, True, 1.0, out=out) is out
    np.testing.assert_allclose(out, [0.5, -0.25, 0.6], rtol=0, atol=1e-15)


def test_sight_low_acuity_by_hand():
    # a = 3: x1 = 0.5^3 = 0.125, x2 = -(0.5^3) = -0.125, x3 = 1 - 2 * 0.1 = 0.8
    np.testing.assert_allclose(sensors.sight(0.5, -0.5, 0.1, True, 3.0), [0.125, -0.125, 0.8],
                               atol=1e-15)
    # a = 3 flattens the centre: |x| < |c| for 0 < |c| < 1; the edges stay at +-1; 0 stays 0
    np.testing.assert_allclose(sensors.sight(-1.0, 1.0, 0.3, True, 3.0)[:2], [-1.0, 1.0])
    np.testing.assert_array_equal(sensors.sight(0.0, -0.0, 0.3, True, 3.0)[:2], [0.0, 0.0])
    low = sensors.sight(0.2, 0.2, 0.3, True, 3.0)
    high = sensors.sight(0.2, 0.2, 0.3, True, 1.0)
    assert low[0] == pytest.approx(0.008) and high[0] == pytest.approx(0.2)


def test_sight_distance_boundary():
    x3 = lambda l: sensors.sight(0.0, 0.0, l, True, 1.0)[2]  # noqa: E731
    assert x3(0.0) == 1.0  # touching the camera
    assert x3(0.25) == 0.5  # 1 - 2 * 0.25
    assert x3(0.4999) == pytest.approx(0.0002)  # 1 - 0.9998
    assert x3(0.5) == 0.0  # l < 0.5 is false at 0.5: Eq. 3's "otherwise"
    assert x3(3.0) == 0.0


def test_sight_out_of_view_reads_nothing():
    assert sensors.NO_SIGHT == 0.0
    out = np.full(3, 9.0)
    sensors.sight(0.5, 0.5, 0.2, False, 1.0, out=out)
    np.testing.assert_array_equal(out, [sensors.NO_SIGHT] * 3)


# ------------------------------------------------------------------------------------ offset
def test_offset_by_hand():
    # ball at (12, -3) deg, hand at (5, 4) deg: d = (7, -7) deg -> 0.1 * d = (0.7, -0.7)
    out = np.zeros(2)
    assert sensors.offset((12.0, -3.0), (5.0, 4.0), True, out=out) is out
    np.testing.assert_allclose(out, [0.7, -0.7], atol=1e-15)


def test_offset_clamps_at_d_max():
    # exactly +-d_max = +-10 deg -> +-1; beyond -> clamped to +-1
    np.testing.assert_allclose(sensors.offset((10.0, -10.0), (0.0, 0.0), True), [1.0, -1.0])
    np.testing.assert_allclose(sensors.offset((40.0, -3.0), (0.0, 30.0), True), [1.0, -1.0])
    # other d_max and z: d = (4, -8), clamp 5 -> (4, -5), times 0.2 -> (0.8, -1.0)
    np.testing.assert_allclose(sensors.offset((4.0, -8.0), (0.0, 0.0), True, d_max=5.0, z=0.2),
                               [0.8, -1.0])
    assert sensors.OFFSET_D_MAX_DEG * sensors.OFFSET_SCALE == pytest.approx(1.0)


def test_offset_reads_nothing_unless_both_in_view():
    out = np.full(2, 9.0)
    sensors.offset((7.0, 3.0), (0.0, 0.0), False, out=out)
    np.testing.assert_array_equal(out, [sensors.NO_SIGHT] * 2)


# ----------------------------------------------------------------------------- fitness terms
def test_p_sight_by_hand():
    assert sensors.p_sight(0.0, 0.0, True) == 1.0
    # hypot(0.3, 0.4) = 0.5 -> 1 - 0.5 / sqrt 2 = 0.646447
    assert sensors.p_sight(0.3, -0.4, True) == pytest.approx(0.6464466094)
    # edge of the image on an axis: 1 - 1 / sqrt 2 = 0.292893
    assert sensors.p_sight(-1.0, 0.0, True) == pytest.approx(0.2928932188)
    assert sensors.p_sight(1.0, 1.0, True) == pytest.approx(0.0, abs=1e-15)  # corner
    assert sensors.p_sight(0.0, 0.0, False) == 0.0
    assert sensors.p_sight(2.0, 2.0, True) == 0.0  # never negative


def test_p_touch_and_p_multimodal():
    assert sensors.p_touch(0, 16) == 0.0
    assert sensors.p_touch(3, 16) == 0.1875  # 3 / 16
    assert sensors.p_touch(16, 16) == 1.0
    with pytest.raises(ValueError):
        sensors.p_touch(17, 16)
    with pytest.raises(ValueError):
        sensors.p_touch(-1, 16)
    with pytest.raises(ValueError):
        sensors.p_touch(0, 0)
    assert sensors.p_multimodal(0.3, 0.5) == 0.3
    assert sensors.p_multimodal(p_sight=0.9, p_touch=0.0) == 0.0


# ------------------------------------------------------------------------- ranges (random)
def test_every_encoding_stays_in_unit_range_for_random_inputs():
    rng = np.random.default_rng(20130)
    lower = rng.uniform(-2.0, 0.0, 14)
    upper = lower + rng.uniform(0.1, 3.0, 14)
    x = np.zeros(25)
    for _ in range(2000):
        sensors.proprioception(rng.uniform(-4.0, 4.0, 14), lower, upper, out=x[0:14])
        sensors.touch(rng.random(6) < 0.5, out=x[14:20])
        ball = rng.uniform([-2.0, -2.0, -1.0], [2.0, 2.0, 2.0])
        hand = rng.uniform([-2.0, -2.0, -1.0], [2.0, 2.0, 2.0])
        cx, cy, vis = sensors.project(ball)
        sensors.sight(cx, cy, float(np.linalg.norm(ball)), vis, rng.choice([1.0, 3.0]),
                      out=x[20:23])
        sensors.offset(sensors.visual_angles(ball), sensors.visual_angles(hand),
                       vis and sensors.project(hand)[2], out=x[23:25])
        assert np.isfinite(x).all()
        assert (np.abs(x) <= 1.0).all()
        assert 0.0 <= sensors.p_sight(cx, cy, vis) <= 1.0
        n = int(rng.integers(0, 17))
        assert 0.0 <= sensors.p_multimodal(sensors.p_sight(cx, cy, vis),
                                           sensors.p_touch(n, 16)) <= 1.0


def test_the_living_models_image_and_touch_pay_are_version_1s_to_the_last_bit():
    from dart_reach.model.kernels import sensing
    from dart_reach.model.levers import TouchPay

    rng = np.random.default_rng(7)
    points = np.vstack([rng.normal(size=(500, 3)), [[0.0, 0.0, 0.0], [0.1, 0.0, -0.0],
                                                     [TAN56, -TAN47, 1.0]]])
    for p in points.tolist():
        assert sensing.project(*p) == sensors.project(p)
    for pay in TouchPay:
        code, reference_pay = sensing.PAY_CODES[pay], sensors.p_touch_of(pay)
        assert [sensing.touch_pay(n, 16, code) for n in range(17)] == \
            [reference_pay(n, 16) for n in range(17)]
