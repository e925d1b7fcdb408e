"""The pre-reacher's profile per replication, and whether it is the paper's (IV-A-1, Fig. 6).

From a post-evaluation table (one row per trial: ``postevaluation.systematic``'s measures),
per replication (or any grouping): the means over its trials with the ball (``normal``) of the
reach rate, the elbow, shoulder and trunk SD, the hand-shoulder distance and its CV, the hand
path and the fitness, and the babbling rates with and without the ball (``no-ball``). The
paper's pre-reacher (``Criteria``, thresholds fixed in docs/results/levers.md before any run of
the levers study):

1. ``reach``: the reach rate within ``reach_band`` ("in about half of the trials");
2. ``elbow_locked``: the elbow's SD below both the shoulder's and the trunk's ("a limited use
   (locking) of the DOF of the elbow");
3. ``arm_extended``: the hand-shoulder distance at least ``extended_m`` and its CV below
   ``constant_cv`` ("produced with the arm extended ... almost constant");
4. ``babbling``: babbling in at least ``babbling_share`` of the trials with the ball or of
   those without it ("large quasi-periodic circular movements").
"""

from __future__ import annotations

from dataclasses import dataclass

import polars as pl
from scipy import stats

from .strategies import STILL, strategies

#: The measures of a profile: column of the table -> name in the profile (normal senses).
PROFILE_MEASURES = {"reached": "reach", "var_elbow": "elbow_sd", "var_shoulder": "shoulder_sd",
                    "var_trunk": "trunk_sd", "hand_shoulder_mean": "hand_shoulder_m",
                    "hand_shoulder_cv": "hand_shoulder_cv", "hand_path": "hand_path_m",
                    "babbling": "babbling", "fitness": "fitness"}
CRITERIA = ("reach", "elbow_locked", "arm_extended", "babbling")


@dataclass(frozen=True)
class Criteria:
    """The paper's pre-reacher (the module's docstring); lengths in m, rates in [0, 1]."""

    reach_band: tuple[float, float] = (0.35, 0.65)
    extended_m: float = 0.31
    constant_cv: float = 0.05
    babbling_share: float = 0.5


def profiles(table: pl.DataFrame, by: tuple[str, ...] = ("replication",),
             criteria: Criteria = Criteria()) -> pl.DataFrame:
    """One row per group of ``by``: the profile's means (normal senses), ``babbling_no_ball``
    (NaN without ball-absent trials), each criterion as a bool column named ``is_<criterion>``
    and ``paper`` (all four)."""
    by = list(by)
    normal = (table.filter(pl.col("senses") == "normal").group_by(by)
              .agg([pl.col(c).cast(pl.Float64).mean().alias(n)
                    for c, n in PROFILE_MEASURES.items()] + [pl.len().alias("trials")]))
    absent = (table.filter(pl.col("senses") == "no-ball").group_by(by)
              .agg(pl.col("babbling").cast(pl.Float64).mean().alias("babbling_no_ball")))
    low, high = criteria.reach_band
    out = (normal.join(absent, on=by, how="left")
           .with_columns(pl.col("babbling_no_ball").fill_null(float("nan")))
           .with_columns(
               is_reach=pl.col("reach").is_between(low, high),
               is_elbow_locked=(pl.col("elbow_sd") < pl.col("shoulder_sd"))
               & (pl.col("elbow_sd") < pl.col("trunk_sd")),
               is_arm_extended=(pl.col("hand_shoulder_m") >= criteria.extended_m)
               & (pl.col("hand_shoulder_cv") < criteria.constant_cv),
               is_babbling=(pl.col("babbling") >= criteria.babbling_share)
               | (pl.col("babbling_no_ball").fill_nan(0.0) >= criteria.babbling_share))
           .with_columns(paper=pl.all_horizontal([f"is_{c}" for c in CRITERIA]))
           .sort(by))
    return out


