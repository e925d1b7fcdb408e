"""Training: best and mean fitness per generation (not a paper figure)."""

from __future__ import annotations

import polars as pl
from matplotlib.figure import Figure

from .style import phase_colours


def training_curves(stats_table: pl.DataFrame, phases: pl.DataFrame | None = None) -> Figure:
    """Best and mean fitness per generation (``generations.parquet``), one panel per condition;
    the phases follow each other on the x axis (a phase's generations after its predecessor's),
    dotted lines at phase boundaries. Thin lines: the best fitness of each replication; thick:
    its mean over replications; dashed: the population mean fitness averaged over
    replications. ``phases``: ``systematic.run_phases`` of the run, to draw a phase shared by
    conditions (trained once) in each of them; default: the conditions of the table."""
    if phases is None:
        seq = (stats_table.select("condition", "phase", "phase_key")
               .unique(maintain_order=True))
    else:
        seq = phases.select("condition", "phase", "phase_key")
    conditions = list(dict.fromkeys(seq["condition"].to_list())) or ["(none)"]
    fig = Figure(figsize=(11, 2.8 * len(conditions) + 0.4), layout="constrained")
    axes = fig.subplots(len(conditions), 1, squeeze=False)[:, 0]
    colours = phase_colours(list(dict.fromkeys(seq["phase"].to_list())))
    for ax, condition in zip(axes, conditions):
        offset = 0
        for phase, key in seq.filter(pl.col("condition") == condition).select(
                "phase", "phase_key").iter_rows():
            rows = stats_table.filter(pl.col("phase_key") == key)
            if rows.height == 0:
                ax.text(offset + 0.5, 0.5, f"{phase}: no data", transform=ax.get_xaxis_transform(),
                        fontsize=9, color="0.4")
                offset += 1
                continue
            c = colours[phase]
            for _, r in rows.sort("generation").group_by("replication", maintain_order=True):
                ax.plot(r["generation"] + offset, r["best"], color=c, alpha=0.3, linewidth=0.8)
            avg = rows.group_by("generation").agg(pl.col("best").mean(),
                                                  pl.col("mean").mean()).sort("generation")
            g = avg["generation"].to_numpy() + offset
            ax.plot(g, avg["best"], color=c, linewidth=2, marker="o" if len(g) < 20 else None,
                    markersize=3, label=f"{phase}: best (mean over replications)")
            ax.plot(g, avg["mean"], color=c, linewidth=1.2, linestyle="--",
                    label=f"{phase}: population mean")
            if offset:
                ax.axvline(offset + 0.5, color="0.5", linestyle=":", linewidth=1)
            ax.text(offset + 0.5, 1.01, phase, transform=ax.get_xaxis_transform(), fontsize=9,
                    va="bottom")
            offset += int(rows["generation"].max())
        ax.set_title(f"condition {condition}", fontsize=10, loc="right", pad=14)
        ax.set_xlabel("generation (phases in sequence)")
        ax.set_ylabel("fitness (mean $p_{multimodal}$)")
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=9, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return fig
