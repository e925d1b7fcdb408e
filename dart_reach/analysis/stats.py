"""Statistics of the paper's comparisons (section IV-B, IV-C; Figs. 9, 10).

- ``kruskal_wallis``: does a value differ among several groups (section IV-B: "performance
  significantly varies within the four experimental conditions ... Kruskal-Wallis test");
- ``mann_whitney``: every pair of groups, two-tailed Mann-Whitney U test (Figs. 9, 10,
  "p < 0.05, two tailed Mann-Whitney U test");
- ``significance_matrix``: the pairs as a square table of booleans, the black squares of the
  comparison tables of Figs. 9 and 10;
- ``holm``: the pairs' p-values corrected for multiple comparisons (Holm 1979), which the
  paper does not report: Figs. 9 and 10 compare up to 66 pairs.

Inputs are long polars tables: one row per unit (a robot in Fig. 9, a replication in Fig. 10),
a ``value`` column and a ``group`` column. Null and NaN values are dropped before testing (e.g.
a reaching speed is NaN for a robot that never reaches).

Degenerate samples: when every value of the samples compared is the same number (e.g. all
robots of two conditions score 0) there is no evidence of a difference: the tests return
H = 0 (Kruskal-Wallis) or U = n_a n_b / 2 (Mann-Whitney) and p = 1.0 rather than NaN.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np
import polars as pl
from scipy import stats as sps


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


def holm(pairs: pl.DataFrame, alpha: float = 0.05) -> pl.DataFrame:
    """``pairs`` (``mann_whitney``'s table) with ``p_holm`` and ``significant_holm``: the
    p-values adjusted by Holm's step-down method over the family of every tested pair (rows
    with a NaN p are left out of the family and stay NaN), which controls the family-wise
    error rate at ``alpha`` without assuming independence. Adjusted p = max over the first i
    sorted p of (m - j + 1) p_(j), capped at 1."""
    if not 0.0 < alpha < 1.0:
        raise ValueError(f"alpha must be in (0, 1), got {alpha!r}")
    _require(pairs, ["p"])
    p = pairs["p"].cast(pl.Float64).to_numpy().copy()
    tested = np.flatnonzero(~np.isnan(p))
    adjusted = np.full(len(p), np.nan)
    order = tested[np.argsort(p[tested], kind="stable")]
    m = len(order)
    running = 0.0
    for j, k in enumerate(order):
        running = max(running, min(1.0, (m - j) * p[k]))
        adjusted[k] = running
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
