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
- ``trial_metrics``: all of the above as one flat dict, one row of a per-trial table.

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

from .ctrnn import MOTOR_NAMES

#: Control step (s) of section III-B: row t of a trial record is the state at t * DT.
DT = 0.1

#: Motor indices of the joint groups of Fig. 6 (bottom): elbow, shoulder and trunk.
ELBOW_JOINTS = (MOTOR_NAMES.index("r_elbow"),)
SHOULDER_JOINTS = tuple(MOTOR_NAMES.index(n)
                        for n in ("r_shoulder_pitch", "r_shoulder_roll", "r_shoulder_yaw"))
TRUNK_JOINTS = tuple(MOTOR_NAMES.index(n) for n in ("torso_pitch", "torso_roll", "torso_yaw"))
JOINT_GROUPS = {"elbow": ELBOW_JOINTS, "shoulder": SHOULDER_JOINTS, "trunk": TRUNK_JOINTS}

#: Column of the palm in the contact arrays (``icub.HAND_SEGMENTS[0] == "r_hand"``); columns
#: 1..15 are the finger phalanges.
PALM = 0

#: RMS (m) of the detrended hand path below which the hand counts as at rest in
#: ``hand_periodicity`` (no meaningful spectrum).
REST_TOLERANCE = 1e-9

#: Sectors of the ball's area (Fig. 2): 3 elevation rows x 3 azimuth columns.
SECTOR_ROWS = SECTOR_COLS = 3


# ---------------------------------------------------------------------------------------------
# Reach and grasp (section IV-A)
# ---------------------------------------------------------------------------------------------

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


# ---------------------------------------------------------------------------------------------
# Kinematics (Figs. 5, 6)
# ---------------------------------------------------------------------------------------------

def _points(points, name: str = "points") -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3:
        raise ValueError(f"{name} must be a (T, 3) array, got shape {p.shape}")
    return p


def path_length(points) -> float:
    """Length (m) of the polyline through the (T, 3) points (m); 0 for fewer than 2 points."""
    p = _points(points)
    if len(p) < 2:
        return 0.0
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def reaching_speed(hand, contacts, dt: float = DT) -> float:
    """Mean hand speed (m/s) from the start of the trial to the first touch (Fig. 5,
    bottom-left): length of the hand's path over rows 0..first_touch divided by
    first_touch * dt (dt in s).

    NaN when the ball is never touched, or touched already at step 0 (no movement to time).
    """
    k = first_touch(contacts)
    if k <= 0:
        return math.nan
    return path_length(_points(hand, "hand")[:k + 1]) / (k * dt)


def straightness(hand, ball, contacts) -> float:
    """Reaching straightness (Fig. 5 caption, after [26], [27]): the initial hand-ball distance
    (hand palm point to ball centre, row 0) divided by the length of the hand's path from the
    start to the first touch (rows 0..first_touch). Dimensionless; 1 = a straight line.

    NaN when the ball is never touched or the path has zero length (touch at step 0).

    Not bounded by 1: the path ends where the hand touches the ball's surface, not at its
    centre, and the ball (a pendulum) may swing towards the hand, so a direct reach can give a
    ratio slightly above 1 (by up to about (ball radius + palm-to-contact offset) / path).
    """
    k = first_touch(contacts)
    if k < 0:
        return math.nan
    h, b = _points(hand, "hand"), _points(ball, "ball")
    length = path_length(h[:k + 1])
    if length <= 0.0:
        return math.nan
    return float(np.linalg.norm(h[0] - b[0])) / length


def joint_variability(joints) -> dict[str, float]:
    """Movement variability per joint group (Fig. 6, bottom: "standard deviation of the joint
    encoders"): the standard deviation over time (population std, ddof = 0; rad) of each joint
    of the group, averaged over the group's joints.

    ``joints``: (T, 14) rad in ``ctrnn.MOTOR_NAMES`` order. Keys "elbow" (r_elbow),
    "shoulder" (r_shoulder pitch/roll/yaw), "trunk" (torso pitch/roll/yaw). NaN for T = 0.
    """
    q = np.asarray(joints, dtype=float)
    if q.ndim != 2 or q.shape[1] != len(MOTOR_NAMES):
        raise ValueError(f"joints must be a (T, {len(MOTOR_NAMES)}) array, got shape {q.shape}")
    if len(q) == 0:
        return {name: math.nan for name in JOINT_GROUPS}
    sd = q.std(axis=0)
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
    return np.linalg.norm(_points(hand, "hand") - _points(shoulder, "shoulder"), axis=1)


