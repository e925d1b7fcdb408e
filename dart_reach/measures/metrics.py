"""Behavioural measures of one trial (paper section IV-A, Figs. 5-7), plus a few measures
beyond the paper.

Per-trial measures are pure functions of the per-step arrays of a ``task.TrialData``
(row t = state at t * dt, dt = 0.1 s, the control step of section III-B):

- reach and grasp (section IV-A): ``first_touch``, ``reached``, ``first_grasp``, ``grasped``;
- reaching speed and straightness (Fig. 5, bottom): ``reaching_speed``, ``straightness``;
- movement variability per joint group (Fig. 6, bottom): ``joint_variability``;
- hand-shoulder and hand-ball distances (Fig. 6, top): ``hand_shoulder_distance``,
  ``hand_ball_distance``;
- beyond the paper: ``elbow_freezing`` (the locked elbow of section IV-A-1) and
  ``hand_periodicity`` (the "quasi-periodic circular movements" of motor babbling, IV-A-1);
- ``trial_metrics``: all of the above and the measures of ``contacts`` (touches, anticipatory
  grasp, swipes) and ``kinematics`` (the reach's path, arm orienting, babbling) as one flat
  dict, one row of a per-trial table.

The measures of whole post-evaluation tables (rates per sector, per robot, per replication)
are in ``analysis.summaries``.

Rates are fractions in [0, 1] (the paper's figures show percentages).
"""

from __future__ import annotations

import math

import numpy as np

from . import contacts as touches
from . import kinematics
from .fitness import contact_after_first
from .contacts import PALM, first_grasp, first_touch, grasped, reached  # noqa: F401
from ..model.ctrnn import MOTOR_NAMES
from .kinematics import REST_TOLERANCE, hand_periodicity, path_length, points  # noqa: F401

#: Control step (s) of section III-B: row t of a trial record is the state at t * DT.
DT = 0.1

#: Motor indices of the joint groups of Fig. 6 (bottom): elbow, shoulder and trunk.
ELBOW_JOINTS = (MOTOR_NAMES.index("r_elbow"),)
SHOULDER_JOINTS = tuple(MOTOR_NAMES.index(n)
                        for n in ("r_shoulder_pitch", "r_shoulder_roll", "r_shoulder_yaw"))
TRUNK_JOINTS = tuple(MOTOR_NAMES.index(n) for n in ("torso_pitch", "torso_roll", "torso_yaw"))
JOINT_GROUPS = {"elbow": ELBOW_JOINTS, "shoulder": SHOULDER_JOINTS, "trunk": TRUNK_JOINTS}


# ---------------------------------------------------------------------------------------------
# Reach, grasp and the reach's path (section IV-A, Fig. 5): ``contacts`` and ``kinematics``
# ---------------------------------------------------------------------------------------------

def reaching_speed(hand, contacts, dt: float = DT) -> float:
    """Mean hand speed (m/s) from the start of the trial to the first touch of ``contacts``
    (Fig. 5, bottom-left; ``kinematics.reaching_speed``). NaN when the ball is never touched,
    or touched already at step 0."""
    return kinematics.reaching_speed(hand, first_touch(contacts), dt)


def straightness(hand, ball, contacts, radius: float = 0.0) -> float:
    """Reaching straightness (Fig. 5 caption, after [26], [27]) up to the first touch of
    ``contacts``: the initial hand-ball distance less ``radius`` over the hand's path
    (``kinematics.straightness``; ``radius`` = the ball's radius measures it to the ball's
    surface, 0 to its centre). NaN when the ball is never touched or the path has zero
    length."""
    return kinematics.straightness(hand, ball, first_touch(contacts), radius)


