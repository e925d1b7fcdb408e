"""The figures of section IV (Figs. 5-10) from a post-evaluated run, with matplotlib.

Every figure function takes tables (the post-evaluation table of ``evaluation.load_evaluation``,
the training statistics of ``generations.parquet``) and, when it draws recorded trials, the run
directory; it returns a ``matplotlib.figure.Figure`` (created without pyplot, so it holds no
global state: display it in a notebook, or ``fig.savefig(path)``).

- ``training_curves``: best and mean fitness per generation (not a paper figure);
- ``fig5_performance``: % grasped, % reached, reaching speed, straightness per phase;
- ``fig6_distances_variability``: hand-shoulder and hand-ball distance over 9 recorded trials
  (one per sector) of the best pre-reacher, and movement variability (elbow, shoulder, trunk)
  per phase; beyond the paper, elbow freezing per phase;
- ``fig7_sector_maps``: reach and grasp rate per sector and phase; beyond the paper,
  ``fig7_reach_regression``: the per-sector change of the reach rate from pre to gross;
- ``fig8_trajectories``: recorded hand paths per phase and sensory condition; beyond the paper,
  ``fig8_babbling``: dominant frequency and power share of the hand's movement per phase;
- ``fig9_sensory_deprivation``: performance per phase and sensory condition, Kruskal-Wallis
  within each phase and the Mann-Whitney comparisons of every phase x senses group;
- ``fig10_conditions``: per-replication performance of every (condition, phase) of one or
  several runs (``load_runs``) as box plots, and their pairwise Mann-Whitney comparisons;
- ``budget_figure`` (not a paper figure): each claim's effect against the generations per
  phase of runs trained at several budgets (``budgets.findings_by_budget``).

The statistics drawn are also returned as tables (``performance_summary``,
``phase_statistics``, ``fig9_statistics``, ``fig10_statistics``) so that a notebook can show the
numbers behind every bar. Bars are means over robots (a robot's value is the mean over its
trials, see ``summaries.robot_means``), error bars one standard error of that mean. Missing data
(a phase not evaluated, a measure that is NaN for every robot, a trial not recorded) leaves an
empty slot marked "n/a" rather than failing.

Needs matplotlib (the ``notebooks`` or ``dev`` extras); the rest of the package does not.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import polars as pl
from matplotlib import colormaps
from matplotlib.collections import LineCollection
from matplotlib.colors import ListedColormap, Normalize
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle
from matplotlib.ticker import MaxNLocator

from . import budgets, stats, summaries
from ..measures import metrics
from ..postevaluation.systematic import BALL_ABSENT, SENSES, TESTS, load_evaluation, run_phases
from ..evolution.run import Run
from ..recording.rrd import read_rrd
from ..model.world import POINTS_PER_SECTOR, SectorConfig

#: Colours of the sensory conditions (section IV-B, Figs. 8, 9).
SENSES_COLOURS = {"normal": "#333333", "no-touch": "#1f77b4", "no-sight": "#ff7f0e",
                  "nothing": "#d62728"}

#: Fig. 5: (column of the evaluation table, axis label, scale).
FIG5_MEASURES = (("grasped", "grasped objects (%)", 100.0),
                 ("reached", "reached objects (%)", 100.0),
                 ("speed", "reaching speed (m/s)", 1.0),
                 ("straightness", "reaching straightness", 1.0))

#: Fig. 6, bottom: movement variability (rad) and, beyond the paper, elbow freezing (m).
FIG6_MEASURES = (("var_elbow", "elbow variability (rad)", 1.0),
                 ("var_shoulder", "shoulder variability (rad)", 1.0),
                 ("var_trunk", "trunk variability (rad)", 1.0),
                 ("elbow_freezing", "elbow freezing: s.d. of\nhand-shoulder distance (m)", 1.0))

#: Beyond the paper (Fig. 8 / section IV-A-1): motor babbling.
BABBLING_MEASURES = (("babbling_freq_hz", "dominant frequency of the hand (Hz)", 1.0),
                     ("babbling_share", "power share of that frequency", 1.0))

#: Trials drawn in Fig. 6 (top): the centre of each sector (the first of its 5 positions).
SECTOR_CENTRE_TRIALS = tuple(POINTS_PER_SECTOR * s for s in range(9))

#: Fewer values than this in a group of Fig. 10: dots and their median, no box plot.
BOX_MIN = 5

#: Trial drawn in Fig. 8 by default: the centre of the middle sector (4).
FIG8_TRIAL = POINTS_PER_SECTOR * 4

_ROBOT = ("phase", "replication", "rank")


# ---------------------------------------------------------------------------------------------
# Run helpers
# ---------------------------------------------------------------------------------------------

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
    return Run.open(run_dir).settings.world.sectors


def ball_radius(run_dir) -> float:
    """The ball radius (m) of a run (drawn in Fig. 8)."""
    return float(Run.open(run_dir).settings.world.ball.radius)


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
        table = load_evaluation(run_dir)
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
    """The trials (sorted by trial) of the best recorded robot of ``phase`` under ``senses``:
    among robots with recordings, the one of highest lifetime fitness, i.e. by default the best
    robot (rank 0) of the best replication (Figs. 6, 8). Empty when nothing was recorded."""
    rows = table.filter((pl.col("phase") == phase) & (pl.col("senses") == senses)
                        & pl.col("recording").is_not_null())
    if rows.height == 0:
        return rows
    best = (rows.group_by("replication", "rank")
            .agg(pl.col("lifetime_fitness").first())
            .sort(["lifetime_fitness", "rank", "replication"], descending=[True, False, False])
            .row(0, named=True))
    return rows.filter((pl.col("replication") == best["replication"])
                       & (pl.col("rank") == best["rank"])).sort("trial")


def _xyz(rec: pl.DataFrame, entity: str) -> np.ndarray:
    return rec.select([f"robot/positions/{entity}/{a}" for a in "xyz"]).to_numpy().astype(float)


# ---------------------------------------------------------------------------------------------
# Tables behind the figures
# ---------------------------------------------------------------------------------------------

def _phases(table: pl.DataFrame, phases: Sequence[str] | None) -> list[str]:
    if phases is None:
        return list(dict.fromkeys(table["phase"].to_list()))
    return list(phases)


def _select(table: pl.DataFrame, phases: Sequence[str], senses: str | Sequence[str]):
    senses = [senses] if isinstance(senses, str) else list(senses)
    return table.filter(pl.col("phase").is_in(list(phases)) & pl.col("senses").is_in(senses))


def performance_summary(table: pl.DataFrame, measures: Sequence[str],
                        phases: Sequence[str] | None = None,
                        senses: str = "normal") -> pl.DataFrame:
    """Mean, s.d. and s.e.m. over robots of each measure per phase (the bars of Figs. 5, 6 and
    ``fig8_babbling``): ``summaries.group_summary`` of ``summaries.robot_means`` of the trials of
    ``senses``, phases in the order given."""
    phases = _phases(table, phases)
    robots = summaries.robot_means(_select(table, phases, senses), measures, by=_ROBOT)
    summary = summaries.group_summary(robots, measures, by=("phase",))
    rank = {p: i for i, p in enumerate(phases)}
    return (summary.with_columns(pl.col("phase").replace_strict(rank, return_dtype=pl.Int64)
                                 .alias("_p"))
            .sort("_p", maintain_order=True).drop("_p"))


_PAIRS_SCHEMA = {"a": pl.Utf8, "b": pl.Utf8, "n_a": pl.Int64, "n_b": pl.Int64, "U": pl.Float64,
                 "p": pl.Float64, "significant": pl.Boolean}


def _mann_whitney(units: pl.DataFrame, value: str, group: str, order: list,
                  alpha: float) -> pl.DataFrame:
    present = set(units[group].cast(pl.Utf8).to_list())
    order = [g for g in order if g in present]
    if len(order) < 2:
        return pl.DataFrame(schema=_PAIRS_SCHEMA)
    units = units.with_columns(pl.col(group).cast(pl.Utf8))
    return stats.mann_whitney(units, value, group, order=order, alpha=alpha)


def _with_holm(pairs: pl.DataFrame, alpha: float) -> pl.DataFrame:
    """``stats.holm`` over the family of pairs (an empty table gets the empty columns)."""
    if pairs.height == 0:
        return pairs.with_columns(pl.lit(None, pl.Float64).alias("p_holm"),
                                  pl.lit(None, pl.Boolean).alias("significant_holm"))
    return stats.holm(pairs, alpha)


def phase_statistics(table: pl.DataFrame, measures: Sequence[str],
                     phases: Sequence[str] | None = None, senses: str = "normal",
                     alpha: float = 0.05) -> pl.DataFrame:
    """Two-tailed Mann-Whitney U tests between every pair of phases for each measure, the robot
    being the unit (its mean over its trials): the p-values section IV-A quotes for Figs. 5 and
    6. Columns: measure, then those of ``stats.mann_whitney``."""
    phases = _phases(table, phases)
    robots = summaries.robot_means(_select(table, phases, senses), measures, by=_ROBOT)
    parts = [_mann_whitney(robots, m, "phase", phases, alpha)
             .with_columns(pl.lit(m).alias("measure")) for m in measures]
    out = pl.concat(parts, how="diagonal_relaxed") if parts else pl.DataFrame(schema=_PAIRS_SCHEMA)
    if "measure" not in out.columns:
        out = out.with_columns(pl.lit(None, pl.Utf8).alias("measure"))
    return out.select("measure", *_PAIRS_SCHEMA)


def fig9_statistics(table: pl.DataFrame, phases: Sequence[str] | None = None,
                    senses: Sequence[str] = SENSES, alpha: float = 0.05) -> dict[str, pl.DataFrame]:
    """The numbers of Fig. 9: ``robots`` (one row per robot: ``summaries.robot_performance`` of
    each phase x senses, with its group label "phase / senses"), ``summary`` (mean, s.d., s.e.m.
    of the robots' fitness per phase and senses), ``kruskal`` (Kruskal-Wallis across senses
    within each phase, section IV-B; NaN when fewer than two sensory conditions have robots),
    ``pairs`` (two-tailed Mann-Whitney between every pair of groups, with ``p_holm``: Holm's
    correction over the pairs, ``stats.holm``), ``matrix`` (the pairs as the square table of
    ``stats.significance_matrix``, uncorrected as in the paper) and ``matrix_holm`` (the same
    after Holm's correction)."""
    phases = _phases(table, phases)
    senses = list(senses)
    robots = summaries.robot_performance(_select(table, phases, senses),
                                       by=("phase", "senses", "replication", "rank"))
    robots = robots.with_columns(pl.format("{} / {}", "phase", "senses").alias("group"))
    summary = summaries.group_summary(robots, ["fitness"], by=("phase", "senses"))
    order = [f"{p} / {s}" for p in phases for s in senses]
    key = {g: i for i, g in enumerate(order)}
    summary = (summary.with_columns(pl.format("{} / {}", "phase", "senses")
                                    .replace_strict(key, return_dtype=pl.Int64).alias("_k"))
               .sort("_k").drop("_k"))
    kw_rows = []
    for p in phases:
        try:
            kw = stats.kruskal_wallis(robots.filter(pl.col("phase") == p), "fitness", "senses")
            kw_rows.append({"phase": p, **kw.row(0, named=True)})
        except ValueError:
            kw_rows.append({"phase": p, "groups": 0, "n": 0, "H": math.nan, "p": math.nan})
    kruskal = pl.DataFrame(kw_rows, schema={"phase": pl.Utf8, "groups": pl.Int64, "n": pl.Int64,
                                            "H": pl.Float64, "p": pl.Float64})
    present = set(robots["group"].to_list())
    order = [g for g in order if g in present]
    pairs = _with_holm(_mann_whitney(robots, "fitness", "group", order, alpha), alpha)
    return {"robots": robots, "summary": summary, "kruskal": kruskal, "pairs": pairs,
            "matrix": stats.significance_matrix(pairs, order),
            "matrix_holm": stats.significance_matrix(pairs, order, "significant_holm")}


def _groups(replications: pl.DataFrame, order: Sequence[str] | None) -> list[str]:
    if order is not None:
        return [str(g) for g in order]
    dtype = replications.schema["group"]
    if isinstance(dtype, pl.Enum):
        present = set(replications["group"].cast(pl.Utf8).to_list())
        return [g for g in dtype.categories.to_list() if g in present]
    return [str(g) for g in dict.fromkeys(replications["group"].to_list())]


def fig10_statistics(replications: pl.DataFrame, order: Sequence[str] | None = None,
                     value: str = "fitness", alpha: float = 0.05) -> dict[str, pl.DataFrame]:
    """The numbers of Fig. 10 from a per-replication table with a ``group`` column (e.g.
    ``summaries.replication_performance(load_runs(dirs), by=("group",))``): ``summary`` (per
    group: replications, median, mean, min, max of ``value``; the median is the thickness of
    the boxes of the paper's top diagram), ``pairs`` (two-tailed Mann-Whitney between every pair
    of groups, with Holm's ``p_holm``), ``matrix`` (``stats.significance_matrix``, uncorrected
    as in the paper) and ``matrix_holm`` (after Holm's correction)."""
    groups = _groups(replications, order)
    units = replications.with_columns(pl.col("group").cast(pl.Utf8))
    key = {g: i for i, g in enumerate(groups)}
    summary = (units.filter(pl.col("group").is_in(groups))
               .with_columns(pl.col(value).cast(pl.Float64).fill_nan(None))
               .group_by("group")
               .agg(pl.col(value).count().alias("replications"),
                    pl.col(value).median().alias("median"), pl.col(value).mean().alias("mean"),
                    pl.col(value).min().alias("min"), pl.col(value).max().alias("max"))
               .with_columns(pl.col("group").replace_strict(key, return_dtype=pl.Int64)
                             .alias("_k"))
               .sort("_k").drop("_k"))
    pairs = _with_holm(_mann_whitney(units, value, "group", groups, alpha), alpha)
    present = [g for g in groups if g in set(units["group"].to_list())]
    return {"summary": summary, "pairs": pairs,
            "matrix": stats.significance_matrix(pairs, present),
            "matrix_holm": stats.significance_matrix(pairs, present, "significant_holm")}


# ---------------------------------------------------------------------------------------------
# Drawing helpers
# ---------------------------------------------------------------------------------------------

def _phase_colours(phases: Sequence[str]) -> dict[str, tuple]:
    cmap = colormaps["tab10"]
    return {p: cmap(i % 10) for i, p in enumerate(phases)}


def _na(ax, x, text="n/a"):
    ax.text(x, 0.02, text, transform=ax.get_xaxis_transform(), ha="center", va="bottom",
            fontsize=9, color="0.4")


def _bar_panel(ax, summary: pl.DataFrame, measure: str, phases: Sequence[str], scale: float,
               label: str, colours: dict) -> None:
    rows = {r["phase"]: r for r in summary.filter(pl.col("measure") == measure)
            .iter_rows(named=True)}
    x = np.arange(len(phases))
    top = 0.0
    for i, p in enumerate(phases):
        r = rows.get(p)
        mean = r["mean"] * scale if r else math.nan
        sem = r["sem"] * scale if r else math.nan
        if math.isfinite(mean):
            ax.bar(i, mean, color=colours[p], width=0.65, edgecolor="black", linewidth=0.6)
            if math.isfinite(sem):
                ax.errorbar(i, mean, yerr=sem, color="black", capsize=4, linewidth=1)
            top = max(top, mean + (sem if math.isfinite(sem) else 0.0))
        else:
            _na(ax, i)
    ax.set_xticks(x, [f"{p}\nn={rows[p]['n'] if p in rows else 0}" for p in phases])
    ax.set_xlim(-0.6, len(phases) - 0.4)
    ax.set_ylim(0, top * 1.15 if top > 0 else 1.0)
    ax.set_ylabel(label)
    ax.grid(axis="y", alpha=0.3)


def _bars_figure(table, measures, phases, senses, grid, size):
    """A figure of one bar panel per (measure, label, scale) of ``measures``, phases as bars."""
    summary = performance_summary(table, [m for m, _, _ in measures], phases, senses)
    colours = _phase_colours(phases)
    fig = Figure(figsize=size, layout="constrained")
    axes = fig.subplots(*grid)
    for ax, (m, label, scale) in zip(axes.ravel(), measures):
        _bar_panel(ax, summary, m, phases, scale, label, colours)
    return fig, axes


def _draw_matrix(ax, st: dict, alpha: float) -> None:
    """The pairs of ``st`` (``fig9_statistics``, ``fig10_statistics``) as a square table:
    black where p < alpha after Holm's correction over the pairs, grey where only the
    uncorrected p (the paper's test) is below alpha."""
    matrix = st["matrix"]
    names = matrix["group"].to_list()
    n = len(names)
    sig = (matrix.drop("group").to_numpy().astype(float)
           + st["matrix_holm"].drop("group").to_numpy().astype(float)) if n else np.zeros((0, 0))
    if n:
        np.fill_diagonal(sig, np.nan)
    cmap = ListedColormap(["white", "0.62", "black"]).with_extremes(bad="0.9")
    ax.imshow(np.ma.masked_invalid(sig) if n else np.zeros((1, 1)), cmap=cmap, vmin=0, vmax=2,
              interpolation="nearest")
    ax.set_xticks(range(n), names, rotation=90, fontsize=9)
    ax.set_yticks(range(n), names, fontsize=9)
    ax.set_xticks(np.arange(-0.5, n, 1), minor=True)
    ax.set_yticks(np.arange(-0.5, n, 1), minor=True)
    ax.grid(which="minor", color="0.5", linewidth=0.5)
    ax.tick_params(which="minor", length=0)
    tested = int(st["pairs"]["p"].is_not_nan().sum()) if st["pairs"].height else 0
    ax.set_title(f"Mann-Whitney, two-tailed, {tested} pairs\nblack: p < {alpha:g} after Holm's "
                 f"correction;\ngrey: p < {alpha:g} uncorrected only (the paper's test)",
                 fontsize=9)
    if n < 2:
        ax.text(0.5, 0.5, "fewer than 2 groups", transform=ax.transAxes, ha="center",
                va="center", fontsize=9, color="0.4")


# ---------------------------------------------------------------------------------------------
# Training
# ---------------------------------------------------------------------------------------------

def training_curves(stats_table: pl.DataFrame, phases: pl.DataFrame | None = None) -> Figure:
    """Best and mean fitness per generation (``generations.parquet``), one panel per condition;
    the phases follow each other on the x axis (a phase's generations after its predecessor's),
    dotted lines at phase boundaries. Thin lines: the best fitness of each replication; thick:
    its mean over replications; dashed: the population mean fitness averaged over
    replications. ``phases``: ``evaluation.run_phases`` of the run, to draw a phase shared by
    conditions (trained once) in each of them; default: the conditions of the table."""
    if phases is None:
        seq = (stats_table.select("condition", "phase", "phase_key")
               .unique(maintain_order=True))
    else:
        seq = phases.select("condition", "phase", "phase_key")
    conditions = list(dict.fromkeys(seq["condition"].to_list())) or ["(none)"]
    fig = Figure(figsize=(11, 2.8 * len(conditions) + 0.4), layout="constrained")
    axes = fig.subplots(len(conditions), 1, squeeze=False)[:, 0]
    colours = _phase_colours(list(dict.fromkeys(seq["phase"].to_list())))
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


# ---------------------------------------------------------------------------------------------
# Fig. 5
# ---------------------------------------------------------------------------------------------

def fig5_performance(table: pl.DataFrame, phases: Sequence[str] | None = None,
                     senses: str = "normal") -> Figure:
    """Fig. 5: percentage of grasped and of reached objects (top), reaching speed and
    straightness (bottom) at the end of each phase, post-evaluation under ``senses``. Bars: mean
    over robots of each robot's mean over its trials (speed and straightness over its reaching
    trials only); error bars: s.e.m. over robots; n = robots with a value."""
    phases = _phases(table, phases)
    fig, axes = _bars_figure(table, FIG5_MEASURES, phases, senses, (2, 2), (8, 6.5))
    for ax in axes[0]:
        ax.set_ylim(0, 100)
    fig.suptitle(f"Fig. 5 - grasping and reaching at the end of each phase\n"
                 f"(post-evaluation, {senses} senses; mean $\\pm$ s.e.m. over robots)",
                 fontsize=10)
    return fig


# ---------------------------------------------------------------------------------------------
# Fig. 6
# ---------------------------------------------------------------------------------------------

def fig6_distances_variability(table: pl.DataFrame, run_dir, phases: Sequence[str] | None = None,
                               senses: str = "normal", phase: str = "pre",
                               trials: Sequence[int] = SECTOR_CENTRE_TRIALS) -> Figure:
    """Fig. 6. Top: hand-shoulder and hand-ball distance (m) over ``trials`` (default the centre
    of each of the 9 sectors) of the best recorded robot of ``phase`` (the best robot of the
    best replication at the end of pre-reaching), read from its recordings, one after the other;
    dotted lines mark the start of each trial (posture reset). Bottom: movement variability
    (s.d. over time of the joint encoders) of elbow, shoulder and trunk per phase, and beyond
    the paper the elbow freezing (s.d. of the hand-shoulder distance): mean $\\pm$ s.e.m. over
    robots."""
    phases = _phases(table, phases)
    fig = Figure(figsize=(11, 6.8), layout="constrained")
    grid = fig.add_gridspec(2, 4, height_ratios=[1.1, 1])
    top = fig.add_subplot(grid[0, :])
    robot = recorded_robot(table, phase, senses)
    by_trial = {r["trial"]: r for r in robot.iter_rows(named=True)}
    offset = 0.0
    drawn = 0
    for k in trials:
        r = by_trial.get(k)
        if r is None:
            continue
        rec = read_rrd(Path(run_dir) / r["recording"])
        t = rec["sim_time"].to_numpy()
        hand = _xyz(rec, "hand")
        d_shoulder = metrics.hand_shoulder_distance(hand, _xyz(rec, "shoulder"))
        d_ball = metrics.hand_ball_distance(hand, _xyz(rec, "ball"))
        top.plot(offset + t, d_shoulder, color="#1f77b4", linewidth=1.3, zorder=3,
                 label="hand-shoulder" if drawn == 0 else None)
        top.plot(offset + t, d_ball, color="#d62728", linewidth=1.1,
                 label="hand-ball" if drawn == 0 else None)
        top.axvline(offset, color="0.3", linestyle=":", linewidth=1)
        top.text(offset, 1.0, f" sector {r['sector']}", transform=top.get_xaxis_transform(),
                 fontsize=9, va="bottom", ha="left")
        dt = float(t[1] - t[0]) if len(t) > 1 else metrics.DT
        offset += float(t[-1]) + dt if len(t) else 0.0
        drawn += 1
    if drawn:
        r0 = robot.row(0, named=True)
        top.set_title(f"{phase}: best recorded robot (replication {r0['replication']}, rank "
                      f"{r0['rank']}), {senses} senses, {drawn} trials", fontsize=9, pad=14)
        top.set_xlim(0, offset)
        top.set_ylim(bottom=0)
        top.legend(fontsize=9, loc="upper right")
    else:
        top.text(0.5, 0.5, f"no recorded trial of phase {phase!r} ({senses} senses): "
                 "evaluate the run with recordings", transform=top.transAxes, ha="center",
                 va="center", color="0.4")
    top.set_xlabel("time (s), trials one after the other")
    top.set_ylabel("distance (m)")
    top.grid(alpha=0.3)

    names = [m for m, _, _ in FIG6_MEASURES]
    summary = performance_summary(table, names, phases, senses)
    colours = _phase_colours(phases)
    for j, (m, label, scale) in enumerate(FIG6_MEASURES):
        ax = fig.add_subplot(grid[1, j])
        _bar_panel(ax, summary, m, phases, scale, label, colours)
        if m == "elbow_freezing":
            ax.set_title("beyond the paper", fontsize=9, color="0.35")
    fig.suptitle("Fig. 6 - hand distances (top) and movement variability (bottom; mean "
                 f"$\\pm$ s.e.m. over robots, {senses} senses)", fontsize=10)
    return fig


# ---------------------------------------------------------------------------------------------
# Fig. 7
# ---------------------------------------------------------------------------------------------

def _sector_ticks(ax, sectors: SectorConfig, left: bool, bottom: bool) -> None:
    az, el = sectors.azimuth_edges, sectors.elevation_edges
    ax.set_xticks(range(3), [f"{az[i]:g} to {az[i + 1]:g}" for i in range(3)] if bottom else [],
                  fontsize=9)
    ax.set_yticks(range(3), [f"{el[i]:g} to {el[i + 1]:g}" for i in range(3)] if left else [],
                  fontsize=9)
    if bottom:
        ax.set_xlabel("azimuth (deg, 0 = ahead)", fontsize=9)


def _annotate_grid(ax, grid: np.ndarray, text) -> None:
    """Write ``text(row, col)`` in each cell: white on the dark (low) end of viridis."""
    for row in range(grid.shape[0]):
        for col in range(grid.shape[1]):
            ax.text(col, row, text(row, col), ha="center", va="center", fontsize=9,
                    color="white" if np.isfinite(grid[row, col]) and grid[row, col] < 50
                    else "black")


def fig7_sector_maps(table: pl.DataFrame, phases: Sequence[str] | None = None,
                     senses: str = "normal", sectors: SectorConfig | None = None) -> Figure:
    """Fig. 7: percentage of trials with a reach (upper row) and with a grasp (lower row) in
    each of the 9 sectors at the end of each phase (columns), post-evaluation under ``senses``.
    Each map is the sector patch as the robot sees it: elevation row 0 (lowest) at the bottom,
    azimuth column 0 (straight ahead) on the left. Grey: no trial."""
    phases = _phases(table, phases)
    sectors = sectors or SectorConfig()
    rates = summaries.sector_success(_select(table, phases, senses), by=("phase",))
    n = max(len(phases), 1)
    fig = Figure(figsize=(2.9 * n + 1.2, 6.0), layout="constrained")
    axes = fig.subplots(2, n, squeeze=False)
    cmap = colormaps["viridis"].with_extremes(bad="0.85")
    image = None
    for j in range(n):
        p = phases[j] if phases else None
        sub = rates.filter(pl.col("phase") == p) if p is not None else rates.head(0)
        for i, (value, what) in enumerate((("reach_rate", "reach"), ("grasp_rate", "grasp"))):
            ax = axes[i, j]
            grid = summaries.sector_grid(sub, value) * 100
            image = ax.imshow(np.ma.masked_invalid(grid), origin="lower", cmap=cmap, vmin=0,
                              vmax=100, interpolation="nearest")
            _annotate_grid(ax, grid, lambda r, c, g=grid: f"{g[r, c]:.0f}%"
                           if np.isfinite(g[r, c]) else "-")
            _sector_ticks(ax, sectors, left=j == 0, bottom=i == 1)
            if i == 0:
                ax.set_title(p if p is not None else "(no phase)", fontsize=10)
            if j == 0:
                ax.set_ylabel(f"{what}\nelevation (deg)", fontsize=9)
    fig.colorbar(image, ax=axes.ravel().tolist(), label="% of trials", shrink=0.8)
    fig.suptitle(f"Fig. 7 - where the robots reach (top) and grasp (bottom), {senses} senses",
                 fontsize=10)
    return fig


def fig7_reach_regression(table: pl.DataFrame, before: str = "pre", after: str = "gross",
                          senses: str = "normal", sectors: SectorConfig | None = None) -> Figure:
    """Beyond the paper (section IV-A-2, Fig. 7): the change of the reach rate per sector from
    phase ``before`` to phase ``after`` (``summaries.reach_regression``), in percentage points;
    red where reaching regresses, blue where it improves. Each cell reads
    "before% -> after%"."""
    sectors = sectors or SectorConfig()
    fig = Figure(figsize=(5.2, 4.4), layout="constrained")
    ax = fig.subplots()
    cmap = colormaps["RdBu"].with_extremes(bad="0.85")
    sub = table.filter(pl.col("senses") == senses)
    try:
        reg = summaries.reach_regression(sub, before, after)
    except ValueError as exc:
        reg, message = None, str(exc)
    if reg is None:
        grid = b = a = np.full((3, 3), np.nan)
        ax.text(0.5, 0.5, message, transform=ax.transAxes, ha="center", va="center",
                fontsize=9, color="0.3")
    else:
        grid = summaries.sector_grid(reg, "change") * 100
        b = summaries.sector_grid(reg, "reach_before") * 100
        a = summaries.sector_grid(reg, "reach_after") * 100

    def text(r, c):
        if reg is None:
            return ""
        if not np.isfinite(grid[r, c]):
            return "-"
        return f"{b[r, c]:.0f}% -> {a[r, c]:.0f}%\n({grid[r, c]:+.0f})"
    image = ax.imshow(np.ma.masked_invalid(grid), origin="lower", cmap=cmap, vmin=-100,
                      vmax=100, interpolation="nearest")
    for r in range(3):
        for c in range(3):
            ax.text(c, r, text(r, c), ha="center", va="center", fontsize=9,
                    color="white" if np.isfinite(grid[r, c]) and abs(grid[r, c]) > 60
                    else "black")
    _sector_ticks(ax, sectors, left=True, bottom=True)
    ax.set_ylabel("elevation (deg)", fontsize=9)
    fig.colorbar(image, ax=ax, label="reach rate change (percentage points)")
    ax.set_title(f"reach rate per sector, {before} -> {after} ({senses} senses)\n"
                 "beyond the paper", fontsize=9)
    return fig


# ---------------------------------------------------------------------------------------------
# Fig. 8
# ---------------------------------------------------------------------------------------------

#: 2D projections of the world frame (+x backward, +y to the robot's right, +z up):
#: (horizontal axis, vertical axis) as (coordinate index, sign, label).
VIEWS = {
    "front": ((1, 1.0, "y: to the robot's right (m)"), (2, 1.0, "z: up (m)")),
    "side": ((0, -1.0, "-x: forward (m)"), (2, 1.0, "z: up (m)")),
    "top": ((1, 1.0, "y: to the robot's right (m)"), (0, -1.0, "-x: forward (m)")),
}


def _project(points: np.ndarray, view: str) -> tuple[np.ndarray, np.ndarray]:
    (i, si, _), (j, sj, _) = VIEWS[view]
    return si * points[:, i], sj * points[:, j]


def fig8_trajectories(table: pl.DataFrame, run_dir, phases: Sequence[str] | None = None,
                      senses: Sequence[str] = TESTS, trial: int = FIG8_TRIAL,
                      view: str = "front", radius: float | None = None) -> Figure:
    """Fig. 8: the hand's path (palm point) in one trial (default the centre of sector 4) of the
    best recorded robot of each phase (columns) under each sensory condition (rows), read from
    the recordings, projected on a plane: ``view`` "front" (as seen from behind the robot),
    "side" (forward to the right) or "top". The path's colour is time; o marks the start, x the
    end; the red disc is the ball at the start (its path in red), + the shoulder. The row of
    the ball-absent test (no-ball, section IV-A-1) draws a dashed circle where the ball would
    hang. All panels share one scale."""
    if view not in VIEWS:
        raise ValueError(f"view must be one of {', '.join(VIEWS)}, got {view!r}")
    phases = _phases(table, phases)
    senses = list(senses)
    radius = ball_radius(run_dir) if radius is None else radius
    rows, cols = max(len(senses), 1), max(len(phases), 1)
    fig = Figure(figsize=(2.9 * cols + 1.2, 2.7 * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, cols, squeeze=False)
    paths = {}
    t_max = 0.0
    for i, s in enumerate(senses):
        for j, p in enumerate(phases):
            robot = recorded_robot(table, p, s).filter(pl.col("trial") == trial)
            if robot.height:
                rec = read_rrd(Path(run_dir) / robot["recording"][0])
                paths[i, j] = (rec["sim_time"].to_numpy(), _xyz(rec, "hand"), _xyz(rec, "ball"),
                               _xyz(rec, "shoulder"), robot.row(0, named=True))
                t_max = max(t_max, float(paths[i, j][0][-1]) if rec.height else 0.0)
    norm = Normalize(0.0, t_max or 1.0)
    cmap = colormaps["viridis"]
    (_, _, xlabel), (_, _, ylabel) = VIEWS[view]
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for i in range(rows):
        for j in range(cols):
            ax = axes[i, j]
            if (i, j) not in paths:
                ax.text(0.5, 0.5, "no recording", transform=ax.transAxes, ha="center",
                        va="center", fontsize=9, color="0.4")
            else:
                t, hand, ball, shoulder, info = paths[i, j]
                hx, hy = _project(hand, view)
                bx, by = _project(ball, view)
                sx, sy = _project(shoulder, view)
                pts = np.column_stack([hx, hy])
                if len(pts) > 1:
                    seg = np.stack([pts[:-1], pts[1:]], axis=1)
                    lc = LineCollection(seg, cmap=cmap, norm=norm, linewidth=1.1)
                    lc.set_array(t[:-1])
                    ax.add_collection(lc)
                if senses[i] == BALL_ABSENT:
                    ax.add_patch(Circle((bx[0], by[0]), radius, fill=False, color="#d62728",
                                        linestyle="--", linewidth=0.8))
                else:
                    ax.plot(bx, by, color="#d62728", linewidth=0.8, alpha=0.7)
                    ax.add_patch(Circle((bx[0], by[0]), radius, color="#d62728", alpha=0.6))
                ax.plot(hx[:1], hy[:1], "o", color=cmap(0.0), markersize=5, mec="black", mew=0.5)
                ax.plot(hx[-1:], hy[-1:], "x", color="black", markersize=6)
                ax.plot([sx.mean()], [sy.mean()], "+", color="black", markersize=9)
                xs = np.concatenate([hx, bx, sx])
                ys = np.concatenate([hy, by, sy])
                lo = np.minimum(lo, [xs.min() - radius, ys.min() - radius])
                hi = np.maximum(hi, [xs.max() + radius, ys.max() + radius])
                flags = ("reached" if info["reached"] else "no reach") + (
                    ", grasped" if info["grasped"] else "")
                ax.text(0.02, 0.98, f"rep {info['replication']} #{info['rank']}: {flags}",
                        transform=ax.transAxes, fontsize=9, va="top")
            if i == 0:
                ax.set_title(phases[j] if phases else "(no phase)", fontsize=10)
            if j == 0:
                ax.set_ylabel(f"{senses[i] if senses else ''}\n{ylabel}", fontsize=9)
            if i == rows - 1:
                ax.set_xlabel(xlabel, fontsize=9)
            ax.tick_params(labelsize=9)
            ax.grid(alpha=0.25)
    if np.all(np.isfinite(lo)):
        centre, half = (lo + hi) / 2, max((hi - lo).max() / 2, 0.05) * 1.05
        for ax in axes.ravel():
            ax.set_xlim(centre[0] - half, centre[0] + half)
            ax.set_ylim(centre[1] - half, centre[1] + half)
            ax.set_aspect("equal", adjustable="box")
    fig.colorbar(_mappable(cmap, norm), ax=axes.ravel().tolist(), label="time (s)",
                 shrink=0.6)
    fig.suptitle(f"Fig. 8 - hand trajectories, trial {trial} (sector {trial // POINTS_PER_SECTOR}),"
                 f" {view} view", fontsize=10)
    return fig


def _mappable(cmap, norm):
    """A ScalarMappable for a colour bar of ``cmap`` over ``norm``."""
    from matplotlib.cm import ScalarMappable
    return ScalarMappable(norm=norm, cmap=cmap)


def fig8_babbling(table: pl.DataFrame, phases: Sequence[str] | None = None,
                  senses: str = "normal") -> Figure:
    """Beyond the paper (section IV-A-1, Fig. 8): motor babbling per phase, from
    ``metrics.hand_periodicity``: the dominant frequency of the hand's movement and the share of
    the movement's power at that frequency (near 1 for one steady oscillation, small for
    irregular movement); mean $\\pm$ s.e.m. over robots."""
    phases = _phases(table, phases)
    fig, axes = _bars_figure(table, BABBLING_MEASURES, phases, senses, (1, 2), (8, 3.6))
    axes[1].set_ylim(0, 1)
    fig.suptitle(f"Motor babbling: periodicity of the hand's movement ({senses} senses; beyond "
                 "the paper)", fontsize=10)
    return fig


# ---------------------------------------------------------------------------------------------
# Fig. 9
# ---------------------------------------------------------------------------------------------

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
                _na(ax, x, "-")
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
    phases = _phases(table, phases)
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
    _draw_matrix(fig.add_subplot(grid[1, 0]), st, alpha)
    right = fig.add_subplot(grid[1, 1])
    _grouped_bars(right, st["summary"], senses, phases, "senses", "phase",
                  _phase_colours(phases))
    right.set_title("the same, grouped by sensory condition", fontsize=9)
    fig.suptitle("Fig. 9 - performance with and without touch and sight", fontsize=10)
    return fig


# ---------------------------------------------------------------------------------------------
# Fig. 10
# ---------------------------------------------------------------------------------------------

def fig10_conditions(replications: pl.DataFrame, order: Sequence[str] | None = None,
                     value: str = "fitness", alpha: float = 0.05) -> Figure:
    """Fig. 10 (bottom). Left: the per-replication performance of every group (a phase of a
    condition: ``load_runs`` then ``summaries.replication_performance(..., by=("group",))``),
    each replication a dot, with a box plot where a group has at least ``BOX_MIN`` values
    (a red line at the median otherwise). Right: black squares where two groups differ
    (two-tailed Mann-Whitney, p < ``alpha`` after Holm's correction; grey: uncorrected
    only). See ``fig10_statistics``."""
    groups = _groups(replications, order)
    st = fig10_statistics(replications, groups, value, alpha)
    fig = Figure(figsize=(12, 5.2), layout="constrained")
    grid = fig.add_gridspec(1, 2, width_ratios=[1.5, 1])
    ax = fig.add_subplot(grid[0, 0])
    units = replications.with_columns(pl.col("group").cast(pl.Utf8))
    rng = np.random.default_rng(0)
    for i, g in enumerate(groups):
        x = units.filter(pl.col("group") == g)[value].cast(pl.Float64).to_numpy()
        x = x[np.isfinite(x)]
        if len(x) == 0:
            _na(ax, i + 1)
            continue
        if len(x) >= BOX_MIN:
            ax.boxplot([x], positions=[i + 1], widths=0.55, showfliers=False,
                       medianprops={"color": "#d62728", "linewidth": 1.5})
        else:  # a strip plot: too few values for quartiles
            ax.hlines(np.median(x), i + 0.75, i + 1.25, color="#d62728", linewidth=1.5)
        ax.plot(i + 1 + rng.uniform(-0.12, 0.12, len(x)), x, "o", color="#1f77b4",
                markersize=5, alpha=0.8)
    ax.set_xticks(range(1, len(groups) + 1), groups, rotation=45 if len(groups) > 5 else 0,
                  ha="right" if len(groups) > 5 else "center")
    ax.set_xlim(0.4, len(groups) + 0.6)
    ax.set_ylabel(f"{value} per replication\n(post-evaluation, best robot)")
    ax.grid(axis="y", alpha=0.3)
    counts = {r["group"]: r["replications"] for r in st["summary"].iter_rows(named=True)}
    ax.set_title("replications per group: " + ", ".join(f"{g} {counts.get(g, 0)}"
                                                        for g in groups)
                 + f"\nbox plots for {BOX_MIN} or more replications; red line: median",
                 fontsize=9)
    _draw_matrix(fig.add_subplot(grid[0, 1]), st, alpha)
    fig.suptitle("Fig. 10 - performance of every phase and condition", fontsize=10)
    return fig


# ---------------------------------------------------------------------------------------------
# Issue 22: the behaviours of Table I and section IV-A, the development over generations
# ---------------------------------------------------------------------------------------------

#: Table I and section IV-A behaviours per phase (column, label, scale); definitions and
#: thresholds in docs/analysis.md.
BEHAVIOUR_MEASURES = (
    ("babbling", "motor babbling (% of trials)", 100.0),
    ("heading", "arm orienting: heading\ntoward the ball (-1..1)", 1.0),
    ("hand_shoulder_cv", "arm as a lever: CV of the\nhand-shoulder distance", 1.0),
    ("movement_units", "movement units\nbefore the first touch", 1.0),
    ("anticipatory_grasp", "anticipatory grasps\n(% of palm touches)", 100.0),
    ("palm_up_swipe", "palm-up upward swipes\n(% of first touches)", 100.0))


def table1_behaviours(table: pl.DataFrame, phases: Sequence[str] | None = None,
                      senses: str = "normal") -> Figure:
    """The behaviours Table I and section IV-A attribute to the phases (``BEHAVIOUR_MEASURES``:
    babbling, arm orienting, the arm as a lever, smoothness, anticipatory grasp, the
    gross-reachers' swipes), mean $\\pm$ s.e.m. over robots of each robot's mean over its
    trials (a rate for the 0/1 measures, over the trials where it is defined)."""
    phases = _phases(table, phases)
    present = tuple(m for m in BEHAVIOUR_MEASURES if m[0] in table.columns)
    fig, _ = _bars_figure(table, present, phases, senses, (2, 3), (11, 6.5))
    fig.suptitle(f"Table I behaviours per phase ({senses} senses; mean $\\pm$ s.e.m. over "
                 "robots)", fontsize=10)
    return fig


def development_figure(course_table: pl.DataFrame, measure: str, label: str | None = None,
                       condition: str | None = None) -> Figure:
    """The course of one measure over the generations of a condition's phases
    (``development.course``): a thin line per replication, the median over replications in
    black, a dashed line where each phase starts (its name above). ``condition``: default
    "standard" if present, else the first."""
    conditions = course_table["condition"].unique(maintain_order=True).to_list()
    if condition is None:
        condition = "standard" if "standard" in conditions or not conditions else conditions[0]
    sub = course_table.filter(pl.col("condition") == condition).sort("x")
    fig = Figure(figsize=(8, 3.4), layout="constrained")
    ax = fig.subplots()
    if sub.height == 0 or measure not in sub.columns:
        ax.text(0.5, 0.5, f"no development data for {measure!r}", transform=ax.transAxes,
                ha="center", va="center", color="0.4")
        return fig
    reps = sorted(sub["replication"].unique().to_list())
    cmap = colormaps["tab10"]
    for i, r in enumerate(reps):
        line = sub.filter(pl.col("replication") == r)
        ax.plot(line["x"], line[measure], color=cmap(i % 10), linewidth=0.8, alpha=0.6,
                marker=".", markersize=3, label=f"rep {r}")
    median = (sub.group_by("x").agg(pl.col(measure).fill_nan(None).median()).sort("x"))
    ax.plot(median["x"], median[measure], color="black", linewidth=1.8, label="median")
    starts = (sub.group_by("notation", "offset").agg(pl.col("x").min()).sort("offset"))
    for row in starts.iter_rows(named=True):
        ax.axvline(row["offset"], color="0.5", linestyle="--", linewidth=0.8)
        ax.text(row["offset"], 1.01, f" {row['notation']}", transform=ax.get_xaxis_transform(),
                fontsize=8, va="bottom")
    ax.set_xlabel(f"generation ({condition}: counted through its phases)")
    ax.set_ylabel(label or measure)
    ax.grid(alpha=0.3)
    if len(reps) <= 10:
        ax.legend(fontsize=7, ncol=min(len(reps) + 1, 6), loc="best")
    return fig


#: Colours of a claim's movement as the budget grows (``budgets.movement``).
MOVEMENT_COLOURS = {budgets.TOWARD: "#2ca02c", budgets.AWAY: "#d62728",
                    budgets.NO_CHANGE: "0.35", budgets.NOT_RUN: "0.55"}


def budget_figure(by_budget: pl.DataFrame, claims: Sequence[str] | None = None,
                  columns: int = 5) -> Figure:
    """Each claim's effect against the generations per phase (x, log scale) of the budgets of
    ``by_budget`` (``budgets.findings_by_budget``): one small panel per claim, the effect on
    the scale where up is the paper's direction (``budgets.toward_paper``; the claim's own
    units, the dashed line at 0: no effect, or the claim's boundary) with its interval (a
    hollow point: none, or an unbounded one), a line per scene, and the claim's movement as
    the budget grows (``budgets.movement``) under the panel, in its colour. ``claims``: the claim ids to
    draw (default: those with an effect at two budgets or more), in the frame's order."""
    scored = budgets.toward_paper(by_budget)
    if claims is None:
        counts = (scored.filter(pl.col("toward").is_not_nan())
                  .group_by("claim").len().filter(pl.col("len") >= 2))
        claims = [c for c in scored["claim"].unique(maintain_order=True).to_list()
                  if c in set(counts["claim"].to_list())]
    claims = list(claims)
    moves = budgets.movement(by_budget)
    scenes = scored["scene"].unique(maintain_order=True).to_list()
    scene_colours = ({scenes[0]: "0.15"} if len(scenes) == 1
                     else {s: colormaps["tab10"](i % 10) for i, s in enumerate(scenes)})
    gens = sorted(scored["generations_per_phase"].unique().to_list())
    if not claims:
        fig = Figure(figsize=(8, 2), layout="constrained")
        ax = fig.subplots()
        ax.axis("off")
        ax.text(0.5, 0.5, "no claim has an effect at two budgets", ha="center", va="center",
                color="0.4", fontsize=10)
        return fig
    rows = math.ceil(len(claims) / columns)
    fig = Figure(figsize=(2.4 * columns, 2.0 * rows + 0.5), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, columns, squeeze=False)).ravel()
    for ax in axes[len(claims):]:
        ax.set_visible(False)
    for ax, claim in zip(axes, claims):
        sub = scored.filter(pl.col("claim") == claim)
        for scene in scenes:
            pts = (sub.filter((pl.col("scene") == scene) & pl.col("toward").is_not_nan())
                   .sort("generations_per_phase"))
            if pts.height == 0:
                continue
            colour = scene_colours[scene]
            x, y = pts["generations_per_phase"].to_numpy(), pts["toward"].to_numpy()
            lo, hi = pts["toward_low"].to_numpy(), pts["toward_high"].to_numpy()
            bounded = np.isfinite(lo) & np.isfinite(hi)
            ax.plot(x, y, color=colour, linewidth=1.0)
            if bounded.any():
                ax.errorbar(x[bounded], y[bounded],
                            yerr=np.clip([y[bounded] - lo[bounded],
                                          hi[bounded] - y[bounded]], 0, None),
                            fmt="o", color=colour, markersize=4, capsize=2, linewidth=1.0)
            ax.plot(x[~bounded], y[~bounded], "o", markerfacecolor="white", color=colour,
                    markersize=4)
        ax.axhline(0, color="0.5", linestyle="--", linewidth=0.7)
        ax.set_xscale("log")
        ax.set_xticks(gens, [str(g) for g in gens])
        ax.minorticks_off()
        ax.set_xlim(gens[0] / 1.3, gens[-1] * 1.3)
        ax.tick_params(labelsize=9)
        ax.yaxis.set_major_locator(MaxNLocator(3))
        ax.set_title(textwrap.fill(claim, 26), fontsize=9, loc="left")
        words = [(m["scene"], m["movement"] + (" (points)" if m["basis"] == budgets.POINTS
                                               else ""), m["movement"])
                 for m in moves.filter(pl.col("claim") == claim).iter_rows(named=True)]
        if len(words) == 1:  # under the axis, in the movement's colour
            ax.set_xlabel(words[0][1], fontsize=9, color=MOVEMENT_COLOURS[words[0][2]])
        elif words:  # one line per scene, in the scene's colour
            ax.set_xlabel("\n".join(f"{s}: {w}" for s, w, _ in words), fontsize=9)
    fig.supxlabel("generations per phase (the paper: 500)", fontsize=10)
    fig.supylabel("effect, the paper's direction up (claim's units)", fontsize=10)
    fig.suptitle("Each claim's effect against the budget (interval: the claim's own)",
                 fontsize=10)
    if len(scenes) > 1:
        handles = [Line2D([], [], color=scene_colours[s], marker="o", label=s) for s in scenes]
        fig.legend(handles=handles, loc="outside upper right", fontsize=9, ncol=len(scenes))
    return fig
