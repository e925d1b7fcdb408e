"""Training: best and mean fitness per generation (not paper figures)."""

from __future__ import annotations

import polars as pl
from matplotlib import colormaps
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


#: The panels of ``training_by_strategy`` (column of ``generations.parquet``: label).
TRAINING_PANELS = {"mean": "population's mean fitness", "best": "best fitness"}


def training_by_strategy(stats_table: pl.DataFrame, strategies: dict[int, str],
                         still: str, window: int = 10, phase: str = "pre") -> Figure:
    """The training's fitness of ``phase`` per replication, every generation
    (``generations.parquet``; not a paper figure): one panel per ``TRAINING_PANELS``, each
    replication a thin line of the raw values and a thick one of their running mean over
    ``window`` generations (from the ``window``-th on), solid where ``strategies`` (the
    replication's strategy at the last snapshot) is not ``still``, dashed where it is;
    colours as ``strategy_figure``'s."""
    rows = stats_table.filter(pl.col("phase") == phase).sort("replication", "generation")
    fig = Figure(figsize=(8.5, 5.2), layout="constrained")
    axes = fig.subplots(len(TRAINING_PANELS), 1, sharex=True)
    cmap = colormaps["tab10"]
    for ax, (column, label) in zip(axes, TRAINING_PANELS.items()):
        for i, ((r,), line) in enumerate(rows.group_by("replication", maintain_order=True)):
            colour = cmap(i % 10)
            ax.plot(line["generation"], line[column], color=colour, linewidth=0.5, alpha=0.25)
            smooth = line.select("generation", pl.col(column).rolling_mean(window)).drop_nulls()
            ax.plot(smooth["generation"], smooth[column], color=colour, linewidth=1.4,
                    linestyle="--" if strategies.get(r) == still else "-",
                    label=f"rep {r} ({strategies.get(r, 'no snapshot')})")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel(f"generation of {phase}-reaching (thick: running mean over {window}; "
                        f"dashed: {still} at the last snapshot)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="outside right upper")
    return fig
