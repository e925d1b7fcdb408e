"""The report's first words: a plain answer per phenomenon of the paper.

The paper's claims of its robots (``findings.reading``, the headline) are grouped by the
phenomenon they test (``PHENOMENA``: data, each with the paper's section and its claims, the
lead claim first: the one that states the phenomenon), and each phenomenon gets one answer at
each budget (``answer``, the one rule, ``RULE`` its words). The lead claim decides:

- *reproduced*: the lead claim reproduced and no other contradicted;
- *partly reproduced*: the lead claim reproduced and another contradicted;
- *not reproduced*: the lead claim contradicted;
- *inconclusive*: the lead claim inconclusive (it could have been decided and was not),
  whatever the others: other claims reproduced do not make the phenomenon reproduced, and
  inconclusive is never "not reproduced";
- *not yet testable at this budget*: the lead claim underpowered or not run.

Each answer comes with the numbers that say why (``why``): the lead claim's verdict and its
effect with its interval (or the sample sizes that could not decide), and how its other
claims came out. A run too small to judge (no claim decided, or most claims underpowered:
``too_small``) says so, and names the run beside it whose saved findings (``findings.parquet``,
``report --findings``) decide the most claims (``reference_run``), so a reader of a demo's
report knows where the paper is tested.
"""

from __future__ import annotations

import html
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import polars as pl

from . import budgets, findings, formatting, scales, verdicts
from .verdict_core import one_mode


@dataclass(frozen=True)
class Phenomenon:
    """A phenomenon of the paper in plain words, the paper's ``section`` that reports it, and
    the ids of the claims (``claims.CLAIMS``) that test it, the most telling first."""

    name: str
    section: str
    claims: tuple[str, ...]


PHENOMENA: tuple[Phenomenon, ...] = (
    Phenomenon("Pre-reaching: the ball touched in about half the trials, the arm oriented "
               "toward it", "IV-A-1, Fig. 5; Table I",
               ("F1 reach about half", "T1 arm orienting", "F1 arm extended")),
    Phenomenon("Motor babbling: it emerges in pre-reaching, whether or not the ball is seen, "
               "and fades later", "IV-A-1, Fig. 8; V",
               ("F1 babbling", "V3 babbling appears in pre", "V4 babbling fades in gross",
                "T4 babbling reduced in gross", "T4 babbling reduced in fine",
                *[f"A1 ball absent, pre: {m} same"
                  for m in ("babbling", "hand_amplitude", "hand_path", "var_shoulder")],
                *[f"A3 no sight, pre: {m} same"
                  for m in ("babbling", "hand_amplitude", "hand_path")])),
    Phenomenon("DOF freezing: the elbow locked in pre-reaching, freed in fine-reaching",
               "IV-A-1, IV-A-3, Fig. 6; V",
               ("F1 elbow locked: elbow < shoulder", "F1 elbow locked: elbow < trunk",
                "F1 hand-shoulder constant vs random", "F1 hand-shoulder constant vs fine",
                "F3 elbow variability up", "F3 elbow un-freezes later",
                "V2 elbow un-freezes in fine")),
    Phenomenon("Gross-reaching: grasping rises while reaching regresses (fewer touches, "
               "fewer sectors, slower and straighter swipes)", "IV-A-2, Figs. 5-7",
               ("F2 grasp up", "F2 reach down", "F2 success in fewer sectors",
                "F2 straighter", "F2 slower", "F2 shoulder variability down",
                "F2 swipes again", "T11 palm-up swipes: gross > pre",
                "T11 palm-up swipes: gross > fine", "P1 peri-personal space shrinks in gross")),
    Phenomenon("Fine-reaching: reach and grasp rise again, in every sector, without faster or "
               "straighter movements", "IV-A-3, Figs. 5-7",
               ("F3 grasp up", "F3 reach up", "F3 all sectors", "P2 and re-expands in fine",
                "F3 shoulder variability up", "F3 trunk variability up",
                "F3 speed not better", "F3 straightness not better")),
    Phenomenon("Senses: performance rises phase by phase; touch, then sight, become "
               "necessary", "IV-B, Fig. 9; V",
               ("F4 normal: fine > gross", "F4 normal: gross > pre",
                "F4 senses differ (pre)", "F4 senses differ (gross)",
                "F4 senses differ (fine)", "F4 no-touch: fine > gross",
                "F4 no-touch: gross > pre", "F4 no-sight: gross > fine",
                "F4 nothing: gross > fine", "D1 no-sight drop: fine > gross",
                "D1 no-sight drop: fine > pre", "D2 no touch, pre: reach same",
                "D3 no touch, gross: fitness down", "D3 no touch, fine: fitness down",
                "D3 no-touch drop: gross > pre")),
    Phenomenon("Maturational constraints: the incremental course beats training all at once "
               "(Fig. 10), the other constraints matter little", "IV-C, Fig. 10",
               ("F5 gross > gross^",
                *[f"F6 {s} not better than {c}" for s, c in (
                    ("pre", "pre-h"), ("gross", "gross-h"), ("pre", "pre*"),
                    ("gross^", "gross^*"), ("fine^", "fine*"), ("fine", "fine^"))],
                "F7 fine* never babbles", "F7 fine^ never babbles",
                "V5 fine* never babbles during development",
                "V5 fine^ never babbles during development",
                *[f"C {a} vs {b}: {m} same" for a, b in (
                    ("pre", "pre-h"), ("pre", "pre*"), ("gross^", "gross^*"),
                    ("fine^", "fine*"))
                  for m in ("babbling", "hand_amplitude", "heading", "hand_shoulder_cv")])),
)

