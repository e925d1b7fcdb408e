"""The scene study's page (docs/results/scene-study.md, its tables and figure): the project's
study of where the ball hangs, read with the package's generic tool
(``dart_reach.studies.scene_study``: a study folder's runs, their summary, robots, levers and
sector rates).

Each candidate scene was trained alone (``make scene-study``: the standard condition's
pre-reaching phase, the same seeds for every scene) and post-evaluated: the best 5 robots of
each replication and 10 random genomes, normal senses and the ball absent. ``LEVERS`` are the
study's contrasts, each changing one lever of the scene. ``python -m reports.scene_study
STUDY_DIR OUT_DIR`` writes ``scene-study.md`` (both tables) and ``scene-study.png`` (the
figure) into OUT_DIR; ``reports.results`` renders the page's template from the same tables.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import dart_reach  # noqa: F401  first: it pins numpy's kernels before numpy loads
import numpy as np
import polars as pl
from matplotlib.figure import Figure

from dart_reach.analysis import formatting, said, summaries, verdicts
from dart_reach.analysis.claims import ABOUT_HALF
from dart_reach.studies.scene_study import (MEASURES, levers, robots, sector_rates, study_runs,
                                            summary)

#: The scene study's contrasts (lever, scene before, scene after): each changes one lever of
#: the scene, the last both (docs/results/scene-study.md).
LEVERS = (("height: neck level to shoulder level", "near", "near-shoulder"),
          ("distance: 0.30 m to arm's length", "near-shoulder", "arm-length-shoulder"),
          ("both", "near", "arm-length-shoulder"))
#: The summary's rates, shown in whole per cent; its other measures with 3 significant digits.
RATES = ("reached", "grasped", "babbling", "babbling_no_ball", "reach_low", "reach_high")


def cell(value: float, measure: str = "") -> str:
    """A summary's value as the page's template shows it: a rate (``RATES``) in whole per
    cent, else 3 significant digits (``formatting``); a missing value as an en dash."""
    if value is not None and np.isfinite(value) and measure in RATES:
        return formatting.percent(value)
    return formatting.significant(value)


def levers_markdown(table: pl.DataFrame) -> str:
    """``levers`` as a markdown table."""
    head = ["lever", "measure", "before", "after", "shift [95% CI]", "p (robots)",
            "replications agree"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in table.iter_rows(named=True):
        lines.append("| " + " | ".join([
            r["lever"], r["measure"], f"{r['mean_before']:.3g}", f"{r['mean_after']:.3g}",
            f"{r['shift']:+.3g} [{r['shift_low']:+.3g}, {r['shift_high']:+.3g}]",
            f"{r['p']:.2g}", "yes" if r["replications_agree"] else "no"]) + " |")
    return "\n".join(lines) + "\n"


def levers_grid(table: pl.DataFrame) -> str:
    """``levers`` as a markdown grid: one row per measure, one column per lever, each cell the
    shift and its 95 % interval, ✓ where the replications agree."""
    names = list(dict.fromkeys(table["lever"].to_list()))
    lines = ["| measure | " + " | ".join(names) + " |", "|" + "---|" * (len(names) + 1)]
    for (label,), rows in table.group_by("measure", maintain_order=True):
        cells = {r["lever"]: f"{r['shift']:+.2g} [{r['shift_low']:+.2g}, {r['shift_high']:+.2g}]"
                 + (" ✓" if r["replications_agree"] else "") for r in rows.iter_rows(named=True)}
        lines.append(f"| {label} | " + " | ".join(cells.get(n, "–") for n in names) + " |")
    return "\n".join(lines) + "\n"


def markdown(table: pl.DataFrame) -> str:
    """The summary as a markdown table (rates in %, lengths in m)."""
    head = ["scene", "group", "robots", *[label for _, label in MEASURES], "reach 95% CI",
            "babbling, no ball"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in table.iter_rows(named=True):
        cells = [r["scene"], r["group"], str(r["robots"])]
        for m, _ in MEASURES:
            v = r[m]
            cells.append("–" if not np.isfinite(v) else f"{v:.0%}" if m in
                         ("reached", "grasped", "babbling") else f"{v:.3g}")
        cells.append(f"{r['reach_low']:.0%}–{r['reach_high']:.0%}")
        nb = r["babbling_no_ball"]
        cells.append("–" if not np.isfinite(nb) else f"{nb:.0%}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def figure(table: pl.DataFrame, sectors: pl.DataFrame):
    """F1's measures per scene (evolved robots beside random genomes) and the per-sector reach
    rates (3 x 3 grids, row 0 the lowest), one figure (made without pyplot, so it holds no
    global state)."""
    scenes = list(dict.fromkeys(table["scene"].to_list()))
    shown = [("reached", "reach rate"), ("hand_shoulder_cv", "hand-shoulder CV"),
             ("var_elbow_norm", "elbow var. / range"), ("var_shoulder_norm",
                                                        "shoulder var. / range"),
             ("hand_amplitude", "hand amplitude (m)"), ("babbling", "babbling rate")]
    fig = Figure(figsize=(13, 7), layout="constrained")
    top = fig.subfigures(2, 1, height_ratios=[1.2, 1])
    axes = top[0].subplots(1, len(shown))
    x = np.arange(len(scenes))
    for ax, (m, label) in zip(axes, shown):
        for k, (group, colour) in enumerate((("evolved", "tab:blue"), ("random", "tab:grey"))):
            sub = {r["scene"]: r[m] for r in table.filter(pl.col("group") == group)
                   .iter_rows(named=True)}
            ax.bar(x + (k - 0.5) * 0.38, [sub.get(s, np.nan) for s in scenes], 0.38,
                   color=colour, label=group)
        ax.set_xticks(x, scenes, rotation=30, ha="right", fontsize=9)
        ax.set_title(label, fontsize=10)
    axes[0].legend(fontsize=9)
    grids = top[1].subplots(1, len(scenes), squeeze=False)[0]
    for ax, scene in zip(grids, scenes):
        grid = summaries.sector_grid(sectors.filter(pl.col("scene") == scene), "reach_rate")
        im = ax.imshow(grid, origin="lower", vmin=0, vmax=1, cmap="viridis")
        for (i, j), v in np.ndenumerate(grid):
            ax.text(j, i, f"{v:.0%}", ha="center", va="center", fontsize=9,
                    color="white" if v < 0.6 else "black")
        ax.set_title(f"{scene}: reach by sector", fontsize=10)
        ax.set_xticks([])
        ax.set_yticks([])
    top[1].colorbar(im, ax=list(grids), shrink=0.8)
    return fig


def lever_table(runs: Sequence[Path]) -> pl.DataFrame:
    """The study's ``LEVERS`` over its runs' evolved robots (``studies.scene_study.levers``)."""
    return levers(robots(runs), LEVERS)


#: The measures whose move with each lever the page words by the gated rule (``lever_words``).
WORDED = ("reached", "grasped", "hand_shoulder_mean")
#: The scene whose reach rate the page sets against the paper's "about half" (IV-A-1).
DEFAULT_SCENE = "arm-length-shoulder"


def replication_means(robot_table: pl.DataFrame, scene: str, measure: str) -> np.ndarray:
    """The replications' means of ``measure`` over their robots in ``scene`` (``robots``'s
    table): the study's independent units."""
    return (robot_table.filter(pl.col("scene") == scene).group_by("replication")
            .agg(pl.col(measure).fill_nan(None).mean()).sort("replication")[measure]
            .drop_nulls().to_numpy())


