"""The factors of Eq. 5's fitness (``measures.fitness``) against small trials worked by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dart_reach.measures import fitness


def contacts(*rows: int) -> np.ndarray:
    """(T, 16) inner-face touches: row t has its first ``rows[t]`` segments touching."""
    c = np.zeros((len(rows), 16), bool)
    for t, n in enumerate(rows):
        c[t, :n] = True
    return c


def trial(p_sight, touching):
    """A trial's arrays as the model computes them: p_touch = n / 16, p_multimodal = min."""
    s = np.asarray(p_sight, float)
    c = contacts(*touching)
    t = c.sum(axis=1) / 16
    return s, t, np.minimum(s, t), c


def test_a_trial_worked_by_hand():
    # 6 steps: in sight on 4 (levels .5 .5 .2 .4), touched on 3 (1, 4 and 2 faces of 16),
    # two touches (steps 1-2, then step 4); steps 1, 2 and 4 score min(.5, 1/16),
    # min(.2, 4/16) = .2, min(.4, 2/16).
    terms = fitness.fitness_terms(*trial([0, .5, .2, 0, .4, .5], [0, 1, 4, 0, 2, 0]), dt=0.1)
    assert terms["sight_share"] == pytest.approx(4 / 6)
    assert terms["sight_level"] == pytest.approx((.5 + .2 + .4 + .5) / 4)
    assert terms["touch_share"] == pytest.approx(3 / 6)
    assert terms["touch_level"] == pytest.approx((1 + 4 + 2) / 16 / 3)
    assert terms["scoring_share"] == pytest.approx(3 / 6)
    assert terms["scoring_level"] == pytest.approx((1 / 16 + .2 + 2 / 16) / 3)
    assert terms["fitness"] == pytest.approx((1 / 16 + .2 + 2 / 16) / 6)
    assert terms["fitness"] == pytest.approx(terms["scoring_share"] * terms["scoring_level"])
    assert terms["touch_limits"] == pytest.approx(2 / 3)  # steps 1 and 4: touch is the min
    assert terms["touches"] == 2
    assert terms["contact_after_first"] == pytest.approx(3 / 5)  # steps 1-5, touching 1, 2, 4
    assert terms["contact_bout_s"] == pytest.approx((0.2 + 0.1) / 2)
    assert terms["first_touch_s"] == pytest.approx(0.1)
    assert list(terms) == list(fitness.TERMS)


def test_a_hand_resting_on_the_ball_out_of_sight_scores_nothing():
    terms = fitness.fitness_terms(*trial([0, 0, 0, 0], [0, 3, 3, 3]))
    assert terms["fitness"] == 0 and terms["scoring_share"] == 0
    assert math.isnan(terms["scoring_level"]) and math.isnan(terms["touch_limits"])
    assert math.isnan(terms["sight_level"]) and terms["sight_share"] == 0
    assert terms["touch_share"] == pytest.approx(3 / 4)
    assert terms["touches"] == 1 and terms["contact_after_first"] == 1.0
    assert terms["contact_bout_s"] == pytest.approx(0.3)


def test_no_touch_and_no_steps():
    terms = fitness.fitness_terms(*trial([.3, .3], [0, 0]))
    assert terms["touches"] == 0 and terms["touch_share"] == 0
    assert math.isnan(terms["touch_level"]) and math.isnan(terms["contact_after_first"])
    assert math.isnan(terms["contact_bout_s"]) and math.isnan(terms["first_touch_s"])
    assert terms["sight_level"] == pytest.approx(.3)
    empty = fitness.fitness_terms(np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 16)))
    assert empty["touches"] == 0 and math.isnan(empty["fitness"])


def test_bouts_and_contact_after_the_first_touch():
    c = contacts(1, 1, 0, 0, 2, 0, 1, 1, 1)
    assert fitness.contact_bouts(c).tolist() == [2, 1, 3]
    assert fitness.contact_after_first(c) == pytest.approx(6 / 9)
    assert fitness.contact_after_first(contacts(0, 0, 5, 5)) == 1.0
    assert fitness.contact_bouts(contacts(0, 0)).tolist() == []


def test_arrays_of_different_lengths_are_refused():
    s, t, m, c = trial([.1, .2], [1, 1])
    with pytest.raises(ValueError, match="same number of steps"):
        fitness.fitness_terms(s, t, m, c[:1])
    with pytest.raises(ValueError, match=r"p_sight must be a \(T,\) array"):
        fitness.fitness_terms(s[:, None], t, m, c)


def test_a_diverged_trial_scores_zero():
    class Data:
        p_sight, p_touch, p_multimodal, contacts = trial([.5, .5, .5], [4, 4, 0])
        steps_run, diverged = 2, True
    terms = fitness.trial_fitness_terms(Data())
    assert terms["fitness"] == 0.0
    assert terms["scoring_share"] == 1.0  # of the 2 steps it ran
    Data.diverged = False
    assert fitness.trial_fitness_terms(Data())["fitness"] == pytest.approx(.25)
