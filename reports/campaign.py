"""The campaign's page (docs/results/campaign.md, pre-registered): the paper's pre-reacher judged
in the paper's units on the committed populations, the scene calibrated on Fig. 5's reach,
where the campaign on version 3 stands and, once a phase has finished and been post-evaluated
(``make campaign-phases``), the paper's claims its finished phases can judge.

    python -m reports.campaign              # rewrites the page's generated part
                                            # (below "## Results")
    python -m reports.campaign --check      # exit 1 when the page differs from the tables
    python -m reports.campaign --extension  # the best robots run again for A3 (a minute)
    python -m reports.campaign --screen     # the calibration's screen (minutes on 2 cores)

``--extension`` and ``--screen`` write their tables under ``recordings/campaign/`` (committed);
the page is generated from those and the committed post-evaluation tables only.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path

import dart_reach  # noqa: F401  first: it pins numpy's kernels before numpy loads
import numpy as np
import polars as pl

from dart_reach.analysis import budgets, findings, verdicts
from dart_reach.analysis.formatting import decimals, effect
from dart_reach.analysis.profile import PAPER_UNITS, paper_units, profiles, robot_profiles
from dart_reach.evolution.backends import worker_trial
from dart_reach.evolution.genome import as_groups, decode
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.evolution.settings import trial_config
from dart_reach.files import atomic_write
from dart_reach.measures.metrics import arm_extension
from dart_reach.model.scenes import load_scene
from dart_reach.model.task import Senses, network_for
from dart_reach.model.world import POINTS_PER_SECTOR, SectorConfig
from dart_reach.postevaluation import results
from dart_reach.postevaluation.snapshots import load_development
from dart_reach.postevaluation.systematic import load_evaluation
from dart_reach.studies.lever_screen import Arm, screen

from .text import markdown_table, write_page

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "results" / "campaign.md"
MARK = "## Results\n"
STUDY = ROOT / "recordings" / "campaign"
EXTENSION = STUDY / "extension.parquet"
CAMPAIGN = STUDY / "standard-v3"
#: The campaign's pre-reaching generations judged (pre-registered) and the stop rule's.
CAMPAIGN_JUDGED = (50, 100, 250, 500)
PHASE_NAMES = {"pre": "pre-reaching", "gross": "gross-reaching", "fine": "fine-reaching"}
STOP_AT = 100
SCREEN = STUDY / "scene-screen.parquet"
#: The committed populations at generation 50 of pre-reaching (name -> run, and the
#: generation of its development table, or None for its final post-evaluation).
JUDGED = 50
POPULATIONS = {"far": ("levers/far", JUDGED), "reflex-evolved": ("levers/reflex-evolved", JUDGED),
               "self-collision": ("levers/self-collision", JUDGED),
               "capped": ("levers/capped", JUDGED),
               "standard-500x10": ("standard-500x10", JUDGED),
               "replication-50x10": ("replication-50x10", None)}
#: A3's window: the palm-shoulder distance from this step on (2 s at 0.1 s a step).
FROM_STEP = 20
#: The calibration's grid (pre-registered): radii (m) and widening factors of the patch.
RADII = (0.42, 0.44, 0.46, 0.48, 0.50)
WIDENINGS = (1.0, 1.25, 1.5, 2.0)
#: The patch widened: ``beyond-arm-length``'s, about its centre (deg).
BASE_SCENE = "beyond-arm-length"
AZIMUTH_CENTRE, ELEVATION_CENTRE = 22.5, -13.4
#: The rule: mean reach closest to this; tied within TIE of the closest.
TARGET, TIE = 0.5, 0.02
#: At least this many robots must qualify for the screen to run.
MIN_ROBOTS = 5


def population_table(name: str) -> pl.DataFrame:
    """The best 5 robots' trials (every replication, every senses) of a committed population
    at generation 50 of pre-reaching."""
    run, generation = POPULATIONS[name]
    path = ROOT / "recordings" / run
    if generation is None:
        table = load_evaluation(path)
    else:
        table = load_development(path, senses=None)
        table = table.filter(pl.col("generation") == generation)
    return table.filter((pl.col("phase") == "pre") & ~pl.col("baseline")
                        & pl.col("senses").is_in(["normal", "no-ball"]))


def best_robot(run_dir: Path, generation: int, phase: str = "pre"):
    """(run, phase, replication, genome) of the best robot of the best replication (highest
    lifetime fitness of its rank-0 robot) in a snapshot."""
    run = RunDirectory.open(run_dir)
    ph = next(p for _, p in run.unique_phases() if p.name == phase)
    snaps = {g: (genomes, fit) for g, genomes, fit in run.snapshots(ph)}
    genomes, fit = snaps[generation]
    best = int(np.argmax(fit[:, 0]))
    return run, ph, best, genomes[best, 0]


def best_robot_extension(run_dir: Path, generation: int, phase: str = "pre") -> dict:
    """A3's measure: the best robot of the best replication run again on the 45 positions,
    normal senses; the means over its trials of the palm-shoulder distance's mean (m) and CV
    from ``FROM_STEP`` on (``measures.metrics.arm_extension``)."""
    run, ph, replication, genome = best_robot(run_dir, generation, phase)
    trial = replace(trial_config(ph, run.settings), senses=Senses("normal"))
    runner = worker_trial(run.settings.world, trial)
    network = network_for(decode(genome, as_groups(ph.free_groups)), trial)
    means, cvs = [], []
    for k, position in enumerate(runner.world.systematic_points()):
        data = runner.run(network, k // POINTS_PER_SECTOR, position)
        n = int(data.steps_run)
        m, cv = arm_extension(data.hand[:n], data.shoulder[:n], FROM_STEP)
        means.append(m)
        cvs.append(cv)
    return {"replication": replication, "hand_shoulder_m": float(np.mean(means)),
            "hand_shoulder_cv": float(np.mean(cvs)), "trials": len(means)}


def build_extension() -> pl.DataFrame:
    """A3's measure for every committed population and the campaign's judged snapshots kept
    so far, written to ``EXTENSION``."""
    rows = [{"population": name, "generation": JUDGED,
             **best_robot_extension(ROOT / "recordings" / run, JUDGED)}
            for name, (run, _) in POPULATIONS.items()]
    if (CAMPAIGN / "manifest.json").exists():  # the campaign's judged snapshots kept so far
        run = RunDirectory.open(CAMPAIGN)
        pre = next(p for _, p in run.unique_phases() if p.name == "pre")
        kept = {g for g, _, _ in run.snapshots(pre)}
        rows += [{"population": "campaign", "generation": g,
                  **best_robot_extension(CAMPAIGN, g)} for g in CAMPAIGN_JUDGED if g in kept]
    table = pl.DataFrame(rows)
    STUDY.mkdir(parents=True, exist_ok=True)
    atomic_write(EXTENSION, lambda p: table.write_parquet(p, compression="zstd"))
    return table


def selected_robots() -> pl.DataFrame:
    """Every robot of the committed populations with its per-robot profile and
    ``moves_as_paper``; ``selected`` marks the calibration's robots (the pre-registered rule,
    with its fallback when fewer than ``MIN_ROBOTS`` qualify)."""
    robots = pl.concat([robot_profiles(population_table(name)).with_columns(
        population=pl.lit(name)) for name in POPULATIONS], how="diagonal_relaxed")
    rule = "moves_as_paper"
    if robots[rule].sum() < MIN_ROBOTS:
        rule = "arm_and_babbling"
        robots = robots.with_columns(
            arm_and_babbling=pl.col("is_arm_extended") & pl.col("is_babbling_no_ball"))
    return robots.with_columns(selected=pl.col(rule), rule=pl.lit(rule))


def grid() -> list[tuple[float, float, SectorConfig]]:
    """The calibration's scenes: (radius, widening, sectors), ``BASE_SCENE`` first."""
    base = load_scene(BASE_SCENE).sectors
    out = []
    for w in WIDENINGS:
        az = tuple(round(AZIMUTH_CENTRE + w * (a - AZIMUTH_CENTRE), 4)
                   for a in base.azimuth_edges)
        el = tuple(round(ELEVATION_CENTRE + w * (e - ELEVATION_CENTRE), 4)
                   for e in base.elevation_edges)
        out += [(r, w, SectorConfig(radius=r, azimuth_edges=az, elevation_edges=el))
                for r in RADII]
    return sorted(out, key=lambda x: (x[1], x[0]))


