"""Every two-group rule gated and held to its null where a two-mode group meets a narrow one, and
a rate's claim of no change judged on the rate's own scale.

- Each rule (``directional``, ``equivalent``, ``not_better``) against its null at 3 vs 7, 6 vs
  6 and 10 vs 10, with a two-mode group (babbling or still) against a narrow one at
  theta = 0.5: it decides against the claim's null at most ALPHA within Monte-Carlo error
  (``SHAPE_DATASETS`` data sets: seconds); the same rules without the gate fail at 3 vs 7, so
  the check can fail.
- ``not_better`` runs its permutation test once.
- The A1/A3 rule (``verdicts.paired_rate_equivalent``): a unit at 0 against a unit at 1/225
  is not a difference; the rule is the exact sign-flip test (scipy's ``permutation_test``)
  as two one-sided tests, and no paired rule of no change decides below 6 pairs, where the
  paired t-tests before it "contradicted" two-mode changes a quarter of the time at 3 pairs.
- Where the changes are lopsided (``verdicts.lopsided``) no paired rule of no change shows no
  change, though the sign-flip test alone would; a change shown still contradicts.
"""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest
from scipy.stats import permutation_test

from dart_reach.analysis import brunner_munzel
from dart_reach.analysis import calibration as cal
from dart_reach.analysis import paired_calibration as pcal
from dart_reach.analysis import verdict_core, verdicts as v

#: Data sets a (rule, sizes) cell; its bound: ALPHA + Z_MC Monte-Carlo s.e. (0.075 at 400).
SHAPE_DATASETS = 400
BOUND = v.ALPHA + cal.Z_MC * (v.ALPHA * (1 - v.ALPHA) / SHAPE_DATASETS) ** 0.5
SIZES = ((3, 7), (6, 6), (10, 10))
#: Each rule and what is an error under theta = 0.5 (its null of a contradiction, or for the
#: directional rule, of any decision).
RULES = {
    "directional": (lambda a, b: v.directional(a, b, +1), v.DECIDED),
    "equivalent": (v.equivalent, (v.CONTRADICTED,)),
    "not_better": (lambda a, b: v.not_better(a, b, +1), (v.CONTRADICTED,)),
}


def _two_mode_null(n_a: int, n_b: int, seed: int):
    """``SHAPE_DATASETS`` pairs (a, b) of replication means: a two-mode group of n_a against
    a narrow one of n_b at theta = 0.5 (``calibration.shaped``)."""
    rng = np.random.default_rng(seed)
    nest = cal.Nesting(n_a, 5, 1.0, cal.RUN_RATIOS[0])
    return [cal.shaped(rng, nest, cal.SHAPES[0], replications=n_b)
            for _ in range(SHAPE_DATASETS)]


def _error_rate(rule: str, data) -> float:
    judge, errors = RULES[rule]
    return float(np.mean([judge(a, b).verdict in errors for a, b in data]))


@pytest.mark.parametrize("rule", sorted(RULES))
@pytest.mark.parametrize("sizes", SIZES, ids=lambda s: f"{s[0]} vs {s[1]}")
def test_each_rule_holds_its_null_with_a_two_mode_group(rule, sizes):
    assert _error_rate(rule, _two_mode_null(*sizes, seed=sum(sizes))) <= BOUND


@pytest.mark.parametrize("rule", ["equivalent", "not_better"])
def test_without_the_gate_the_no_difference_rules_fail_at_3_vs_7(rule):
    """What the gate prevents (and proof that the check above can fail): with it switched off
    a two-mode group of 3 against 7 narrow units is 'contradicted' far above the bound."""
    data = _two_mode_null(3, 7, seed=10)
    with mock.patch.object(verdict_core, "one_mode", lambda n_a, n_b: 0.0):
        assert _error_rate(rule, data) > BOUND


