"""Runs at several budgets (``dart_reach.analysis.budgets``): the budget key of a run directory
(its scene, generations per phase, replications and model), the scale on which the paper's
direction is up, and how a claim's intervals lie as the budget grows, on hand-made findings
rows where each word must come out (apart higher or lower, overlap, no interval, not run),
words that state no result."""

from __future__ import annotations

import math
from dataclasses import replace

import polars as pl
import pytest

from dart_reach.analysis import budgets as bd
from dart_reach.analysis import verdicts as vd
from dart_reach.analysis.claims import Kind
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import Trainer
from dart_reach.model.scenes import load_scene

NAN = math.nan


# ------------------------------------------------------------------------------ the key
def _run(out, generations: int, sectors=None, conditions=("standard", "gross-hat"),
         replications: int = 2, model_version: int = 3):
    """A run directory with its manifest only (nothing trained)."""
    settings = Settings(replications=replications, model_version=model_version)
    if sectors is not None:
        settings = replace(settings, world=replace(settings.world, sectors=sectors))
    Trainer(out, [scaled(load_condition(c), generations) for c in conditions], settings)
    return out


def test_the_budget_is_the_scene_the_generations_per_phase_and_the_replications(tmp_path):
    shoulder = load_scene("arm-length-shoulder").sectors
    a = _run(tmp_path / "a", 50, shoulder)
    b = _run(tmp_path / "b", 50, shoulder, conditions=("pre-h",))
    c = _run(tmp_path / "c", 10, shoulder)
    d = _run(tmp_path / "d", 50, load_scene("near").sectors)
    # gross^ trains 100 generations: 2 phases' worth of 50
    # version 3 on another scene than its own: a variant of it
    shoulder_v3 = "v3+scene=arm-length-shoulder"
    assert bd.budget_of(a) == bd.Budget("arm-length-shoulder", 50, 2, shoulder_v3)
    assert bd.budget_of(b) == bd.budget_of(a)
    assert bd.budget_of(c) == bd.Budget("arm-length-shoulder", 10, 2, shoulder_v3)
    assert bd.budget_of(d) == bd.Budget("near", 50, 2, "v3+scene=near")
    assert bd.budget_of(a).label == "arm-length-shoulder, 50 generations per phase, 2 replications"
    # more replications: another design (the transitions merge the best of each), never pooled
    ten = _run(tmp_path / "ten", 50, shoulder, replications=10)
    assert bd.budget_of(ten) == bd.Budget("arm-length-shoulder", 50, 10, shoulder_v3)
    # another model on the same scene and budget: another sample, never pooled
    v1 = _run(tmp_path / "v1", 50, shoulder, model_version=1)
    assert bd.budget_of(v1) == bd.Budget("arm-length-shoulder", 50, 2, "v1")
    assert bd.labels([bd.budget_of(v1), bd.budget_of(a)]) == {
        bd.budget_of(v1): "arm-length-shoulder, 50 generations per phase, 2 replications, "
                          "model v1",
        bd.budget_of(a): f"{bd.budget_of(a).label}, model {shoulder_v3}"}
    assert bd.labels([bd.budget_of(a)]) == {bd.budget_of(a): bd.budget_of(a).label}
    # two user scenes are two scenes, each named by its numbers
    e = _run(tmp_path / "e", 50, replace(shoulder, radius=0.40))
    f = _run(tmp_path / "f", 50, replace(shoulder, radius=0.41))
    assert bd.budget_of(e).scene.startswith("custom") and "0.4 m" in bd.budget_of(e).scene
    assert bd.budget_of(e) != bd.budget_of(f)
    groups = bd.budget_groups([c, ten, a, v1, d, b, a])
    assert list(groups) == [bd.Budget("arm-length-shoulder", 10, 2, shoulder_v3),
                            bd.Budget("arm-length-shoulder", 50, 2, "v1"),
                            bd.Budget("arm-length-shoulder", 50, 2, shoulder_v3),
                            bd.Budget("arm-length-shoulder", 50, 10, shoulder_v3),
                            bd.Budget("near", 50, 2, "v3+scene=near")]
    assert groups[bd.Budget("arm-length-shoulder", 50, 2, shoulder_v3)] == [a, b]  # twice: once
    assert groups[bd.Budget("arm-length-shoulder", 50, 2, "v1")] == [v1]