def arm_name(radius: float, widening: float) -> str:
    return f"r{radius:.2f}-w{widening:g}"


def _selected_rows(table: pl.DataFrame, robots: pl.DataFrame) -> pl.DataFrame:
    """The rows of the selected ``robots`` in a screen table."""
    return table.join(robots.select("population", "replication", "rank"),
                      on=["population", "replication", "rank"], how="semi")


def build_screen(workers: int | None = None) -> pl.DataFrame:
    """The calibration's screen: every selected robot on the 45 positions of every scene of
    ``grid``, normal senses, under its own run's version and levers; written to ``SCREEN``
    after each population, so that a run stopped part-way resumes with the next one."""
    robots = selected_robots().filter(pl.col("selected"))
    table = _selected_rows(pl.read_parquet(SCREEN), robots) if SCREEN.exists() else None
    done = set() if table is None else set(table["population"].unique().to_list())
    for name, (run, _) in POPULATIONS.items():
        mine = robots.filter(pl.col("population") == name)
        if mine.is_empty() or name in done:
            continue
        run_dir = ROOT / "recordings" / run
        settings = RunDirectory.open(run_dir).settings
        arms = [Arm(arm_name(r, w), replace(settings.world, sectors=sectors), settings.levers)
                for r, w, sectors in grid()]
        only = {(int(a), int(b)) for a, b in mine.select("replication", "rank").iter_rows()}
        part = (screen(run_dir, JUDGED, arms, robots=5, senses=("normal",), workers=workers,
                       only=only).with_columns(population=pl.lit(name)))
        table = part if table is None else pl.concat([table, part], how="diagonal_relaxed")
        STUDY.mkdir(parents=True, exist_ok=True)
        atomic_write(SCREEN, lambda p: table.write_parquet(p, compression="zstd"))
        print(f"screened {name}: {mine.height} robots", flush=True)
    return table


