"""A scene study: how F1's measures of pre-reaching move with where the ball hangs (sections
II-B, III, IV-A-1; Figs. 2, 5-8), over a folder of runs, one per scene, each trained and
post-evaluated alike (the best robots of each replication and random genomes, normal senses
and the ball absent).

``study_runs`` lists a study folder's post-evaluated runs; ``summary`` gives one row per scene
and group (evolved robots, random genomes) with F1's measures: means over robots (a robot: its
mean over its 45 trials) and a 95 % percentile bootstrap interval over robots for the reach
rate; ``robots`` the evolved robots' means; ``levers`` how each measure moves between two
scenes (the contrasts are the caller's); ``sector_rates`` the reach rate per sector (Fig. 7's
top row). The project's own study, its contrasts and its page: ``reports.scene_study``
(docs/results/scene-study.md).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import polars as pl
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


def levers(robot_table: pl.DataFrame, pairs: Sequence[tuple[str, str, str]]) -> pl.DataFrame:
    """How each measure moves with each lever of ``pairs`` ((lever, scene before, scene
    after), each a contrast of the study): one row per (lever, measure) whose two scenes
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


def sector_rates(run_dirs: Sequence[Path]) -> pl.DataFrame:
    """The evolved robots' reach and grasp rate per sector, one row per scene and sector."""
    tables = []
    for d in map(Path, run_dirs):
        scene = scene_of(RunDirectory.open(d).settings.world.sectors) or d.name
        normal = _groups(d)[0][1].filter(pl.col("senses") == "normal")
        tables.append(summaries.sector_success(normal.with_columns(pl.lit(scene).alias("scene")),
                                             by=("scene",)))
    return pl.concat(tables)


def study_runs(study: Path) -> list[Path]:
    """The post-evaluated scene runs in ``study``, by name."""
    return sorted(d for d in Path(study).iterdir() if exists(d / TABLE))