# ------------------------------------------------------------------------------ movement
#: The kinds whose effect is theta: a case's effect e stands for theta = 0.5 + e.
THETA = (Kind.DIRECTIONAL, Kind.NEVER)


def _rows(budget: int, specs: dict, scene: str = "near", replications: int = 4,
          model: str = "v3") -> list[dict]:
    """Findings rows of one budget: {claim: (kind, sign, effect, low, high)} (directional
    and never: effect and interval as theta - 0.5)."""
    specs = {c: (k, s, *(x + 0.5 * (k in THETA) for x in (e, lo, hi)))
             for c, (k, s, e, lo, hi) in specs.items()}
    return [{"scene": scene, "generations_per_phase": budget, "replications": replications,
             "model": model, "runs": f"r{budget}",
             "sign": sign, "claim": claim, "section": "S", "kind": kind.value,
             "effect": e, "effect_low": lo, "effect_high": hi,
             "verdict": (vd.NOT_RUN if math.isnan(e) else vd.REPRODUCED if claim == "overlap"
                         else vd.INCONCLUSIVE),
             "verdict_robots": vd.REPRODUCED if claim in ("overlap", "unbounded") else None}
            for claim, (kind, sign, e, lo, hi) in specs.items()]


K = Kind
#: claim: (its row at 10 generations per phase, at 50, the movement)
CASES = {
    "up, intervals apart": ((K.DIRECTIONAL, +1, 0.1, 0.0, 0.2),
                            (K.DIRECTIONAL, +1, 0.5, 0.3, 0.7), bd.APART_HIGHER),
    "lower wanted, rises": ((K.DIRECTIONAL, -1, -0.5, -0.7, -0.3),
                            (K.DIRECTIONAL, -1, 0.4, 0.3, 0.5), bd.APART_LOWER),
    "overlap": ((K.DIRECTIONAL, +1, 0.1, -0.1, 0.3),
                (K.DIRECTIONAL, +1, 0.2, 0.0, 0.4), bd.OVERLAP),
    "sign flips, overlap": ((K.DIRECTIONAL, +1, -0.05, -0.2, 0.1),
                            (K.DIRECTIONAL, +1, 0.05, -0.1, 0.2), bd.OVERLAP),
    "unbounded": ((K.DIRECTIONAL, +1, 0.1, -math.inf, math.inf),
                  (K.DIRECTIONAL, +1, 5.0, 4.0, 6.0), bd.OVERLAP),
    "not run at 50": ((K.DIRECTIONAL, +1, 0.1, 0.0, 0.2),
                      (K.DIRECTIONAL, +1, NAN, NAN, NAN), bd.NOT_RUN),
    "theta to 0.5": ((K.NO_DIFFERENCE, 0, 0.9, 0.8, 1.0),
                     (K.NO_DIFFERENCE, 0, 0.52, 0.45, 0.6), bd.APART_HIGHER),
    "theta from 0.5": ((K.NO_DIFFERENCE, 0, 0.52, 0.45, 0.6),
                       (K.NO_DIFFERENCE, 0, 0.1, 0.02, 0.2), bd.APART_LOWER),
    "never: share falls": ((K.NEVER, -1, 0.1, 0.0, 0.2),
                           (K.NEVER, -1, -0.3, -0.4, -0.2), bd.APART_HIGHER),
    # a one-sided interval [0, upper]: its image always reaches the margin, so it can only
    # move away or not at all
    "not better: theta falls": ((K.NOT_BETTER, +1, 0.9, 0.0, 0.99),
                                (K.NOT_BETTER, +1, 0.3, 0.0, 0.45), bd.OVERLAP),
    "band: into it": ((K.BAND, 0, 0.1, 0.05, 0.15),
                      (K.BAND, 0, 0.5, 0.4, 0.6), bd.APART_HIGHER),
    "band: through it": ((K.BAND, 0, 0.1, 0.05, 0.15),
                         (K.BAND, 0, 0.95, 0.9, 1.0), bd.OVERLAP),
    "sectors: floor": ((K.EVERY_SECTOR, 0, 0.3, 0.2, 0.4),
                       (K.EVERY_SECTOR, 0, 0.0, 0.0, 0.05), bd.APART_LOWER),
    "same: change shrinks": ((K.SAME_PAIRED, 0, -0.4, -0.5, -0.3),
                             (K.SAME_PAIRED, 0, 0.01, -0.05, 0.07), bd.APART_HIGHER),
    "W falls": ((K.PAIRED, 0, 0.8, NAN, NAN), (K.PAIRED, 0, 0.3, NAN, NAN), bd.NO_INTERVAL),
    "paired change equal": ((K.CHANGE_PAIRED, -1, -0.1, NAN, NAN),
                            (K.CHANGE_PAIRED, -1, -0.1, NAN, NAN), bd.NO_INTERVAL),
    "one interval missing": ((K.DIRECTIONAL, +1, 0.1, NAN, NAN),
                             (K.DIRECTIONAL, +1, 0.2, 0.15, 0.25), bd.NO_INTERVAL),
}