def joint_variability(joints, ranges=None) -> dict[str, float]:
    """Movement variability per joint group (Fig. 6, bottom: "standard deviation of the joint
    encoders"): the standard deviation over time (population std, ddof = 0; rad) of each joint
    of the group, averaged over the group's joints.

    ``joints``: (T, 14) rad in ``ctrnn.MOTOR_NAMES`` order. Keys "elbow" (r_elbow),
    "shoulder" (r_shoulder pitch/roll/yaw), "trunk" (torso pitch/roll/yaw). NaN for T = 0.
    ``ranges``: (14,) joint ranges (rad): each joint's standard deviation is then divided by
    its range before averaging (dimensionless; joints of unequal range weigh alike).
    """
    q = np.asarray(joints, dtype=float)
    if q.ndim != 2 or q.shape[1] != len(MOTOR_NAMES):
        raise ValueError(f"joints must be a (T, {len(MOTOR_NAMES)}) array, got shape {q.shape}")
    if len(q) == 0:
        return {name: math.nan for name in JOINT_GROUPS}
    sd = q.std(axis=0)
    if ranges is not None:
        sd = sd / np.asarray(ranges, dtype=float)
    return {name: float(sd[list(idx)].mean()) for name, idx in JOINT_GROUPS.items()}


#: Steps of the moving window of ``variability_over_time``: 2 s, two periods of the ~1 Hz
#: quasi-periodic movements of pre-reachers (``hand_periodicity``).
VARIABILITY_WINDOW = 20


def variability_over_time(joints, window: int = VARIABILITY_WINDOW) -> dict[str, np.ndarray]:
    """Movement variability (``joint_variability``) as it builds up over a trial, per step:
    ``"cumulative/<group>"``, the standard deviation (ddof = 0, rad) of each joint of the group
    over steps 0..t averaged over the group's joints (at the last step it equals
    ``joint_variability``); ``"window/<group>"``, the same over the last ``window`` steps
    (fewer at the start). Groups: elbow, shoulder, trunk. Each value is a (T,) array."""
    q = np.asarray(joints, dtype=float)
    if q.ndim != 2 or q.shape[1] != len(MOTOR_NAMES):
        raise ValueError(f"joints must be a (T, {len(MOTOR_NAMES)}) array, got shape {q.shape}")
    if window < 1:
        raise ValueError(f"window must be at least 1 step, got {window}")
    x = q - q[:1]  # about the first posture: the sums below lose no precision
    zero = np.zeros((1, x.shape[1]))
    s1 = np.concatenate([zero, np.cumsum(x, axis=0)])
    s2 = np.concatenate([zero, np.cumsum(x * x, axis=0)])
    t = np.arange(1, len(x) + 1)[:, None]
    start = np.maximum(t - window, 0)
    out = {}
    for kind, lo in (("cumulative", np.zeros_like(t)), ("window", start)):
        n = (t - lo).astype(float)
        mean = (s1[t[:, 0]] - s1[lo[:, 0]]) / n
        var = np.maximum((s2[t[:, 0]] - s2[lo[:, 0]]) / n - mean * mean, 0.0)
        sd = np.sqrt(var)
        for name, idx in JOINT_GROUPS.items():
            out[f"{kind}/{name}"] = sd[:, list(idx)].mean(axis=1)
    return out


def hand_shoulder_distance(hand, shoulder) -> np.ndarray:
    """(T,) distance (m) between the palm point and the shoulder at each step (Fig. 6, top)."""
    return np.linalg.norm(points(hand, "hand") - points(shoulder, "shoulder"), axis=1)


def hand_ball_distance(hand, ball) -> np.ndarray:
    """(T,) distance (m) between the palm point and the ball centre at each step (Fig. 6,
    top)."""
    return np.linalg.norm(points(hand, "hand") - points(ball, "ball"), axis=1)


# ---------------------------------------------------------------------------------------------
# Beyond the paper: elbow locking and motor babbling (section IV-A-1)
# ---------------------------------------------------------------------------------------------

