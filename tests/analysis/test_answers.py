"""The report's answers per phenomenon (``answers``), the scales of the forest (``scales``) and
its caption (``figures.forest_caption``), on findings frames made here (no run trained)."""

from __future__ import annotations

import html
import json
import math
import re
from pathlib import Path

import polars as pl
import pytest

from dart_reach.analysis import answers, budgets, figures, findings, scales, verdicts
from dart_reach.analysis.claims import CLAIMS, Kind

HEAD = [c for c in CLAIMS if not c.own and not c.infants]


def _frame(verdict_of, gens: int = 3, reps: int = 2) -> pl.DataFrame:
    """A findings-by-budget frame of every claim at one budget, the verdict of a claim
    ``verdict_of(claim)``; a decided or inconclusive claim gets an effect with an interval."""
    rows = []
    for c in CLAIMS:
        v = verdict_of(c)
        run = v in (verdicts.REPRODUCED, verdicts.CONTRADICTED, verdicts.INCONCLUSIVE)
        e = 0.8 if v == verdicts.REPRODUCED else 0.2 if v == verdicts.CONTRADICTED else 0.55
        rows.append({"scene": "s", "generations_per_phase": gens, "replications": reps,
                     "model": "v1", "runs": "r", "sign": c.sign, "claim": c.id,
                     "section": c.section,
                     "kind": c.kind.value, "own": c.own, "infants": c.infants,
                     "measured": "not run: no units of pre-h" if v == verdicts.NOT_RUN
                     else "m", "n": f"{reps} replications vs {reps} replications",
                     "effect": e if run else math.nan,
                     "effect_low": e - 0.1 if run else math.nan,
                     "effect_high": e + 0.1 if run else math.nan, "verdict": v,
                     "p_holm": 0.01 if v == verdicts.REPRODUCED else 1.0,
                     "p_holm_against": 0.01 if v == verdicts.CONTRADICTED else 1.0,
                     "note": ""})
    return pl.DataFrame(rows)


def test_every_claim_of_the_paper_belongs_to_one_phenomenon_with_its_section():
    listed = [c for p in answers.PHENOMENA for c in p.claims]
    assert sorted(listed) == sorted(c.id for c in HEAD)  # each once, none unknown
    assert all(p.section and p.name for p in answers.PHENOMENA)
    names = " ".join(p.name for p in answers.PHENOMENA)
    for phenomenon in ("Pre-reaching", "Gross-reaching", "Fine-reaching", "babbling",
                       "DOF freezing", "Maturational constraints", "Fig. 10"):
        assert phenomenon in names
    assert answers.FEWEST_DECIDING == 6  # the two-group rules' gate (verdict_core.one_mode)


@pytest.mark.parametrize("lead, others, expected", [
    (verdicts.REPRODUCED, (verdicts.INCONCLUSIVE, verdicts.UNDERPOWERED), answers.REPRODUCED),
    (verdicts.REPRODUCED, (verdicts.REPRODUCED, verdicts.CONTRADICTED), answers.PARTLY),
    (verdicts.CONTRADICTED, (verdicts.REPRODUCED, verdicts.REPRODUCED), answers.NOT_REPRODUCED),
    (verdicts.UNDERPOWERED, (verdicts.REPRODUCED,), answers.NOT_TESTABLE),
    (verdicts.NOT_RUN, (verdicts.CONTRADICTED,), answers.NOT_TESTABLE),
    # the lead claim inconclusive: never "not reproduced", whatever the others
    (verdicts.INCONCLUSIVE, (verdicts.CONTRADICTED,), answers.INCONCLUSIVE),
    (verdicts.INCONCLUSIVE, (verdicts.NOT_RUN,) * 26, answers.INCONCLUSIVE),
])
def test_the_lead_claim_decides_the_answer(lead, others, expected):
    assert answers.answer(lead, others) == expected


