"""The babbling detector (``measures.kinematics``) against the synthetic paths of known label
(``measures.babbling_synthetic``; docs/model/measures.md, "Validating the detector"): what it
must find and what it must never call babbling, family by family, so that a change of the
rule that loses either fails here."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from dart_reach.measures import babbling_synthetic as bs
from dart_reach.measures import kinematics as k


def _called(paths) -> Counter:
    out = Counter()
    for p in paths:
        f, s = k.hand_periodicity(p.hand)
        out[p.family] += k.is_babbling(f, s, k.hand_amplitude(p.hand))
    return out


#: Paths a family: enough for the rates to be stable to a few per cent (~1 s).
N = 200


@pytest.fixture(scope="module")
def labelled():
    return bs.labelled_set(per_family=N, seed=7)


def test_the_set_is_what_the_protocol_says(labelled):
    assert {p.family for p in labelled} == set(bs.FAMILIES)
    assert all(p.hand.shape == (bs.STEPS, 3) and np.isfinite(p.hand).all() for p in labelled)
    assert all(p.babbling == (p.family in bs.BABBLING_FAMILIES) for p in labelled)
    interrupted = [p for p in labelled if p.family.endswith("interrupted")]
    # an interrupted path holds still somewhere for at least 0.5 s (5 rows)
    held = [np.any(np.convolve((np.linalg.norm(np.diff(p.hand, axis=0), axis=1) < 0.03)
                               .astype(float), np.ones(5), "valid") == 5) for p in interrupted]
    assert np.mean(held) > 0.9
    with pytest.raises(ValueError, match="unknown family"):
        bs.path("flail", np.random.default_rng(0))


def test_still_paths_are_almost_never_called_babbling(labelled):
    """No hand at rest, reach and hold, drift, small circles or slow sweeps is called
    babbling; smooth random wandering of babbling size now and then (at most 1 in 10)."""
    called = _called(labelled)
    assert {f: called[f] for f in bs.STILL_FAMILIES if f != "wander"} == {
        f: 0 for f in bs.STILL_FAMILIES if f != "wander"}
    assert called["wander"] <= 0.1 * N


def test_steady_babbling_is_found_and_interruptions_cost_less_than_two_fifths(labelled):
    """Steady circles and sweeps: at least 90 % found (the misses are narrow sweeps whose RMS
    falls under 5 cm); interrupted by stops at the ball: at least 60 % (what the rule
    measurably loses there, docs/results/babbling-detector.md)."""
    called, n = _called(labelled), N
    for family in ("circle", "sweep"):
        assert called[family] >= 0.9 * n, (family, called[family])
    for family in ("circle, interrupted", "sweep, interrupted"):
        assert called[family] >= 0.6 * n, (family, called[family])


def test_a_detector_that_only_looks_at_size_fails_here(labelled):
    """The set can fail a rule: calling every large movement babbling (no rhythm test) calls
    the still families' random wandering and slow sweeps babbling."""
    wrong = Counter(p.family for p in labelled if not p.babbling
                    and k.hand_amplitude(p.hand) >= k.BABBLING_AMPLITUDE)
    assert wrong["wander"] > 0.8 * N and wrong["slow sweeps"] > 0.5 * N


def test_moving_is_path_and_amplitude():
    assert k.is_moving(1.0, 0.05) and not k.is_moving(0.99, 0.2)
    assert not k.is_moving(5.0, 0.049) and not k.is_moving(float("nan"), 0.1)