def hand_ball_distance(hand, ball) -> np.ndarray:
    """(T,) distance (m) between the palm point and the ball centre at each step (Fig. 6,
    top)."""
    return np.linalg.norm(_points(hand, "hand") - _points(ball, "ball"), axis=1)


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
    h = _points(hand, "hand")
    n = len(h)
    if n < 4:
        return math.nan, math.nan
    t = np.arange(n, dtype=float)
    design = np.column_stack([np.ones(n), t - t.mean()])
    coef, *_ = np.linalg.lstsq(design, h, rcond=None)
    resid = h - design @ coef
    if math.sqrt(float(np.mean(resid ** 2))) <= REST_TOLERANCE:
        return math.nan, math.nan
    power = (np.abs(np.fft.rfft(resid, axis=0)) ** 2).sum(axis=1)[1:]
    freqs = np.fft.rfftfreq(n, dt)[1:]
    total = float(power.sum())
    k = int(np.argmax(power))
    share = float(power[max(k - 1, 0):k + 2].sum()) / total
    return float(freqs[k]), share


# ---------------------------------------------------------------------------------------------
# One trial as a table row
# ---------------------------------------------------------------------------------------------

def trial_metrics(data, dt: float = DT) -> dict[str, float | int | bool]:
    """Every per-trial measure of a ``task.TrialData`` as a flat dict (one table row).

    Only the first ``data.steps_run`` rows are used (a diverged trial stops early and its later
    rows are zeros); contacts before the divergence count. Times in s, distances in m, speed in
    m/s, joint variability in rad, frequency in Hz. Keys:

    sector, fitness (``data.fitness``: mean p_multimodal, 0 when diverged), reached, grasped,
    first_touch_s / first_grasp_s (NaN if none), speed, straightness, var_elbow, var_shoulder,
    var_trunk, hand_shoulder_mean, elbow_freezing, hand_ball_initial, hand_ball_min,
    babbling_freq_hz, babbling_share, diverged, steps_run.
    """
    n = int(data.steps_run)
    hand, shoulder, ball = data.hand[:n], data.shoulder[:n], data.ball[:n]
    contacts, joints = data.contacts[:n], data.joints[:n]
    touch, grasp = first_touch(contacts), first_grasp(contacts)
    var = joint_variability(joints)
    d_shoulder = hand_shoulder_distance(hand, shoulder)
    d_ball = hand_ball_distance(hand, ball)
    freq, share = hand_periodicity(hand, dt)
    return {
        "sector": int(data.sector),
        "fitness": float(data.fitness),
        "reached": touch >= 0,
        "grasped": grasp >= 0,
        "first_touch_s": touch * dt if touch >= 0 else math.nan,
        "first_grasp_s": grasp * dt if grasp >= 0 else math.nan,
        "speed": reaching_speed(hand, contacts, dt),
        "straightness": straightness(hand, ball, contacts),
        "var_elbow": var["elbow"],
        "var_shoulder": var["shoulder"],
        "var_trunk": var["trunk"],
        "hand_shoulder_mean": float(d_shoulder.mean()) if n else math.nan,
        "elbow_freezing": elbow_freezing(hand, shoulder),
        "hand_ball_initial": float(d_ball[0]) if n else math.nan,
        "hand_ball_min": float(d_ball.min()) if n else math.nan,
        "babbling_freq_hz": freq,
        "babbling_share": share,
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
                      pl.col("lifetime_fitness").cast(pl.Float64).first()))
    return (per_robot.group_by([*by, "replication"])
            .agg(pl.len().alias("robots"),
                 *[pl.col(c).mean() for c in ("fitness", "reach_rate", "grasp_rate",
                                              "lifetime_fitness")])
            .sort([*by, "replication"]))
