"""Each claim's effect against the budget (generations per phase) of runs trained at several
budgets (not a paper figure; ``budgets.findings_by_budget``)."""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence

import numpy as np
import polars as pl
from matplotlib import colormaps
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator

from .. import budgets

#: Colours of how a claim's intervals lie as the budget grows (``budgets.movement``): greys,
#: darker where they are apart; no green or red, as the words state no result.
MOVEMENT_COLOURS = {budgets.APART_HIGHER: "0.1", budgets.APART_LOWER: "0.1",
                    budgets.OVERLAP: "0.35", budgets.NO_INTERVAL: "0.55",
                    budgets.NOT_RUN: "0.55"}


def budget_figure(by_budget: pl.DataFrame, claims: Sequence[str] | None = None,
                  columns: int = 5) -> Figure:
    """Each claim's effect against the generations per phase (x, log scale) of the budgets of
    ``by_budget`` (``budgets.findings_by_budget``): one small panel per claim, the effect on
    the scale where up is the paper's direction (``budgets.toward_paper``; the claim's own
    units, the dashed line at 0: no effect, or the claim's boundary) with its interval (a
    hollow point: none, or an unbounded one), a line per series (a scene, a number of
    replications and a model), and how the claim's intervals lie as the budget grows
    (``budgets.movement``, a description, not a test) under the panel, in its grey.
    ``claims``: the claim ids to draw (default: those with an effect at two budgets or more),
    in the frame's order."""
    scored = budgets.with_series(budgets.toward_paper(by_budget))
    if claims is None:
        counts = (scored.filter(pl.col("toward").is_not_nan())
                  .group_by("claim").len().filter(pl.col("len") >= 2))
        claims = [c for c in scored["claim"].unique(maintain_order=True).to_list()
                  if c in set(counts["claim"].to_list())]
    claims = list(claims)
    moves = budgets.movement(by_budget)
    lines = scored["series"].unique(maintain_order=True).to_list()
    colours = ({lines[0]: "0.15"} if len(lines) == 1
               else {s: colormaps["tab10"](i % 10) for i, s in enumerate(lines)})
    gens = sorted(scored["generations_per_phase"].unique().to_list())
    if not claims:
        fig = Figure(figsize=(8, 2), layout="constrained")
        ax = fig.subplots()
        ax.axis("off")
        ax.text(0.5, 0.5, "no claim has an effect at two budgets", ha="center", va="center",
                color="0.4", fontsize=10)
        return fig
    rows = math.ceil(len(claims) / columns)
    fig = Figure(figsize=(2.4 * columns, 2.0 * rows + 0.5), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, columns, squeeze=False)).ravel()
    for ax in axes[len(claims):]:
        ax.set_visible(False)
    for ax, claim in zip(axes, claims):
        sub = scored.filter(pl.col("claim") == claim)
        for line in lines:
            pts = (sub.filter((pl.col("series") == line) & pl.col("toward").is_not_nan())
                   .sort("generations_per_phase"))
            if pts.height == 0:
                continue
            colour = colours[line]
            x, y = pts["generations_per_phase"].to_numpy(), pts["toward"].to_numpy()
            lo, hi = pts["toward_low"].to_numpy(), pts["toward_high"].to_numpy()
            bounded = np.isfinite(lo) & np.isfinite(hi)
            ax.plot(x, y, color=colour, linewidth=1.0)
            if bounded.any():
                ax.errorbar(x[bounded], y[bounded],
                            yerr=np.clip([y[bounded] - lo[bounded],
                                          hi[bounded] - y[bounded]], 0, None),
                            fmt="o", color=colour, markersize=4, capsize=2, linewidth=1.0)
            ax.plot(x[~bounded], y[~bounded], "o", markerfacecolor="white", color=colour,
                    markersize=4)
        ax.axhline(0, color="0.5", linestyle="--", linewidth=0.7)
        ax.set_xscale("log")
        ax.set_xticks(gens, [str(g) for g in gens])
        ax.minorticks_off()
        ax.set_xlim(gens[0] / 1.3, gens[-1] * 1.3)
        ax.tick_params(labelsize=9)
        ax.yaxis.set_major_locator(MaxNLocator(3))
        ax.set_title(textwrap.fill(claim, 26), fontsize=9, loc="left")
        words = [(m["series"], m["movement"], m["movement"])
                 for m in moves.filter(pl.col("claim") == claim).iter_rows(named=True)]
        if len(words) == 1:  # under the axis, in the movement's colour
            ax.set_xlabel(words[0][1], fontsize=9, color=MOVEMENT_COLOURS[words[0][2]])
        elif words:  # one line per series, in its colour
            ax.set_xlabel("\n".join(f"{s}: {w}" for s, w, _ in words), fontsize=9)
    fig.supxlabel("generations per phase (the paper: 500)", fontsize=10)
    fig.supylabel("effect, the paper's direction up (claim's units)", fontsize=10)
    fig.suptitle("Each claim's effect against the budget (interval: the claim's own)",
                 fontsize=10)
    if len(lines) > 1:
        handles = [Line2D([], [], color=colours[s], marker="o", label=s) for s in lines]
        fig.legend(handles=handles, loc="outside upper right", fontsize=9, ncol=len(lines))
    return fig