#: The answers, and the CSS class of each in the report.
REPRODUCED, PARTLY, NOT_REPRODUCED, INCONCLUSIVE, NOT_TESTABLE = (
    "reproduced", "partly reproduced", "not reproduced", "inconclusive",
    "not yet testable at this budget")
ANSWERS = {REPRODUCED: "yes", PARTLY: "partly", NOT_REPRODUCED: "no", INCONCLUSIVE: "open",
           NOT_TESTABLE: "untestable"}
#: ``answer``'s rule in the report's words.
RULE = ("A phenomenon is answered by its lead claim, the one that states it (listed first): "
        "<i>reproduced</i> only when the lead claim is reproduced and no other claim is "
        "contradicted, <i>partly reproduced</i> when the lead claim is reproduced and another "
        "is contradicted, <i>not reproduced</i> when the lead claim is contradicted, "
        "<i>inconclusive</i> when the lead claim could have been decided and was not (never "
        "\"not reproduced\", and other claims reproduced do not make it reproduced), <i>not "
        "yet testable at this budget</i> when the lead claim is underpowered or not run.")
#: The fewest replications a group at which a two-group rule can decide at all
#: (``verdict_core.one_mode``: below it every such claim is underpowered).
FEWEST_DECIDING = next(n for n in range(2, 100) if one_mode(n, n) <= verdicts.ALPHA)
#: The paper's generations per phase (III-D).
PAPER_GENERATIONS = 500


def answer(lead: str, others: Sequence[str]) -> str:
    """The answer of a phenomenon from the verdict of its lead claim, ``lead``, and those of
    its other claims, ``others`` (the rule of the module's text, ``RULE``)."""
    if lead == verdicts.REPRODUCED:
        return PARTLY if verdicts.CONTRADICTED in others else REPRODUCED
    return {verdicts.CONTRADICTED: NOT_REPRODUCED,
            verdicts.INCONCLUSIVE: INCONCLUSIVE}.get(lead, NOT_TESTABLE)


def _effect(row: dict) -> str:
    values = [math.nan if row[c] is None else row[c]
              for c in ("effect", "effect_low", "effect_high")]
    return (f"{scales.scale_of(row['claim'], row['kind']).symbol} = "
            f"{formatting.effect(*values)}")


def why(lead: dict | None, rows: pl.DataFrame) -> str:
    """The numbers behind a phenomenon's answer: its lead claim's verdict (``lead``, a
    findings row; None when the frame lacks it) with its effect and interval, or the sizes
    that could not decide, or why it was not run; then how its claims (``rows``, findings
    rows of one budget, the lead among them) came out."""
    if lead is None:
        said = "lead claim not in the findings"
    elif lead["verdict"] == verdicts.UNDERPOWERED:
        said = f"{lead['claim']}: underpowered, n = {lead['n']}"
    elif lead["verdict"] == verdicts.NOT_RUN:
        said = f"{lead['claim']}: not run ({lead['measured'].removeprefix('not run: ')})"
    else:
        said = f"{lead['claim']}: {lead['verdict']}, {_effect(lead)}"
    count = [(v, rows.filter(pl.col("verdict") == v).height) for v in verdicts.VERDICTS]
    tally = ", ".join(f"{k} {v}" for v, k in count if k)
    return f"{said}; of its {rows.height} claims {tally}"


