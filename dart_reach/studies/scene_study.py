"""The scene study (docs/results/scene-study.md): how F1's measures of pre-reaching move with
where the ball hangs (sections II-B, III, IV-A-1; Figs. 2, 5-8).

Each candidate scene was trained alone (``make scene-study``: the standard condition's
pre-reaching phase, the same seeds for every scene) and post-evaluated: the best 5 robots of
each replication and 10 random genomes, normal senses and the ball absent. ``summary`` gives
one row per scene and group (evolved robots, random genomes) with F1's measures: means over
robots (a robot: its mean over its 45 trials) and a 95 % percentile bootstrap interval over
robots for the reach rate; ``sector_rates`` the reach rate per sector (Fig. 7's top row);
``figure`` draws both; ``levers`` says how each measure moves when one lever of the scene
changes (``LEVERS``). ``python -m dart_reach.studies.scene_study STUDY_DIR OUT_DIR`` writes
``scene-study.md`` (both tables) and ``scene-study.png`` (the figure) into OUT_DIR.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import polars as pl
from matplotlib.figure import Figure
from scipy import stats as sps

from ..analysis import stats, summaries, verdicts
from ..evolution.rundir import RunDirectory
from ..model.scenes import scene_of
from ..postevaluation.results import exists
from ..postevaluation.systematic import TABLE, load_evaluation

#: F1's measures (column, label): the reach and grasp rates, when the first touch comes, the
#: arm's extension and lever, the joints' use (normalised by each joint's range), babbling.
MEASURES = (("reached", "reach"), ("grasped", "grasp"), ("first_touch_s", "first touch (s)"),
            ("hand_shoulder_mean", "hand-shoulder (m)"),
            ("hand_shoulder_cv", "hand-shoulder CV"), ("var_elbow_norm", "elbow var."),
            ("var_shoulder_norm", "shoulder var."), ("var_trunk_norm", "trunk var."),
            ("hand_amplitude", "amplitude (m)"), ("babbling", "babbling"))
_ROBOT = ("replication", "rank")
BOOTSTRAP_SEED = 2013
#: The scene study's contrasts (lever, scene before, scene after): each changes one lever of
#: the scene, the last both (docs/results/scene-study.md).
LEVERS = (("height: neck level to shoulder level", "near", "near-shoulder"),
          ("distance: 0.30 m to arm's length", "near-shoulder", "arm-length-shoulder"),
          ("both", "near", "arm-length-shoulder"))


def _groups(run_dir: Path) -> list[tuple[str, pl.DataFrame]]:
    table = load_evaluation(run_dir, baseline=None)
    return [("evolved", table.filter(~pl.col("baseline"))),
            ("random", table.filter(pl.col("baseline")))]


def summary(run_dirs: Sequence[Path]) -> pl.DataFrame:
    """One row per scene (the run's) and group ("evolved": the best robots, "random": the
    random genomes): robots, every measure of ``MEASURES`` under normal senses (means over
    robots; first_touch_s: the median over reached trials), reach_low / reach_high (95 %
    bootstrap over robots) and, for the ball-absent trials where evaluated, babbling_no_ball
    and hand_amplitude_no_ball."""
    rows = []
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    for d in map(Path, run_dirs):
        run = RunDirectory.open(d)
        scene = scene_of(run.settings.world.sectors) or d.name
        for group, trials in _groups(d):
            normal = trials.filter(pl.col("senses") == "normal")
            if normal.height == 0:
                continue
            names = [m for m, _ in MEASURES]
            robots = summaries.robot_means(normal, names, by=_ROBOT)
            row = {"scene": scene, "group": group, "robots": robots.height,
                   "radius_m": run.settings.world.sectors.radius}
            row.update({m: float(robots[m].mean()) for m in names})
            row["first_touch_s"] = float(normal["first_touch_s"].median() or np.nan)
            _, row["reach_low"], row["reach_high"] = stats.bootstrap_mean_interval(
                robots["reached"].to_numpy(), rng)
            absent = trials.filter(pl.col("senses") == "no-ball")
            for m in ("babbling", "hand_amplitude"):
                row[f"{m}_no_ball"] = (float(summaries.robot_means(absent, [m], by=_ROBOT)[m]
                                             .mean()) if absent.height else np.nan)
            rows.append(row)
    return pl.DataFrame(rows)


def robots(run_dirs: Sequence[Path]) -> pl.DataFrame:
    """The evolved robots' means over their normal-senses trials, one row per robot: scene,
    replication, rank and every measure of ``MEASURES`` (first_touch_s: the mean over its
    reached trials)."""
    names = [m for m, _ in MEASURES]
    tables = []
    for d in map(Path, run_dirs):
        scene = scene_of(RunDirectory.open(d).settings.world.sectors) or d.name
        normal = _groups(d)[0][1].filter(pl.col("senses") == "normal")
        tables.append(summaries.robot_means(normal, names, by=_ROBOT)
                      .with_columns(pl.lit(scene).alias("scene")))
    return pl.concat(tables).select("scene", *_ROBOT, *names)


def levers(robot_table: pl.DataFrame, pairs=LEVERS) -> pl.DataFrame:
    """How each measure moves with each lever: one row per (lever, measure) whose two scenes
    are both in ``robot_table`` (``robots``): the means over robots before and after, the
    Hodges-Lehmann shift (after - before) with its 95 % interval and the two-sided
    Mann-Whitney p over robots, and ``replications_agree``: every replication's mean after
    differs from every replication's mean before in the shift's direction. Robots of one
    replication descend from one population, so the replication is the independent unit: with
    2 replications per scene, read p as a description of the robots, and trust a shift whose
    replications agree."""
    rows = []
    scenes = set(robot_table["scene"].to_list())
    for lever, before, after in pairs:
        if before not in scenes or after not in scenes:
            continue
        a_tab = robot_table.filter(pl.col("scene") == before)
        b_tab = robot_table.filter(pl.col("scene") == after)
        for m, label in MEASURES:
            a, b = a_tab[m].drop_nans().to_numpy(), b_tab[m].drop_nans().to_numpy()
            if len(a) < 2 or len(b) < 2:
                continue
            shift, low, high = verdicts.hodges_lehmann(a, b)
            p = (1.0 if np.ptp(np.concatenate([a, b])) == 0
                 else float(sps.mannwhitneyu(b, a, alternative="two-sided").pvalue))
            rep_a, rep_b = (t.group_by("replication").agg(pl.col(m).fill_nan(None).mean())[m]
                            .drop_nulls().to_numpy() for t in (a_tab, b_tab))
            gaps = (rep_b[None, :] - rep_a[:, None]).ravel()
            agree = bool(shift != 0 and gaps.size and np.all(np.sign(gaps) == np.sign(shift)))
            rows.append({"lever": lever, "before": before, "after": after, "measure": label,
                         "mean_before": float(a.mean()), "mean_after": float(b.mean()),
                         "shift": shift, "shift_low": low, "shift_high": high, "p": p,
                         "replications_agree": agree})
    return pl.DataFrame(rows)


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


def sector_rates(run_dirs: Sequence[Path]) -> pl.DataFrame:
    """The evolved robots' reach and grasp rate per sector, one row per scene and sector."""
    tables = []
    for d in map(Path, run_dirs):
        scene = scene_of(RunDirectory.open(d).settings.world.sectors) or d.name
        normal = _groups(d)[0][1].filter(pl.col("senses") == "normal")
        tables.append(summaries.sector_success(normal.with_columns(pl.lit(scene).alias("scene")),
                                             by=("scene",)))
    return pl.concat(tables)


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


def study_runs(study: Path) -> list[Path]:
    """The post-evaluated scene runs in ``study``, by name."""
    return sorted(d for d in Path(study).iterdir() if exists(d / TABLE))


def tables_text(runs: Sequence[Path]) -> str:
    """scene-study.md: the summary and the levers' full table."""
    return markdown(summary(runs)) + "\n" + levers_markdown(levers(robots(runs)))


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        print("usage: python -m dart_reach.studies.scene_study STUDY_DIR OUT_DIR", file=sys.stderr)
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
