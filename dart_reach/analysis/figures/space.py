"""Where the hand goes and where the robots reach: Fig. 6 (hand distances over recorded trials,
movement variability per phase), Fig. 7 (reach and grasp rate per sector) and Fig. 8 (hand
paths per phase and sensory condition, motor babbling)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import polars as pl
from matplotlib import colormaps
from matplotlib.cm import ScalarMappable
from matplotlib.collections import LineCollection
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from .. import summaries
from ..stats import performance_summary
from ..tables import ball_radius, phase_list, positions, recorded_robot, select_trials
from ...measures import metrics
from ...model.world import POINTS_PER_SECTOR, SectorConfig
from ...postevaluation import replay
from ...postevaluation.systematic import BALL_ABSENT, TESTS
from ...recording.rrd import read_rrd
from .style import bar_panel, bars_figure, phase_colours

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

#: Trial drawn in Fig. 8 by default: the centre of the middle sector (4).
FIG8_TRIAL = POINTS_PER_SECTOR * 4

#: 2D projections of the world frame (+x backward, +y to the robot's right, +z up):
#: (horizontal axis, vertical axis) as (coordinate index, sign, label).
VIEWS = {
    "front": ((1, 1.0, "y: to the robot's right (m)"), (2, 1.0, "z: up (m)")),
    "side": ((0, -1.0, "-x: forward (m)"), (2, 1.0, "z: up (m)")),
    "top": ((1, 1.0, "y: to the robot's right (m)"), (0, -1.0, "-x: forward (m)")),
}


def fig6_distances_variability(table: pl.DataFrame, run_dir, phases: Sequence[str] | None = None,
                               senses: str = "normal", phase: str = "pre",
                               trials: Sequence[int] = SECTOR_CENTRE_TRIALS,
                               cache=None) -> Figure:
    """Fig. 6. Top: hand-shoulder and hand-ball distance (m) over ``trials`` (default the centre
    of each of the 9 sectors) of the best recorded robot of ``phase`` (the best robot of the
    best replication at the end of pre-reaching), read from its recordings, one after the other;
    dotted lines mark the start of each trial (posture reset). Bottom: movement variability
    (s.d. over time of the joint encoders) of elbow, shoulder and trunk per phase, and beyond
    the paper the elbow freezing (s.d. of the hand-shoulder distance): mean $\\pm$ s.e.m. over
    robots. Trials without a recording are run again and recorded under ``cache`` (default
    ``run_dir``; ``replay.recording``)."""
    phases = phase_list(table, phases)
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
        rec = read_rrd(replay.recording(run_dir, r, cache))
        t = rec["sim_time"].to_numpy()
        hand = positions(rec, "hand")
        d_shoulder = metrics.hand_shoulder_distance(hand, positions(rec, "shoulder"))
        d_ball = metrics.hand_ball_distance(hand, positions(rec, "ball"))
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
    colours = phase_colours(phases)
    for j, (m, label, scale) in enumerate(FIG6_MEASURES):
        ax = fig.add_subplot(grid[1, j])
        bar_panel(ax, summary, m, phases, scale, label, colours)
        if m == "elbow_freezing":
            ax.set_title("beyond the paper", fontsize=9, color="0.35")
    fig.suptitle("Fig. 6 - hand distances (top) and movement variability (bottom; mean "
                 f"$\\pm$ s.e.m. over robots, {senses} senses)", fontsize=10)
    return fig


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
    phases = phase_list(table, phases)
    sectors = sectors or SectorConfig()
    rates = summaries.sector_success(select_trials(table, phases, senses), by=("phase",))
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


def _project(points: np.ndarray, view: str) -> tuple[np.ndarray, np.ndarray]:
    (i, si, _), (j, sj, _) = VIEWS[view]
    return si * points[:, i], sj * points[:, j]


def fig8_trajectories(table: pl.DataFrame, run_dir, phases: Sequence[str] | None = None,
                      senses: Sequence[str] = TESTS, trial: int = FIG8_TRIAL,
                      view: str = "front", radius: float | None = None,
                      cache=None) -> Figure:
    """Fig. 8: the hand's path (palm point) in one trial (default the centre of sector 4) of the
    best recorded robot of each phase (columns) under each sensory condition (rows), read from
    the recordings, projected on a plane: ``view`` "front" (as seen from behind the robot),
    "side" (forward to the right) or "top". The path's colour is time; o marks the start, x the
    end; the red disc is the ball at the start (its path in red), + the shoulder. The row of
    the ball-absent test (no-ball, section IV-A-1) draws a dashed circle where the ball would
    hang. All panels share one scale. Trials without a recording are run again and recorded
    under ``cache`` (default ``run_dir``; ``replay.recording``)."""
    if view not in VIEWS:
        raise ValueError(f"view must be one of {', '.join(VIEWS)}, got {view!r}")
    phases = phase_list(table, phases)
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
                rec = read_rrd(replay.recording(run_dir, robot.row(0, named=True), cache))
                paths[i, j] = (rec["sim_time"].to_numpy(), positions(rec, "hand"),
                               positions(rec, "ball"), positions(rec, "shoulder"),
                               robot.row(0, named=True))
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
    return ScalarMappable(norm=norm, cmap=cmap)


def fig8_babbling(table: pl.DataFrame, phases: Sequence[str] | None = None,
                  senses: str = "normal") -> Figure:
    """Beyond the paper (section IV-A-1, Fig. 8): motor babbling per phase, from
    ``metrics.hand_periodicity``: the dominant frequency of the hand's movement and the share of
    the movement's power at that frequency (near 1 for one steady oscillation, small for
    irregular movement); mean $\\pm$ s.e.m. over robots."""
    phases = phase_list(table, phases)
    fig, axes = bars_figure(table, BABBLING_MEASURES, phases, senses, (1, 2), (8, 3.6))
    axes[1].set_ylim(0, 1)
    fig.suptitle(f"Motor babbling: periodicity of the hand's movement ({senses} senses; beyond "
                 "the paper)", fontsize=10)
    return fig
