"""Findings of runs trained at different budgets, side by side (docs/model/claims.md, "Several
budgets").

The paper trains 500 generations per phase (III-D); the replications here train fewer, and the
same claim is judged at several budgets to see where it is heading. A run's *budget* is its
scene, its generations per phase, its replications and its model (the model version and
variant it was trained under, ``model.versions``) (:class:`Budget`, :func:`budget_of`). Runs of
one budget are pooled, as the paper's replications are, and judged once
(``findings.findings``); runs of different budgets, two models among them, are never pooled:
``findings_by_budget`` gives one block of findings rows per budget.

Each claim's effect is put on one scale per claim on which the paper's direction is up
(:func:`toward_paper`, in the units of the claim's effect), and its intervals at the smallest
and the largest budget of a series are set side by side (:func:`movement`): *apart, higher*
when the largest budget's lies wholly above the smallest's, *apart, lower* when wholly below,
*overlap* otherwise. That is a description, not a test: no rule of ``verdicts`` decides it, no
level is held and nothing is corrected over the claims, so it names no direction as a result.
``side_by_side`` is the table of the report: one row per claim, each budget's effect [CI] and
verdict, and the intervals as the budget grows.

Every function but :func:`budget_of`, :func:`budget_groups`, :func:`pooled` and
:func:`findings_by_budget` (which read run directories) is pure: it takes the
findings-by-budget frame, so a notebook or a script (docs/results/replication.md) gets the
same tables as the report.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import polars as pl

from . import findings, formatting, unfinished, verdicts
from ..evolution.rundir import RunDirectory
from .claims import ABOUT_HALF, CLAIMS, Claim, Kind
from ..model.scenes import scene_of
from ..model.versions import variant_name
from ..postevaluation import results
from ..postevaluation.snapshots import load_development
from ..postevaluation.systematic import load_evaluation
from .tables import load_runs

__all__ = ["Budget", "Pooled", "MOVEMENTS", "APART_HIGHER", "APART_LOWER", "OVERLAP",
           "NOT_RUN", "MOVEMENT_COLUMN", "MOVEMENT_NOTE", "movement_column", "budget_of",
           "model_of", "budget_groups", "pooled", "label_findings", "findings_by_budget",
           "budgets", "of_budget", "labels", "toward_paper",
           "movement", "side_by_side", "REPLICATION_OUTCOMES", "replications_decide"]

#: How a claim's replication-level intervals at the smallest and the largest budget of a series
#: lie, on the ``toward_paper`` scale: a description, not a test (no rule of ``verdicts``
#: decides it). Where either end has no interval (Friedman's W, an underpowered rule) two
#: points say nothing (``NO_INTERVAL``).
APART_HIGHER, APART_LOWER, OVERLAP, NO_INTERVAL, NOT_RUN = (
    "apart, higher", "apart, lower", "overlap", "no interval", "not run")
MOVEMENTS = (APART_HIGHER, APART_LOWER, OVERLAP, NO_INTERVAL, NOT_RUN)
#: The name of ``side_by_side``'s column of ``movement`` (``movement_column``): it says what
#: it compares, and that it is no test.
MOVEMENT_COLUMN = "intervals as the budget grows (not a test)"
#: What ``MOVEMENT_COLUMN`` says, for a page's legend (the report's; docs/results/replication.md's).
MOVEMENT_NOTE = (
    "Intervals as the budget grows: a claim's replication-level intervals at the smallest and "
    "the largest budget of a series (a scene, a number of replications and a model), on a "
    "scale where the paper's direction is up: apart, higher when the largest budget's lies "
    "wholly above the smallest's; apart, lower when wholly below; overlap otherwise; no "
    "interval where an end has none; not run where neither end has an effect. A description, "
    "not a test: no rule of the verdicts decides it, no level is held and nothing is "
    "corrected over the claims, so it is no result that a claim moves toward or away from "
    "the paper; each budget's verdict is the result.")
#: The columns of a findings-by-budget frame that name its budget (``Budget``'s fields).
BUDGET_COLUMNS = ("scene", "generations_per_phase", "replications", "model")
#: Columns ``findings_by_budget`` puts before the findings' own.
KEY_COLUMNS = (*BUDGET_COLUMNS, "runs", "sign")


@dataclass(frozen=True, order=True)
class Budget:
    """What a run was trained at, as far as pooling goes: the scene (the ball's sectors, II-B),
    the generations per standard phase (the paper: 500, III-D), the replications (the
    paper: 10; they set the transitions, the best 20 of the replications' populations, III-D)
    and the model (``model_of``: its version, or the variant of it, e.g. "v1",
    "v3+touch_pay=binary"; two models' robots are two samples even on one scene). Ordered by
    scene, generations, replications, model."""

    scene: str
    generations_per_phase: int
    replications: int
    model: str

    @property
    def label(self) -> str:
        """The budget in words, without its model (``labels`` adds it where runs of several
        models are shown)."""
        n, r = self.generations_per_phase, self.replications
        return (f"{self.scene}, {n} generation{'' if n == 1 else 's'} per phase, {r} "
                f"replication{'' if r == 1 else 's'}")


def labels(budgets_: Sequence[Budget]) -> dict[Budget, str]:
    """Each budget's ``label``, its model added ("..., model v2") only where the budgets hold
    more than one model: runs of one model read as before models were told apart."""
    several = len({b.model for b in budgets_}) > 1
    return {b: f"{b.label}, model {b.model}" if several else b.label for b in budgets_}


def generations_per_phase(run: RunDirectory) -> tuple[int, ...]:
    """The generations per standard phase of a run's phases (``generations // budget_phases``:
    gross^ trains 2 phases' worth, fine^ 3), sorted; one value for a run trained with one
    ``--generations``."""
    return tuple(sorted({p.generations // p.budget_phases for c in run.conditions
                         for p in c.phases}))


def _scene_name(run: RunDirectory) -> str:
    """The shipped scene whose sectors the run was trained with (``scenes.scene_of``), else its
    sectors written out: two custom scenes are two scenes. The sectors of the settings decide,
    not the manifest's ``scene``, which older runs lack and which names every user scene
    "custom"."""
    sectors = run.settings.world.sectors
    name = scene_of(sectors)
    if name is not None:
        return name
    az, el = sectors.azimuth_edges, sectors.elevation_edges
    return (f"custom (radius {sectors.radius:g} m, azimuth {az[0]:g} to {az[-1]:g} deg, "
            f"elevation {el[0]:g} to {el[-1]:g} deg, edges "
            f"{'/'.join(f'{x:g}' for x in (*az, *el))})")


def model_of(run: RunDirectory) -> str:
    """The model a run was trained under: its version's name ("v1") or its variant's
    ("v3+touch_pay=binary", ``versions.variant_name``), from its settings as the manifest holds
    them (``Settings.from_json``: a manifest from before model versions is version 1's)."""
    return variant_name(run.settings.model_version, run.settings.variant)


def budget_of(run_dir) -> Budget:
    """The budget of a run directory: its scene, its largest generations per phase (the
    budget ``report.budget_text`` states), its replications and its model."""
    run = RunDirectory.open(run_dir)
    return Budget(_scene_name(run), generations_per_phase(run)[-1], run.settings.replications,
                  model_of(run))


def budget_groups(run_dirs: Sequence) -> dict[Budget, list[Path]]:
    """The runs of each budget, budgets in order (scene, generations per phase, replications,
    model), runs in the order given; a run given twice counts once."""
    groups: dict[Budget, list[Path]] = {}
    for d in {Path(d).resolve(): Path(d) for d in run_dirs}.values():
        groups.setdefault(budget_of(d), []).append(d)
    return dict(sorted(groups.items()))


@dataclass(frozen=True)
class Pooled:
    """The post-evaluation tables of the evaluated runs among some runs, pooled: trials
    (``tables.load_runs``), random baseline trials and development (snapshot) trials, each
    with a ``run`` column; None where no run has them."""

    table: pl.DataFrame | None
    baseline: pl.DataFrame | None
    development: pl.DataFrame | None

    def findings(self) -> pl.DataFrame:
        """Every claim judged on these tables (``findings.findings``; every claim "not run"
        when no run is post-evaluated)."""
        table = self.table if self.table is not None else _empty_table()
        return findings.findings(table, self.baseline, development=self.development)


def pooled(run_dirs: Sequence) -> Pooled:
    """The pooled tables of ``run_dirs`` (those without ``evaluation.parquet`` are left out,
    but for an unfinished run's post-evaluated snapshots: ``unfinished.snapshot_trials``)."""
    evaluated = [Path(d) for d in run_dirs if unfinished.judged(d)]
    if not evaluated:
        return Pooled(None, None, None)
    baselines = [load_evaluation(d, baseline=True).with_columns(pl.lit(d.name).alias("run"))
                 for d in evaluated if results.exists(d / results.EVALUATION)
                 or results.exists(d / results.BASELINE)]
    developments = [dev.with_columns(pl.lit(d.name).alias("run")) for d in evaluated
                    if (dev := load_development(d)) is not None]
    return Pooled(load_runs(evaluated),
                  pl.concat(baselines, how="diagonal_relaxed") if baselines else None,
                  pl.concat(developments, how="diagonal_relaxed") if developments else None)


def _empty_table() -> pl.DataFrame:
    cols = {"notation": pl.Utf8, "senses": pl.Utf8, "replication": pl.Int64, "rank": pl.Int64,
            "sector": pl.Int64, "reached": pl.Boolean, "grasped": pl.Boolean,
            "lifetime_fitness": pl.Float64}
    cols.update({m: pl.Float64 for m in ("fitness", "speed", "straightness", "var_elbow",
                                         "var_shoulder", "var_trunk", "babbling_share")})
    cols["babbling"] = pl.Boolean
    return pl.DataFrame(schema=cols)


def label_findings(found: pl.DataFrame, budget: Budget, run_dirs: Sequence,
                   claims: tuple[Claim, ...] = CLAIMS) -> pl.DataFrame:
    """``found`` (``findings.findings`` of the runs of one budget) with the columns of
    ``KEY_COLUMNS`` in front: the budget, the runs' names, and each claim's ``sign`` (+1 or -1
    for a directional or change claim, 0 otherwise)."""
    signs = {c.id: c.sign for c in claims}
    return found.select(
        pl.lit(budget.scene).alias("scene"),
        pl.lit(budget.generations_per_phase, dtype=pl.Int64).alias("generations_per_phase"),
        pl.lit(budget.replications, dtype=pl.Int64).alias("replications"),
        pl.lit(budget.model).alias("model"),
        pl.lit(", ".join(Path(d).name for d in run_dirs)).alias("runs"),
        pl.col("claim").replace_strict(signs, default=0, return_dtype=pl.Int64).alias("sign"),
        pl.all())


def findings_by_budget(run_dirs: Sequence) -> pl.DataFrame:
    """The findings of ``run_dirs``, one block of rows per budget (``budget_groups``): the runs
    of a budget pooled and judged together (``findings.findings``, Holm within the block), runs
    of different budgets (of two models among them) never. Columns: ``KEY_COLUMNS``, then
    the findings' columns."""
    return pl.concat([label_findings(pooled(dirs).findings(), budget, dirs)
                      for budget, dirs in budget_groups(run_dirs).items()])


def budgets(by_budget: pl.DataFrame) -> list[Budget]:
    """The budgets of a findings-by-budget frame, in order."""
    return sorted(Budget(*row) for row in by_budget.select(BUDGET_COLUMNS).unique().iter_rows())


def of_budget(by_budget: pl.DataFrame, budget: Budget) -> pl.DataFrame:
    """The rows of ``by_budget`` at ``budget``."""
    return by_budget.filter(*[pl.col(c) == getattr(budget, c) for c in BUDGET_COLUMNS])


def with_series(by_budget: pl.DataFrame) -> pl.DataFrame:
    """``by_budget`` with ``series``: the budgets along which a claim's intervals are set side
    by side with the generations alone differing, named by the scene, with
    the replications and the model only where the frame's budgets differ in them."""
    parts = [pl.col("scene")]
    if by_budget["replications"].n_unique() > 1:
        parts.append(pl.format(", {} replications", "replications"))
    if by_budget["model"].n_unique() > 1:
        parts.append(pl.format(", model {}", "model"))
    return by_budget.with_columns(pl.concat_str(parts).alias("series"))


# ------------------------------------------------------------------------------ direction
def _fold(effect: float, centre: float, top: float):
    """``top - |x - centre|`` of a value, and the map of an interval to its image."""
    def image(lo: float, hi: float) -> tuple[float, float]:
        far = max(abs(lo - centre), abs(hi - centre))
        near = 0.0 if lo <= centre <= hi else min(abs(lo - centre), abs(hi - centre))
        return top - far, top - near
    return top - abs(effect - centre), image


def _band_depth(x: float) -> float:
    lo, hi = ABOUT_HALF
    return min(x - lo, hi - x)


def _toward(kind: str, sign: int, effect: float, low: float, high: float,
            floor: float = math.nan) -> tuple[float, float, float]:
    """One claim's effect and interval on the scale where the paper's direction is up (see
    ``toward_paper``); the interval NaN where the claim has none."""
    if kind in (Kind.DIRECTIONAL.value, Kind.NEVER.value):  # theta
        point = sign * (effect - 0.5)
        image = lambda lo, hi: sorted((sign * (lo - 0.5), sign * (hi - 0.5)))  # noqa: E731
    elif kind in (Kind.CHANGE_PAIRED.value, Kind.WITHIN.value):
        point, image = sign * effect, lambda lo, hi: sorted((sign * lo, sign * hi))
    elif kind == Kind.NOT_BETTER.value:  # theta of "b better": the lower, the more so
        top = 0.5 + verdicts.EQUIVALENCE_MARGIN
        point, image = top - effect, lambda lo, hi: (top - hi, top - lo)
    elif kind == Kind.NO_DIFFERENCE.value:
        point, image = _fold(effect, 0.5, verdicts.EQUIVALENCE_MARGIN)
    elif kind == Kind.SAME_PAIRED.value:
        point, image = _fold(effect, 0.0, 0.0)
    elif kind == Kind.BAND.value:
        centre = sum(ABOUT_HALF) / 2
        point = _band_depth(effect)
        def image(lo, hi):
            return min(_band_depth(lo), _band_depth(hi)), _band_depth(min(max(centre, lo), hi))
    elif kind in (Kind.EVERY_SECTOR.value, Kind.AT_LEAST.value):
        f = verdicts.SECTOR_FLOOR if kind == Kind.EVERY_SECTOR.value else floor
        point, image = effect - f, lambda lo, hi: (lo - f, hi - f)
    elif kind == Kind.PAIRED.value:  # Kendall's W: the senses matter more
        point, image = effect, lambda lo, hi: (lo, hi)
    else:
        raise ValueError(f"unknown kind of claim {kind!r}")
    if math.isnan(point) or math.isnan(low) or math.isnan(high):
        return point, math.nan, math.nan
    lo, hi = image(low, high)
    return point, lo, hi


def toward_paper(by_budget: pl.DataFrame) -> pl.DataFrame:
    """``by_budget`` with ``toward``, ``toward_low``, ``toward_high``: each claim's effect and
    interval (NaN: none) on a scale where up is the paper's direction, in the units of the
    claim's effect:

    - directional, never: ``sign`` x (theta - 0.5) (0: no difference);
    - change (paired), within, and a development claim of one phase at two moments
      (``Claim.effect_kind``): ``sign`` x effect (0: no difference);
    - at least: the mean above the claim's floor;
    - not better: 0.65 - theta(better) (0: the margin, above it: not better);
    - no difference: 0.15 - |theta - 0.5| (``verdicts.EQUIVALENCE_MARGIN``; 0: the margin,
      above it: inside);
    - no change (paired): -|mean change| (0: no change; the margin is relative to the data);
    - band: the distance inside the band [1/3, 2/3] (negative: outside);
    - every sector: the weakest sector's rate - 0.10 (``verdicts.SECTOR_FLOOR``);
    - paired (Friedman): Kendall's W.

    An interval maps to its image (e.g. theta's interval [0.45, 0.6] to [0.05, 0.15])."""
    floors = {c.id: c.floor for c in CLAIMS}
    kinds = {c.id: c.effect_kind.value for c in CLAIMS}  # a paired development claim: a change
    rows = [_toward(kinds.get(c, k), s, e, lo, hi, floors.get(c, math.nan))
            for c, k, s, e, lo, hi in by_budget.select(
                "claim", "kind", "sign", pl.col("effect").fill_null(math.nan),
                pl.col("effect_low").fill_null(math.nan),
                pl.col("effect_high").fill_null(math.nan)).iter_rows()]
    t, lo, hi = zip(*rows) if rows else ((), (), ())
    return by_budget.with_columns(pl.Series("toward", t, pl.Float64),
                                  pl.Series("toward_low", lo, pl.Float64),
                                  pl.Series("toward_high", hi, pl.Float64))


def _move(small: tuple[float, float, float], large: tuple[float, float, float]
          ) -> str:
    (s, s_lo, s_hi), (b, b_lo, b_hi) = small, large
    if math.isnan(s) or math.isnan(b):
        return NOT_RUN
    if any(math.isnan(x) for x in (s_lo, s_hi, b_lo, b_hi)):
        return NO_INTERVAL
    return APART_HIGHER if b_lo > s_hi else APART_LOWER if b_hi < s_lo else OVERLAP


def movement(by_budget: pl.DataFrame) -> pl.DataFrame:
    """How each claim's intervals lie as the budget grows, per series (``with_series``: a
    scene, a number of replications and a model) with at least two budgets: at its smallest
    and its largest generations per phase, on the ``toward_paper`` scale. A description, not a
    test: two 95 % intervals apart are no test of the change at any stated level, no rule of
    ``verdicts`` gates it and nothing is corrected over the claims; each budget's verdict is
    the result.

    - ``not run``: no effect at either end (the claim not run, or decided underpowered before
      any effect was computed);
    - with a replication-level interval at both ends: ``apart, higher`` when the largest
      budget's interval lies wholly above the smallest's, ``apart, lower`` when wholly below,
      ``overlap`` otherwise (an unbounded interval overlaps everything);
    - ``no interval`` where either end has none (Friedman's W, an underpowered rule).

    Columns: claim, series, from_generations, to_generations, movement (one of
    ``MOVEMENTS``); one row per claim and series, in the frame's order."""
    scored = with_series(toward_paper(by_budget))
    claims = scored["claim"].unique(maintain_order=True).to_list()
    rows = []
    for series in scored["series"].unique(maintain_order=True).to_list():
        gens = sorted(scored.filter(pl.col("series") == series)["generations_per_phase"]
                      .unique().to_list())
        if len(gens) < 2:
            continue
        ends = [{r[0]: tuple(r[1:]) for r in scored.filter(
            (pl.col("series") == series) & (pl.col("generations_per_phase") == g))
            .select("claim", "toward", "toward_low", "toward_high").iter_rows()}
            for g in (gens[0], gens[-1])]
        nan3 = (math.nan,) * 3
        for claim in claims:
            rows.append((claim, series, gens[0], gens[-1],
                         _move(ends[0].get(claim, nan3), ends[1].get(claim, nan3))))
    return pl.DataFrame(rows, orient="row", schema={
        "claim": pl.Utf8, "series": pl.Utf8, "from_generations": pl.Int64,
        "to_generations": pl.Int64, "movement": pl.Utf8})


# ------------------------------------------------------------------------------ replications
#: What more replications did to a claim's verdict at the same scene and generations
#: (``replications_decide``).
DECIDED_NOW, STILL_OPEN, SAME, REVERSED, UNDECIDED_NOW = (
    "decided", "still open", "the same", "reversed", "no longer decided")
REPLICATION_OUTCOMES = (DECIDED_NOW, STILL_OPEN, SAME, REVERSED, UNDECIDED_NOW, NOT_RUN)


def _replication_outcome(few: str | None, many: str | None) -> str:
    if few in (None, verdicts.NOT_RUN) or many in (None, verdicts.NOT_RUN):
        return NOT_RUN
    decided = few in verdicts.DECIDED, many in verdicts.DECIDED
    if decided == (False, True):
        return DECIDED_NOW
    if decided == (False, False):
        return STILL_OPEN
    if decided == (True, False):
        return UNDECIDED_NOW
    return SAME if few == many else REVERSED


def replications_decide(by_budget: pl.DataFrame) -> pl.DataFrame:
    """What more replications decided: for every scene and generations per phase judged at
    several replication counts, each claim's verdict at the fewest (``few``) and the most
    (``many``) and the ``outcome`` (``REPLICATION_OUTCOMES``): *decided* (reproduced or
    contradicted where the fewer left it inconclusive or underpowered), *still open*, *the
    same*, *reversed* (reproduced <-> contradicted), *no longer decided*, *not run* (at either).
    Replications of one model only are compared. Columns: claim, scene, generations_per_phase,
    model, replications_few, replications_many, few, many, outcome; in the frame's order."""
    rows = []
    claims = by_budget["claim"].unique(maintain_order=True).to_list()
    for (scene, gens, model), block in by_budget.group_by(
            "scene", "generations_per_phase", "model", maintain_order=True):
        counts = sorted(block["replications"].unique().to_list())
        if len(counts) < 2:
            continue
        ends = [dict(block.filter(pl.col("replications") == r).select("claim", "verdict")
                     .iter_rows()) for r in (counts[0], counts[-1])]
        for claim in claims:
            few, many = ends[0].get(claim), ends[1].get(claim)
            rows.append((claim, scene, gens, model, counts[0], counts[-1], few, many,
                         _replication_outcome(few, many)))
    return pl.DataFrame(rows, orient="row", schema={
        "claim": pl.Utf8, "scene": pl.Utf8, "generations_per_phase": pl.Int64,
        "model": pl.Utf8, "replications_few": pl.Int64, "replications_many": pl.Int64,
        "few": pl.Utf8, "many": pl.Utf8, "outcome": pl.Utf8})


# ------------------------------------------------------------------------------ the table
def budget_column(budget: Budget, one_scene: bool, one_replications: bool = True,
                  one_model: bool = True) -> str:
    """The name of a budget's columns in ``side_by_side``: its generations per phase, with its
    scene, its replications and its model where the frame has several."""
    name = f"{budget.generations_per_phase} gen/phase"
    if not one_replications:
        name += f" x {budget.replications}"
    if not one_model:
        name += f", model {budget.model}"
    return name if one_scene else f"{budget.scene}, {name}"


def movement_column(series: str | None = None) -> str:
    """``MOVEMENT_COLUMN``, with the series it is of (``with_series``) where there are
    several."""
    return (MOVEMENT_COLUMN if series is None
            else f"intervals as the budget grows ({series}; not a test)")


def side_by_side(by_budget: pl.DataFrame) -> pl.DataFrame:
    """One row per claim (in the frame's order): claim, section, kind; for each budget
    (``budgets``; named by ``budget_column``) its ``effect [CI]`` (the claim's own effect,
    ``formatting.effect``), ``verdict`` (the replication as the unit; "not run" where the budget's
    runs lack it) and ``robots as units`` (the paper's analysis, never a headline); and the
    intervals as the budget grows (``movement``, under ``MOVEMENT_COLUMN``: one column per
    series with two budgets or more, its series in brackets when there are several)."""
    order = by_budget.select("claim", "section", "kind").unique("claim", maintain_order=True)
    all_budgets = budgets(by_budget)
    scenes = list(dict.fromkeys(b.scene for b in all_budgets))
    one_replications = len({b.replications for b in all_budgets}) == 1
    one_model = len({b.model for b in all_budgets}) == 1
    out = order
    for b in all_budgets:
        name = budget_column(b, len(scenes) == 1, one_replications, one_model)
        block = of_budget(by_budget, b)
        cells = pl.DataFrame(
            {"claim": block["claim"],
             f"{name}: effect [CI]": [formatting.effect(*r) for r in block.select(
                 pl.col(c).fill_null(math.nan) for c in ("effect", "effect_low", "effect_high")
             ).iter_rows()],
             f"{name}: verdict": block["verdict"],
             f"{name}: robots as units": block["verdict_robots"]})
        out = out.join(cells, on="claim", how="left", maintain_order="left").with_columns(
            pl.col(f"{name}: effect [CI]").fill_null("–"),
            pl.col(f"{name}: verdict").fill_null(verdicts.NOT_RUN),
            pl.col(f"{name}: robots as units").fill_null("–"))
    moves = movement(by_budget)
    moved = moves["series"].unique(maintain_order=True).to_list()
    several = with_series(by_budget)["series"].n_unique() > 1
    for series in moved:
        name = movement_column(series if several else None)
        m = moves.filter(pl.col("series") == series).select("claim",
                                                             pl.col("movement").alias(name))
        out = out.join(m, on="claim", how="left", maintain_order="left")
    return out
