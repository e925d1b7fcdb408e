"""The verdict rules against their definitions: the exact distributions and tests agree with
scipy's (the Brunner-Munzel test's: tests/analysis/test_brunner_munzel.py), Holm with
statsmodels', every rule gives each of its verdicts on data made to show it, and zero spread
is never evidence."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats as sps
from statsmodels.stats.multitest import multipletests

from dart_reach.analysis import stats, verdicts as v


def test_wilcoxon_equals_scipy_exact_and_approximate():
    rng = np.random.default_rng(2)
    for trial in range(200):
        d = rng.normal(0.3, 1, int(rng.integers(3, 15)))
        if trial % 2:
            d = np.round(d * 2) / 2
        nonzero = d[d != 0]
        if not len(nonzero):
            continue
        tied = len(np.unique(np.abs(nonzero))) < len(nonzero)
        for alternative in ("two-sided", "greater", "less"):
            ref = sps.wilcoxon(nonzero, alternative=alternative,
                               method="approx" if tied else "exact").pvalue
            assert v.wilcoxon(d, alternative)[0] == pytest.approx(ref, abs=1e-12)


def test_friedman_and_t_equal_scipy():
    rng = np.random.default_rng(3)
    for trial in range(100):
        x = rng.normal(size=(int(rng.integers(3, 12)), 4))
        if trial % 2:
            x = np.round(x)
        if np.ptp(x) == 0:
            continue
        ref = sps.friedmanchisquare(*x.T)
        assert v.friedman(x) == pytest.approx((ref.statistic, ref.pvalue), abs=1e-10)
    for df in (1.5, 3, 9, 40):
        assert v.t_quantile(0.975, df) == pytest.approx(sps.t.ppf(0.975, df), rel=1e-12)
        assert v.t_cdf(-1.3, df) == pytest.approx(sps.t.cdf(-1.3, df), rel=1e-12)


def test_the_exact_distributions_are_the_textbook_ones():
    """P(U = 0) = 1 / C(n + m, n); P(T+ = 0) = 2^-n; both symmetric and summing to 1."""
    for n, m in ((4, 4), (10, 10), (3, 7)):
        d = v.u_distribution(n, m)
        assert d[0] == pytest.approx(1 / math.comb(n + m, n))
        assert d.sum() == pytest.approx(1) and np.allclose(d, d[::-1])
    for n in (4, 10):
        d = v.signed_rank_distribution(n)
        assert d[0] == pytest.approx(2.0 ** -n) and np.allclose(d, d[::-1])


def test_holm_equals_statsmodels_and_keeps_nan():
    rng = np.random.default_rng(4)
    p = rng.uniform(0, 0.2, 30)
    assert np.allclose(stats.holm_adjusted(p), multipletests(p, method="holm")[1])
    with_nan = np.r_[p[:5], np.nan, p[5:10]]
    adjusted = stats.holm_adjusted(with_nan)
    assert math.isnan(adjusted[5])
    assert np.allclose(np.delete(adjusted, 5), multipletests(np.r_[p[:5], p[5:10]],
                                                             method="holm")[1])


def test_hodges_lehmann_interval_is_the_exact_one():
    """At 4 vs 4 the 95 % interval is the range of the 16 differences (P(U = 0) = 1/70 <=
    0.025 < P(U <= 1) = 2/70); at 2 vs 2 it is unbounded."""
    a, b = np.array([0.0, 1, 2, 3]), np.array([10.0, 11, 12, 14])
    shift, low, high = v.hodges_lehmann(a, b)
    d = b[None, :] - a[:, None]
    assert (low, high) == (d.min(), d.max()) and shift == np.median(d)
    assert v.hodges_lehmann([0.0, 1], [2.0, 3])[1:] == (-math.inf, math.inf)


def test_directional_gives_every_verdict():
    rng = np.random.default_rng(5)
    a = rng.normal(0, 1, 10)
    assert v.directional(a, a + 5, +1).verdict == v.REPRODUCED
    assert v.directional(a, a - 5, +1).verdict == v.CONTRADICTED
    assert v.directional(a, rng.normal(0, 1, 10), +1).verdict == v.INCONCLUSIVE
    assert v.directional(a[:3], a[:3] + 5, +1).verdict == v.UNDERPOWERED  # 4 / 20 = 0.2
    # 4 / 70 = 0.057; and a two-mode group of 5 falls in one mode 1 / 16 of the time
    assert v.directional(a[:4], a[:4] + 5, +1).verdict == v.UNDERPOWERED
    assert "one mode" in v.directional(a[:5], a[:5] + 5, +1).note
    assert v.directional(a[:6], a[:6] + 5, +1).verdict == v.REPRODUCED
    assert v.directional(np.ones(6), np.ones(6), +1).verdict == v.INCONCLUSIVE


def test_equivalence_and_non_superiority_give_every_verdict():
    rng = np.random.default_rng(6)
    a = rng.normal(0, 1, 60)
    assert v.equivalent(a, a + rng.normal(0, 0.01, 60)).verdict == v.REPRODUCED
    assert v.equivalent(a, a + 3).verdict == v.CONTRADICTED
    assert v.equivalent(a[:10], rng.normal(0, 1, 10)).verdict == v.UNDERPOWERED
    assert v.equivalent(np.ones(30), np.ones(30)).verdict == v.INCONCLUSIVE
    # "not better": b worse is evidence; b better contradicts; lower-is-better flips it
    assert v.not_better(a[:10], a[:10] - 3, +1).verdict == v.REPRODUCED
    assert v.not_better(a[:10], a[:10] + 3, +1).verdict == v.CONTRADICTED
    assert v.not_better(a[:10], a[:10] + 3, -1).verdict == v.REPRODUCED
    assert v.not_better(a[:10], a[:10] + rng.normal(0, 0.1, 10), +1).verdict \
        == v.INCONCLUSIVE


def test_interval_rules_give_every_verdict_and_never_count_zero_spread():
    rng = np.random.default_rng(7)
    band = (1 / 3, 2 / 3)
    assert v.in_band(rng.normal(0.5, 0.02, 10), band).verdict == v.REPRODUCED
    assert v.in_band(rng.normal(0.9, 0.02, 10), band).verdict == v.CONTRADICTED
    assert v.in_band(rng.normal(0.6, 0.3, 10), band).verdict == v.INCONCLUSIVE
    assert v.in_band([0.5, 0.5], band).verdict == v.UNDERPOWERED
    assert v.in_band([0.5] * 10, band).verdict == v.INCONCLUSIVE  # zero spread: no evidence
    cells = {k: rng.normal(0.6, 0.05, 10) for k in range(18)}
    assert v.at_least(cells, 0.1).verdict == v.REPRODUCED
    assert v.at_least({**cells, 3: rng.normal(0.02, 0.01, 10)}, 0.1).verdict \
        == v.CONTRADICTED
    assert v.at_least({**cells, 3: np.full(10, 0.9)}, 0.1).verdict == v.INCONCLUSIVE


def test_the_rules_on_rates_decide_from_their_gates_at_their_levels():
    """The band decides from ``BAND_MIN_UNITS`` replications, by an interval at
    1 - 2 ``BAND_LEVEL``; the paired change from the pairs whose smallest p is below
    ``PAIRED_CHANGE_LEVEL`` (7), "senses differ" from the blocks whose is below
    ``FRIEDMAN_LEVEL`` (4 of 4 conditions); every sector's bound at 1 - ``SECTOR_LEVEL``."""
    band, inside = (1 / 3, 2 / 3), np.linspace(0.45, 0.55, v.BAND_MIN_UNITS)
    assert v.in_band(inside[:-1], band).verdict == v.UNDERPOWERED
    out = v.in_band(inside, band)
    assert out.verdict == v.REPRODUCED and out.confidence == pytest.approx(1 - 2 * v.BAND_LEVEL)
    half = v.t_quantile(1 - v.BAND_LEVEL, len(inside) - 1) * inside.std(ddof=1) / np.sqrt(
        len(inside))
    assert (out.low, out.high) == pytest.approx((0.5 - half, 0.5 + half))
    up = np.arange(1.0, 8.0)
    assert v.paired_directional(np.zeros(6), up[:6], +1).verdict == v.UNDERPOWERED
    assert v.paired_directional(np.zeros(7), up, +1).verdict == v.REPRODUCED
    assert v.paired_directional(np.zeros(7), up, +1).confidence == pytest.approx(
        1 - v.PAIRED_CHANGE_LEVEL)
    ordered = np.tile(np.arange(4.0), (4, 1))
    assert v.senses_differ(ordered[:3]).verdict == v.UNDERPOWERED
    assert v.senses_differ(ordered).verdict == v.REPRODUCED
    cell = np.array([0.14, 0.16, 0.18, 0.20, 0.22])  # lower bound between the two levels' floors
    lower = {lv: v.mean_interval(cell, 1 - 2 * lv)[1] for lv in (v.SECTOR_LEVEL, v.ALPHA)}
    floor = (lower[v.SECTOR_LEVEL] + lower[v.ALPHA]) / 2
    assert v.at_least({0: cell}, floor).verdict == v.INCONCLUSIVE
    assert v.at_least({0: cell}, floor, level=v.ALPHA).verdict == v.REPRODUCED