def scene_reach(table: pl.DataFrame) -> pl.DataFrame:
    """Per scene of the screen: radius, widening, the robots' mean reach (each robot's rate
    over its trials, averaged over robots), the robots, and the change from ``BASE_SCENE``."""
    per_robot = (table.group_by("arm", "population", "replication", "rank")
                 .agg(pl.col("reached").cast(pl.Float64).mean().alias("reach")))
    names = {arm_name(r, w): (r, w) for r, w, _ in grid()}
    return (per_robot.group_by("arm")
            .agg(pl.col("reach").mean(), pl.len().alias("robots"),
                 pl.col("reach").min().alias("reach_min"),
                 pl.col("reach").max().alias("reach_max"))
            .with_columns(radius=pl.col("arm").replace_strict({k: v[0] for k, v in names.items()}),
                          widening=pl.col("arm").replace_strict({k: v[1] for k, v in
                                                                 names.items()}))
            .with_columns(change=((pl.col("radius") - RADII[0]) / (RADII[-1] - RADII[0])
                                  + (pl.col("widening") - 1.0) / (WIDENINGS[-1] - 1.0))
                          .round(9))
            .sort("widening", "radius"))


def tied_scenes(by_scene: pl.DataFrame) -> pl.DataFrame:
    """The scenes the rule weighs: those whose mean reach is within ``TIE`` of the closest to
    ``TARGET``, in the rule's order (the smallest change from ``BASE_SCENE``, then the smaller
    widening, then the smaller radius)."""
    gap = (by_scene["reach"] - TARGET).abs().round(9)  # ties are not decided by rounding
    return (by_scene.filter(gap <= round(gap.min() + TIE, 9))
            .sort("change", "widening", "radius"))


def choose_scene(by_scene: pl.DataFrame) -> dict:
    """The pre-registered rule: the first of ``tied_scenes``."""
    return tied_scenes(by_scene).row(0, named=True)


# ------------------------------------------------------------------------------ the page
YES = {True: "yes", False: "no"}
#: The columns of a judgement's row after its first (the population or the generation).
JUDGEMENT_COLUMNS = ("replications | reach (A1) | elbow / shoulder / trunk SD (A2) | best "
                     "robot's hand-shoulder from 2 s, m / CV (A3) | robots babbling without "
                     "the ball (A4) | still replications (A5) | A1 | A2 | A3 | A4 | paper's | "
                     "replications meeting the levers study's conjunction")


