"""The studentized permutation Brunner-Munzel test against scipy: its statistic is
``scipy.stats.brunnermunzel``'s, its exact p ``scipy.stats.permutation_test``'s over every
split, its Monte Carlo p the same for the same data; and the directional verdict and its
interval always agree, ties included."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy import stats as sps

from dart_reach.analysis import brunner_munzel as bm
from dart_reach.analysis import verdicts as v


def _samples(rng, trials=120, low=2, high=12):
    for trial in range(trials):
        n, m = (int(x) for x in rng.integers(low, high, 2))
        a, b = rng.normal(size=n), rng.normal(size=m) * rng.uniform(0.3, 3) + rng.normal()
        if trial % 2:  # ties
            a, b = np.round(a), np.round(b)
        yield a, b


def test_the_statistic_is_brunner_munzels_on_the_logit_scale():
    """T = logit(theta) theta (1 - theta) / se (theta's logit over its delta-method s.e.),
    se scipy's Brunner-Munzel one ((theta - 0.5) / its statistic)."""
    rng = np.random.default_rng(1)
    for a, b in _samples(rng):
        res = bm.test(a, b)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # scipy warns where the variances are 0
            ref = sps.brunnermunzel(a, b)
        theta = res.theta
        if np.isfinite(ref.statistic) and ref.statistic != 0 and 0 < theta < 1:
            se = (theta - 0.5) / ref.statistic
            if se > bm.smallest_se(len(a), len(b)):
                expected = np.log(theta / (1 - theta)) * theta * (1 - theta) / se
                assert res.statistic == pytest.approx(expected, rel=1e-9)
        assert res.theta == pytest.approx(
            np.mean((b[None, :] > a[:, None]) + 0.5 * (b[None, :] == a[:, None])), abs=1e-12)


def _abs_statistic(x, y, axis=-1):
    """|T| from scipy's Brunner-Munzel statistic: se = (theta - 0.5) / its statistic, floored
    at ``smallest_se``; theta clipped 1 / (n_a n_b) inside (0, 1)."""
    n, m = x.shape[axis], y.shape[axis]
    theta = ((y[..., None, :] > x[..., :, None])
             + 0.5 * (y[..., None, :] == x[..., :, None])).mean(axis=(-1, -2))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        se = (theta - 0.5) / sps.brunnermunzel(x, y, axis=axis).statistic
    se = np.maximum(np.nan_to_num(se, nan=0.0), bm.smallest_se(n, m))
    c = np.clip(theta, 1 / (n * m), 1 - 1 / (n * m))
    return np.abs(np.log(c / (1 - c)) * c * (1 - c) / se)


def test_the_exact_p_is_scipys_permutation_test():
    """Every split (C(n_a + n_b, n_b) <= EXACT_SPLITS): the share with |T| at least the
    observed one, as scipy.stats.permutation_test gives it over every split."""
    rng = np.random.default_rng(2)
    for a, b in _samples(rng, trials=30, low=3, high=6):
        ref = sps.permutation_test((a, b), _abs_statistic, permutation_type="independent",
                                   vectorized=True, alternative="greater",
                                   n_resamples=np.inf).pvalue
        res = bm.test(a, b)
        assert res.exact and res.p == pytest.approx(ref, abs=1e-12)


def test_one_sided_p_and_monte_carlo():
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=10), rng.normal(2.0, 2.0, 10)
    two, up, down = (bm.test(a, b, alt) for alt in ("two-sided", "greater", "less"))
    assert not two.exact and two.splits == bm.PERMUTATIONS + 1
    assert up.p < 0.05 < down.p and up.p + down.p >= 1.0
    assert bm.test(a, b).p == two.p  # the same splits: the same p
    assert 1 / two.splits <= two.p <= 1.0


def test_complete_separation_ties_one_pair_short_of_it():
    """Complete separation (se 0) has a finite statistic, equal to that of one pair swapped:
    the four splits tie at the top, p = 4 / C(n_a + n_b, n_a); its interval is not a point."""
    sep = bm.test([0.0, 1, 2, 3, 4, 5], [6.0, 7, 8, 9, 10, 11])
    swap = bm.test([0.0, 1, 2, 3, 4, 6], [5.0, 7, 8, 9, 10, 11])
    assert np.isfinite(sep.statistic) and sep.statistic == pytest.approx(swap.statistic)
    assert sep.p == swap.p == pytest.approx(4 / 924)
    assert sep.theta == 1.0 and 0.5 < sep.low < sep.high < 1.0
    tied = bm.test([0.0] * 4, [1.0] * 4)  # separated, no spread at all: still no point
    assert tied.theta == 1.0 and tied.low < tied.high
    same = bm.test([1.0, 1, 1], [1.0, 1, 1])
    assert same.p == 1.0 and same.low <= 0.5 <= same.high


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="at least 2"):
        bm.test([1.0], [1.0, 2.0])
    with pytest.raises(ValueError, match="alternative"):
        bm.test([1.0, 2], [1.0, 2.0], "both")
    with pytest.raises(ValueError, match="confidence"):
        bm.test([1.0, 2], [1.0, 2.0], confidence=1.5)


def test_the_verdict_and_its_interval_agree():
    """Decided exactly when theta's interval leaves 0.5 out, at 6 and 10 units (the fewest
    the rule decides at, and the paper's) and with ties (a zero-inflated group against a
    continuous one)."""
    rng = np.random.default_rng(4)
    seen = set()
    for trial in range(400):
        n = (6, 10)[trial % 2]
        a = np.where(rng.random(n) < 0.4, 0.0, rng.normal(1.0, 0.5, n))
        b = rng.normal(rng.uniform(-1, 2), rng.uniform(0.2, 2), n)
        if trial % 4 == 1:
            b = np.round(b, 1)
        out = v.directional(a, b, +1)
        seen.add(out.verdict)
        decided = out.verdict in v.DECIDED
        assert decided == (not out.low <= 0.5 <= out.high), (a, b, out)
    assert {v.REPRODUCED, v.CONTRADICTED, v.INCONCLUSIVE} <= seen


def test_the_probabilistic_index_is_scipys_brunner_munzel():
    """theta, its standard error and degrees of freedom, the ones the verdicts use on theta's
    own scale, are the observed split of the permutation test's and scipy's: its statistic is
    (theta - 0.5) / se, its t p-value over the same degrees of freedom."""
    rng = np.random.default_rng(2)
    for a, b in _samples(rng):
        theta, se, df = bm.probabilistic_index(a, b)
        res = bm.test(a, b)
        assert theta == pytest.approx(res.theta, abs=1e-12)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ref = sps.brunnermunzel(a, b)
        if se == 0:
            assert not np.isfinite(ref.statistic) or theta in (0.0, 1.0)
            continue
        assert (theta - 0.5) / se == pytest.approx(ref.statistic, rel=1e-9, abs=1e-12)
        p = 2 * sps.t.sf(abs(theta - 0.5) / se, df)
        assert p == pytest.approx(ref.pvalue, rel=1e-7, abs=1e-12)
    assert bm.probabilistic_index([1.0], [2.0, 3.0])[0] == 1.0
