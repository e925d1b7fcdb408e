"""Kinematic measures of the hand in one trial (paper sections IV-A, V; Figs. 5, 6, 8; Table I).

Pure functions of per-step arrays (row t = the state at t * dt, dt = 0.1 s, section III-B):
``hand`` and ``ball`` are (T, 3) positions in metres (the palm point and the ball's centre),
``end`` is the row of the first touch (``contacts.first_touch``; -1 when the ball is never
touched). Speeds are in m/s, times in s, lengths in m. Every threshold is a module constant,
fixed before any data was looked at and documented with its reason in docs/model/measures.md.

- the reach's path: ``path_length``, ``step_speeds``, ``movement_onset``, ``reaching_speed``,
  ``peak_speed``, ``final_approach``, ``final_speed``, ``straightness``,
  ``straightness_onset``, ``movement_units`` (smoothness: speed peaks before the touch);
- arm orienting (Table I, pre-reaching): ``approach``, ``heading``;
- motor babbling (IV-A-1: "large quasi-periodic circular movements"): ``hand_periodicity``,
  ``hand_amplitude``, ``is_babbling``; the same before the first touch (the candidate for the
  ball-absent claim A1): ``before_touch``, ``babbling_before_touch``; beside rhythm, the
  movement's amount and size: ``is_moving``.
"""

from __future__ import annotations

import math

import numpy as np

#: Control step (s) of section III-B.
DT = 0.1
#: m/s: the hand moves when its speed over a step exceeds this (movement onset, the floor of
#: a movement unit's peak). 10 % of an infant's ~0.5 m/s peak reaching speed; a hand held by
#: the springs at the home posture moves at ~0.
ONSET_SPEED = 0.05
#: m per step: the hand must move more than this toward the ball in a step (0.01 m/s) for the
#: step to belong to the final approach (``final_approach``).
APPROACH_STEP = 0.001
#: m/s: a speed peak counts as a movement unit when it stands this far above the lowest speed
#: on each side (before the previous peak, after the next one; von Hofsten 1991's units).
UNIT_PROMINENCE = 0.05
#: Motor babbling: at least this share of the detrended hand path's power in its dominant
#: rhythm (3 bins), ...
BABBLING_SHARE = 0.4
#: ... a rhythm of at least this frequency (Hz; 5 cycles in a 20 s trial), ...
BABBLING_MIN_HZ = 0.25
#: ... and a movement at least this large (m, RMS of the detrended hand path: the radius of a
#: circle; 5 cm, a circle wider than the 7 cm ball).
BABBLING_AMPLITUDE = 0.05
#: A trial is *moving* when the hand's path is at least this long (m: a mean speed of
#: ``ONSET_SPEED`` over the 20 s trial) and its amplitude at least ``BABBLING_AMPLITUDE``.
MOVING_PATH = 1.0
#: RMS (m) of the detrended hand path below which the hand counts as at rest.
REST_TOLERANCE = 1e-9
#: s: the shortest window of ``babbling_before_touch`` (2.5 cycles of the slowest rhythm the
#: rule accepts, a spectrum of 0.1 Hz bins); fixed before the second validation sample.
BEFORE_TOUCH_MIN_S = 10.0


def points(p, name: str = "points") -> np.ndarray:
    """``p`` as a (T, 3) float array, or ValueError naming it."""
    a = np.asarray(p, dtype=float)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must be a (T, 3) array, got shape {a.shape}")
    return a


def path_length(p) -> float:
    """Length (m) of the polyline through the (T, 3) points (m); 0 for fewer than 2 points."""
    a = points(p)
    if len(a) < 2:
        return 0.0
    return float(np.linalg.norm(np.diff(a, axis=0), axis=1).sum())


def step_speeds(hand, dt: float = DT) -> np.ndarray:
    """(T - 1,) mean hand speed (m/s) over each step: |h[t+1] - h[t]| / dt."""
    return np.linalg.norm(np.diff(points(hand, "hand"), axis=0), axis=1) / dt