def judgement_row(first: str, j: dict, per_rep: pl.DataFrame, a4: str) -> str:
    """One row of a judgement table: ``first``, then ``paper_units``'s measures and criteria
    (``j``; A4 written as ``a4``) and how many replications of ``per_rep`` (``profiles``)
    meet the levers study's conjunction."""
    lo, hi = j["still_interval"]
    return (f"| {first} | {j['replications']} | {decimals(j['reach'], 2)} | "
            f"{decimals(j['elbow_sd'])} / {decimals(j['shoulder_sd'])} / "
            f"{decimals(j['trunk_sd'])} | {decimals(j['hand_shoulder_m'])} / "
            f"{decimals(j['hand_shoulder_cv'])} | {j['babbling_robots']} of {j['robots']} | "
            f"{j['still']} of {j['replications']} [{lo:.2f}, {hi:.2f}] | {YES[j['A1']]} | "
            f"{YES[j['A2']]} | {YES[j['A3']]} | {a4} | **{YES[j['paper']]}** | "
            f"{int(per_rep['paper'].sum())} of {per_rep.height} |")


def profile_table(per_rep: pl.DataFrame) -> list[str]:
    """The per-replication profile (``profiles``) as table lines: its means and criteria."""
    lines = ["| replication | reach | elbow / shoulder / trunk SD | hand-shoulder, m / CV | "
             "babbling with / without the ball | reach | elbow | arm | babbling | all four |",
             "|---:|---:|---|---|---|---|---|---|---|---|"]
    for r in per_rep.iter_rows(named=True):
        lines.append(
            f"| {r['replication']} | {decimals(r['reach'], 2)} | {decimals(r['elbow_sd'])} / "
            f"{decimals(r['shoulder_sd'])} / {decimals(r['trunk_sd'])} | "
            f"{decimals(r['hand_shoulder_m'])} / {decimals(r['hand_shoulder_cv'])} | "
            f"{decimals(r['babbling'], 2)} / {decimals(r['babbling_no_ball'], 2)} | "
            f"{YES[r['is_reach']]} | {YES[r['is_elbow_locked']]} | "
            f"{YES[r['is_arm_extended']]} | {YES[r['is_babbling']]} | {YES[r['paper']]} |")
    return lines


def criteria_section() -> str:
    ext = pl.read_parquet(EXTENSION) if EXTENSION.exists() else None
    lines = ["### (a) The committed populations at generation 50, in the paper's units", "",
             "Generated from the committed post-evaluation tables (best 5 robots of every "
             "replication, 45 positions, normal and no-ball) and "
             "`recordings/campaign/extension.parquet` (`python -m reports.campaign "
             "--extension`: the best robot of the best replication run again, A3). "
             + " ".join(f"{k}: {v}." for k, v in PAPER_UNITS.items()), "",
             f"| population | {JUDGEMENT_COLUMNS} |",
             "|---|---:|---:|---|---|---:|---|---|---|---|---|---|---:|"]
    for name in POPULATIONS:
        table = population_table(name)
        extension = (float("nan"), float("nan"))
        if ext is not None and name in ext["population"].to_list():
            row = ext.filter(pl.col("population") == name).row(0, named=True)
            extension = (row["hand_shoulder_m"], row["hand_shoulder_cv"])
        j = paper_units(table, extension)
        lines.append(judgement_row(name, j, profiles(table), YES[j["A4"]]))
    return "\n".join(lines) + "\n"