def lever_words(robot_table: pl.DataFrame, calibration: pl.DataFrame) -> dict[str, str]:
    """The page's words on the levers, from the gated rules alone, the replication as the
    unit: ``rule.<before>.<after>.<measure>``, what ``said.two_groups`` may say of each
    lever's scene after against before (``LEVERS``, ``WORDED``; ``calibration``: the
    committed calibration table, for its intervals' labels), and ``rule.about_half``,
    ``verdicts.in_band`` of ``DEFAULT_SCENE``'s reach rates in ``claims.ABOUT_HALF``."""
    out = {}
    for _, before, after in LEVERS:
        for m in WORDED:
            out[f"rule.{before}.{after}.{m}"] = said.two_groups(
                replication_means(robot_table, before, m),
                replication_means(robot_table, after, m), before, after, calibration)
    reach = replication_means(robot_table, DEFAULT_SCENE, "reached")
    band = verdicts.in_band(reach, ABOUT_HALF)
    interval = ("" if band.verdict == verdicts.UNDERPOWERED else
                f"; mean {formatting.percent(band.effect)}, {100 * band.confidence:g} % interval "
                f"{formatting.percent(band.low)}-{formatting.percent(band.high)}")
    out["rule.about_half"] = (f"{band.verdict} (band {formatting.percent(ABOUT_HALF[0])}-"
                              f"{formatting.percent(ABOUT_HALF[1])}, n = {len(reach)} replications"
                              + (f": {band.note}" if band.note else "") + interval + ")")
    return out


def tables_text(runs: Sequence[Path]) -> str:
    """scene-study.md: the summary and the levers' full table."""
    return markdown(summary(runs)) + "\n" + levers_markdown(lever_table(runs))


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        print("usage: python -m reports.scene_study STUDY_DIR OUT_DIR", file=sys.stderr)
        return 2
    study, out = Path(argv[0]), Path(argv[1])
    runs = study_runs(study)
    if not runs:
        print(f"{study}: no post-evaluated scene run", file=sys.stderr)
        return 2
    table = summary(runs)
    text = tables_text(runs)
    (out / "scene-study.md").write_text(text)
    figure(table, sector_rates(runs)).savefig(out / "scene-study.png", dpi=90)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
