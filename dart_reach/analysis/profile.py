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