def answers(by_budget: pl.DataFrame, phenomena: Sequence[Phenomenon] = PHENOMENA
            ) -> pl.DataFrame:
    """One row per phenomenon and budget (phenomena in order, then ``budgets.budgets``):
    budget (its label, ``budgets.labels``), phenomenon, section, claims (how many of its
    claims the frame has), the count of each verdict, answer (``ANSWERS``) and why.
    ``by_budget``: the frame of ``budgets.findings_by_budget``; only the paper's claims of its
    robots count."""
    head = findings.reading(by_budget)
    named = budgets.labels(budgets.budgets(by_budget))
    blocks = [(b, budgets.of_budget(head, b)) for b in named]
    out = []
    for p in phenomena:
        order = {c: i for i, c in enumerate(p.claims)}
        for b, block in blocks:
            rows = (block.filter(pl.col("claim").is_in(list(p.claims)))
                    .with_columns(pl.col("claim").replace_strict(order, return_dtype=pl.Int64)
                                  .alias("_order")).sort("_order").drop("_order"))
            if rows.height == 0:
                continue
            lead = (rows.row(0, named=True) if rows["claim"][0] == p.claims[0] else None)
            said = answer(lead["verdict"] if lead else verdicts.NOT_RUN,
                          rows["verdict"][0 if lead is None else 1:].to_list())
            out.append({"budget": named[b], "phenomenon": p.name, "section": p.section,
                        "claims": rows.height,
                        **{v: rows.filter(pl.col("verdict") == v).height
                           for v in verdicts.VERDICTS},
                        "answer": said, "why": why(lead, rows)})
    schema = {"budget": pl.Utf8, "phenomenon": pl.Utf8, "section": pl.Utf8, "claims": pl.Int64,
              **{v: pl.Int64 for v in verdicts.VERDICTS}, "answer": pl.Utf8, "why": pl.Utf8}
    return pl.DataFrame(out, schema=schema)


def _largest(by_budget: pl.DataFrame) -> pl.DataFrame:
    """The paper's claims of its robots at the frame's largest budget (generations per phase,
    then replications; one scene, one model: a frame saved before models were told apart
    has no ``model`` and is read as one)."""
    head = findings.reading(by_budget)
    keys = [c for c in ("generations_per_phase", "replications", "scene", "model")
            if c in head.columns]
    top = head.select(keys).unique().sort(keys).row(-1)
    return head.filter(*[pl.col(c) == v for c, v in zip(keys, top)])


def decided(by_budget: pl.DataFrame) -> tuple[int, int, int]:
    """At the frame's largest budget: how many of the paper's claims of its robots were
    decided (reproduced or contradicted), how many were underpowered, and how many were run."""
    rows = _largest(by_budget)
    run = rows.filter(pl.col("verdict") != verdicts.NOT_RUN)
    return (run.filter(pl.col("verdict").is_in(list(verdicts.DECIDED))).height,
            run.filter(pl.col("verdict") == verdicts.UNDERPOWERED).height, run.height)


def too_small(by_budget: pl.DataFrame) -> bool:
    """Whether the runs are too small to judge the paper: at their largest budget no claim
    decided, or most of the claims run underpowered."""
    yes, under, run = decided(by_budget)
    return yes == 0 or under > run / 2


@dataclass(frozen=True)
class Reference:
    """A run that can judge the paper: its directory, its budget (from its saved findings) and
    how many of the paper's claims of its robots they decide."""

    path: Path
    generations_per_phase: int
    replications: int
    decided: int
    claims: int


