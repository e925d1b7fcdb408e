"""Statistics of the paper's comparisons (section IV-A, IV-B, IV-C; Figs. 5, 6, 9, 10).

The tests:

- ``kruskal_wallis``: does a value differ among several groups (section IV-B: "performance
  significantly varies within the four experimental conditions ... Kruskal-Wallis test");
- ``mann_whitney``: every pair of groups, two-tailed Mann-Whitney U test (Figs. 9, 10,
  "p < 0.05, two tailed Mann-Whitney U test");
- ``significance_matrix``: the pairs as a square table of booleans, the black squares of the
  comparison tables of Figs. 9 and 10;
- ``holm``: the pairs' p-values corrected for multiple comparisons (Holm 1979), which the
  paper does not report: Figs. 9 and 10 compare up to 66 pairs; ``holm_adjusted``: the same
  correction of an array of p-values (the findings table's ``p_holm``).

Inputs are long polars tables: one row per unit (a robot in Fig. 9, a replication in Fig. 10),
a ``value`` column and a ``group`` column. Null and NaN values are dropped before testing (e.g.
a reaching speed is NaN for a robot that never reaches).

Degenerate samples: when every value of the samples compared is the same number (e.g. all
robots of two conditions score 0) there is no evidence of a difference: the tests return
H = 0 (Kruskal-Wallis) or U = n_a n_b / 2 (Mann-Whitney) and p = 1.0 rather than NaN.

The numbers behind the figures (what a notebook shows beside each figure, and the report's
statistics), from the post-evaluation table (``tables.condition_trials``) or the
per-replication table of Fig. 10:

- ``performance_summary``: mean, s.d. and s.e.m. over robots of each measure per phase (the
  bars of Figs. 5, 6 and of motor babbling);
- ``phase_statistics``: Mann-Whitney between every pair of phases for each measure (the
  p-values section IV-A quotes for Figs. 5 and 6);
- ``fig9_statistics``, ``fig10_statistics``: the summaries, tests and significance matrices
  of Figs. 9 and 10 (``group_order``: the groups of Fig. 10 in order).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np
import polars as pl
from scipy import stats as sps

from . import summaries
from ..postevaluation.systematic import SENSES
from .tables import phase_list, select_trials


def _require(df: pl.DataFrame, columns: Sequence[str]) -> None:
    missing = [c for c in columns if c not in df.columns]
    if missing:
        raise ValueError(f"table lacks the column(s) {missing}; it has {df.columns}")


def _samples(df: pl.DataFrame, value: str, group: str, order=None) -> dict:
    """{group name: finite float values} in ``order`` (default: first appearance)."""
    _require(df, [value, group])
    names = df[group].unique(maintain_order=True).to_list()
    if order is None:
        order = names
    else:
        order = list(order)
        unknown = [g for g in order if g not in names]
        if unknown:
            raise ValueError(f"groups {unknown} not in column {group!r} (it has {names})")
        if len(set(order)) != len(order):
            raise ValueError(f"order repeats a group: {order}")
    out = {}
    for g in order:
        x = df.filter(pl.col(group) == g)[value].drop_nulls().cast(pl.Float64).to_numpy()
        out[g] = x[~np.isnan(x)]
    return out


def _all_equal(*samples: np.ndarray) -> bool:
    x = np.concatenate(samples)
    return len(x) > 0 and bool(np.all(x == x[0]))


def kruskal_wallis(df: pl.DataFrame, value: str, group: str) -> pl.DataFrame:
    """Kruskal-Wallis H test of ``value`` across the groups of column ``group``
    (``scipy.stats.kruskal``: tie-corrected H, p from the chi-square distribution with
    groups - 1 degrees of freedom). Section IV-B.

    Returns one row: groups (number of groups with at least one value), n (values tested),
    H, p. Groups with no (non-null, non-NaN) value are left out. All values equal: H = 0,
    p = 1. ValueError for a missing column or fewer than 2 groups.
    """
    samples = [x for x in _samples(df, value, group).values() if len(x)]
    if len(samples) < 2:
        raise ValueError(f"Kruskal-Wallis needs at least 2 groups with values in column "
                         f"{group!r}, got {len(samples)}")
    if _all_equal(*samples):
        h, p = 0.0, 1.0
    else:
        res = sps.kruskal(*samples)
        h, p = float(res.statistic), float(res.pvalue)
    return pl.DataFrame({"groups": [len(samples)], "n": [sum(len(x) for x in samples)],
                         "H": [h], "p": [p]})


def mann_whitney(df: pl.DataFrame, value: str, group: str, order: Sequence | None = None,
                 alpha: float = 0.05) -> pl.DataFrame:
    """Two-tailed Mann-Whitney U test of ``value`` between every unordered pair of groups
    (Figs. 9, 10).

    ``order``: the groups to compare, in the order of the pairs (a before b); default all the
    groups of column ``group`` in order of first appearance. Uses
    ``scipy.stats.mannwhitneyu(a, b, alternative="two-sided")`` with its default method: exact
    p for samples of at most 8 values without ties, otherwise the normal approximation with
    tie correction and continuity correction. No correction for multiple comparisons (the paper
    reports none).

    Returns one row per pair: a, b, n_a, n_b, U (the statistic of sample a: number of pairs
    (x in a, y in b) with x > y, ties counting 1/2), p, significant (p < alpha). Both samples
    constant and equal: U = n_a n_b / 2, p = 1. A sample without values: U and p NaN,
    significant False. ValueError for a missing column, an unknown or repeated group in
    ``order``, fewer than 2 groups, or alpha outside (0, 1).
    """
    if not 0.0 < alpha < 1.0:
        raise ValueError(f"alpha must be in (0, 1), got {alpha!r}")
    samples = _samples(df, value, group, order)
    if len(samples) < 2:
        raise ValueError(f"Mann-Whitney needs at least 2 groups in column {group!r}, "
                         f"got {len(samples)}")
    rows = []
    for a, b in itertools.combinations(samples, 2):
        x, y = samples[a], samples[b]
        if len(x) == 0 or len(y) == 0:
            u, p = math.nan, math.nan
        elif _all_equal(x, y):
            u, p = len(x) * len(y) / 2.0, 1.0
        else:
            res = sps.mannwhitneyu(x, y, alternative="two-sided")
            u, p = float(res.statistic), float(res.pvalue)
        rows.append({"a": a, "b": b, "n_a": len(x), "n_b": len(y), "U": u, "p": p,
                     "significant": bool(p < alpha)})
    return pl.DataFrame(rows, schema_overrides={"U": pl.Float64, "p": pl.Float64})


#: Resamples of ``bootstrap_mean_interval``.
RESAMPLES = 10_000


def bootstrap_mean_interval(units, rng: np.random.Generator, confidence: float = 0.95
                            ) -> tuple[float, float, float]:
    """Mean of ``units`` and its percentile bootstrap interval (``RESAMPLES`` resamples): a
    description for the studies (many units), not a verdict rule (``verdicts`` uses Student's
    t, calibrated at the runs' few replications)."""
    x = np.asarray(units, float)
    x = x[np.isfinite(x)]
    means = x[rng.integers(0, len(x), (RESAMPLES, len(x)))].mean(axis=1)
    tail = (1 - confidence) / 2
    return float(x.mean()), float(np.quantile(means, tail)), float(np.quantile(means, 1 - tail))


def holm_adjusted(p: Sequence[float]) -> np.ndarray:
    """Holm's step-down adjusted p-values of ``p`` (Holm 1979), in the order given: the j-th
    smallest of the m tested, p_(j), becomes the maximum over k <= j of min(1, (m - k + 1)
    p_(k)), as ``statsmodels.stats.multitest.multipletests(p, method="holm")``. A NaN p is left
    out of the family (not counted in m) and stays NaN. This controls the family-wise error
    rate without assuming independence."""
    p = np.array(p, dtype=float)
    tested = np.flatnonzero(~np.isnan(p))
    adjusted = np.full(len(p), np.nan)
    order = tested[np.argsort(p[tested], kind="stable")]
    m = len(order)
    running = 0.0
    for j, k in enumerate(order):
        running = max(running, min(1.0, (m - j) * p[k]))
        adjusted[k] = running
    return adjusted


def holm(pairs: pl.DataFrame, alpha: float = 0.05) -> pl.DataFrame:
    """``pairs`` (``mann_whitney``'s table) with ``p_holm`` and ``significant_holm``: the
    p-values adjusted by Holm's step-down method over the family of every tested pair
    (``holm_adjusted``: rows with a NaN p are left out of the family and stay NaN), which
    controls the family-wise error rate at ``alpha``. An empty table gets the two columns,
    empty."""
    if not 0.0 < alpha < 1.0:
        raise ValueError(f"alpha must be in (0, 1), got {alpha!r}")
    _require(pairs, ["p"])
    adjusted = holm_adjusted(pairs["p"].cast(pl.Float64).to_numpy())
    return pairs.with_columns(pl.Series("p_holm", adjusted, dtype=pl.Float64),
                              pl.Series("significant_holm", np.nan_to_num(adjusted, nan=1.0)
                                        < alpha))


def significance_matrix(pairs: pl.DataFrame, order: Sequence | None = None,
                        column: str = "significant") -> pl.DataFrame:
    """Square table of the significant pairs of ``mann_whitney`` (the black squares of the
    comparison tables of Figs. 9 and 10).

    ``order``: the groups (rows and columns), default in order of first appearance in columns
    a then b; pairs with a group outside ``order`` are ignored. Group names are turned into
    strings. Returns column "group" (str) then one bool column per group: True where the pair
    is significant, False elsewhere (diagonal, non-significant or untested pairs); symmetric.
    ``column``: the column that says significant (``significant_holm`` after ``holm``).
    """
    _require(pairs, ["a", "b", column])
    if order is None:
        order = list(dict.fromkeys(pairs["a"].to_list() + pairs["b"].to_list()))
    names = [str(g) for g in order]
    if len(set(names)) != len(names):
        raise ValueError(f"order repeats a group: {names}")
    if "group" in names:
        raise ValueError('a group may not be called "group" (the name column)')
    index = {g: i for i, g in enumerate(names)}
    sig = np.zeros((len(names), len(names)), bool)
    for a, b, s in zip(pairs["a"].to_list(), pairs["b"].to_list(),
                       pairs[column].to_list()):
        i, j = index.get(str(a)), index.get(str(b))
        if i is None or j is None or i == j or not s:
            continue
        sig[i, j] = sig[j, i] = True
    return pl.DataFrame({"group": names, **{g: sig[:, k] for k, g in enumerate(names)}},
                        schema={"group": pl.Utf8, **{g: pl.Boolean for g in names}})


# ---------------------------------------------------------------------------------------------
# The numbers behind the figures
# ---------------------------------------------------------------------------------------------

#: The columns that name one robot in the post-evaluation table.
_ROBOT = ("phase", "replication", "rank")


def performance_summary(table: pl.DataFrame, measures: Sequence[str],
                        phases: Sequence[str] | None = None,
                        senses: str = "normal") -> pl.DataFrame:
    """Mean, s.d. and s.e.m. over robots of each measure per phase (the bars of Figs. 5, 6 and
    ``fig8_babbling``): ``summaries.group_summary`` of ``summaries.robot_means`` of the trials of
    ``senses``, phases in the order given."""
    phases = phase_list(table, phases)
    robots = summaries.robot_means(select_trials(table, phases, senses), measures, by=_ROBOT)
    summary = summaries.group_summary(robots, measures, by=("phase",))
    rank = {p: i for i, p in enumerate(phases)}
    return (summary.with_columns(pl.col("phase").replace_strict(rank, return_dtype=pl.Int64)
                                 .alias("_p"))
            .sort("_p", maintain_order=True).drop("_p"))


_PAIRS_SCHEMA = {"a": pl.Utf8, "b": pl.Utf8, "n_a": pl.Int64, "n_b": pl.Int64, "U": pl.Float64,
                 "p": pl.Float64, "significant": pl.Boolean}


def _pairs(units: pl.DataFrame, value: str, group: str, order: list,
           alpha: float) -> pl.DataFrame:
    """``mann_whitney`` of the groups of ``order`` that have rows (an empty table of pairs when
    fewer than two have)."""
    present = set(units[group].cast(pl.Utf8).to_list())
    order = [g for g in order if g in present]
    if len(order) < 2:
        return pl.DataFrame(schema=_PAIRS_SCHEMA)
    units = units.with_columns(pl.col(group).cast(pl.Utf8))
    return mann_whitney(units, value, group, order=order, alpha=alpha)


def phase_statistics(table: pl.DataFrame, measures: Sequence[str],
                     phases: Sequence[str] | None = None, senses: str = "normal",
                     alpha: float = 0.05) -> pl.DataFrame:
    """Two-tailed Mann-Whitney U tests between every pair of phases for each measure, the robot
    being the unit (its mean over its trials): the p-values section IV-A quotes for Figs. 5 and
    6. Columns: measure, then those of ``mann_whitney``."""
    phases = phase_list(table, phases)
    robots = summaries.robot_means(select_trials(table, phases, senses), measures, by=_ROBOT)
    parts = [_pairs(robots, m, "phase", phases, alpha)
             .with_columns(pl.lit(m).alias("measure")) for m in measures]
    out = pl.concat(parts, how="diagonal_relaxed") if parts else pl.DataFrame(schema=_PAIRS_SCHEMA)
    if "measure" not in out.columns:
        out = out.with_columns(pl.lit(None, pl.Utf8).alias("measure"))
    return out.select("measure", *_PAIRS_SCHEMA)


def fig9_statistics(table: pl.DataFrame, phases: Sequence[str] | None = None,
                    senses: Sequence[str] = SENSES, alpha: float = 0.05) -> dict[str, pl.DataFrame]:
    """The numbers of Fig. 9: ``robots`` (one row per robot: ``summaries.robot_performance`` of
    each phase x senses, with its group label "phase / senses"), ``summary`` (mean, s.d., s.e.m.
    of the robots' fitness per phase and senses), ``kruskal`` (Kruskal-Wallis across senses
    within each phase, section IV-B; NaN when fewer than two sensory conditions have robots),
    ``pairs`` (two-tailed Mann-Whitney between every pair of groups, with ``p_holm``: Holm's
    correction over the pairs, ``holm``), ``matrix`` (the pairs as the square table of
    ``significance_matrix``, uncorrected as in the paper) and ``matrix_holm`` (the same
    after Holm's correction)."""
    phases = phase_list(table, phases)
    senses = list(senses)
    robots = summaries.robot_performance(select_trials(table, phases, senses),
                                         by=("phase", "senses", "replication", "rank"))
    robots = robots.with_columns(pl.format("{} / {}", "phase", "senses").alias("group"))
    summary = summaries.group_summary(robots, ["fitness"], by=("phase", "senses"))
    order = [f"{p} / {s}" for p in phases for s in senses]
    key = {g: i for i, g in enumerate(order)}
    summary = (summary.with_columns(pl.format("{} / {}", "phase", "senses")
                                    .replace_strict(key, return_dtype=pl.Int64).alias("_k"))
               .sort("_k").drop("_k"))
    kw_rows = []
    for p in phases:
        try:
            kw = kruskal_wallis(robots.filter(pl.col("phase") == p), "fitness", "senses")
            kw_rows.append({"phase": p, **kw.row(0, named=True)})
        except ValueError:
            kw_rows.append({"phase": p, "groups": 0, "n": 0, "H": math.nan, "p": math.nan})
    kruskal = pl.DataFrame(kw_rows, schema={"phase": pl.Utf8, "groups": pl.Int64, "n": pl.Int64,
                                            "H": pl.Float64, "p": pl.Float64})
    present = set(robots["group"].to_list())
    order = [g for g in order if g in present]
    pairs = holm(_pairs(robots, "fitness", "group", order, alpha), alpha)
    return {"robots": robots, "summary": summary, "kruskal": kruskal, "pairs": pairs,
            "matrix": significance_matrix(pairs, order),
            "matrix_holm": significance_matrix(pairs, order, "significant_holm")}


def group_order(replications: pl.DataFrame, order: Sequence[str] | None = None) -> list[str]:
    """The groups of Fig. 10 in order: ``order`` if given, else the categories of the
    ``group`` Enum (``tables.load_runs``) that have rows, else order of first appearance."""
    if order is not None:
        return [str(g) for g in order]
    dtype = replications.schema["group"]
    if isinstance(dtype, pl.Enum):
        present = set(replications["group"].cast(pl.Utf8).to_list())
        return [g for g in dtype.categories.to_list() if g in present]
    return [str(g) for g in dict.fromkeys(replications["group"].to_list())]


def fig10_statistics(replications: pl.DataFrame, order: Sequence[str] | None = None,
                     value: str = "fitness", alpha: float = 0.05) -> dict[str, pl.DataFrame]:
    """The numbers of Fig. 10 from a per-replication table with a ``group`` column (e.g.
    ``summaries.replication_performance(tables.load_runs(dirs), by=("group",))``):
    ``summary`` (per group: replications, median, mean, min, max of ``value``; the median is
    the thickness of the boxes of the paper's top diagram), ``pairs`` (two-tailed Mann-Whitney
    between every pair of groups, with Holm's ``p_holm``), ``matrix``
    (``significance_matrix``, uncorrected as in the paper) and ``matrix_holm`` (after Holm's
    correction)."""
    groups = group_order(replications, order)
    units = replications.with_columns(pl.col("group").cast(pl.Utf8))
    key = {g: i for i, g in enumerate(groups)}
    summary = (units.filter(pl.col("group").is_in(groups))
               .with_columns(pl.col(value).cast(pl.Float64).fill_nan(None))
               .group_by("group")
               .agg(pl.col(value).count().alias("replications"),
                    pl.col(value).median().alias("median"), pl.col(value).mean().alias("mean"),
                    pl.col(value).min().alias("min"), pl.col(value).max().alias("max"))
               .with_columns(pl.col("group").replace_strict(key, return_dtype=pl.Int64)
                             .alias("_k"))
               .sort("_k").drop("_k"))
    pairs = holm(_pairs(units, value, "group", groups, alpha), alpha)
    present = [g for g in groups if g in set(units["group"].to_list())]
    return {"summary": summary, "pairs": pairs,
            "matrix": significance_matrix(pairs, present),
            "matrix_holm": significance_matrix(pairs, present, "significant_holm")}