def elbow_freezing(hand, shoulder) -> float:
    """Standard deviation (m, ddof = 0) over time of the hand-shoulder distance.

    Small when the elbow is locked and the arm moves as a rigid lever around the shoulder
    (section IV-A-1: "the distance between the shoulder and the hand remains almost constant",
    Fig. 6 top). Not in the paper as a number. NaN for an empty trial.
    """
    d = hand_shoulder_distance(hand, shoulder)
    return float(d.std()) if len(d) else math.nan


def arm_extension(hand, shoulder, first_step: int = 0) -> tuple[float, float]:
    """(mean in m, CV) of the palm-shoulder distance over the steps from ``first_step`` on:
    the arm "extended" with "the distance between the shoulder and the hand ... almost
    constant" of IV-A-1 (Fig. 6 top), leaving out the arm's first extension from the home
    posture when ``first_step`` > 0. The CV is the distance's s.d. (ddof = 0) over its mean.
    (NaN, NaN) when no step is left."""
    d = hand_shoulder_distance(hand, shoulder)[first_step:]
    if not len(d) or d.mean() <= 0:
        return math.nan, math.nan
    return float(d.mean()), float(d.std() / d.mean())


# ---------------------------------------------------------------------------------------------
# One trial as a table row
# ---------------------------------------------------------------------------------------------

#: Radius (m) of the shipped ball (``world.BallConfig``), the default of ``trial_metrics``.
BALL_RADIUS = 0.035
#: Motor index of the hand (mean finger flexion, rad) in ``TrialData.joints``.
HAND_MOTOR = MOTOR_NAMES.index("r_hand_fingers")