def calibration_section() -> str:
    robots = selected_robots()
    chosen = robots.filter(pl.col("selected"))
    rule = robots["rule"][0]
    lines = ["### (b) The calibration", "",
             f"Robots whose movement is the paper's by every criterion but reach (per robot, "
             f"committed tables): **{chosen.height} of {robots.height}**"
             + ("" if rule == "moves_as_paper" else
                " (fewer than 5 met all three: the pre-registered fallback dropped the elbow "
                "criterion)") + ". By population: "
             + ", ".join(f"{p} {int(chosen.filter(pl.col('population') == p).height)} of "
                         f"{robots.filter(pl.col('population') == p).height}"
                         for p in POPULATIONS) + ".", ""]
    if chosen.height:
        lines += [f"Their own reach (committed, under their own scene): mean "
                  f"{chosen['reach'].mean():.2f}, range {chosen['reach'].min():.2f}-"
                  f"{chosen['reach'].max():.2f}.", ""]
    if not SCREEN.exists():
        return "\n".join(lines + ["The screen has not run yet (`python -m reports.campaign "
                                  "--screen`).", ""])
    screened = pl.read_parquet(SCREEN)
    done = set(screened["population"].unique().to_list())
    wanted = [p for p in POPULATIONS if chosen.filter(pl.col("population") == p).height]
    missing = [p for p in wanted if p not in done]
    by_scene = scene_reach(screened)
    if missing:
        n = screened.select("population", "replication", "rank").unique().height
        return "\n".join(lines + [
            f"The screen is part-way: {n} of {chosen.height} robots screened ("
            f"{', '.join(p for p in wanted if p in done)}); still to screen: "
            f"{', '.join(missing)} (`python -m reports.campaign --screen` resumes). The "
            f"decision waits for every robot, as pre-registered.", ""])
    tied, pick = tied_scenes(by_scene), choose_scene(by_scene)
    lines += ["Mean reach of those robots under each scene of the grid (`recordings/campaign/"
              "scene-screen.parquet`; 45 positions, normal senses; rows: widening w of the "
              f"patch, columns: radius; `r = 0.42, w = 1` is `{BASE_SCENE}`):", "",
              "| w \\ r | " + " | ".join(f"{r:.2f} m" for r in RADII) + " |",
              "|---|" + "---:|" * len(RADII)]
    for w in WIDENINGS:
        row = by_scene.filter(pl.col("widening") == w).sort("radius")
        lines.append(f"| {w:g} | " + " | ".join(
            f"**{x:.3f}**" if (r, w) == (pick["radius"], pick["widening"]) else f"{x:.3f}"
            for r, x in zip(row["radius"], row["reach"])) + " |")
    lines += ["", f"**Decision (the pre-registered rule):** the scene with radius "
              f"{pick['radius']:.2f} m and the patch widened by {pick['widening']:g} "
              f"(mean reach {pick['reach']:.3f} over {pick['robots']} robots, each robot's "
              f"from {pick['reach_min']:.2f} to {pick['reach_max']:.2f}), shipped as "
              "`calibrated-reach` and registered as model version 3's scene. Tied within "
              f"{TIE} of the closest to {TARGET}: "
              + "; ".join(f"r = {t['radius']:.2f}, w = {t['widening']:g} (reach "
                          f"{t['reach']:.3f}, change {t['change']:g})"
                          for t in tied.iter_rows(named=True))
              + ". Version 3's reach is therefore calibrated on Fig. 5, not a test of it.", ""]
    return "\n".join(lines)


def campaign_extension(generation: int) -> tuple[float, float]:
    """A3's measure for the campaign's snapshot at ``generation`` (``EXTENSION`` rows of
    population ``campaign``), or NaNs until it is computed."""
    if EXTENSION.exists():
        rows = pl.read_parquet(EXTENSION).filter((pl.col("population") == "campaign")
                                                 & (pl.col("generation") == generation))
        if rows.height:
            return rows["hand_shoulder_m"][0], rows["hand_shoulder_cv"][0]
    return float("nan"), float("nan")


def a4_sensitivity() -> float:
    """The lowest no-ball sensitivity of the detector its validation on this model's robots
    allows (the third sample's one-sided 95 % lower limit), which reads the campaign's A4
    (the page's "Addendum")."""
    from .babbling_validation import THIRD, sensitivity_lower_limit, trials

    return sensitivity_lower_limit(trials(ROOT, THIRD), "detector (whole trial)", "no-ball")


