"""What the figures share: the colours of the sensory conditions and of the phases, the bar
panel of Figs. 5, 6 and 8 (mean $\\pm$ s.e.m. over robots per phase, "n/a" where there is no
value) and the square table of the significant pairs of Figs. 9 and 10."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import polars as pl
from matplotlib import colormaps
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure

from ..stats import performance_summary

#: Colours of the sensory conditions (section IV-B, Figs. 8, 9).
SENSES_COLOURS = {"normal": "#333333", "no-touch": "#1f77b4", "no-sight": "#ff7f0e",
                  "nothing": "#d62728"}


def phase_colours(phases: Sequence[str]) -> dict[str, tuple]:
    """A colour per phase, in the order given (matplotlib's tab10)."""
    cmap = colormaps["tab10"]
    return {p: cmap(i % 10) for i, p in enumerate(phases)}


def mark_na(ax, x, text="n/a") -> None:
    """Write ``text`` at the foot of ``ax`` at ``x``: a slot without data."""
    ax.text(x, 0.02, text, transform=ax.get_xaxis_transform(), ha="center", va="bottom",
            fontsize=9, color="0.4")


def bar_panel(ax, summary: pl.DataFrame, measure: str, phases: Sequence[str], scale: float,
              label: str, colours: dict) -> None:
    """One bar per phase of ``measure`` (times ``scale``) from ``summary``
    (``stats.performance_summary``), its s.e.m. as error bar, n under each phase."""
    rows = {r["phase"]: r for r in summary.filter(pl.col("measure") == measure)
            .iter_rows(named=True)}
    x = np.arange(len(phases))
    top = 0.0
    for i, p in enumerate(phases):
        r = rows.get(p)
        mean = r["mean"] * scale if r else math.nan
        sem = r["sem"] * scale if r else math.nan
        if math.isfinite(mean):
            ax.bar(i, mean, color=colours[p], width=0.65, edgecolor="black", linewidth=0.6)
            if math.isfinite(sem):
                ax.errorbar(i, mean, yerr=sem, color="black", capsize=4, linewidth=1)
            top = max(top, mean + (sem if math.isfinite(sem) else 0.0))
        else:
            mark_na(ax, i)
    ax.set_xticks(x, [f"{p}\nn={rows[p]['n'] if p in rows else 0}" for p in phases])
    ax.set_xlim(-0.6, len(phases) - 0.4)
    ax.set_ylim(0, top * 1.15 if top > 0 else 1.0)
    ax.set_ylabel(label)
    ax.grid(axis="y", alpha=0.3)


def bars_figure(table, measures, phases, senses, grid, size):
    """A figure of one bar panel per (measure, label, scale) of ``measures``, phases as bars."""
    summary = performance_summary(table, [m for m, _, _ in measures], phases, senses)
    colours = phase_colours(phases)
    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(*grid)
    for ax, (m, label, scale) in zip(axes.ravel(), measures):
        bar_panel(ax, summary, m, phases, scale, label, colours)
    return fig, axes


def draw_matrix(ax, st: dict, alpha: float) -> None:
    """The pairs of ``st`` (``fig9_statistics``, ``fig10_statistics``) as a square table:
    black where p < alpha after Holm's correction over the pairs, grey where only the
    uncorrected p (the paper's test) is below alpha."""
    matrix = st["matrix"]
    names = matrix["group"].to_list()
    n = len(names)
    sig = (matrix.drop("group").to_numpy().astype(float)
           + st["matrix_holm"].drop("group").to_numpy().astype(float)) if n else np.zeros((0, 0))
    if n:
        np.fill_diagonal(sig, np.nan)
    cmap = ListedColormap(["white", "0.62", "black"]).with_extremes(bad="0.9")
    ax.imshow(np.ma.masked_invalid(sig) if n else np.zeros((1, 1)), cmap=cmap, vmin=0, vmax=2,
              interpolation="nearest")
    ax.set_xticks(range(n), names, rotation=90, fontsize=9)
    ax.set_yticks(range(n), names, fontsize=9)
    ax.set_xticks(np.arange(-0.5, n, 1), minor=True)
    ax.set_yticks(np.arange(-0.5, n, 1), minor=True)
    ax.grid(which="minor", color="0.5", linewidth=0.5)
    ax.tick_params(which="minor", length=0)
    tested = int(st["pairs"]["p"].is_not_nan().sum()) if st["pairs"].height else 0
    ax.set_title(f"Mann-Whitney, two-tailed, {tested} pairs\nblack: p < {alpha:g} after Holm\n"
                 f"grey: p < {alpha:g} uncorrected only", fontsize=9)
    if n < 2:
        ax.text(0.5, 0.5, "fewer than 2 groups", transform=ax.transAxes, ha="center",
                va="center", fontsize=9, color="0.4")