def _frame(cases=CASES, middle: bool = True) -> pl.DataFrame:
    rows = _rows(10, {c: v[0] for c, v in cases.items()})
    rows += _rows(50, {c: v[1] for c, v in cases.items()})
    if middle:  # a budget between them, every claim the opposite way: it must not count
        rows += _rows(20, {c: (k, s, e, e - 1, e + 1)
                           for c, ((k, s, *_), _, _) in cases.items()
                           for e in [-10.0 * s if s else 10.0]})
    rows += _rows(50, {"only at 50": (K.DIRECTIONAL, +1, 0.3, 0.2, 0.4)})
    return pl.DataFrame(rows)


def test_movement_follows_the_rule_on_constructed_rows():
    moves = bd.movement(_frame())
    got = {r["claim"]: r["movement"] for r in moves.iter_rows(named=True)}
    assert got == {**{c: m for c, (_, _, m) in CASES.items()}, "only at 50": bd.NOT_RUN}
    assert set(moves["from_generations"]) == {10} and set(moves["to_generations"]) == {50}
    assert set(moves["movement"]) == set(bd.MOVEMENTS)


def test_the_scale_puts_the_papers_direction_up():
    scored = bd.toward_paper(_frame(middle=False)).filter(pl.col("generations_per_phase") == 50)
    row = {r["claim"]: (r["toward"], r["toward_low"], r["toward_high"])
           for r in scored.iter_rows(named=True)}
    assert row["lower wanted, rises"] == pytest.approx((-0.4, -0.5, -0.3))
    # theta 0.52 in [0.45, 0.6]: 0.15 - |theta - 0.5|, the interval's image [0.05, 0.15]
    assert row["theta to 0.5"] == pytest.approx((0.13, 0.05, 0.15))
    assert row["never: share falls"] == pytest.approx((0.3, 0.2, 0.4))
    assert row["not better: theta falls"] == pytest.approx((0.35, 0.2, 0.65))
    assert row["band: into it"] == pytest.approx((1 / 6, 1 / 15, 1 / 6))
    assert row["sectors: floor"] == pytest.approx((-0.1, -0.1, -0.05))
    assert row["same: change shrinks"] == pytest.approx((-0.01, -0.07, 0.0))
    assert row["W falls"][0] == 0.3 and math.isnan(row["W falls"][1])