@pytest.mark.parametrize("rule", sorted(RULES))
def test_every_two_group_rule_is_gated_below_6_a_group(rule):
    """Whatever the data (here complete separation, and two identical-looking groups), 3 vs 7
    and 5 vs 10 are underpowered, 6 vs 6 is not, and the note says why."""
    judge, _ = RULES[rule]
    rng = np.random.default_rng(3)
    # one mode 2^(1 - n) of the smaller group; Mann-Whitney's smallest p 2 / C(n_a + n_b, n_a)
    expected = {(3, 7): ("0.25", "0.0167"), (7, 3): ("0.25", "0.0167"),
                (5, 10): ("0.062", "0.000666")}
    for (n_a, n_b), (mode, smallest) in expected.items():
        for a, b in ((rng.normal(0, 1, n_a), rng.normal(10, 1, n_b)),
                     (rng.normal(0, 1, n_a), rng.normal(0, 1, n_b))):
            out = judge(a, b)
            assert out.verdict == v.UNDERPOWERED, (n_a, n_b, out)
            assert f"falls in one mode {mode} of the time" in out.note, out.note
            assert f"the smallest Mann-Whitney p possible is {smallest}" in out.note, out.note
    out = judge(rng.normal(0, 1, 6), rng.normal(10, 1, 6))
    assert out.verdict != v.UNDERPOWERED


def test_not_better_runs_its_permutation_test_once():
    rng = np.random.default_rng(4)
    a, b = rng.normal(0, 1, 10), rng.normal(0.2, 1, 10)
    with mock.patch.object(brunner_munzel, "test", wraps=brunner_munzel.test) as spy:
        out = v.not_better(a, b, +1)
    assert spy.call_count == 1
    one = brunner_munzel.test(a, b, "greater")
    assert out.p_against == pytest.approx(one.p, abs=1e-15)
    # complete separation, b worse: the p of non-superiority is the other one-sided p
    worse = v.not_better(a, a - 10, +1)
    assert worse.verdict == v.REPRODUCED
    assert worse.p == pytest.approx(brunner_munzel.test(a, a - 10, "less").p, abs=1e-15)


# ----------------------------------------------------------------------------- rates (A1, A3)
def test_a_unit_at_0_against_a_unit_at_1_in_225_is_no_difference():
    """Five still replications babble in 1 trial of 225 with the ball and in none without it,
    five babbling ones keep their rate: the relative change says -2 for each still one and
    decides a difference; on the rate's own scale it is a change of 0.0044, within the
    margin."""
    rng = np.random.default_rng(5)
    moving = rng.uniform(0.3, 0.7, 5)
    ref = np.concatenate([np.full(5, 1 / 225), moving])
    new = np.concatenate([np.zeros(5), moving + rng.normal(0, 0.01, 5)])
    assert v.paired_equivalent(ref, new, relative=True).verdict == v.CONTRADICTED
    out = v.paired_rate_equivalent(ref, new)
    assert out.verdict == v.REPRODUCED
    assert abs(out.effect) < 0.01 and out.p_against > v.ALPHA
    # one unit alone at 0 against 1/225, every other unchanged: never a difference
    one = v.paired_rate_equivalent(np.r_[1 / 225, moving], np.r_[0.0, moving])
    assert one.verdict != v.CONTRADICTED


def test_a_rate_that_rises_by_a_quarter_is_a_difference():
    """The check can fail the other way: babbling up by 0.25 without the ball in every
    replication (as at generation 250) is contradicted, not 'the same'."""
    rng = np.random.default_rng(6)
    ref = rng.uniform(0.0, 0.5, 10)
    out = v.paired_rate_equivalent(ref, ref + rng.normal(0.25, 0.05, 10))
    assert out.verdict == v.CONTRADICTED and out.effect == pytest.approx(0.25, abs=0.05)


def _flip_p(d, alternative):
    """scipy's exact sign-flip test of the sum of ``d`` (every one of the 2^n sign vectors)."""
    return permutation_test((np.asarray(d, float),), np.sum, permutation_type="samples",
                            alternative=alternative, n_resamples=np.inf).pvalue


@pytest.mark.parametrize("seed", range(5))
def test_the_rate_rule_is_scipys_exact_sign_flip_test(seed):
    """Both one-sided p (the changes less / plus the margin) and the two-tailed p of a
    difference are scipy's exact permutation test of the changes' signs; the interval's ends
    are the centres where the one-sided tests stop rejecting."""
    rng = np.random.default_rng(seed)
    ref = rng.uniform(0, 1, 10)
    new = np.clip(ref + rng.normal(0.03 * seed, 0.08, 10), 0, 1)
    d = new - ref
    out = v.paired_rate_equivalent(ref, new)
    p_eq = max(_flip_p(d - v.RATE_MARGIN, "less"), _flip_p(d + v.RATE_MARGIN, "greater"))
    assert out.p == pytest.approx(p_eq, rel=1e-12)
    assert out.p_against == pytest.approx(_flip_p(d, "two-sided"), rel=1e-12)
    assert out.effect == pytest.approx(np.mean(d), abs=1e-15)
    eps, level = 1e-9, v.PAIRED_EQUIVALENCE_LEVEL
    assert out.confidence == 1 - 2 * level
    assert _flip_p(d - (out.high + eps), "less") < level <= _flip_p(d - (out.high - eps), "less")
    assert _flip_p(d - (out.low - eps), "greater") < level <= _flip_p(d - (out.low + eps),
                                                                      "greater")


