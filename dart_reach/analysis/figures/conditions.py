"""Fig. 10: the performance of every phase of every condition, one value per replication."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import polars as pl
from matplotlib.figure import Figure

from ..stats import fig10_statistics, group_order
from .style import draw_matrix, mark_na

#: Fewer values than this in a group of Fig. 10: dots and their median, no box plot.
BOX_MIN = 5


def fig10_conditions(replications: pl.DataFrame, order: Sequence[str] | None = None,
                     value: str = "fitness", alpha: float = 0.05) -> Figure:
    """Fig. 10 (bottom). Left: the per-replication performance of every group (a phase of a
    condition: ``tables.load_runs`` then ``summaries.replication_performance(..., by=("group",))``),
    each replication a dot, with a box plot where a group has at least ``BOX_MIN`` values
    (a red line at the median otherwise). Right: black squares where two groups differ
    (two-tailed Mann-Whitney, p < ``alpha`` after Holm's correction; grey: uncorrected
    only). See ``fig10_statistics``."""
    groups = group_order(replications, order)
    st = fig10_statistics(replications, groups, value, alpha)
    # room for the matrix's labels: a square of one row per group beside the box plots
    fig = Figure(figsize=(12 + 0.1 * len(groups), max(5.2, 3.0 + 0.3 * len(groups))),
                 layout="constrained")
    grid = fig.add_gridspec(1, 2, width_ratios=[1.5, 1])
    ax = fig.add_subplot(grid[0, 0])
    units = replications.with_columns(pl.col("group").cast(pl.Utf8))
    rng = np.random.default_rng(0)
    for i, g in enumerate(groups):
        x = units.filter(pl.col("group") == g)[value].cast(pl.Float64).to_numpy()
        x = x[np.isfinite(x)]
        if len(x) == 0:
            mark_na(ax, i + 1)
            continue
        if len(x) >= BOX_MIN:
            ax.boxplot([x], positions=[i + 1], widths=0.55, showfliers=False,
                       medianprops={"color": "#d62728", "linewidth": 1.5})
        else:  # a strip plot: too few values for quartiles
            ax.hlines(np.median(x), i + 0.75, i + 1.25, color="#d62728", linewidth=1.5)
        ax.plot(i + 1 + rng.uniform(-0.12, 0.12, len(x)), x, "o", color="#1f77b4",
                markersize=5, alpha=0.8)
    counts = {r["group"]: r["replications"] for r in st["summary"].iter_rows(named=True)}
    ax.set_xticks(range(1, len(groups) + 1), [f"{g} (n={counts.get(g, 0)})" for g in groups],
                  rotation=45 if len(groups) > 5 else 0,
                  ha="right" if len(groups) > 5 else "center", rotation_mode="anchor")
    ax.set_xlim(0.4, len(groups) + 0.6)
    ax.set_ylabel(f"{value} per replication\n(post-evaluation, best robot)")
    ax.grid(axis="y", alpha=0.3)
    ax.set_title(f"n: replications per group; a box plot from {BOX_MIN} replications; red "
                 f"line: median", fontsize=9, loc="left")
    draw_matrix(fig.add_subplot(grid[0, 1]), st, alpha)
    fig.suptitle("Fig. 10 - performance of every phase and condition", fontsize=10)
    return fig