def test_side_by_side_has_one_row_per_claim_and_the_movement():
    frame = _frame()
    table = bd.side_by_side(frame)
    claims = frame["claim"].unique(maintain_order=True).to_list()
    assert table["claim"].to_list() == claims
    assert table.columns == ["claim", "section", "kind",
                             *[f"{g} gen/phase: {c}" for g in (10, 20, 50)
                               for c in ("effect [CI]", "verdict", "robots as units")],
                             bd.MOVEMENT_COLUMN]
    row = {r["claim"]: r for r in table.iter_rows(named=True)}
    assert row["up, intervals apart"]["50 gen/phase: effect [CI]"] == "1 [0.8, 1.2]"
    assert row["W falls"]["10 gen/phase: effect [CI]"] == "0.8"
    assert row["W falls"][bd.MOVEMENT_COLUMN] == bd.NO_INTERVAL
    assert row["only at 50"]["10 gen/phase: verdict"] == vd.NOT_RUN
    assert row["only at 50"]["10 gen/phase: effect [CI]"] == "–"
    # the words describe the intervals and state no result: no "toward", "away", "change"
    assert row["overlap"][bd.MOVEMENT_COLUMN] == "overlap"
    assert row["up, intervals apart"][bd.MOVEMENT_COLUMN] == "apart, higher"
    assert bd.MOVEMENT_COLUMN == "intervals as the budget grows (not a test)"
    assert not any(w in m for m in bd.MOVEMENTS for w in ("toward", "away", "change"))
    # the paper's analysis, robots as units, is its own column, never the verdict
    assert row["overlap"]["50 gen/phase: verdict"] == vd.REPRODUCED
    assert row["unbounded"]["50 gen/phase: verdict"] == vd.INCONCLUSIVE
    assert row["unbounded"]["50 gen/phase: robots as units"] == vd.REPRODUCED
    assert row["up, intervals apart"]["50 gen/phase: robots as units"] == "–"
    assert row["up, intervals apart"]["50 gen/phase: verdict"] == vd.INCONCLUSIVE


def test_scenes_are_never_compared_with_each_other():
    """Two scenes: the movement is within each; a scene with one budget has none."""
    one = {"c": (K.DIRECTIONAL, +1, 0.1, 0.0, 0.2)}
    up = {"c": (K.DIRECTIONAL, +1, 0.9, 0.8, 1.0)}
    frame = pl.DataFrame(_rows(10, one, "near") + _rows(50, up, "near")
                         + _rows(10, up, "far") + _rows(50, one, "far")
                         + _rows(30, up, "lone"))
    moves = {r["series"]: r["movement"] for r in bd.movement(frame).iter_rows(named=True)}
    assert moves == {"near": bd.APART_HIGHER, "far": bd.APART_LOWER}
    table = bd.side_by_side(frame)
    assert "intervals as the budget grows (near; not a test)" in table.columns
    assert "intervals as the budget grows (far; not a test)" in table.columns
    assert "far, 10 gen/phase: verdict" in table.columns
    assert not any("lone)" in c for c in table.columns)


def test_more_replications_are_a_series_of_their_own():
    """10 x 4 -> 50 x 4 is a movement; 50 x 10 sits beside 50 x 4 as a column of its own,
    never the end of the 4-replication series."""
    low = {"c": (K.DIRECTIONAL, +1, 0.1, 0.0, 0.2)}
    high = {"c": (K.DIRECTIONAL, +1, 0.9, 0.8, 1.0)}
    frame = pl.DataFrame(_rows(10, low) + _rows(50, high) + _rows(50, low, replications=10))
    moves = bd.movement(frame)
    assert moves.select("series", "movement").rows() == [("near, 4 replications", bd.APART_HIGHER)]
    table = bd.side_by_side(frame)
    assert {"10 gen/phase x 4: verdict", "50 gen/phase x 4: verdict",
            "50 gen/phase x 10: verdict",
            "intervals as the budget grows (near, 4 replications; not a test)"
            } <= set(table.columns)
    assert table["50 gen/phase x 10: effect [CI]"][0] == "0.6 [0.5, 0.7]"