@pytest.mark.parametrize("phenomenon, verdicts_, expected", [
    # reproduced on one of three claims (arm orienting) while its lead claim, reach in about
    # half the trials, is inconclusive: inconclusive, not "reproduced"
    ("Pre-reaching", (verdicts.INCONCLUSIVE, verdicts.REPRODUCED, verdicts.INCONCLUSIVE),
     answers.INCONCLUSIVE),
    # 0 of 7 claims decided: inconclusive, never "not reproduced"
    ("DOF freezing", (verdicts.INCONCLUSIVE,) * 7, answers.INCONCLUSIVE),
    # 9 of 10 claims tested, one underpowered: inconclusive, not "not yet testable"
    ("Gross-reaching", (verdicts.INCONCLUSIVE,) * 6 + (verdicts.UNDERPOWERED,)
     + (verdicts.INCONCLUSIVE,) * 3, answers.INCONCLUSIVE),
    ("Fine-reaching", (verdicts.REPRODUCED, verdicts.CONTRADICTED) + (verdicts.REPRODUCED,) * 6,
     answers.PARTLY),
])
def test_each_phenomenon_is_answered_by_its_lead_claim(phenomenon, verdicts_, expected):
    p = next(p for p in answers.PHENOMENA if p.name.startswith(phenomenon))
    of = dict(zip(p.claims, verdicts_))
    frame = _frame(lambda c: of.get(c.id, verdicts.NOT_RUN), 50, 10)
    row = answers.answers(frame).filter(pl.col("phenomenon") == p.name).row(0, named=True)
    assert row["answer"] == expected
    assert row["why"].startswith(f"{p.claims[0]}: {verdicts_[0]}")
    tally = [f"{verdicts_.count(v)} {v}" for v in verdicts.VERDICTS if v in verdicts_]
    assert row["why"].endswith(f"of its {len(p.claims)} claims {', '.join(tally)}")


def test_the_committed_ten_replication_run_is_answered_by_its_lead_claims():
    """The cases the rule was written for, on the committed findings of the 50-generation,
    10-replication run: pre-reaching (arm orienting reproduced, its lead claim not), DOF
    freezing (nothing decided) and gross-reaching (9 of 10 tested) are inconclusive."""
    saved = Path(__file__).parents[2] / "recordings" / "replication-50x10" / "findings.parquet"
    table = {r["phenomenon"].split(":")[0]: r
             for r in answers.answers(pl.read_parquet(saved)).iter_rows(named=True)}
    pre = table["Pre-reaching"]
    assert (pre["answer"], pre[verdicts.REPRODUCED]) == (answers.INCONCLUSIVE, 1)
    assert pre["why"].startswith("F1 reach about half: inconclusive, mean = ")
    dof = table["DOF freezing"]
    assert (dof["answer"], dof[verdicts.INCONCLUSIVE], dof["claims"]) == (
        answers.INCONCLUSIVE, 7, 7)
    gross = table["Gross-reaching"]
    assert (gross["answer"], gross[verdicts.INCONCLUSIVE], gross[verdicts.UNDERPOWERED]) == (
        answers.INCONCLUSIVE, 9, 1)
    assert table["Fine-reaching"]["answer"] == answers.PARTLY  # F3 grasp up reproduced
    assert table["Senses"]["answer"] == answers.REPRODUCED


def test_a_run_with_nothing_decided_is_too_small_and_names_the_run_beside_it_that_can(tmp_path):
    small = _frame(lambda c: verdicts.UNDERPOWERED)
    table = answers.answers(small)
    assert table.height == len(answers.PHENOMENA)
    assert set(table["answer"]) == {answers.NOT_TESTABLE}
    assert all("underpowered" in w and "2 replications" in w for w in table["why"])
    assert answers.too_small(small) and answers.decided(small) == (0, len(HEAD), len(HEAD))

    # beside it: a run whose saved findings decide claims, one that decides fewer, and a
    # folder that is no run
    runs = tmp_path / "runs"
    for name, frame in (("big", _frame(lambda c: verdicts.REPRODUCED, 50, 10)),
                        ("mid", _frame(lambda c: verdicts.REPRODUCED if c.id.startswith("F2")
                                       else verdicts.INCONCLUSIVE, 10, 10)),
                        ("loose", _frame(lambda c: verdicts.REPRODUCED, 500, 10))):
        (runs / name).mkdir(parents=True)
        frame.write_parquet(runs / name / "findings.parquet")
        if name != "loose":
            (runs / name / "manifest.json").write_text(json.dumps({}))
    (runs / "demo").mkdir()
    ref = answers.reference_run([runs / "demo"])
    assert ref is not None and ref.path.name == "big"
    assert (ref.generations_per_phase, ref.replications, ref.decided) == (50, 10, len(HEAD))
    assert answers.reference_run([runs / "big"]).path.name == "mid"  # itself left out
    (tmp_path / "alone").mkdir()
    assert answers.reference_run([tmp_path / "alone"]) is None  # nothing beside it

    text = answers.answers_html(small, [runs / "demo"])
    assert "class='answers too-small'" in text
    assert "too small to test the paper" in text and "<code>big</code>" in text
    cells = [c for c in text.split("<td class='")[1:]]
    assert len(cells) == len(answers.PHENOMENA)
    assert all(c.startswith("untestable'>") for c in cells)
    assert "at least 6 replications a group" in text
    # ten replications that decide nothing: too small, but not for want of replications
    ten = answers.answers_html(_frame(lambda c: verdicts.INCONCLUSIVE, 3, 10), [runs / "demo"])
    assert "too small to test the paper" in ten and "replications a group" not in ten
    assert "<code>big</code>" in ten


