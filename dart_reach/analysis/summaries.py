"""Summaries of post-evaluation tables (paper section IV-A, Figs. 5, 7, 9 and 10).

Each function takes a polars post-evaluation table (one row per trial, with at least ``phase``,
``sector``, ``reached``, ``grasped`` and grouping columns such as ``senses``, ``replication``,
``rank``) and returns a polars table: ``sector_success`` / ``sector_grid`` (Fig. 7),
``reach_regression`` (section IV-A-2), ``robot_performance`` (the per-robot unit of Fig. 9's
statistics), ``replication_performance`` (Fig. 10's unit), ``peripersonal_space`` and
``condition_contrast``. Rates are fractions in [0, 1] (the paper's figures show percentages).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import polars as pl

#: Sectors of the ball's area (Fig. 2): 3 elevation rows x 3 azimuth columns.
SECTOR_ROWS = SECTOR_COLS = 3



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