def movement_onset(hand, end: int | None = None, dt: float = DT,
                   threshold: float = ONSET_SPEED) -> int:
    """Row at which the hand starts moving: the first t (< ``end`` when given) whose step
    t -> t + 1 is faster than ``threshold`` m/s; -1 when it never does."""
    v = step_speeds(hand, dt)
    if end is not None:
        v = v[:max(end, 0)]
    moving = v > threshold
    return int(np.argmax(moving)) if moving.any() else -1


def reaching_speed(hand, end: int, dt: float = DT) -> float:
    """Mean hand speed (m/s) from the start of the trial to the first touch (row ``end``):
    the path over rows 0..end divided by end * dt (Fig. 5, bottom-left). NaN when ``end`` <= 0
    (no touch, or a touch at row 0: no movement to time)."""
    if end <= 0:
        return math.nan
    return path_length(points(hand, "hand")[:end + 1]) / (end * dt)


def peak_speed(hand, end: int, dt: float = DT) -> float:
    """Highest step speed (m/s) of the hand before the first touch (steps 0..end - 1). NaN
    when ``end`` <= 0."""
    if end <= 0:
        return math.nan
    return float(step_speeds(points(hand, "hand")[:end + 1], dt).max())


def _toward(h: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(T - 1,) each step's hand displacement (m) along the direction to the ball's centre,
    the direction taken from the step's midpoint (hand and ball)."""
    step = np.diff(h, axis=0)
    to_ball = (b[:-1] + b[1:] - h[:-1] - h[1:]) / 2
    norm = np.linalg.norm(to_ball, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norm > 0, (step * to_ball).sum(axis=1) / norm, 0.0)


def final_approach(hand, ball, end: int) -> int:
    """First row of the final movement toward the ball: the longest run of steps ending at
    the first touch (row ``end``) in each of which the hand moves more than ``APPROACH_STEP``
    toward the ball's centre (its displacement along the direction to the ball). Returns
    ``end`` when the last step before the touch does not approach (the ball swung into a hand
    that was still or moving past), -1 when ``end`` < 0."""
    if end < 0:
        return -1
    h, b = points(hand, "hand")[:end + 1], points(ball, "ball")[:end + 1]
    closer = _toward(h, b) > APPROACH_STEP
    start = end
    while start > 0 and closer[start - 1]:
        start -= 1
    return start


def final_speed(hand, ball, end: int, dt: float = DT) -> float:
    """Mean hand speed (m/s) over the final approach (``final_approach`` .. ``end``): the
    speed of "the final movement toward the ball", not diluted by time spent still or
    babbling before it. NaN without a touch or without an approaching step."""
    start = final_approach(hand, ball, end)
    if start < 0 or start == end:
        return math.nan
    return path_length(points(hand, "hand")[start:end + 1]) / ((end - start) * dt)


def straightness(hand, ball, end: int, radius: float = 0.0) -> float:
    """Reaching straightness (Fig. 5 caption: "the ratio between the hand/object initial
    distance and the length of the trajectory of the hand during successfully reaching
    actions"): (|hand[0] - ball[0]| - ``radius``) over the hand's path over rows 0..end.

    ``radius`` = the ball's radius (m) measures the initial distance to the ball's surface,
    where the reach ends; 0 measures it to the centre (the earlier definition, biased
    up by radius / path). NaN without a touch or with a path of zero length."""
    if end < 0:
        return math.nan
    h, b = points(hand, "hand"), points(ball, "ball")
    length = path_length(h[:end + 1])
    if length <= 0.0:
        return math.nan
    return (float(np.linalg.norm(h[0] - b[0])) - radius) / length


def straightness_onset(hand, end: int, dt: float = DT) -> float:
    """Straightness of the hand's own path from movement onset to the first touch: the
    displacement |hand[end] - hand[onset]| over the path length between them, in (0, 1]
    (the index of [12], [27]; independent of the ball's size and of where on the hand the
    touch happens). NaN without a touch or when the hand did not move before it."""
    if end <= 0:
        return math.nan
    h = points(hand, "hand")
    onset = movement_onset(h, end, dt)
    if onset < 0:
        return math.nan
    length = path_length(h[onset:end + 1])
    return float(np.linalg.norm(h[end] - h[onset])) / length if length > 0 else math.nan


def movement_units(hand, end: int, dt: float = DT, prominence: float = UNIT_PROMINENCE) -> float:
    """Smoothness of a reach (Table I, fine-reaching: "smoother ... reach"; [27]): the number
    of movement units, i.e. peaks of the hand's step speed with a prominence of at least
    ``prominence`` m/s, from movement onset to the first touch (row ``end``). The speed is
    taken as 0 before the onset and at the touch, so a single smooth reach has 1 unit and a
    reach made of corrective sub-movements more. NaN without a touch or a movement."""
    if end <= 0:
        return math.nan
    h = points(hand, "hand")[:end + 1]
    onset = movement_onset(h, end, dt)
    if onset < 0:
        return math.nan
    from scipy.signal import find_peaks  # here: scipy.signal is 0.6 s of every process's start

    v = np.concatenate([[0.0], step_speeds(h, dt)[onset:], [0.0]])
    return float(len(find_peaks(v, prominence=prominence)[0]))


# ---------------------------------------------------------------------------------- orienting
def approach(hand, ball, end: int = -1) -> float:
    """How far the hand closes on the ball (Table I, pre-reaching: "arm orienting"): 1 - the
    smallest hand–ball-centre distance over rows 0..end (the whole trial when ``end`` < 0)
    divided by the initial one. 0 = never closer than at the start; dimensionless."""
    h, b = points(hand, "hand"), points(ball, "ball")
    if len(h) == 0:
        return math.nan
    stop = end + 1 if end >= 0 else len(h)
    d = np.linalg.norm(h[:stop] - b[:stop], axis=1)
    return 1.0 - float(d.min()) / float(d[0]) if d[0] > 0 else math.nan


def heading(hand, ball, end: int = -1) -> float:
    """How much of the hand's movement goes toward the ball (arm orienting): the sum over the
    steps before the first touch (the whole trial when ``end`` < 0) of the displacement's
    component along the direction to the ball's centre, over the sum of the displacements'
    lengths, the direction to the ball taken from each step's midpoint (so circling the ball
    scores 0 whatever the sampling). 1 = every movement straight at the ball, 0 = as much
    toward as away (random flailing) or around it, -1 = straight away. NaN when the hand does
    not move."""
    h, b = points(hand, "hand"), points(ball, "ball")
    stop = end + 1 if end >= 0 else len(h)
    h, b = h[:stop], b[:stop]
    if len(h) < 2:
        return math.nan
    total = float(np.linalg.norm(np.diff(h, axis=0), axis=1).sum())
    if total <= REST_TOLERANCE:
        return math.nan
    along = _toward(h, b)
    return float(along.sum()) / total


# ---------------------------------------------------------------------------------- babbling
def _detrended(hand) -> np.ndarray:
    """The (T, 3) hand path less its least-squares linear trend per coordinate (and mean)."""
    h = points(hand, "hand")
    n = len(h)
    t = np.arange(n, dtype=float)
    design = np.column_stack([np.ones(n), t - t.mean()])
    coef, *_ = np.linalg.lstsq(design, h, rcond=None)
    return h - design @ coef


def hand_amplitude(hand) -> float:
    """Size of the hand's movement about its drift (m): the RMS length of the linearly
    detrended hand path (a circle of radius r gives r; a hand at rest 0). NaN for T < 2."""
    if len(points(hand, "hand")) < 2:
        return math.nan
    return math.sqrt(float(np.mean((_detrended(hand) ** 2).sum(axis=1))))


def hand_periodicity(hand, dt: float = DT) -> tuple[float, float]:
    """Dominant frequency and its power share of the hand's movement, a measure of the
    "quasi-periodic circular movements" of motor babbling (section IV-A-1; not in the paper).

    Each coordinate of the (T, 3) hand path (m) loses its least-squares linear trend (which also
    removes its mean); the power spectra (``numpy.fft.rfft``, bins k / (T dt) Hz) of the three
    coordinates are summed and the DC bin dropped. Returns (frequency of the strongest bin in
    Hz, share of the total non-DC power in that bin and its two neighbours). The share is near 1
    for a single steady oscillation (a circle, a to-and-fro swing), about 1/m for m equal
    oscillations at distinct frequencies, and small for noise.

    (nan, nan) when the hand is at rest (RMS of the detrended path below ``REST_TOLERANCE``),
    moves along a straight line at constant speed, or T < 4.
    """
    h = points(hand, "hand")
    n = len(h)
    if n < 4:
        return math.nan, math.nan
    resid = _detrended(h)
    if math.sqrt(float(np.mean(resid ** 2))) <= REST_TOLERANCE:
        return math.nan, math.nan
    power = (np.abs(np.fft.rfft(resid, axis=0)) ** 2).sum(axis=1)[1:]
    freqs = np.fft.rfftfreq(n, dt)[1:]
    total = float(power.sum())
    k = int(np.argmax(power))
    share = float(power[max(k - 1, 0):k + 2].sum()) / total
    return float(freqs[k]), share


def is_babbling(frequency: float, share: float, amplitude: float) -> bool:
    """Motor babbling in a trial (IV-A-1, Table I: "large quasi-periodic circular movements";
    docs/model/measures.md): a dominant rhythm (``share`` >= ``BABBLING_SHARE`` at ``frequency`` >=
    ``BABBLING_MIN_HZ``) AND a large movement (``amplitude`` >= ``BABBLING_AMPLITUDE``). A
    hand at rest (NaN share) is not babbling."""
    return bool(share >= BABBLING_SHARE and frequency >= BABBLING_MIN_HZ
                and amplitude >= BABBLING_AMPLITUDE)


def is_moving(path: float, amplitude: float) -> bool:
    """The hand moves in a trial (docs/model/measures.md, "Moving, beside rhythm"): its path
    (m, ``path_length``) is at least ``MOVING_PATH`` and its amplitude (m,
    ``hand_amplitude``) at least ``BABBLING_AMPLITUDE``, rhythm or not. NaN is not moving."""
    return bool(path >= MOVING_PATH and amplitude >= BABBLING_AMPLITUDE)


def before_touch(hand, end: int, dt: float = DT,
                 min_s: float = BEFORE_TOUCH_MIN_S) -> np.ndarray:
    """The hand path (m) before the first touch, over at least the first ``min_s`` s: rows
    0 .. max(``end``, ``min_s`` / ``dt``) - 1 of the (T, 3) path for a first touch at row
    ``end``, the whole path without a touch (``end`` < 0) or when it is shorter."""
    h = points(hand, "hand")
    if end < 0:
        return h
    return h[:max(end, int(round(min_s / dt)))]


def babbling_before_touch(hand, end: int, dt: float = DT,
                          min_s: float = BEFORE_TOUCH_MIN_S) -> bool:
    """Motor babbling before the first touch (section IV-A-1; the candidate measure of the
    ball-absent claim A1, docs/model/measures.md, "The second validation sample"):
    ``is_babbling`` of ``hand_periodicity`` and ``hand_amplitude`` on ``before_touch``
    (thresholds unchanged: share >= 0.4 at >= 0.25 Hz, RMS >= 0.05 m). A touch that stops or
    changes the rhythm no longer counts; without a touch (``end`` < 0, the ball absent) it is
    the detector on the whole trial."""
    window = before_touch(hand, end, dt, min_s)
    frequency, share = hand_periodicity(window, dt)
    return is_babbling(frequency, share, hand_amplitude(window))
