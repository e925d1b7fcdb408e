"""Every claim at a glance (not a paper figure): its effect with its replication-level interval
against the paper's direction, one row per claim grouped by section of the paper, one marker
per budget (the report's first screen)."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from .. import budgets, findings, verdicts
from ..counts import never_run, section_part

#: Colours of the verdicts (as the report's table).
VERDICT_COLOURS = {verdicts.REPRODUCED: "#2ca02c", verdicts.CONTRADICTED: "#d62728",
                   verdicts.INCONCLUSIVE: "#c9a000", verdicts.UNDERPOWERED: "#7f7fbf",
                   verdicts.NOT_RUN: "0.6"}
#: Where a claim without a bounded interval at a budget gets its marker: a column of its own
#: right of the scaled axis (-1..1), so that every claim that was run has a marker.
NO_INTERVAL_X = 1.4
#: Font sizes (points): the claims' labels and the legend, the sections' titles.
LABEL_PT, SECTION_PT = 10, 11
#: Inches per claim row and per section title.
ROW_IN, TITLE_IN = 0.27, 0.45


def _bounded(*values) -> bool:
    return all(v is not None and math.isfinite(v) for v in values)


def forest_figure(by_budget: pl.DataFrame, own: bool = False) -> Figure:
    """One row per claim of ``by_budget`` (``budgets.findings_by_budget``; the paper's claims,
    or with ``own`` the project's), in one panel per section of the paper
    (``counts.section_part``), its effect on the scale where the paper's direction is right
    (``budgets.toward_paper``), each row divided by the largest magnitude of its effect and
    interval ends so that claims in different units share one axis: 0 is no effect (or the
    claim's boundary), a row whose interval lies wholly right of 0 points the paper's way.
    The marker's colour is the verdict, its shape the budget. A claim without a bounded
    interval at a budget (Kendall's W, an underpowered rule) gets its marker in the column
    "no interval" on the right; a claim no budget ran (``counts.never_run``) is left out (the
    report lists it under the figure), one not run at some budget has no marker there."""
    who = findings.OWN if own else findings.ROBOTS
    scored = findings.reading(budgets.toward_paper(by_budget), who)
    scored = scored.filter(~pl.col("claim").is_in(never_run(by_budget, who)["claim"].implode()))
    scored = scored.with_columns(section_part().alias("part"))
    parts = scored["part"].unique(maintain_order=True).to_list()
    claims = {p: scored.filter(pl.col("part") == p)["claim"].unique(maintain_order=True)
              .to_list() for p in parts}
    labels = sorted(scored.select("generations_per_phase", "replications", "scene")
                    .unique().rows())
    markers = dict(zip(labels, "osD^v<>"))
    offsets = dict(zip(labels, np.linspace(-0.22, 0.22, len(labels)) if len(labels) > 1
                       else [0.0]))
    rows = [len(claims[p]) for p in parts] or [1]
    height = 1.3 + sum(ROW_IN * n + TITLE_IN for n in rows)
    fig = Figure(figsize=(10, height), layout="constrained")
    axes = fig.subplots(len(rows), 1, sharex=True, squeeze=False,
                        gridspec_kw={"height_ratios": [n + TITLE_IN / ROW_IN for n in rows]})
    for ax, part in zip(axes[:, 0], parts):
        names = claims[part]
        for r in scored.filter(pl.col("part") == part).iter_rows(named=True):
            if r["verdict"] == verdicts.NOT_RUN:
                continue
            key = (r["generations_per_phase"], r["replications"], r["scene"])
            y = names.index(r["claim"]) + offsets[key]
            colour = VERDICT_COLOURS.get(r["verdict"], "0.6")
            t, lo, hi = r["toward"], r["toward_low"], r["toward_high"]
            if _bounded(t, lo, hi):
                scale = max(abs(t), abs(lo), abs(hi)) or 1.0
                ax.plot([lo / scale, hi / scale], [y, y], color=colour, linewidth=1.4)
                x = t / scale
            else:
                x = NO_INTERVAL_X
            ax.plot(x, y, markers[key], color=colour, markersize=6,
                    markeredgecolor="0.15", markeredgewidth=0.4)
        ax.axvline(0, color="0.4", linestyle="--", linewidth=0.8)
        ax.axvline((1 + NO_INTERVAL_X) / 2 + 0.05, color="0.75", linewidth=0.8)
        ax.set_yticks(range(len(names)), names, fontsize=LABEL_PT)
        ax.set_ylim(len(names) - 0.5, -0.5)
        ax.set_title(part, loc="left", fontsize=SECTION_PT, fontweight="bold")
        ax.grid(axis="y", color="0.93", linewidth=0.6)
    ax = axes[-1, 0]
    ax.set_xlim(-1.1, NO_INTERVAL_X + 0.2)
    ax.set_xticks([-1, -0.5, 0, 0.5, 1, NO_INTERVAL_X],
                  ["-1", "-0.5", "0", "0.5", "1", "no\ninterval"], fontsize=LABEL_PT)
    ax.set_xlabel("effect, the paper's direction to the right (each row scaled to its "
                  "largest end)", fontsize=LABEL_PT)
    axes[0, 0].tick_params(labeltop=True, labelsize=LABEL_PT)
    handles = [Line2D([], [], color=c, marker="o", linestyle="", label=v)
               for v, c in VERDICT_COLOURS.items() if v != verdicts.NOT_RUN]
    several = {i: len({k[i] for k in labels}) > 1 for i in (1, 2)}
    handles += [Line2D([], [], color="0.3", marker=markers[k], linestyle="",
                       label=f"{k[0]} gen/phase" + (f" x {k[1]}" if several[1] else "")
                       + (f", {k[2]}" if several[2] else ""))
                for k in labels]
    fig.legend(handles=handles, fontsize=LABEL_PT, loc="outside upper center",
               ncol=min(len(handles), 4), frameon=False)
    return fig