@pytest.mark.parametrize("pairs", [3, 4, 5])
def test_no_paired_rule_of_no_change_decides_below_6_pairs(pairs):
    """Two-mode changes all in one mode (the luck of 1 in 2^(n - 1) under no change) and
    changes at 0: underpowered whatever the data, the note giving the smallest p; the paired
    t TOST before decided both (a difference, and no change)."""
    rng = np.random.default_rng(pairs)
    ref = rng.uniform(0.3, 0.6, pairs)
    one_mode = ref + 0.15 + rng.normal(0, 0.005, pairs)
    same = ref + rng.normal(0, 0.005, pairs)
    for new in (one_mode, same):
        for out in (v.paired_rate_equivalent(ref, new),
                    v.paired_equivalent(ref, new, relative=True)):
            assert out.verdict == v.UNDERPOWERED, out
            assert f"{pairs} pairs: the smallest possible p" in out.note
    assert cal._t_tost(one_mode - ref, v.RATE_MARGIN) == v.CONTRADICTED
    assert cal._t_tost(same - ref, v.RATE_MARGIN) == v.REPRODUCED
    six = rng.uniform(0.3, 0.6, 6)
    assert v.paired_rate_equivalent(six, six + 0.15 + rng.normal(0, 0.005, 6)).verdict \
        == v.CONTRADICTED


def test_the_rate_rule_is_underpowered_or_no_evidence_where_it_should_be():
    assert v.paired_rate_equivalent([0.1, 0.2], [0.1, 0.2]).verdict == v.UNDERPOWERED
    assert v.paired_rate_equivalent(np.zeros(10), np.zeros(10)).verdict == v.INCONCLUSIVE


@pytest.mark.parametrize("n_a, n_b, smallest", [
    (6, 6, 4 / 924),     # both complete separations and the splits one pair short: 4 of C(12, 6)
    (7, 7, 4 / 3432),
    (6, 10, 6 / 8008),   # 6 of C(16, 6) splits tie at the top there
    (10, 10, 1 / 2000),  # Monte Carlo (184,756 splits): 1 / (1 + 1,999) at best
    (3, 7, 4 / 120),
])
def test_the_directional_rule_s_smallest_p_is_the_one_its_test_reaches(n_a, n_b, smallest):
    """The smallest p the sentences and tables quote is the one the directional rule's own
    test gives at complete separation (not 4 / C(n_a + n_b, n_a) where more splits tie, nor
    below the Monte Carlo floor), and complete separation at 6 vs 6 reaches it."""
    assert v.smallest_directional_p(n_a, n_b) == pytest.approx(smallest)
    if n_a >= 6 and n_b >= 6 and n_a + n_b <= 16:
        apart = v.directional(np.arange(n_a) * 1.0, np.arange(n_b) + 100.0, +1)
        assert apart.verdict == v.REPRODUCED and apart.p == pytest.approx(smallest)


# -------------------------------------------------------------------------- lopsided changes
#: Ten replications' changes: five unchanged, four up a little and one down (lopsided: of the
#: five that changed, one moved against the rest), in margins.
LOPSIDED = np.array([0, 0, 0, 0, 0, 0.1, 0.1, 0.1, 0.1, -0.5])


def test_lopsided_changes_cannot_show_no_change():
    """Five replications unchanged, four up a little and one down: the sign-flip test alone
    shows the change within the margin (p below the rule's level) and no difference; the
    gated rules refuse it (inconclusive, the note saying why, with the pairs and the smallest
    p), for a rate and a measure's relative change alike."""
    rng = np.random.default_rng(3)
    ref = rng.uniform(0.3, 0.6, 10)
    new = ref + LOPSIDED * v.RATE_MARGIN
    p_eq, p_diff, *_ = v.sign_flip_tost(new - ref, v.RATE_MARGIN)
    assert p_eq < v.PAIRED_EQUIVALENCE_LEVEL and p_diff >= v.ALPHA  # without the gate: same
    assert v.lopsided(new - ref) == "of 10 pairs 4 moved up, 1 down, 5 not at all"
    out = v.paired_rate_equivalent(ref, new)
    assert out.verdict == v.INCONCLUSIVE, out
    assert "lopsided" in out.note and "10 pairs" in out.note and "smallest possible p" in out.note
    assert out.p == pytest.approx(p_eq)  # the test's p kept beside the refusal
    c = LOPSIDED * v.PAIRED_MARGIN
    ref = np.full(10, 10.0)
    new = ref * (2 + c) / (2 - c)  # relative changes c
    assert v.sign_flip_tost(v.relative_changes(ref, new), v.PAIRED_MARGIN)[0] \
        < v.PAIRED_EQUIVALENCE_LEVEL
    assert v.paired_equivalent(ref, new, relative=True).verdict == v.INCONCLUSIVE


