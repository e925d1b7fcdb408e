"""Behavioural measures of a trial and of the post-evaluation tables (paper section IV-A,
Figs. 5-7), plus a few measures beyond the paper.

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

Table functions take a polars post-evaluation table (one row per trial, with at least
``phase``, ``sector``, ``reached``, ``grasped`` and grouping columns such as ``senses``,
``replication``, ``rank``) and return polars tables: ``sector_success`` / ``sector_grid``
(Fig. 7), ``reach_regression`` (section IV-A-2) and ``robot_performance`` (the per-robot unit
of Fig. 9's statistics).

Rates are fractions in [0, 1] (the paper's figures show percentages).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import polars as pl

from . import contacts as touches
from . import kinematics
from .contacts import PALM, first_grasp, first_touch, grasped, reached  # noqa: F401
from .ctrnn import MOTOR_NAMES
from .kinematics import REST_TOLERANCE, hand_periodicity, path_length, points  # noqa: F401

#: Control step (s) of section III-B: row t of a trial record is the state at t * DT.
DT = 0.1

#: Motor indices of the joint groups of Fig. 6 (bottom): elbow, shoulder and trunk.
ELBOW_JOINTS = (MOTOR_NAMES.index("r_elbow"),)
SHOULDER_JOINTS = tuple(MOTOR_NAMES.index(n)
                        for n in ("r_shoulder_pitch", "r_shoulder_roll", "r_shoulder_yaw"))
TRUNK_JOINTS = tuple(MOTOR_NAMES.index(n) for n in ("torso_pitch", "torso_roll", "torso_yaw"))
JOINT_GROUPS = {"elbow": ELBOW_JOINTS, "shoulder": SHOULDER_JOINTS, "trunk": TRUNK_JOINTS}

#: Sectors of the ball's area (Fig. 2): 3 elevation rows x 3 azimuth columns.
SECTOR_ROWS = SECTOR_COLS = 3


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
    thresholds and the paper's words each measure stands for: docs/analysis.md. Keys:

    - who and how well: sector, fitness (``data.fitness``: mean p_multimodal, 0 when
      diverged), diverged, steps_run;
    - reach and grasp (IV-A): reached (any face of the hand touches the ball, the paper's
      reach), reached_inner (an inner face: the touch sensors' definition), grasped (palm and
      a finger on their inner faces at one step), first_touch_s (any face),
      first_touch_inner_s, first_grasp_s (NaN if none), touches (touch onsets, any face);
    - the reach (Fig. 5; up to the first touch on any face): movement_onset_s, speed (mean
      from t = 0), speed_peak, speed_final (the final approach), straightness (initial
      distance to the ball's surface over the path), straightness_centre (to its centre, the
      definition before issue 22), straightness_onset (displacement over path from movement
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


# ---------------------------------------------------------------------------------------------
# Post-evaluation tables (Figs. 5, 7, 9)
# ---------------------------------------------------------------------------------------------

def _require(table: pl.DataFrame, columns: Sequence[str]) -> None:
    missing = [c for c in columns if c not in table.columns]
    if missing:
        raise ValueError(f"table lacks the column(s) {missing}; it has {table.columns}")


def _rates() -> list[pl.Expr]:
    return [pl.col("reached").cast(pl.Float64).mean().alias("reach_rate"),
            pl.col("grasped").cast(pl.Float64).mean().alias("grasp_rate")]


def sector_success(table: pl.DataFrame, by: Sequence[str] = ("phase",)) -> pl.DataFrame:
    """Reach and grasp rates per group and sector, the data of the Fig. 7 maps.

    Columns: ``*by``, sector, n (trials), reach_rate, grasp_rate (fractions in [0, 1]), row
    (elevation row = sector // 3, 0 = lowest), col (azimuth column = sector % 3, 0 = straight
    ahead). Sorted by ``by`` then sector; a sector without trials in a group has no row.
    """
    by = list(by)
    _require(table, [*by, "sector", "reached", "grasped"])
    return (table.group_by([*by, "sector"]).agg(pl.len().alias("n"), *_rates())
            .with_columns((pl.col("sector") // SECTOR_COLS).alias("row"),
                          (pl.col("sector") % SECTOR_COLS).alias("col"))
            .sort([*by, "sector"]))


def sector_grid(rates: pl.DataFrame, value: str = "reach_rate") -> np.ndarray:
    """(3, 3) array of ``value`` for one group of ``sector_success``: grid[row, col], row 0 =
    the lowest elevation, col 0 = straight ahead (leftmost); flip rows upside down to draw it
    as seen by the robot. NaN for a sector without a row. ValueError when a sector appears more
    than once (filter ``rates`` to one group first)."""
    _require(rates, ["sector", value])
    sectors = rates["sector"].to_numpy()
    if len(np.unique(sectors)) != len(sectors):
        raise ValueError("rates hold several rows for a sector: filter them to one group first")
    if len(sectors) and (sectors.min() < 0 or sectors.max() >= SECTOR_ROWS * SECTOR_COLS):
        raise ValueError(f"sectors must be in 0..{SECTOR_ROWS * SECTOR_COLS - 1}")
    grid = np.full((SECTOR_ROWS, SECTOR_COLS), np.nan)
    values = rates[value].cast(pl.Float64).to_numpy()
    grid[sectors // SECTOR_COLS, sectors % SECTOR_COLS] = values
    return grid


def reach_regression(table: pl.DataFrame, before: str = "pre", after: str = "gross",
                     by: Sequence[str] = ()) -> pl.DataFrame:
    """Per sector, the reach rate in phase ``before`` and in phase ``after``: the temporary
    regression of reaching during gross-reaching, where robots specialise on some regions
    (section IV-A-2, Fig. 7; the per-sector numbers are beyond the paper).

    Columns: ``*by``, sector, row, col, n_before, n_after, reach_before, reach_after, change
    (= reach_after - reach_before; > 0 improves, < 0 regresses). A sector present in only one
    phase has nulls for the other. ValueError when either phase has no trials.
    """
    by = list(by)
    _require(table, ["phase", *by, "sector", "reached"])
    keys = [*by, "sector"]
    parts = []
    for phase, tag in ((before, "before"), (after, "after")):
        sub = table.filter(pl.col("phase") == phase)
        if sub.height == 0:
            raise ValueError(f"no trials of phase {phase!r} in the table")
        parts.append(sub.group_by(keys).agg(
            pl.len().alias(f"n_{tag}"),
            pl.col("reached").cast(pl.Float64).mean().alias(f"reach_{tag}")))
    out = parts[0].join(parts[1], on=keys, how="full", coalesce=True)
    return (out.with_columns((pl.col("sector") // SECTOR_COLS).alias("row"),
                             (pl.col("sector") % SECTOR_COLS).alias("col"),
                             (pl.col("reach_after") - pl.col("reach_before")).alias("change"))
            .select([*keys, "row", "col", "n_before", "n_after", "reach_before", "reach_after",
                     "change"])
            .sort(keys))


def robot_performance(table: pl.DataFrame,
                      by: Sequence[str] = ("phase", "senses", "replication", "rank")
                      ) -> pl.DataFrame:
    """One row per robot (group of ``by``): its mean fitness and reach/grasp rates over its
    post-evaluation trials, the unit of Fig. 9's statistics (50 robots per phase = best 5 of
    each of 10 replications, 45 trials each).

    Columns: ``*by``, n (trials), fitness (mean p_multimodal fitness), reach_rate, grasp_rate.
    Sorted by ``by``.
    """
    by = list(by)
    if not by:
        raise ValueError("robot_performance needs at least one column that identifies a robot")
    _require(table, [*by, "fitness", "reached", "grasped"])
    return (table.group_by(by)
            .agg(pl.len().alias("n"), pl.col("fitness").cast(pl.Float64).mean().alias("fitness"),
                 *_rates())
            .sort(by))


# ---------------------------------------------------------------------------------------------
# Summaries for the figures (Figs. 5, 6, 8, 10)
# ---------------------------------------------------------------------------------------------

def robot_means(table: pl.DataFrame, values: Sequence[str],
                by: Sequence[str] = ("phase", "senses", "replication", "rank")) -> pl.DataFrame:
    """One row per robot (group of ``by``): the mean over its trials of each column of
    ``values``, ignoring NaN and null (a reaching speed is NaN in a trial without a reach).

    Booleans count as 0/1 (the mean of ``reached`` is the reach rate). Columns: ``*by``, n
    (trials), then one Float64 column per value: NaN when none of the robot's trials has a
    finite value. Sorted by ``by``. The robot is the unit of the bars and statistics of Figs. 5,
    6 and 9 ("post-evaluating 50 robots ... for 45 trials").
    """
    by, values = list(by), list(values)
    if not by:
        raise ValueError("robot_means needs at least one column that identifies a robot")
    if not values:
        raise ValueError("robot_means needs at least one value column")
    _require(table, [*by, *values])
    return (table.group_by(by)
            .agg(pl.len().alias("n"),
                 *[pl.col(v).cast(pl.Float64).fill_nan(None).mean().alias(v) for v in values])
            .with_columns([pl.col(v).fill_null(math.nan) for v in values])
            .sort(by))


def group_summary(units: pl.DataFrame, values: Sequence[str],
                  by: Sequence[str] = ("phase",)) -> pl.DataFrame:
    """Mean, standard deviation and standard error of each column of ``values`` over the units
    (rows, e.g. robots of ``robot_means``) of each group of ``by``: the bars and error bars of
    Figs. 5 and 6.

    Long table, one row per group and measure: ``*by``, measure (the value's column name), n
    (units with a finite value; NaN and null are left out), mean, sd (ddof = 1), sem
    (sd / sqrt(n)). mean is NaN when n = 0, sd and sem when n < 2. Sorted by ``by``, then
    measures in the order of ``values``.
    """
    by, values = list(by), list(values)
    if not values:
        raise ValueError("group_summary needs at least one value column")
    _require(units, [*by, *values])
    order = {v: i for i, v in enumerate(values)}
    long = (units.select([*by, *[pl.col(v).cast(pl.Float64) for v in values]])
            .unpivot(index=by or None, on=values, variable_name="measure", value_name="value")
            .with_columns(pl.col("value").fill_nan(None)))
    keys = [*by, "measure"]
    out = (long.group_by(keys)
           .agg(pl.col("value").count().alias("n"), pl.col("value").mean().alias("mean"),
                pl.col("value").std(ddof=1).alias("sd"))
           .with_columns(pl.col("mean").fill_null(math.nan),
                         pl.when(pl.col("n") >= 2).then(pl.col("sd")).otherwise(math.nan)
                         .fill_null(math.nan).alias("sd"))
           .with_columns((pl.col("sd") / pl.col("n").cast(pl.Float64).sqrt()).alias("sem"))
           .with_columns(pl.col("measure").replace_strict(order, return_dtype=pl.Int64)
                         .alias("_order"))
           .sort([*by, "_order"]).drop("_order"))
    return out.select([*keys, "n", "mean", "sd", "sem"])


def replication_performance(table: pl.DataFrame, senses: str = "normal", robots: int = 1,
                            by: Sequence[str] = ("phase",)) -> pl.DataFrame:
    """One value per replication of each group of ``by``, the unit of Fig. 10 ("the
    distribution of p_multimodal performances obtained in ten replications").

    A replication's performance is the post-evaluation fitness (mean p_multimodal over the 45
    systematic trials, sensory condition ``senses``) of its best robot (rank 0), or with
    ``robots`` = k > 1 the mean of its best k robots' (ranks 0..k-1 that were evaluated). The
    post-evaluation tests every condition on the same positions, sector by sector, while the
    lifetime fitness (the last generation's, on 18 random positions) is the maximum of a noisy
    selection and so biased upwards; it is kept as a column for comparison.

    Columns: ``*by``, replication, robots (robots averaged), fitness, reach_rate, grasp_rate (of
    those robots' trials), lifetime_fitness (mean of those robots' final training fitness).
    Sorted by ``by`` then replication. ValueError when no trial matches ``senses`` and
    ``robots``.
    """
    by = list(by)
    if robots < 1:
        raise ValueError(f"robots must be at least 1, got {robots}")
    _require(table, [*by, "senses", "replication", "rank", "fitness", "reached", "grasped",
                     "lifetime_fitness"])
    sub = table.filter((pl.col("senses") == senses) & (pl.col("rank") < robots))
    if sub.height == 0:
        raise ValueError(f"no trials with senses {senses!r} and rank < {robots} in the table")
    per_robot = (sub.group_by([*by, "replication", "rank"])
                 .agg(pl.col("fitness").cast(pl.Float64).mean(), *_rates(),
                      pl.col("lifetime_fitness").cast(pl.Float64).first())
                 .sort([*by, "replication", "rank"]))  # the means below: the same bits always
    return (per_robot.group_by([*by, "replication"])
            .agg(pl.len().alias("robots"),
                 *[pl.col(c).mean() for c in ("fitness", "reach_rate", "grasp_rate",
                                              "lifetime_fitness")])
            .sort([*by, "replication"]))


# ---------------------------------------------------------------------------------------------
# Per robot: peri-personal space, one condition against another (sections IV-A-2, IV-B, V)
# ---------------------------------------------------------------------------------------------

def peripersonal_space(table: pl.DataFrame,
                       by: Sequence[str] = ("phase", "senses", "replication", "rank")
                       ) -> pl.DataFrame:
    """The region of its peri-personal space in which each robot (group of ``by``) succeeds:
    the space that shrinks during gross-reaching and re-expands in fine-reaching (IV-A-2, V;
    Fig. 7), per robot instead of pooled.

    Columns: ``*by``, trials, sectors_reached / sectors_grasped (sectors, of 9, with at least
    one reach / grasp among the robot's trials there), reach_entropy (Shannon entropy of the
    robot's reaches over the 9 sectors divided by log 9: 1 = reaches spread evenly over every
    sector, 0 = all in one; NaN without a reach). Sorted by ``by``.
    """
    by = list(by)
    _require(table, [*by, "sector", "reached", "grasped"])
    per_sector = (table.group_by([*by, "sector"])
                  .agg(pl.len().alias("n"), pl.col("reached").cast(pl.Int64).sum().alias("r"),
                       pl.col("grasped").cast(pl.Int64).sum().alias("g"))
                  .sort([*by, "sector"]))  # sums below in sector order: the same bits every time
    total = pl.col("r").sum().over(by)
    share = pl.col("r") / total
    term = pl.when(pl.col("r") > 0).then(-share * share.log()).otherwise(0.0)
    n_sectors = SECTOR_ROWS * SECTOR_COLS
    return (per_sector.with_columns(term.alias("h"))
            .group_by(by)
            .agg(pl.col("n").sum().alias("trials"),
                 (pl.col("r") > 0).sum().cast(pl.Int64).alias("sectors_reached"),
                 (pl.col("g") > 0).sum().cast(pl.Int64).alias("sectors_grasped"),
                 pl.col("r").sum().alias("_reaches"), pl.col("h").sum().alias("_h"))
            .with_columns(pl.when(pl.col("_reaches") > 0)
                          .then(pl.col("_h") / math.log(n_sectors)).otherwise(math.nan)
                          .alias("reach_entropy"))
            .drop("_reaches", "_h").sort(by))


def condition_contrast(table: pl.DataFrame, values: Sequence[str], a: str = "normal",
                       b: str = "no-sight", column: str = "senses",
                       robot: Sequence[str] = ("phase", "replication", "rank")) -> pl.DataFrame:
    """Each robot under two post-evaluation conditions (``column`` = ``a`` and = ``b``, e.g.
    normal and no-sight, normal and no-ball), side by side: the per-robot deprivation drop of
    section IV-B and the paired comparison of the ball-absent test (IV-A-1).

    One row per robot present under both: ``*robot``, then for each measure v of ``values``
    (the robot's mean over its trials, NaN ignored, booleans as rates) ``v_a``, ``v_b`` and
    ``v_drop`` = v_a - v_b (> 0: lower without the sense or the ball). Sorted by ``robot``.
    """
    robot, values = list(robot), list(values)
    _require(table, [*robot, column, *values])
    means = {c: robot_means(table.filter(pl.col(column) == c), values, by=robot).drop("n")
             for c in (a, b)}
    out = means[a].rename({v: f"{v}_a" for v in values}).join(
        means[b].rename({v: f"{v}_b" for v in values}), on=robot, how="inner")
    return (out.with_columns([(pl.col(f"{v}_a") - pl.col(f"{v}_b")).alias(f"{v}_drop")
                              for v in values])
            .select([*robot, *[f"{v}_{s}" for v in values for s in ("a", "b", "drop")]])
            .sort(robot))