def campaign_section() -> str:
    """Where the campaign stands: generations per phase, its cost from its own records and
    the projected total, the judged snapshots post-evaluated so far and the stop rule."""
    from dart_reach.evolution.cost import core_seconds

    lines = ["### (c) The campaign", ""]
    if not (CAMPAIGN / "manifest.json").exists():
        return "\n".join(lines + ["Not started.", ""])
    run = RunDirectory.open(CAMPAIGN)
    per = core_seconds(run)
    reps = run.settings.replications
    total = sum(p.generations for c in run.conditions for p in c.phases) * reps
    done_core_h = float(per["core_s"].drop_nans().sum()) * reps / 3600
    q1, med, q3 = (float(per["core_s"].drop_nans().quantile(q, "linear") or float("nan"))
                   for q in (0.25, 0.5, 0.75))
    status = run.status()
    lines += [f"`{CAMPAIGN.relative_to(ROOT)}`: model version {run.settings.model_version}, "
              f"seed {run.settings.seed}, {reps} replications. Generations trained per phase: "
              + ", ".join(f"{r['phase']} {r['generations']} of {r['of']}"
                          for r in status.unique("phase", maintain_order=True)
                          .iter_rows(named=True)) + ".", "",
              f"Cost from its own records (`evolution.cost.core_seconds`: each generation's "
              f"wall time x the session's workers): {done_core_h:.1f} core-hours for "
              f"{per.height * reps:,} of {total:,} replication-generations; core-seconds per "
              f"replication-generation: median {med:.1f} (quartiles {q1:.1f}-{q3:.1f}), so "
              f"the whole design projects to {med * total / 3600:,.0f} core-hours "
              f"({q1 * total / 3600:,.0f}-{q3 * total / 3600:,.0f}), "
              f"{med * total / 3600 / 2:,.0f} h on 2 cores.", ""]
    sessions = json.loads((CAMPAIGN / "manifest.json").read_text(encoding="utf-8"))["sessions"]
    lines += [processors_line(per, sessions, total - per.height * reps), ""]
    table = load_development(CAMPAIGN, senses=None)
    have = {p: set() if table is None else set(
        table.filter(pl.col("phase") == p)["generation"].unique().to_list())
        for p in PHASE_NAMES}
    judged = judged_snapshots(table)
    between = described_snapshots(table, sorted(have["pre"] - {g for g, _, _ in judged}))
    for phase in ("gross", "fine"):  # no criterion is of them: every snapshot described
        between += described_snapshots(table, sorted(have[phase]), phase)
    if not judged:
        lines += [f"No judged snapshot ({', '.join(map(str, CAMPAIGN_JUDGED))}) is "
                  f"post-evaluated yet.", ""]
        return "\n".join(lines + between)
    sensitivity = a4_sensitivity()
    lines += [f"A1 is calibrated (section (b)), reported, not a test. A4 read as the Addendum "
              f"says: met, failed (fewer than half the best robots babble in at least "
              f"{0.5 * sensitivity:.3f} of their no-ball trials, the detector's no-ball "
              f"sensitivity on this model's robots being at least {sensitivity:.3f}), or not "
              f"decided by this measure. The per-replication profile of each judged "
              f"generation follows the table.", "",
              f"| pre-reaching generation | {JUDGEMENT_COLUMNS} |",
              "|---:|---:|---:|---|---|---:|---|---|---|---|---|---|---:|"]
    judgements, stop_line = [], []
    for g, j, per_rep in judged:
        lines.append(judgement_row(str(g), j, per_rep, a4_word(j)))
        judgements += ["", f"Per replication at generation {g} (means over its best 5 "
                       f"robots' trials; babbling per trial):", "", *profile_table(per_rep)]
        if g == STOP_AT:
            stop = not (j["A2"] or j["A3"]) and j["A4_failed"]
            stop_line = ["", f"**Stop rule at {STOP_AT}:** A2, A3 and A4 "
                         + ("all fail: the training stops here." if stop else
                            "do not all fail: the training goes on.")]
    tail = [""] + between if between else []
    return "\n".join(lines + stop_line + judgements + tail) + "\n"


