"""Performance per phase: Fig. 5 (grasping and reaching), Fig. 9 (with and without touch and
sight) and the behaviours Table I and section IV-A attribute to the phases."""

from __future__ import annotations

import math
from collections.abc import Sequence

import polars as pl
from matplotlib.figure import Figure

from ..stats import fig9_statistics
from ..tables import phase_list
from ...postevaluation.systematic import SENSES
from .style import SENSES_COLOURS, bars_figure, draw_matrix, mark_na, phase_colours

#: Fig. 5: (column of the evaluation table, axis label, scale).
FIG5_MEASURES = (("grasped", "grasped objects (%)", 100.0),
                 ("reached", "reached objects (%)", 100.0),
                 ("speed", "reaching speed (m/s)", 1.0),
                 ("straightness", "reaching straightness", 1.0))


#: Table I and section IV-A behaviours per phase (column, label, scale); definitions and
#: thresholds in docs/model/measures.md.
BEHAVIOUR_MEASURES = (
    ("babbling", "motor babbling (% of trials)", 100.0),
    ("heading", "arm orienting: heading\ntoward the ball (-1..1)", 1.0),
    ("hand_shoulder_cv", "arm as a lever: CV of the\nhand-shoulder distance", 1.0),
    ("movement_units", "movement units\nbefore the first touch", 1.0),
    ("anticipatory_grasp", "anticipatory grasps\n(% of palm touches)", 100.0),
    ("palm_up_swipe", "palm-up upward swipes\n(% of first touches)", 100.0))


def fig5_performance(table: pl.DataFrame, phases: Sequence[str] | None = None,
                     senses: str = "normal") -> Figure:
    """Fig. 5: percentage of grasped and of reached objects (top), reaching speed and
    straightness (bottom) at the end of each phase, post-evaluation under ``senses``. Bars: mean
    over robots of each robot's mean over its trials (speed and straightness over its reaching
    trials only); error bars: s.e.m. over robots; n = robots with a value."""
    phases = phase_list(table, phases)
    fig, axes = bars_figure(table, FIG5_MEASURES, phases, senses, (2, 2), (8, 6.5))
    for ax in axes[0]:
        ax.set_ylim(0, 100)
    fig.suptitle(f"Fig. 5 - grasping and reaching at the end of each phase\n"
                 f"(post-evaluation, {senses} senses; mean $\\pm$ s.e.m. over robots)",
                 fontsize=10)
    return fig


def _grouped_bars(ax, summary: pl.DataFrame, outer: Sequence[str], inner: Sequence[str],
                  outer_col: str, inner_col: str, colours: dict) -> None:
    rows = {(r[outer_col], r[inner_col]): r for r in summary.iter_rows(named=True)}
    width = 0.8 / max(len(inner), 1)
    top = 0.0
    for j, g in enumerate(inner):
        for i, o in enumerate(outer):
            x = i - 0.4 + width * (j + 0.5)
            r = rows.get((o, g))
            if r is None or not math.isfinite(r["mean"]):
                mark_na(ax, x, "-")
                continue
            ax.bar(x, r["mean"], width=width * 0.92, color=colours[g], edgecolor="black",
                   linewidth=0.5, label=g if i == 0 else None)
            if math.isfinite(r["sem"]):
                ax.errorbar(x, r["mean"], yerr=r["sem"], color="black", capsize=2,
                            linewidth=0.8)
            top = max(top, r["mean"] + (r["sem"] if math.isfinite(r["sem"]) else 0))
        if not any((o, g) in rows for o in outer):
            ax.bar([], [], color=colours[g], label=g)
    ax.set_xticks(range(len(outer)), outer)
    ax.set_xlim(-0.6, len(outer) - 0.4)
    ax.set_ylim(0, top * 1.25 if top > 0 else 1.0)
    ax.set_ylabel("performance (mean $p_{multimodal}$)")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=9, ncols=min(len(inner), 4), loc="upper left")


def fig9_sensory_deprivation(table: pl.DataFrame, phases: Sequence[str] | None = None,
                             senses: Sequence[str] = SENSES, alpha: float = 0.05) -> Figure:
    """Fig. 9. Top: performance (mean p_multimodal, Eq. 5, over the 45 trials; mean $\\pm$
    s.e.m. over robots) per phase, normal and deprived of touch and/or sight, with the
    Kruskal-Wallis p across sensory conditions within each phase. Bottom left: black squares
    where two phase x senses groups differ (two-tailed Mann-Whitney, p < ``alpha`` after
    Holm's correction over the pairs; grey: below ``alpha`` uncorrected only). Bottom
    right: the same data grouped by sensory condition. See ``fig9_statistics``."""
    phases = phase_list(table, phases)
    senses = list(senses)
    st = fig9_statistics(table, phases, senses, alpha)
    fig = Figure(figsize=(11, 9), layout="constrained")
    grid = fig.add_gridspec(2, 2, height_ratios=[1, 1.25])
    top = fig.add_subplot(grid[0, :])
    _grouped_bars(top, st["summary"], phases, senses, "phase", "senses", SENSES_COLOURS)
    kw = {r["phase"]: r["p"] for r in st["kruskal"].iter_rows(named=True)}
    for i, p in enumerate(phases):
        pv = kw.get(p, math.nan)
        top.text(i, 1.0, f"Kruskal-Wallis p = {pv:.3g}" if math.isfinite(pv) else "K-W: n/a",
                 transform=top.get_xaxis_transform(), ha="center", va="bottom", fontsize=9)
    top.set_title("performance per phase and sensory condition", fontsize=9, pad=22)
    draw_matrix(fig.add_subplot(grid[1, 0]), st, alpha)
    right = fig.add_subplot(grid[1, 1])
    _grouped_bars(right, st["summary"], senses, phases, "senses", "phase",
                  phase_colours(phases))
    right.set_title("the same, grouped by sensory condition", fontsize=9)
    fig.suptitle("Fig. 9 - performance with and without touch and sight", fontsize=10)
    return fig


def table1_behaviours(table: pl.DataFrame, phases: Sequence[str] | None = None,
                      senses: str = "normal") -> Figure:
    """The behaviours Table I and section IV-A attribute to the phases (``BEHAVIOUR_MEASURES``:
    babbling, arm orienting, the arm as a lever, smoothness, anticipatory grasp, the
    gross-reachers' swipes), mean $\\pm$ s.e.m. over robots of each robot's mean over its
    trials (a rate for the 0/1 measures, over the trials where it is defined)."""
    phases = phase_list(table, phases)
    present = tuple(m for m in BEHAVIOUR_MEASURES if m[0] in table.columns)
    fig, _ = bars_figure(table, present, phases, senses, (2, 3), (11, 6.5))
    fig.suptitle(f"Table I behaviours per phase ({senses} senses; mean $\\pm$ s.e.m. over "
                 "robots)", fontsize=10)
    return fig
