"""Post-evaluated runs as tables, for the figures, the statistics and the notebooks.

- ``repository_path``: a path of the notebooks resolved from the root of the repository;
- ``condition_trials``, ``phase_order``: the post-evaluation trials of one condition's phases
  and those phases in training order (Figs. 5-9 draw one condition);
- ``sector_config``, ``ball_radius``: what a run was trained with (Figs. 7, 8);
- ``load_runs``: the post-evaluation tables of one or several runs as one table, each phase of
  each condition a ``group`` (Fig. 10);
- ``recorded_robot``, ``positions``: the trials of the best recorded robot of a phase and the
  positions its recordings hold (Figs. 6, 8);
- ``phase_list``, ``select_trials``: the phases to draw and the trials of those phases under
  some senses, as every figure and its statistics choose them.

Needs no matplotlib.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import polars as pl

from ..evolution.rundir import RunDirectory
from ..model.world import SectorConfig
from ..postevaluation import before_touch
from ..postevaluation.systematic import load_evaluation, run_phases
from . import unfinished


def repository_path(path) -> Path:
    """``path`` resolved for the notebooks, wherever Jupyter was started: an absolute path as
    it is; a relative one (``recordings/demo-standard``) from the root of the dart_reach
    repository: the nearest folder, from the working directory up, that holds
    ``pyproject.toml`` and ``dart_reach/``, else the checkout this package is imported from
    (an editable install), else the working directory."""
    path = Path(path)
    if path.is_absolute():
        return path
    here = Path.cwd().resolve()
    for folder in (here, *here.parents):
        if (folder / "pyproject.toml").is_file() and (folder / "dart_reach").is_dir():
            return folder / path
    checkout = Path(__file__).resolve().parents[2]
    if (checkout / "pyproject.toml").is_file():
        return checkout / path
    return here / path


def _condition_phases(run_dir, condition: str) -> pl.DataFrame:
    phases = run_phases(run_dir)
    sel = phases.filter(pl.col("condition") == condition)
    if sel.height == 0:
        sel = phases.filter(pl.col("condition") == phases["condition"][0])
    return sel


def phase_order(run_dir, condition: str = "standard") -> list[str]:
    """The phases of ``condition`` in the run, in training order (default the standard
    pre -> gross -> fine of Figs. 5-9); the run's first condition when it lacks that one."""
    return _condition_phases(run_dir, condition)["phase"].to_list()


def condition_trials(run_dir, condition: str = "standard") -> tuple[pl.DataFrame, list[str]]:
    """The post-evaluation trials of one condition's phases and those phases in training
    order (Figs. 5-9 draw one condition). Rows are chosen by phase key, so a phase of another
    condition with the same name (the gross of ``gross-hat``) is not mixed in."""
    phases = _condition_phases(run_dir, condition)
    keys = phases["phase_key"].to_list()
    table = load_evaluation(run_dir).filter(pl.col("phase_key").is_in(keys))
    return table, phases["phase"].to_list()


def sector_config(run_dir) -> SectorConfig:
    """The sector bounds of a run (for the axis labels of Fig. 7)."""
    return RunDirectory.open(run_dir).settings.world.sectors


def ball_radius(run_dir) -> float:
    """The ball radius (m) of a run (drawn in Fig. 8)."""
    return float(RunDirectory.open(run_dir).settings.world.ball.radius)


