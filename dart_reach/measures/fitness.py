"""The terms of a trial's fitness (paper section III-C, Eq. 5), taken apart.

Eq. 5 scores each step t by p_multimodal(t) = min(p_sight(t), p_touch(t)) and a trial by the
mean of p_multimodal over its T steps. Here (``model.kernels.sensing``) p_sight is the
closeness of the ball's image to the centre of the visual field, in [0, 1], 0 out of view;
p_touch is n / N, the fraction of the N = 16 inner faces of the hand's segments (the palm and
15 phalanges) touching the ball. A step scores only when the ball is both in sight and touched, so

    fitness = (share of steps scoring) x (mean p_multimodal over the steps that score)

and each factor is bounded by the one of its two terms that is smaller: the share by the
steps in sight and the steps in touch, the level by p_sight's and p_touch's levels on those
steps. ``fitness_terms`` gives every factor of one trial, with the touches that make the steps
in touch (how many, how long, how much of the time after the first one), so that what a
strategy earns per step can be read beside how often it earns it.

Pure functions of per-step arrays (row t = the state at t * dt, dt = 0.1 s): ``p_sight``,
``p_touch``, ``p_multimodal`` of shape (T,) (``TrialData``'s) and ``contacts`` (T, 16) bool,
the inner-face touches that p_touch counts (``TrialData.contacts``).
"""

from __future__ import annotations

import math

import numpy as np

from ..model.kernels.sensing import PAY_CODES, touch_pay
from ..model.levers import TouchPay
from .contacts import first_touch, touch_onsets
from .kinematics import DT

#: The keys of ``fitness_terms``, in order.
TERMS = ("fitness", "sight_share", "sight_level", "touch_share", "touch_level",
         "scoring_share", "scoring_level", "touch_limits", "touches", "contact_after_first",
         "contact_bout_s", "first_touch_s")


def _steps(name: str, a, dtype=float) -> np.ndarray:
    v = np.asarray(a, dtype=dtype)
    if v.ndim != 1:
        raise ValueError(f"{name} must be a (T,) array, got shape {v.shape}")
    return v


def _mean_where(values: np.ndarray, mask: np.ndarray) -> float:
    return float(values[mask].mean()) if mask.any() else math.nan


def contact_bouts(contacts) -> np.ndarray:
    """The lengths (in steps) of the trial's runs of consecutive steps in which at least one
    inner face touches the ball, in order; an int array, empty without a touch."""
    touching = np.asarray(contacts, dtype=bool).any(axis=1)
    edges = np.diff(np.concatenate([[0], touching.astype(np.int8), [0]]))
    return np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)


def contact_after_first(contacts) -> float:
    """The share of the steps from the first touch to the trial's end (both included) in
    which the hand touches the ball (any inner face): near 1 for a hand that stays on the
    ball, small for one that hits it and moves on. NaN without a touch."""
    c = np.asarray(contacts, dtype=bool)
    k = first_touch(c)
    return float(c[k:].any(axis=1).mean()) if k >= 0 else math.nan


def fitness_terms(p_sight, p_touch, p_multimodal, contacts, dt: float = DT) -> dict[str, float]:
    """Eq. 5's fitness of one trial and its factors (section III-C).

    - ``fitness``: mean p_multimodal over the T steps (the trial's fitness, Eq. 5);
    - ``sight_share``, ``sight_level``: the share of steps with the ball in sight
      (p_sight > 0) and the mean p_sight over them (NaN when never in sight);
    - ``touch_share``, ``touch_level``: the same for the steps in touch (p_touch > 0: at least
      one inner face on the ball) and p_touch; ``touch_level`` x 16 is the mean number of
      inner faces touching;
    - ``scoring_share``, ``scoring_level``: the share of steps with p_multimodal > 0 (in sight
      and in touch at once) and the mean p_multimodal over them, so that ``fitness`` =
      ``scoring_share`` x ``scoring_level`` (0 x NaN = 0 when no step scores);
    - ``touch_limits``: the share of the scoring steps on which p_touch is the smaller term
      (p_touch < p_sight: touch, not sight, sets the step's score; NaN when no step scores);
    - ``touches``: how many times a touch begins (``contacts.touch_onsets``);
      ``contact_after_first``: the share of the steps from the first touch on that touch;
      ``contact_bout_s``: the mean length (s) of an unbroken touch (NaN without one);
      ``first_touch_s``: when the first touch begins (s; NaN without one).

    ``p_sight``, ``p_touch``, ``p_multimodal``: (T,) per step; ``contacts``: (T, 16) bool, the
    inner-face touches p_touch counts. T = 0 gives NaN for every share and level.
    """
    s, t, m = (_steps(n, a) for n, a in (("p_sight", p_sight), ("p_touch", p_touch),
                                         ("p_multimodal", p_multimodal)))
    c = np.asarray(contacts, dtype=bool)
    if c.ndim != 2 or c.shape[0] != len(s) or not len(s) == len(t) == len(m):
        raise ValueError(f"p_sight {s.shape}, p_touch {t.shape}, p_multimodal {m.shape} and "
                         f"contacts {c.shape} must have the same number of steps")
    if len(s) == 0:
        return dict.fromkeys(TERMS, math.nan) | {"touches": 0.0}
    sight, touch, scoring = s > 0, t > 0, m > 0
    bouts = contact_bouts(c)
    k = first_touch(c)
    return {
        "fitness": float(m.mean()),
        "sight_share": float(sight.mean()), "sight_level": _mean_where(s, sight),
        "touch_share": float(touch.mean()), "touch_level": _mean_where(t, touch),
        "scoring_share": float(scoring.mean()), "scoring_level": _mean_where(m, scoring),
        "touch_limits": _mean_where((t < s).astype(float), scoring),
        "touches": float(len(touch_onsets(c))),
        "contact_after_first": contact_after_first(c),
        "contact_bout_s": float(bouts.mean()) * dt if len(bouts) else math.nan,
        "first_touch_s": k * dt if k >= 0 else math.nan,
    }


def trial_fitness_terms(data, dt: float = DT) -> dict[str, float]:
    """``fitness_terms`` of a ``task.TrialData`` over the steps it ran; a diverged trial's
    fitness is 0 (``TrialData.fitness``), its other terms those of the steps it ran."""
    n = int(data.steps_run)
    terms = fitness_terms(data.p_sight[:n], data.p_touch[:n], data.p_multimodal[:n],
                          data.contacts[:n], dt)
    if data.diverged:
        terms["fitness"] = 0.0
    return terms


def fitness_under_touch_pays(data) -> dict[str, float]:
    """A trial's fitness (Eq. 5) scored again under each ``levers.TouchPay``: the mean over
    its steps of min(p_sight, p_touch) with p_touch counted as the lever says from the trial's
    inner-face touches (n of 16 per step), keyed ``fitness_<pay>`` ('-' as '_'); 0 for a
    diverged trial. Under the pay the trial ran with, it is the trial's fitness to the last
    bit. A screen of the touch lever without training (docs/model/levers.md)."""
    steps = len(data.p_sight)
    counts, segments = data.contacts.sum(axis=1).tolist(), data.contacts.shape[1]
    out = {}
    for pay in TouchPay:
        code = PAY_CODES[pay]
        p = np.zeros(steps)
        for t in range(int(data.steps_run)):
            p[t] = min(float(data.p_sight[t]), touch_pay(counts[t], segments, code))
        out[f"fitness_{pay.value.replace('-', '_')}"] = 0.0 if data.diverged else float(p.mean())
    return out