def test_paired_rules_give_every_verdict():
    rng = np.random.default_rng(8)
    ref = rng.normal(10, 1, 10)
    assert v.paired_directional(ref, ref + rng.normal(2, 0.5, 10), +1).verdict == v.REPRODUCED
    assert v.paired_directional(ref, ref - rng.normal(2, 0.5, 10), +1).verdict \
        == v.CONTRADICTED
    assert v.paired_directional(ref[:4], ref[:4] + 2, +1).verdict == v.UNDERPOWERED
    assert v.paired_directional(ref, ref, +1).verdict == v.INCONCLUSIVE
    assert v.paired_equivalent(ref, ref + rng.normal(0, 0.1, 10)).verdict == v.REPRODUCED
    assert v.paired_equivalent(ref, ref + rng.normal(5, 0.1, 10)).verdict == v.CONTRADICTED
    assert v.paired_equivalent(ref, ref + 0.1).verdict == v.INCONCLUSIVE  # zero spread


def test_senses_differ_gives_every_verdict():
    rng = np.random.default_rng(9)
    blocks = rng.normal(10, 1, (10, 1))
    assert v.senses_differ(blocks + np.arange(4) + rng.normal(0, 0.1, (10, 4))).verdict \
        == v.REPRODUCED
    assert v.senses_differ(blocks + rng.normal(0, 0.05, (10, 4))).verdict == v.CONTRADICTED
    assert v.senses_differ(blocks + rng.normal(0, 3, (10, 4))).verdict == v.INCONCLUSIVE
    assert v.senses_differ(blocks[:2] + np.arange(4)).verdict == v.UNDERPOWERED


def test_no_change_relative_to_each_replications_own_level():
    """Two strategies, still (near 0) and babbling (near 1): each replication changing by
    about 30 % of its own level is a change; by about 2 % it is the same."""
    rng = np.random.default_rng(9)
    ref = np.r_[rng.uniform(0.01, 0.02, 5), rng.uniform(0.9, 1.1, 5)]
    new = ref * rng.uniform(1.25, 1.35, 10)
    d = v.relative_changes(ref, new)
    assert np.allclose(d, (new - ref) / ((new + ref) / 2))
    assert v.relative_changes([0.0], [0.0])[0] == 0.0
    assert v.paired_equivalent(ref, new, relative=True).verdict == v.CONTRADICTED
    same = ref * rng.uniform(0.98, 1.02, 10)
    assert v.paired_equivalent(ref, same, relative=True).verdict == v.REPRODUCED