def processors_line(per: pl.DataFrame, sessions: list[dict], left: int) -> str:
    """The cost by the processor that trained each generation (``per``: ``core_seconds``'s
    rows; ``sessions``: the manifest's, whose ``cpu`` names it), and the ``left``
    replication-generations projected at the median of the processor of the latest session:
    a run resumed on another machine changes its pace, which the median of all mixes."""
    def name(k: int) -> str:
        cpu = (sessions[k].get("cpu") or {}) if k >= 0 else {}
        return f"{cpu.get('model', 'a processor not recorded')} ({cpu.get('vector', '?')})"

    rows = (per.with_columns(pl.Series("processor", [name(k) for k in per["session"]]))
            .filter(pl.col("core_s").is_not_nan())
            .group_by("processor", maintain_order=True)
            .agg(pl.len().alias("generations"), pl.col("core_s").median().alias("median"),
                 pl.col("session").max().alias("last")))
    if rows.is_empty():
        return "No generation's cost is known by processor."
    parts = [f"{r['processor']}: {r['generations']} generation"
             f"{'' if r['generations'] == 1 else 's'}, median {r['median']:.1f}"
             for r in rows.iter_rows(named=True)]
    last = rows.sort("last").row(-1, named=True)
    return (f"By the processor that trained them (the sessions' `cpu`), core-seconds per "
            f"replication-generation: {'; '.join(parts)}. The {left:,} replication-generations "
            f"left at the latest one's median: {last['median'] * left / 3600:,.0f} core-hours, "
            f"{last['median'] * left / 3600 / 2:,.0f} h on 2 cores.")


def judged_snapshots(table: pl.DataFrame | None) -> list[tuple[int, dict, pl.DataFrame]]:
    """The judged generations (``CAMPAIGN_JUDGED``) of pre-reaching that the development
    ``table`` holds, each with its judgement in the paper's units (``paper_units``: A3 from
    ``EXTENSION``, A4 read at ``a4_sensitivity``) and its per-replication ``profiles``."""
    have = set() if table is None else set(
        table.filter(pl.col("phase") == "pre")["generation"].unique().to_list())
    generations = [g for g in CAMPAIGN_JUDGED if g in have]
    sensitivity = a4_sensitivity() if generations else float("nan")
    out = []
    for g in generations:
        snap = table.filter((pl.col("phase") == "pre") & (pl.col("generation") == g)
                            & ~pl.col("baseline"))
        out.append((g, paper_units(snap, campaign_extension(g),
                                   babbling_sensitivity=sensitivity), profiles(snap)))
    return out


def a4_word(j: dict) -> str:
    """A4 of a judgement (``paper_units``) as the Addendum reads it."""
    return "met" if j["A4"] else "failed" if j["A4_failed"] else "not decided"


def described_snapshots(table: pl.DataFrame | None, generations: list[int],
                        phase: str = "pre") -> list[str]:
    """``phase``'s snapshots at ``generations``, described in the criteria's measures and not
    judged: pre-reaching's between the judged generations (the pre-registration judges
    ``CAMPAIGN_JUDGED`` only; A3's best robot is not run again for them), gross- and
    fine-reaching's all (no criterion is of them); a table, or nothing when there is none."""
    if not generations:
        return []
    lines = ["Snapshots post-evaluated between the judged generations, **described, not "
             "judged** (the pre-registration judges generations "
             f"{', '.join(map(str, CAMPAIGN_JUDGED))} only; A3's best robot is not run again "
             "for them):" if phase == "pre" else
             f"Snapshots of {PHASE_NAMES[phase]} post-evaluated, **described** in the same "
             "measures (no criterion of the pre-registration is of this phase):", "",
             f"| {PHASE_NAMES[phase]} generation | replications | reach (A1) | elbow / "
             "shoulder / trunk SD (A2) | robots babbling without the ball (A4) | still "
             "replications (A5) |", "|---:|---:|---:|---|---|---|"]
    for g in generations:
        snap = table.filter((pl.col("phase") == phase) & (pl.col("generation") == g)
                            & ~pl.col("baseline"))
        j = paper_units(snap, (float("nan"), float("nan")), phase=phase)
        lo, hi = j["still_interval"]
        lines.append(f"| {g} | {j['replications']} | {decimals(j['reach'], 2)} | "
                     f"{decimals(j['elbow_sd'])} / {decimals(j['shoulder_sd'])} / "
                     f"{decimals(j['trunk_sd'])} | {j['babbling_robots']} of {j['robots']} | "
                     f"{j['still']} of {j['replications']} [{lo:.2f}, {hi:.2f}] |")
    return lines + [""]


