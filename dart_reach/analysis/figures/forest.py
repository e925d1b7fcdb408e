"""Every claim at a glance (not a paper figure): its effect with its replication-level interval
against the paper's direction, one row per claim, one marker per budget (the report's first
screen)."""

from __future__ import annotations

import numpy as np
import polars as pl
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from .. import budgets, findings, verdicts

#: Colours of the verdicts (as the report's table).
VERDICT_COLOURS = {verdicts.REPRODUCED: "#2ca02c", verdicts.CONTRADICTED: "#d62728",
                   verdicts.INCONCLUSIVE: "#c9a000", verdicts.UNDERPOWERED: "#7f7fbf",
                   verdicts.NOT_RUN: "0.6"}


def forest_figure(by_budget: pl.DataFrame, own: bool = False) -> Figure:
    """One row per claim of ``by_budget`` (``budgets.findings_by_budget``; the paper's claims,
    or with ``own`` the project's), its effect on the scale where the paper's direction is
    right (``budgets.toward_paper``), each row divided by the largest magnitude of its
    effect and interval ends so that claims in different units share one axis: 0 is no
    effect (or the claim's boundary), a row whose interval lies wholly right of 0 points the
    paper's way. The marker's colour is the verdict, its shape the budget; a claim without a
    bounded interval at a budget (Friedman's W, an underpowered or unrun rule) has no marker
    there."""
    scored = budgets.toward_paper(by_budget)
    scored = findings.reading(scored, findings.OWN if own else findings.ROBOTS)
    claims = scored["claim"].unique(maintain_order=True).to_list()
    labels = sorted(scored.select("generations_per_phase", "replications", "scene")
                    .unique().rows())
    markers = dict(zip(labels, "osD^v<>"))
    fig = Figure(figsize=(7.5, max(3.0, 0.6 + 0.16 * len(claims))), layout="constrained")
    ax = fig.add_subplot()
    offsets = np.linspace(-0.25, 0.25, len(labels)) if len(labels) > 1 else [0.0]
    for (gens, reps, scene), dy in zip(labels, offsets):
        block = scored.filter((pl.col("generations_per_phase") == gens)
                              & (pl.col("replications") == reps) & (pl.col("scene") == scene))
        for r in block.iter_rows(named=True):
            t, lo, hi = (r[k] for k in ("toward", "toward_low", "toward_high"))
            if not all(x is not None and np.isfinite(x) for x in (t, lo, hi)):
                continue  # no bounded interval: nothing to scale by (the table has the row)
            scale = max(abs(t), abs(lo), abs(hi)) or 1.0
            y = claims.index(r["claim"]) + dy
            colour = VERDICT_COLOURS.get(r["verdict"], "0.6")
            ax.plot([lo / scale, hi / scale], [y, y], color=colour, linewidth=1.2)
            ax.plot(t / scale, y, markers[(gens, reps, scene)], color=colour, markersize=4)
    ax.axvline(0, color="0.4", linestyle="--", linewidth=0.7)
    ax.set_yticks(range(len(claims)), claims, fontsize=6)
    ax.set_ylim(len(claims) - 0.5, -0.5)
    ax.set_xlim(-1.1, 1.1)
    ax.set_xlabel("effect, the paper's direction to the right (each row scaled to its "
                  "largest end)", fontsize=8)
    handles = [Line2D([], [], color=c, marker="o", linestyle="", label=v)
               for v, c in VERDICT_COLOURS.items()]
    several = {i: len({k[i] for k in labels}) > 1 for i in (1, 2)}
    handles += [Line2D([], [], color="0.3", marker=markers[k], linestyle="",
                       label=f"{k[0]} gen/phase" + (f" x {k[1]}" if several[1] else "")
                       + (f", {k[2]}" if several[2] else ""))
                for k in labels]
    ax.legend(handles=handles, fontsize=6, loc="lower right")
    return fig
