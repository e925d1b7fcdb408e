"""The development of a measure over the generations of a condition's phases (not a paper
figure; ``snapshots.course``)."""

from __future__ import annotations

import polars as pl
from matplotlib import colormaps
from matplotlib.figure import Figure

from ..strategies import STILL


def development_figure(course_table: pl.DataFrame, measure: str, label: str | None = None,
                       condition: str | None = None) -> Figure:
    """The course of one measure over the generations of a condition's phases
    (``snapshots.course``): a thin line per replication, the median over replications in
    black, a dashed line where each phase starts (its name above). ``condition``: default
    "standard" if present, else the first."""
    conditions = course_table["condition"].unique(maintain_order=True).to_list()
    if condition is None:
        condition = "standard" if "standard" in conditions or not conditions else conditions[0]
    sub = course_table.filter(pl.col("condition") == condition).sort("x")
    fig = Figure(figsize=(8, 3.4), layout="constrained")
    ax = fig.subplots()
    if sub.height == 0 or measure not in sub.columns:
        ax.text(0.5, 0.5, f"no development data for {measure!r}", transform=ax.transAxes,
                ha="center", va="center", color="0.4")
        return fig
    reps = sorted(sub["replication"].unique().to_list())
    cmap = colormaps["tab10"]
    for i, r in enumerate(reps):
        line = sub.filter(pl.col("replication") == r)
        ax.plot(line["x"], line[measure], color=cmap(i % 10), linewidth=0.8, alpha=0.6,
                marker=".", markersize=3, label=f"rep {r}")
    median = (sub.group_by("x").agg(pl.col(measure).fill_nan(None).median()).sort("x"))
    ax.plot(median["x"], median[measure], color="black", linewidth=1.8, label="median")
    starts = (sub.group_by("notation", "offset").agg(pl.col("x").min()).sort("offset"))
    for row in starts.iter_rows(named=True):
        ax.axvline(row["offset"], color="0.5", linestyle="--", linewidth=0.8)
        ax.text(row["offset"], 1.01, f" {row['notation']}", transform=ax.get_xaxis_transform(),
                fontsize=8, va="bottom")
    ax.set_xlabel(f"generation ({condition}: counted through its phases)")
    ax.set_ylabel(label or measure)
    ax.grid(alpha=0.3)
    if len(reps) <= 10:
        ax.legend(fontsize=7, ncol=min(len(reps) + 1, 6), loc="best")
    return fig


#: The panels of ``strategy_figure``: column of ``strategy_course.course`` -> axis label.
STRATEGY_PANELS = {"babbling_share": "share of trials that babble",
                   "fitness": "fitness (Eq. 5, post-evaluation)"}


def strategy_figure(course_table: pl.DataFrame, still_share: float) -> Figure:
    """The course of the pre-reaching strategies (``strategy_course.course``, not a paper
    figure): per replication, one line over the snapshots' generations in each of
    ``STRATEGY_PANELS``, a filled marker where the population babbles and an open one where it
    is still; the stillness threshold ``still_share`` dashed in the first panel."""
    fig = Figure(figsize=(8.5, 5.2), layout="constrained")
    axes = fig.subplots(len(STRATEGY_PANELS), 1, sharex=True)
    cmap = colormaps["tab10"]
    reps = sorted(course_table["replication"].unique().to_list())
    for ax, (column, label) in zip(axes, STRATEGY_PANELS.items()):
        for i, r in enumerate(reps):
            line = course_table.filter(pl.col("replication") == r).sort("generation")
            colour = cmap(i % 10)
            ax.plot(line["generation"], line[column], color=colour, linewidth=0.9, alpha=0.7,
                    label=f"rep {r}")
            still = (line["strategy"] == STILL).to_numpy()
            x, y = line["generation"].to_numpy(), line[column].to_numpy()
            ax.scatter(x[~still], y[~still], color=colour, s=14, zorder=3)
            ax.scatter(x[still], y[still], facecolor="white", edgecolor=colour, s=14,
                       zorder=3)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].axhline(still_share, color="0.3", linestyle="--", linewidth=0.8)
    axes[0].text(0.995, still_share, "still below", transform=axes[0].get_yaxis_transform(),
                 ha="right", va="bottom", fontsize=7, color="0.3")
    axes[-1].set_xlabel("generation of pre-reaching (filled: babbling, open: still)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="outside right upper")
    return fig