def share_interval(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """The exact (Clopper-Pearson) interval of a share k / n."""
    if n <= 0 or not 0 <= k <= n:
        raise ValueError(f"need 0 <= k <= n and n > 0, got k={k}, n={n}")
    ci = stats.binomtest(k, n).proportion_ci(level, method="exact")
    return float(ci.low), float(ci.high)


def more_than_reference(k: int, n: int, k_ref: int, n_ref: int) -> float:
    """One-sided p of Fisher's exact test that the share k / n exceeds k_ref / n_ref."""
    return float(stats.fisher_exact([[k, n - k], [k_ref, n_ref - k_ref]],
                                    alternative="greater").pvalue)


#: The paper's pre-reacher judged in the paper's own units (docs/results/campaign.md, (a)):
#: criterion -> what it asks.
PAPER_UNITS = {
    "A1 reach": "mean reach of the best robots in the band (Fig. 5: a mean over 50 robots)",
    "A2 elbow locked": "mean elbow SD below the mean shoulder and trunk SDs (Fig. 6 bottom)",
    "A3 arm extended": "the best robot's palm-shoulder distance, from 2 s on, long and "
                       "constant (Fig. 6 top)",
    "A4 babbling": "at least half of the best robots babble in at least half of their trials "
                   "without the ball (Fig. 8)",
}


def robot_profiles(table: pl.DataFrame, criteria: Criteria = Criteria()) -> pl.DataFrame:
    """One row per robot (replication, rank) of a post-evaluation table: ``profiles``'s means
    and, per robot, ``is_babbling_no_ball`` (babbling in at least ``criteria.babbling_share``
    of its trials without the ball) and ``moves_as_paper`` (elbow locked, arm extended and
    babbling without the ball: every criterion but reach)."""
    return (profiles(table, ("replication", "rank"), criteria)
            .with_columns(is_babbling_no_ball=pl.col("babbling_no_ball").fill_nan(0.0)
                          >= criteria.babbling_share)
            .with_columns(moves_as_paper=pl.col("is_elbow_locked") & pl.col("is_arm_extended")
                          & pl.col("is_babbling_no_ball")))


def paper_units(table: pl.DataFrame, extension: tuple[float, float],
                criteria: Criteria = Criteria(), babbling_sensitivity: float = 1.0,
                phase: str = "pre") -> dict:
    """The paper's pre-reacher judged in its own units (``PAPER_UNITS``) for one population:
    ``table`` holds its best robots' trials (every replication's, normal and no-ball), and
    ``extension`` is the best robot's (mean palm-shoulder distance in m, mean CV) from 2 s on
    (``measures.metrics.arm_extension``). Returns the measures, each criterion as a bool
    (``A1``-``A4``), ``paper`` (all four), and A5: ``still`` replications of ``replications``
    (``analysis.strategies``: babbling in fewer than 1 in 20 normal trials) with the share's
    exact 95 % interval. ``phase``: the phase of ``table``'s trials (the criteria are
    pre-reaching's; a later phase's snapshots are described in the same measures).

    ``A4_failed``: A4 is not met even if the babbling measure found only
    ``babbling_sensitivity`` of the babbling trials (the lowest its validation allows): fewer
    than half of the robots babble in at least ``babbling_share`` x ``babbling_sensitivity``
    of their no-ball trials (docs/results/campaign.md, "Addendum"). At sensitivity 1 it is
    ``not A4``; between the two, A4 is not decided by the measure."""
    if not 0 < babbling_sensitivity <= 1:
        raise ValueError(f"a sensitivity is in (0, 1], got {babbling_sensitivity}")
    normal = table.filter(pl.col("senses") == "normal")
    if normal.is_empty():
        raise ValueError("no trial with the ball (senses 'normal') in the table")
    robots = robot_profiles(table, criteria)
    if robots["babbling_no_ball"].is_nan().any():
        raise ValueError("A4 needs every robot's trials without the ball (senses 'no-ball')")
    mean = {c: float(normal[c].cast(pl.Float64).mean())
            for c in ("reached", "var_elbow", "var_shoulder", "var_trunk")}
    babblers = int(robots["is_babbling_no_ball"].sum())
    possible = int((robots["babbling_no_ball"]
                    >= criteria.babbling_share * babbling_sensitivity).sum())
    strat = strategies(table, phase, by=("replication",))
    still = int((strat["strategy"] == STILL).sum())
    low, high = criteria.reach_band
    hs, cv = extension
    out = {"reach": mean["reached"], "elbow_sd": mean["var_elbow"],
           "shoulder_sd": mean["var_shoulder"], "trunk_sd": mean["var_trunk"],
           "hand_shoulder_m": hs, "hand_shoulder_cv": cv, "robots": robots.height,
           "babbling_robots": babblers, "replications": strat.height, "still": still,
           "still_interval": share_interval(still, strat.height),
           "A1": low <= mean["reached"] <= high,
           "A2": mean["var_elbow"] < min(mean["var_shoulder"], mean["var_trunk"]),
           "A3": bool(hs >= criteria.extended_m and cv < criteria.constant_cv),
           "A4": babblers >= robots.height * criteria.babbling_share,
           "A4_failed": possible < robots.height * criteria.babbling_share}
    out["paper"] = all(out[k] for k in ("A1", "A2", "A3", "A4"))
    return out
