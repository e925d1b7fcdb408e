"""Every claim at a glance (not a paper figure): its effect with its replication-level interval
against the paper's direction, one row per claim grouped by section of the paper, one marker
per budget (the report's first screen)."""

from __future__ import annotations

import html
import math

import numpy as np
import polars as pl
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from .. import budgets, findings, formatting, scales, verdicts
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


def _drawn(by_budget: pl.DataFrame, own: bool) -> pl.DataFrame:
    """The rows the forest draws: ``who``'s claims on the ``toward_paper`` scale, with their
    ``part`` of the paper, the claims no budget ran left out."""
    who = findings.OWN if own else findings.ROBOTS
    scored = findings.reading(budgets.toward_paper(by_budget), who)
    scored = scored.filter(~pl.col("claim").is_in(never_run(by_budget, who)["claim"].implode()))
    return scored.with_columns(section_part().alias("part"))


def row_scale(toward: float, low: float, high: float) -> float:
    """What a row's 1 on the forest's axis is, in the units of its ``toward_paper`` scale:
    the largest magnitude of its effect and interval ends (NaN: no bounded interval)."""
    if not _bounded(toward, low, high):
        return math.nan
    return max(abs(toward), abs(low), abs(high)) or 1.0


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
    scored = _drawn(by_budget, own)
    parts = scored["part"].unique(maintain_order=True).to_list()
    claims = {p: scored.filter(pl.col("part") == p)["claim"].unique(maintain_order=True)
              .to_list() for p in parts}
    labels = sorted(scored.select("generations_per_phase", "replications", "scene", "model")
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
            key = (r["generations_per_phase"], r["replications"], r["scene"], r["model"])
            y = names.index(r["claim"]) + offsets[key]
            colour = VERDICT_COLOURS.get(r["verdict"], "0.6")
            t, lo, hi = r["toward"], r["toward_low"], r["toward_high"]
            if _bounded(t, lo, hi):
                scale = row_scale(t, lo, hi)
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
    several = {i: len({k[i] for k in labels}) > 1 for i in (1, 2, 3)}
    handles += [Line2D([], [], color="0.3", marker=markers[k], linestyle="",
                       label=f"{k[0]} gen/phase" + (f" x {k[1]}" if several[1] else "")
                       + (f", {k[2]}" if several[2] else "")
                       + (f", model {k[3]}" if several[3] else ""))
                for k in labels]
    fig.legend(handles=handles, fontsize=LABEL_PT, loc="outside upper center",
               ncol=min(len(handles), 4), frameon=False)
    return fig


def scale_table(by_budget: pl.DataFrame, own: bool = False) -> pl.DataFrame:
    """Per row of the forest (a claim at a budget that was run): its ``scale`` (the kind whose
    effect it carries, ``scales.scale_of``, explained in ``forest_caption``), its ``effect
    [CI]`` in that scale's units, what the forest draws of it before scaling (``drawn [CI]``,
    ``budgets.toward_paper``) and ``1 on the axis`` (``row_scale``, in the drawn units; "–":
    no interval, the marker in the column "no interval")."""
    scored = _drawn(by_budget, own).filter(pl.col("verdict") != verdicts.NOT_RUN)
    names = {v: k for k, v in scales.SCALES.items()}
    rows = []
    for r in scored.iter_rows(named=True):
        s = scales.scale_of(r["claim"], r["kind"])
        values = [math.nan if r[c] is None else r[c] for c in
                  ("effect", "effect_low", "effect_high", "toward", "toward_low", "toward_high")]
        rows.append({"claim": r["claim"], "budget": f"{r['generations_per_phase']} gen/phase",
                     "scale": names[s],
                     "effect [CI]": f"{s.symbol} {formatting.effect(*values[:3])}",
                     "drawn [CI]": formatting.effect(*values[3:]),
                     "1 on the axis": formatting.number(row_scale(*values[3:]))})
    return pl.DataFrame(rows, schema=["claim", "budget", "scale", "effect [CI]", "drawn [CI]",
                                      "1 on the axis"])


def forest_caption(by_budget: pl.DataFrame, own: bool = False) -> str:
    """The forest's caption, from the claims it draws: the scale of each kind of claim drawn
    (its effect, its units, what 0 and the right side are), what each label that reads
    against the axis means (``scales.inverted``), and where each row's units are (HTML; the
    per-row table is ``scale_table``)."""
    scored = _drawn(by_budget, own).filter(pl.col("verdict") != verdicts.NOT_RUN)
    claims = scored["claim"].unique(maintain_order=True).to_list()
    kinds = list(dict.fromkeys(scales.scale_of(c, k) for c, k in scored.select(
        "claim", "kind").iter_rows()))
    flipped = [(c, text) for c in claims if c in scales.CLAIM_IDS and (text := scales.inverted(c))]
    esc = html.escape
    parts = ["<p>Every claim's effect with its interval (nominally 95 %; θ's covers less away "
             "from 0.5 between groups of unequal shapes, as the calibration measured), the "
             "replication as the unit, "
             "grouped by section of the paper. <b>The scale</b>: each row is drawn on the "
             "scale where the paper's direction is right, then divided by the largest of "
             "|effect| and |interval ends| in that row, so the axis runs from -1 to 1 in every "
             "row and rows in different units share it: the position of 0 and the side of "
             "the interval say where the claim stands, the length of a row says nothing "
             "across rows (each row's own units and its 1 on the axis are in the table "
             "below). A claim without a bounded interval is in the column "
             "<i>no interval</i>; one not run at a budget has no marker there.</p>"
             "<ul class='scales'>"]
    names = {v: k for k, v in scales.SCALES.items()}
    parts += [f"<li><i>{esc(names[s])}</i>: effect {esc(s.effect)}; drawn as "
              f"{esc(s.drawn)}.</li>" for s in kinds]
    parts.append("</ul>")
    if flipped:
        parts.append("<p><b>Labels that read against the axis</b>:</p><ul class='inverted'>"
                     + "".join(f"<li><i>{esc(c)}</i>: {esc(t)}.</li>" for c, t in flipped)
                     + "</ul>")
    return "".join(parts)