def load_runs(run_dirs: Sequence) -> pl.DataFrame:
    """The post-evaluation tables of one or several runs as one table, for Fig. 10.

    Adds: run (the directory's name, or its full path when two runs share a name),
    phase_order (rank of the phase in training order within its run, a phase shared by
    conditions counted once) and group: the phase's notation (``gross^``, ``pre-h``), or
    ``notation [run]`` when the same notation comes from several runs (``notation [run key]``
    when it names phases of different keys within a run). ``group``
    is a ``pl.Enum`` whose categories are in the order of the runs given, then training order,
    so sorting by it keeps that order. A run given twice is read once.
    """
    run_dirs = list({Path(d).resolve(): Path(d) for d in run_dirs}.values())  # once each
    if not run_dirs:
        raise ValueError("load_runs needs at least one run directory")
    names = [d.name for d in run_dirs]
    labels = [d.name if names.count(d.name) == 1 else str(d) for d in run_dirs]
    frames = []
    for i, (run_dir, label) in enumerate(zip(run_dirs, labels)):
        table = unfinished.trials(run_dir)  # an unfinished run: its snapshots
        table = before_touch.attach(table, run_dir)  # where measured again (claim A1)
        order = (run_phases(run_dir).unique("phase_key", keep="first", maintain_order=True)
                 .with_row_index("phase_order").select("phase_key", "phase_order"))
        table = (table.join(order, on="phase_key", how="left", maintain_order="left")
                 .with_columns(pl.lit(label).alias("run"), pl.lit(i).alias("run_index"),
                               pl.col("phase_order").cast(pl.Int64)))
        frames.append(table)
    table = pl.concat(frames, how="diagonal_relaxed")
    units = (table.select("run_index", "phase_order", "run", "phase_key", "notation")
             .unique().sort("run_index", "phase_order"))
    many_units = pl.len().over("notation") > 1
    many_keys = pl.len().over("notation", "run") > 1
    units = units.with_columns(
        pl.when(many_keys)
        .then(pl.format("{} [{} {}]", "notation", "run", pl.col("phase_key").str.slice(0, 8)))
        .when(many_units).then(pl.format("{} [{}]", "notation", "run"))
        .otherwise(pl.col("notation")).alias("group"))
    categories = list(dict.fromkeys(units["group"].to_list()))
    table = table.join(units.select("run", "phase_key", "group"), on=["run", "phase_key"],
                       how="left", maintain_order="left")
    return table.with_columns(pl.col("group").cast(pl.Enum(categories)))


def recorded_robot(table: pl.DataFrame, phase: str, senses: str = "normal") -> pl.DataFrame:
    """The trials (sorted by trial) of the robot of ``phase`` under ``senses`` whose
    trajectories Figs. 6 and 8 draw: among the robots with recordings, the one of highest
    lifetime fitness, i.e. by default the best robot (rank 0) of the best replication; where
    none was recorded (``evaluate --record none``, committed results), that robot all the same
    (its recordings are made again on demand: ``replay.recording``). Empty when the phase has
    no trial under ``senses``."""
    rows = table.filter((pl.col("phase") == phase) & (pl.col("senses") == senses))
    recorded = rows.filter(pl.col("recording").is_not_null())
    rows = recorded if recorded.height else rows.filter(pl.col("rank") == 0)
    if rows.height == 0:
        return rows
    best = (rows.group_by("replication", "rank")
            .agg(pl.col("lifetime_fitness").first())
            .sort(["lifetime_fitness", "rank", "replication"], descending=[True, False, False])
            .row(0, named=True))
    return rows.filter((pl.col("replication") == best["replication"])
                       & (pl.col("rank") == best["rank"])).sort("trial")


def positions(recording: pl.DataFrame, entity: str) -> np.ndarray:
    """The (steps, 3) world positions of ``entity`` (hand, shoulder, ball) in a recorded
    trial (``rrd.read_rrd``)."""
    return (recording.select([f"robot/positions/{entity}/{a}" for a in "xyz"])
            .to_numpy().astype(float))


def phase_list(table: pl.DataFrame, phases: Sequence[str] | None) -> list[str]:
    """``phases`` as a list; default the phases of ``table`` in order of first appearance."""
    if phases is None:
        return list(dict.fromkeys(table["phase"].to_list()))
    return list(phases)


def select_trials(table: pl.DataFrame, phases: Sequence[str],
                  senses: str | Sequence[str]) -> pl.DataFrame:
    """The trials of ``table`` of ``phases`` under ``senses`` (one sensory condition or
    several)."""
    senses = [senses] if isinstance(senses, str) else list(senses)
    return table.filter(pl.col("phase").is_in(list(phases)) & pl.col("senses").is_in(senses))