def test_what_more_replications_decided():
    """50 x 4 against 50 x 10, claim by claim: each outcome from its pair of verdicts; the
    10 x 4 budget (one replication count) gives none."""
    pairs = {"decided": (vd.INCONCLUSIVE, vd.REPRODUCED), "open": (vd.UNDERPOWERED,
                                                                   vd.INCONCLUSIVE),
             "same": (vd.CONTRADICTED, vd.CONTRADICTED), "reversed": (vd.REPRODUCED,
                                                                    vd.CONTRADICTED),
             "lost": (vd.REPRODUCED, vd.INCONCLUSIVE), "new": (vd.NOT_RUN, vd.REPRODUCED)}
    spec = {c: (K.DIRECTIONAL, +1, 0.1, 0.0, 0.2) for c in pairs}
    rows = _rows(10, spec)
    for replications, end in ((4, 0), (10, 1)):
        rows += [dict(r, verdict=pairs[r["claim"]][end])
                 for r in _rows(50, spec, replications=replications)]
    got = bd.replications_decide(pl.DataFrame(rows))
    assert got["claim"].to_list() == list(pairs)
    assert set(got["generations_per_phase"]) == {50}
    assert set(got["replications_few"]) == {4} and set(got["replications_many"]) == {10}
    assert got["outcome"].to_list() == [bd.DECIDED_NOW, bd.STILL_OPEN, bd.SAME, bd.REVERSED,
                                        bd.UNDECIDED_NOW, bd.NOT_RUN]
    assert bd.replications_decide(pl.DataFrame(_rows(10, spec) + _rows(50, spec))).height == 0


def test_the_figure_draws_the_claims_with_an_effect_at_two_budgets():
    from dart_reach.analysis import figures

    frame = _frame()
    fig = figures.budget_figure(frame)
    drawn = [ax for ax in fig.axes if ax.get_visible()]
    scored = bd.toward_paper(frame).filter(pl.col("toward").is_not_nan())
    twice = scored.group_by("claim").len().filter(pl.col("len") >= 2).height
    assert len(drawn) == twice == len(CASES)  # "not run at 50" has 10 and 20; "only at 50" one
    titles = [ax.get_title(loc="left").replace("\n", " ") for ax in drawn]
    assert titles[0] == "up, intervals apart"
    assert drawn[0].get_xlabel() == bd.APART_HIGHER
    assert [t.get_text() for t in drawn[0].get_xticklabels()] == ["10", "20", "50"]
    lone = figures.budget_figure(frame.filter(pl.col("claim") == "only at 50"))
    assert "no claim has an effect at two budgets" in [t.get_text() for t in lone.axes[0].texts]


def test_models_are_never_pooled_nor_compared_and_named_only_when_several():
    """Two models on one scene at the same budgets: each model its own columns and series,
    named by its model; one model alone: the names as before models were told apart."""
    low = {"c": (K.DIRECTIONAL, +1, 0.1, 0.0, 0.2)}
    high = {"c": (K.DIRECTIONAL, +1, 0.9, 0.8, 1.0)}
    one = _rows(10, low) + _rows(50, high)
    assert bd.side_by_side(pl.DataFrame(one)).columns[3] == "10 gen/phase: effect [CI]"
    frame = pl.DataFrame(one + _rows(10, high, model="v1") + _rows(50, low, model="v1"))
    assert bd.budgets(frame) == [bd.Budget("near", 10, 4, "v1"), bd.Budget("near", 10, 4, "v3"),
                                 bd.Budget("near", 50, 4, "v1"), bd.Budget("near", 50, 4, "v3")]
    moves = dict(bd.movement(frame).select("series", "movement").rows())
    assert moves == {"near, model v3": bd.APART_HIGHER, "near, model v1": bd.APART_LOWER}
    table = bd.side_by_side(frame)
    assert table["10 gen/phase, model v1: effect [CI]"][0] == "1.4 [1.3, 1.5]"
    assert table["10 gen/phase, model v3: effect [CI]"][0] == "0.6 [0.5, 0.7]"
    assert "intervals as the budget grows (near, model v1; not a test)" in table.columns
    # more replications are compared within one model only
    more = pl.DataFrame(one + _rows(50, high, replications=10, model="v1"))
    assert bd.replications_decide(more).height == 0