def reference_run(run_dirs: Sequence, least: int = 1) -> Reference | None:
    """Among the runs beside ``run_dirs`` (in their folders; themselves left out) whose saved
    findings (``findings.parquet``, the frame of ``budgets.findings_by_budget``) exist, the
    one that decides the most of the paper's claims of its robots at its largest budget (ties:
    more replications, then more generations), if it decides at least ``least``; else None.
    Unreadable findings are passed over."""
    given = {Path(d).resolve() for d in run_dirs}
    best = None
    for folder in dict.fromkeys(Path(d).resolve().parent for d in run_dirs):
        for d in sorted(folder.iterdir()):
            saved = d / "findings.parquet"
            if d in given or not (d / "manifest.json").is_file() or not saved.is_file():
                continue
            try:
                found = pl.read_parquet(saved)
                yes, _, _ = decided(found)
                gens, reps = _largest(found).select("generations_per_phase",
                                                     "replications").row(0)
                claims = _largest(found).height
            except (pl.exceptions.PolarsError, OSError, IndexError):
                continue
            candidate = Reference(d, int(gens), int(reps), yes, claims)
            key = (yes, reps, gens)
            if yes >= least and (best is None or key > (best.decided, best.replications,
                                                       best.generations_per_phase)):
                best = candidate
    return best


def _too_small_html(by_budget: pl.DataFrame, run_dirs: Sequence) -> str:
    yes, under, run = decided(by_budget)
    top = _largest(by_budget).row(0, named=True)
    reps, gens = top["replications"], top["generations_per_phase"]
    these = "These runs are" if len(run_dirs) > 1 else "This run is"
    need = (f": a comparison of two groups needs at least {FEWEST_DECIDING} replications a "
            "group before any data could decide it (the paper: 10)" if reps < FEWEST_DECIDING
            else "")
    text = (f"<p class='too-small'><b>{these} too small to test the paper.</b> At "
            f"{gens} generations per phase ({gens / PAPER_GENERATIONS:.0%} of the paper's "
            f"{PAPER_GENERATIONS}) and {reps} replications, {yes} of the {run} claims that "
            f"were run are decided and {under} are underpowered{need}. The answers below say "
            "what can and cannot be shown at this budget, not whether the paper holds.")
    ref = reference_run(run_dirs, least=yes + 1)
    if ref is not None:
        text += (f" The run <code>{html.escape(str(ref.path.name))}</code> beside it "
                 f"({ref.generations_per_phase} generations per phase, {ref.replications} "
                 f"replications) can: its saved findings decide {ref.decided} of its "
                 f"{ref.claims} claims; <code>dart-reach report "
                 f"{html.escape(os.path.relpath(ref.path))}</code> writes its report.")
    return text + "</p>"


def answers_html(by_budget: pl.DataFrame, run_dirs: Sequence = ()) -> str:
    """The report's first section: for a run too small to judge, a paragraph that says so
    (and names ``reference_run``); then one row per phenomenon and budget: the phenomenon
    and its section, the answer (its cell's class from ``ANSWERS``) and the number why."""
    table = answers(by_budget)
    several = table["budget"].n_unique() > 1
    small = too_small(by_budget) if table.height else True
    rows = []
    for r in table.iter_rows(named=True):
        budget = f"<td>{html.escape(r['budget'])}</td>" if several else ""
        rows.append(f"<tr><td>{html.escape(r['phenomenon'])}</td>"
                    f"<td>{html.escape(r['section'])}</td>{budget}"
                    f"<td class='{ANSWERS[r['answer']]}'>{html.escape(r['answer'])}</td>"
                    f"<td>{html.escape(r['why'])}</td></tr>")
    head = ("<tr><th>phenomenon of the paper</th><th>section</th>"
            + ("<th>budget</th>" if several else "") + "<th>answer</th><th>why</th></tr>")
    return (f"<div class='answers{' too-small' if small else ''}'>"
            + (_too_small_html(by_budget, run_dirs) if small and table.height else "")
            + "<p>Each phenomenon of the paper is answered from the verdicts of the claims "
              "that test it (the replication as the unit). " + RULE + " <i>Why</i>: the "
              "lead claim's verdict and its effect [nominally 95 % interval; θ's covers less "
              "away from 0.5, as the calibration measured] (θ: the chance that a replication "
              "of the claim's group b is higher than one of its group a, 0.5 for none; the "
              "forest's caption gives every scale), or the sizes that could not decide; then "
              "how all its claims came out.</p>"
            + f"<div class='scroll'><table class='answers'><thead>{head}</thead>"
              f"<tbody>{''.join(rows)}</tbody></table></div></div>")