def test_a_run_that_decides_gets_answers_with_the_lead_claims_effect():
    def verdict(c):
        return (verdicts.REPRODUCED if c.id.startswith(("F1", "T1 ")) else
                verdicts.CONTRADICTED if c.id.startswith(("F2", "T11", "P1")) else
                verdicts.NOT_RUN if c.id.startswith(("F5", "F6", "F7", "C ", "V5")) else
                verdicts.INCONCLUSIVE)
    frame = _frame(verdict, 50, 10)
    assert not answers.too_small(frame)
    table = {r["phenomenon"].split(":")[0]: r for r in answers.answers(frame).iter_rows(
        named=True)}
    pre = table["Pre-reaching"]
    assert pre["answer"] == answers.REPRODUCED
    assert pre["why"] == ("F1 reach about half: reproduced, mean = 0.8 [0.7, 0.9]; "
                          "of its 3 claims 3 reproduced")
    gross = table["Gross-reaching"]
    assert gross["answer"] == answers.NOT_REPRODUCED
    assert gross["why"].startswith("F2 grasp up: contradicted, θ = 0.2 [0.1, 0.3]")
    assert gross["why"].endswith("of its 10 claims 10 contradicted")
    assert table["Fine-reaching"]["answer"] == answers.INCONCLUSIVE  # all inconclusive
    fig10 = table["Maturational constraints"]
    assert fig10["answer"] == answers.NOT_TESTABLE
    assert fig10["why"].startswith("F5 gross > gross^: not run (no units of pre-h)")
    text = answers.answers_html(frame)
    assert "too-small" not in text and "<td class='yes'>reproduced</td>" in text


def test_every_kind_has_a_scale_and_paired_development_claims_carry_a_change():
    assert set(scales.SCALES) == {k.value for k in Kind}
    by_id = {c.id: c for c in CLAIMS}
    assert by_id["V4 babbling fades in gross"].effect_kind is Kind.CHANGE_PAIRED
    assert by_id["V1 motor suppression at the start of gross"].effect_kind is Kind.DIRECTIONAL
    assert by_id["F2 grasp up"].effect_kind is Kind.DIRECTIONAL
    # a change of -0.14 in the paper's direction (down) is drawn right of 0, not as theta
    frame = _frame(lambda c: verdicts.REPRODUCED).filter(
        pl.col("claim") == "V4 babbling fades in gross").with_columns(
        effect=pl.lit(-0.14), effect_low=pl.lit(-0.18), effect_high=pl.lit(-0.09))
    scored = budgets.toward_paper(frame).row(0, named=True)
    assert scored["toward"] == pytest.approx(0.14)
    assert scored["toward_low"] == pytest.approx(0.09)
    speed = scales.inverted("F3 speed not better")
    assert "better means a lower speed" in speed and "fine" in speed
    assert "lower" in scales.inverted("F2 reach down")
    assert scales.inverted("F2 grasp up") == ""


def test_the_forest_caption_states_each_drawn_rows_scale_and_its_inverted_labels():
    def verdict(c):
        return (verdicts.NOT_RUN if c.id.startswith(("F5", "F6", "F7", "C ", "V5", "F4"))
                else verdicts.INCONCLUSIVE)
    frame = _frame(verdict, 50, 10)
    text = html.unescape(re.sub(r"<[^>]+>", "", figures.forest_caption(frame)))
    assert "The scale" in text and "divided by the largest" in text
    assert "θ = P(b > a)" in text and "sign × (θ − 0.5)" in text
    assert "0.65 − θ(better)" in text  # F3 speed not better and others are drawn
    assert "Kendall's W" not in text  # no row of senses differ is drawn
    assert "F3 speed not better: better means a lower speed" in text
    assert "F2 reach down: the paper's direction is lower" in text
    assert "F2 grasp up:" not in text  # reads with the axis
    assert "F6 pre not better than pre-h" not in text  # not drawn
    rows = figures.scale_table(frame)
    drawn = findings.reading(frame).filter(pl.col("verdict") != verdicts.NOT_RUN)
    assert rows.height == drawn.height
    grasp = rows.filter(pl.col("claim") == "F2 grasp up").row(0, named=True)
    assert grasp["scale"] == "directional" and grasp["effect [CI]"] == "θ 0.55 [0.45, 0.65]"
    assert grasp["drawn [CI]"] == "0.05 [-0.05, 0.15]" and grasp["1 on the axis"] == "0.15"
