"""Measures of a trial's touches (paper sections IV-A-2, IV-A-3; Table I).

Pure functions of per-step arrays (row t = the state at t * dt, dt = 0.1 s): ``contacts`` is
(T, 16) bool per hand segment (``icub.HAND_SEGMENTS``: the palm, column 0, then the 15
phalanges), either the inner-face touches (``TrialData.contacts``: the touch sensors, p_touch,
grasp) or the any-face touches (``TrialData.contacts_any``: the paper's reach). Thresholds are
module constants fixed before any data was looked at (docs/model/measures.md).

- reach and grasp (section IV-A): ``first_touch``, ``reached``, ``first_grasp``, ``grasped``;
- ``touch_onsets``: the steps at which a touch begins (a swipe's hit, a new attempt);
- ``anticipatory_grasp`` (Table I, fine-reaching: "anticipatory grasp" [54]): the fingers
  close before the palm touches;
- ``upward_swipes`` (IV-A-2: gross-reachers "bring their arm on the lower part of the target
  area while orienting their palm up and then produce long swipes up").
"""

from __future__ import annotations

import math

import numpy as np

from .kinematics import DT, points

#: Column of the palm in the contact arrays.
PALM = 0
#: s before the first palm touch in which finger closing counts as anticipation.
ANTICIPATION_WINDOW = 1.0
#: rad of mean finger flexion (6 % of the hand's [0, pi/2] range) the fingers must have closed
#: within the window for the grasp to be anticipatory.
FLEXION_RISE = 0.1
#: A palm faces up when its inner normal's vertical component is at least cos 45 deg.
PALM_UP = math.cos(math.radians(45.0))
#: m/s, the least upward speed of the palm point over the step that ends at a touch for the
#: touch to be an upward swipe.
SWIPE_SPEED = 0.05


def _contacts(contacts) -> np.ndarray:
    c = np.asarray(contacts, dtype=bool)
    if c.ndim != 2:
        raise ValueError(f"contacts must be a (T, segments) array, got shape {c.shape}")
    return c


def _first(mask: np.ndarray) -> int:
    return int(np.argmax(mask)) if mask.any() else -1


def first_touch(contacts) -> int:
    """Index of the first step at which any hand segment touches the ball, -1 if none.

    ``contacts``: (T, 16) bool, columns in ``icub.HAND_SEGMENTS`` order. Multiply by dt for
    seconds. Section IV-A: "reach" = touch the object at least once with the hand.
    """
    return _first(_contacts(contacts).any(axis=1))


def reached(contacts) -> bool:
    """True when the hand touches the ball at least once (section IV-A-1, Fig. 5 top-right)."""
    return first_touch(contacts) >= 0


def _grasp_steps(contacts) -> np.ndarray:
    c = _contacts(contacts)
    if c.shape[1] < 2:
        raise ValueError(f"contacts need the palm and finger columns, got shape {c.shape}")
    return c[:, PALM] & c[:, PALM + 1:].any(axis=1)


def first_grasp(contacts) -> int:
    """Index of the first step at which the palm (column 0) and at least one finger segment
    (columns 1..15) touch the ball at the same time, -1 if never (section IV-A-2: grasp =
    "touch the object with the palm and at least one of the fingers")."""
    return _first(_grasp_steps(contacts))


def grasped(contacts) -> bool:
    """True when the trial has at least one grasp step (see ``first_grasp``; Fig. 5 top-left)."""
    return first_grasp(contacts) >= 0


def touch_onsets(contacts) -> np.ndarray:
    """Rows at which the hand starts touching the ball (no segment touched at the row before;
    row 0 counts when the hand touches already), as an int array."""
    touching = _contacts(contacts).any(axis=1)
    before = np.concatenate([[False], touching[:-1]])
    return np.flatnonzero(touching & ~before)


def first_palm_touch(contacts) -> int:
    """First row at which the palm (column 0) touches the ball, -1 if never."""
    palm = _contacts(contacts)[:, PALM]
    return int(np.argmax(palm)) if palm.any() else -1


def anticipatory_grasp(flexion, contacts, dt: float = DT, window: float = ANTICIPATION_WINDOW,
                       rise: float = FLEXION_RISE) -> tuple[float, float]:
    """Whether the fingers were closing before the palm first touched the ball, and by how
    long (Table I, fine-reaching: "anticipatory grasp"; the issue: "onset of finger flexion
    before the first palm touch").

    ``flexion``: (T,) mean finger flexion (rad; ``TrialData.joints[:, 13]``); ``contacts``:
    inner-face touches (the palm's sensor is what triggers the grasp reflex). At the first
    palm touch (row k) the fingers' state is still the one the reflex has not acted on yet.
    Anticipatory when the flexion at row k exceeds its lowest value over the ``window`` s
    before (rows k - window/dt .. k) by at least ``rise`` rad. Returns (1.0 or 0.0, lead in s:
    time from the latest lowest point, the onset of the closing, to the touch; NaN when not
    anticipatory), or (NaN, NaN) when the palm never touches.
    """
    f = np.asarray(flexion, dtype=float)
    k = first_palm_touch(contacts)
    if k < 0:
        return math.nan, math.nan
    lo = max(0, k - int(round(window / dt)))
    segment = f[lo:k + 1]
    onset = k - int(np.argmin(segment[::-1]))  # the latest lowest point: the closing's start
    if f[k] - f[onset] >= rise:
        return 1.0, (k - onset) * dt
    return 0.0, math.nan


def upward_swipes(hand, ball, palm_normal, contacts, dt: float = DT) -> tuple[float, float]:
    """Palm-up upward swipes (IV-A-2): touches that begin (``touch_onsets`` of ``contacts``,
    any face) with the palm point below the ball's centre, the palm's normal up (vertical
    component >= ``PALM_UP``) and the palm point rising faster than ``SWIPE_SPEED`` over the
    step that ends at the touch. Returns (whether the first touch is one: 1.0 or 0.0, NaN
    without a touch or without the palm's normal; how many of the trial's touch onsets are
    swipes: NaN without the palm's normal). A touch at row 0 has no step before it and is
    not a swipe."""
    if palm_normal is None:
        return math.nan, math.nan
    h, b = points(hand, "hand"), points(ball, "ball")
    onsets = touch_onsets(contacts)
    if len(onsets) == 0:
        return math.nan, 0
    n = points(palm_normal, "palm_normal")
    k = onsets[onsets > 0]
    swipe = ((h[k, 2] < b[k, 2]) & (n[k, 2] >= PALM_UP)
             & ((h[k, 2] - h[k - 1, 2]) / dt > SWIPE_SPEED))
    first = float(swipe[0]) if len(k) and k[0] == onsets[0] else 0.0
    return first, float(swipe.sum())