def trial_metrics(data, dt: float = DT, ball_radius: float = BALL_RADIUS,
                  joint_ranges=None) -> dict[str, float | int | bool]:
    """Every per-trial measure of a ``task.TrialData`` as a flat dict (one table row).

    Only the first ``data.steps_run`` rows are used (a diverged trial stops early and its later
    rows are zeros); contacts before the divergence count. Times in s, distances in m, speeds
    in m/s, joint variability in rad, frequency in Hz. ``ball_radius`` (m): the run's ball;
    ``joint_ranges``: (14,) rad, the run's joint ranges (``World.motor_limit_upper -
    motor_limit_lower``), for the normalised variabilities (NaN without them). Definitions,
    thresholds and the paper's words each measure stands for: docs/model/measures.md. Keys:

    - who and how well: sector, fitness (``data.fitness``: mean p_multimodal, 0 when
      diverged), diverged, steps_run;
    - reach and grasp (IV-A): reached (any face of the hand touches the ball, the paper's
      reach), reached_inner (an inner face: the touch sensors' definition), grasped (palm and
      a finger on their inner faces at one step), first_touch_s (any face),
      first_touch_inner_s, first_grasp_s (NaN if none), touches (touch onsets, any face),
      contact_after_first (the share of the steps from the first inner-face touch on in
      which an inner face touches: a hand resting on the ball near 1; NaN without a touch);
    - the reach (Fig. 5; up to the first touch on any face): movement_onset_s, speed (mean
      from t = 0), speed_peak, speed_final (the final approach), straightness (initial
      distance to the ball's surface over the path), straightness_centre (to its centre, the
      earlier definition), straightness_onset (displacement over path from movement
      onset), movement_units (speed peaks: smoothness);
    - joints (Fig. 6): var_elbow, var_shoulder, var_trunk (whole trial, rad), var_*_before
      (before the first touch; the whole trial without one), var_*_norm (whole trial, each
      joint's s.d. over its range);
    - arm (IV-A-1, Table I): hand_shoulder_mean (extension, m), hand_shoulder_cv and
      elbow_freezing (constancy), hand_ball_initial, hand_ball_min, approach and heading (arm
      orienting);
    - babbling (IV-A-1): hand_path (m), hand_amplitude (m), babbling_freq_hz, babbling_share,
      babbling (rhythm and amplitude above the thresholds of ``kinematics``);
    - the hand (Table I, IV-A-2): anticipatory_grasp (1/0, NaN without a palm touch),
      grasp_lead_s, palm_up_swipe (1/0, NaN without a touch), swipes.

    A trial read back from a recording without any-face touches (``contacts_any`` None) uses
    the inner-face ones for both.
    """
    n = int(data.steps_run)
    hand, shoulder, ball = data.hand[:n], data.shoulder[:n], data.ball[:n]
    contacts, joints = data.contacts[:n], data.joints[:n]
    any_face = contacts if data.contacts_any is None else data.contacts_any[:n]
    normal = None if data.palm_normal is None else data.palm_normal[:n]
    touch, inner, grasp = first_touch(any_face), first_touch(contacts), first_grasp(contacts)
    var, before = joint_variability(joints), joint_variability(joints[:touch] if touch >= 0
                                                               else joints)
    norm = (joint_variability(joints, joint_ranges) if joint_ranges is not None
            else dict.fromkeys(JOINT_GROUPS, math.nan))
    d_shoulder = hand_shoulder_distance(hand, shoulder)
    d_ball = hand_ball_distance(hand, ball)
    freq, share = hand_periodicity(hand, dt)
    amplitude = kinematics.hand_amplitude(hand)
    onset = kinematics.movement_onset(hand, touch if touch >= 0 else None, dt)
    anticipatory, lead = touches.anticipatory_grasp(joints[:, HAND_MOTOR], contacts, dt)
    swipe, swipes = touches.upward_swipes(hand, ball, normal, any_face, dt)
    seconds = lambda k: k * dt if k >= 0 else math.nan  # noqa: E731
    return {
        "sector": int(data.sector),
        "fitness": float(data.fitness),
        "reached": touch >= 0,
        "reached_inner": inner >= 0,
        "grasped": grasp >= 0,
        "first_touch_s": seconds(touch),
        "first_touch_inner_s": seconds(inner),
        "first_grasp_s": seconds(grasp),
        "touches": len(touches.touch_onsets(any_face)),
        "contact_after_first": contact_after_first(contacts),
        "movement_onset_s": seconds(onset),
        "speed": kinematics.reaching_speed(hand, touch, dt),
        "speed_peak": kinematics.peak_speed(hand, touch, dt),
        "speed_final": kinematics.final_speed(hand, ball, touch, dt),
        "straightness": kinematics.straightness(hand, ball, touch, ball_radius),
        "straightness_centre": kinematics.straightness(hand, ball, touch),
        "straightness_onset": kinematics.straightness_onset(hand, touch, dt),
        "movement_units": kinematics.movement_units(hand, touch, dt),
        **{f"var_{g}": var[g] for g in JOINT_GROUPS},
        **{f"var_{g}_before": before[g] for g in JOINT_GROUPS},
        **{f"var_{g}_norm": norm[g] for g in JOINT_GROUPS},
        "hand_shoulder_mean": float(d_shoulder.mean()) if n else math.nan,
        "hand_shoulder_cv": (float(d_shoulder.std() / d_shoulder.mean())
                             if n and d_shoulder.mean() > 0 else math.nan),
        "elbow_freezing": elbow_freezing(hand, shoulder),
        "hand_ball_initial": float(d_ball[0]) if n else math.nan,
        "hand_ball_min": float(d_ball.min()) if n else math.nan,
        "approach": kinematics.approach(hand, ball, touch) if n else math.nan,
        "heading": kinematics.heading(hand, ball, touch),
        "hand_path": kinematics.path_length(hand),
        "hand_amplitude": amplitude,
        "babbling_freq_hz": freq,
        "babbling_share": share,
        "babbling": kinematics.is_babbling(freq, share, amplitude),
        "anticipatory_grasp": anticipatory,
        "grasp_lead_s": lead,
        "palm_up_swipe": swipe,
        "swipes": swipes,
        "diverged": bool(data.diverged),
        "steps_run": n,
    }