def test_lopsided_pairs_never_make_the_senses_the_same():
    """Four conditions alike in ten replications but for one, whose change from the first is
    lopsided (nine unchanged, one far): "senses differ" is not contradicted, though every
    pair's sign-flip TOST alone shows equivalence."""
    rng = np.random.default_rng(4)
    base = rng.uniform(9.0, 11.0, (10, 1)) + rng.normal(0.0, 0.05, (10, 4))
    x = base.copy()
    x[:, 3] = x[:, 0]
    x[0, 3] += 0.7  # a relative change of 0.07 of the level 10, within the margin
    pairs = [(i, j) for i in range(4) for j in range(i + 1, 4)]
    assert max(v.sign_flip_tost(x[:, j] - x[:, i], v.PAIRED_MARGIN * abs(np.median(x[:, i])))[0]
               for i, j in pairs) < v.PAIRED_EQUIVALENCE_LEVEL
    out = v.senses_differ(x)
    assert out.verdict != v.CONTRADICTED and "lopsided" in out.note, out


def test_symmetric_changes_pass_the_gate():
    """Changes of both signs about 0 (the symmetric shapes' power) are not lopsided, and a
    unit that did not change is not lopsided alone."""
    rng = np.random.default_rng(8)
    d = rng.normal(0.0, 0.05, 10)
    d[:3] = np.abs(d[:3]) * np.array([1, -1, 1])
    d[3:5] = -np.abs(d[3:5])
    assert not v.lopsided(d)
    assert not v.lopsided(np.zeros(10))


# ------------------------------------------------------------- skewed changes across 0
def test_skewed_changes_across_0_are_held_by_the_level_and_were_not_at_0_05():
    """Changes straddling 0 with a mean at the margin (the margin plus an exponential of 2
    margins less its mean: most replications moved a little either way, a few far up): the
    rule calls them no change at most ALPHA within Monte-Carlo error at 10 pairs; with its
    one-sided tests at 0.05 (the rule before) it did far more often (0.13 in the pilot), so
    the check can fail."""
    rng = np.random.default_rng(11)
    data = [pcal.straddling_rates(rng, 10, 2.0) for _ in range(SHAPE_DATASETS)]
    outs = [v.paired_rate_equivalent(a, b) for a, b in data]
    assert np.mean([o.verdict == v.REPRODUCED for o in outs]) <= BOUND
    before = [pcal.at_alpha(o, b - a) for o, (a, b) in zip(outs, data)]
    assert np.mean([x == v.REPRODUCED for x in before]) > BOUND


@pytest.mark.parametrize("pairs, expected", [(6, v.UNDERPOWERED), (7, v.UNDERPOWERED),
                                             (8, v.REPRODUCED)])
def test_no_change_is_shown_from_8_pairs(pairs, expected):
    """Changes far inside the margin, of both signs: below 8 pairs the smallest one-sided p
    (1/2^n: 1/64, 1/128) is not below the level 0.005 and the verdict is underpowered, the
    note saying why; from 8 (1/256) no change is shown; a change is shown from 6 pairs."""
    rng = np.random.default_rng(pairs)
    ref = rng.uniform(0.3, 0.6, pairs)
    d = rng.normal(0.0, 0.005, pairs)
    d[:2] = [0.004, -0.004]  # both signs: not lopsided
    out = v.paired_rate_equivalent(ref, ref + d)
    assert out.verdict == expected, out
    if expected == v.UNDERPOWERED:
        assert f"{pairs} pairs: no change cannot be shown" in out.note
    moved = v.paired_rate_equivalent(ref, ref + 0.3 + d)
    assert moved.verdict == v.CONTRADICTED