def judged_phases(run_dir: Path = CAMPAIGN) -> list:
    """The phases ``run_dir`` has trained to the end and post-evaluated (``make
    campaign-phases``), in training order: those whose claims are judged."""
    if not results.exists(Path(run_dir) / results.EVALUATION):
        return []
    evaluated = set(load_evaluation(run_dir)["phase_key"].unique().to_list())
    run = RunDirectory.open(run_dir)
    return [p for _, p in run.unique_phases()
            if run.final_path(p).exists() and p.key in evaluated]


def phase_claims(run_dir: Path = CAMPAIGN) -> pl.DataFrame | None:
    """Every claim judged as the report judges it (``budgets``: ``findings`` of the run, its
    budget's labels in front) on the phases ``run_dir`` has trained to the end and
    post-evaluated (``make campaign-phases``): their post-evaluation, the random genomes, and
    the snapshots of those phases alone (a phase still training has no start-to-end course
    yet, and the report of an unfinished run would judge its course so far; a phase just
    finished counts once its post-evaluation is here, so that the page and the summary
    change with it). None before a finished phase is post-evaluated."""
    finished = {p.key for p in judged_phases(run_dir)}
    if not finished:
        return None
    tables = budgets.pooled([run_dir])
    development = (None if tables.development is None else
                   tables.development.filter(pl.col("phase_key").is_in(sorted(finished))))
    found = replace(tables, development=development).findings()
    return budgets.label_findings(found, budgets.budget_of(Path(run_dir)), [run_dir])


def phase_claims_section(found: pl.DataFrame | None) -> str:
    """The paper's claims at the end of each phase (``phase_claims``): those the finished
    phases can judge, one row each, and the verdicts counted; or that none has finished."""
    lines = ["### (d) The paper's phase claims at the end of each phase", ""]
    if found is None:
        return "\n".join(lines + ["No phase has finished and been post-evaluated yet "
                                  "(`make campaign-phases` once one has).", ""])
    paper = findings.reading(found)
    judged = paper.filter(pl.col("verdict") != verdicts.NOT_RUN)
    counts = findings.summary(found)
    effects = [effect(*r) for r in judged.select(
        pl.col(c).fill_null(float("nan")) for c in ("effect", "effect_low", "effect_high")
    ).iter_rows()]
    shown = judged.select("claim", "section", "kind").with_columns(
        pl.Series("effect [CI]", effects, pl.Utf8), judged["verdict"],
        judged["verdict_robots"].alias("robots as units (not counted)"), judged["n"])
    lines += [f"The paper's {paper.height} claims of its robots as the report judges them "
              f"(docs/model/claims.md) on the finished phases: their post-evaluation "
              f"(`make campaign-phases`: best 5 robots of every replication, 45 positions, "
              f"the four senses and the ball absent, 10 random genomes per phase; babbling "
              f"before the touch of the final pre-reachers, claim A1) and, for the "
              f"development claims, their snapshots alone. Verdicts: "
              + ", ".join(f"{v}: {counts[v]}" for v in findings.COUNTED)
              + f" (not run: a phase they need has not finished); surviving Holm's "
              f"adjustment over the judged: reproduced {counts['reproduced (Holm)']}, "
              f"contradicted {counts['contradicted (Holm)']}. The {judged.height} judged:",
              "", markdown_table(shown), ""]
    return "\n".join(lines)


def page() -> str:
    head = PAGE.read_text().split(MARK)[0]
    return (head + MARK + "\nThe results are generated below this line by "
            "`python -m reports.campaign`.\n\n" + criteria_section() + "\n"
            + calibration_section() + "\n" + campaign_section().rstrip("\n") + "\n\n"
            + phase_claims_section(phase_claims()))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m reports.campaign", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--check", action="store_true", help="exit 1 when the page is stale")
    p.add_argument("--extension", action="store_true", help="run A3's best robots again first")
    p.add_argument("--screen", action="store_true", help="run the calibration's screen first")
    p.add_argument("--workers", type=int, default=None, help="local processes (default all)")
    args = p.parse_args(argv)
    if args.extension:
        print(build_extension())
    if args.screen:
        print(scene_reach(build_screen(args.workers)))
    return write_page(PAGE, page(), args.check)


if __name__ == "__main__":
    sys.exit(main())
