"""The results docs are their templates rendered from the committed results
(``reports.results``, ``make results``): a committed doc that differs from its
rendering fails here, and so does a doc whose data change."""

from __future__ import annotations

import re
import shutil
import tomllib
from pathlib import Path

import polars as pl
import pytest

from dart_reach.analysis import findings
from dart_reach.analysis.budgets import Budget
from dart_reach.postevaluation import results
from reports import pre_reaching_course
from reports import results as results_docs
from reports import scene_study
from reports.runs import TEN

ROOT = Path(__file__).resolve().parents[2]


def test_every_committed_results_doc_is_its_rendering():
    docs = results_docs.generate(ROOT)
    assert {ROOT / "docs/results/scene-study.md", ROOT / "docs/results/replication.md",
            ROOT / "docs/results/stillness.md", ROOT / "docs/results/pre-reaching-course.md",
            ROOT / "docs/results/summary.md", ROOT / "docs/results/benchmarks.md"} <= set(docs)
    stale = [str(p.relative_to(ROOT)) for p, text in docs.items()
             if p.read_text(encoding="utf-8") != text]
    assert not stale, f"run 'make results': {stale} differ from their rendering"
    for path, frame in results_docs.findings_frames(ROOT).items():
        stored = pl.read_parquet(path)
        assert stored.schema == frame.schema and stored.equals(frame), \
            f"run 'make results': {path.relative_to(ROOT)} differs from the findings"


def test_a_change_in_the_data_changes_the_doc(tmp_path, capsys):
    """The same check on a copy whose results say something else fails: a robot of `near`
    that reached nothing."""
    shutil.copytree(ROOT / "docs/results/templates", tmp_path / results_docs.TEMPLATES)
    shutil.copytree(ROOT / "recordings", tmp_path / "recordings",
                    ignore=shutil.ignore_patterns("*.rrd", ".lock"))
    for page in results_docs.PARTS:
        (tmp_path / page).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / page, tmp_path / page)
    table_path = tmp_path / "recordings/scene-study/near" / results.EVALUATION
    table = results.read_table(table_path)
    changed = table.with_columns(pl.when((pl.col("replication") == 0) & (pl.col("rank") == 0))
                                 .then(False).otherwise(pl.col("reached")).alias("reached"))
    assert not changed.equals(table)
    results.write_table(table_path, changed, results.sessions(table_path))
    for name in ("scene-study.md", "scene-study/scene-study.md"):
        target = tmp_path / results_docs.OUT / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / results_docs.OUT / name, target)
    assert results_docs.main([str(tmp_path), "--check"]) == 1
    assert "scene-study.md: differs from its rendering" in capsys.readouterr().err
    assert results_docs.main([str(tmp_path)]) == 0  # writes the new rendering
    assert (tmp_path / results_docs.OUT / "scene-study.md").read_text() != (
        ROOT / results_docs.OUT / "scene-study.md").read_text()
    assert results_docs.main([str(tmp_path), "--check"]) == 0
    for name, draw in (("pre-reaching-course.png", pre_reaching_course.figure),
                       ("pre-reaching-training.png", pre_reaching_course.training_figure)):
        figure = tmp_path / results_docs.OUT / name  # written beside the docs
        assert figure.read_bytes() == draw(tmp_path / "recordings")
        assert figure.read_bytes().startswith(b"\x89PNG")


def test_a_placeholder_without_a_value_is_named():
    assert results_docs.render("a {{ x }} b {{y.z}}", {"x": "1", "y.z": "2"}) == "a 1 b 2"
    with pytest.raises(KeyError, match="doc: no value for missing, other"):
        results_docs.render("{{ missing }} {{ x }} {{ other }}", {"x": "1"}, "doc")
    assert scene_study.cell(0.5, "reached") == "50 %"
    assert scene_study.cell(0.012345) == "0.0123"
    assert scene_study.cell(float("nan")) == "–"


def test_what_ten_replications_decided_is_counted_and_listed():
    """The paper's claims only; every outcome counted (zeros shown); changed verdicts listed."""
    def rows(replications, verdicts_, own=False):
        return [{"scene": "s", "generations_per_phase": 50, "replications": replications,
                 "model": "v1", "claim": c, "verdict": v, "own": own}
                for c, v in verdicts_.items()]
    few = {"A": "inconclusive", "B": "underpowered", "C": "reproduced"}
    many = {"A": "reproduced", "B": "inconclusive", "C": "reproduced"}
    frame = pl.DataFrame(rows(4, few) + rows(10, many) + rows(4, {"own": "inconclusive"}, True)
                         + rows(10, {"own": "reproduced"}, True))
    text = results_docs.replications_text(frame)
    assert "| decided | 1 |" in text and "| still open | 1 |" in text
    assert "| the same | 1 |" in text and "| reversed | 0 |" in text
    assert "| A | 50 | 4 | inconclusive | 10 | reproduced | decided |" in text
    assert "| claim | generations per phase | replications | verdict | more replications |" in text
    assert "own" not in text.split("Where the verdict changed")[1]
    assert "Not yet" in results_docs.replications_text(pl.DataFrame(rows(4, few)))


def test_the_plain_words_name_every_claim_by_its_verdict():
    """The paper's claims only, each named under its verdict once; a decided one with what was
    measured and whether it survives Holm; a run not judged yet says so."""
    verdict = {"A": "reproduced", "B": "contradicted", "C": "inconclusive", "D": "underpowered",
               "E": "not run", "F": "reproduced", "G": "not run"}
    measured = {"G": findings.UNTESTABLE + "the same by construction"}
    frame = pl.DataFrame([{"runs": "ten", "generations_per_phase": 50, "replications": 10,
                           "claim": c, "verdict": v, "own": False,
                           "measured": measured.get(c, f"m{c}"),
                           "p_holm": 0.01 if c == "A" else 0.2, "p_holm_against": 0.2}
                          for c, v in verdict.items()]
                         + [{"runs": "ten", "generations_per_phase": 50, "replications": 10,
                             "claim": "OWN", "verdict": "reproduced", "own": True,
                             "measured": "x", "p_holm": 0.01, "p_holm_against": 0.2}])
    values = results_docs.plain_values(frame, "ten")
    text = values["plain"]
    assert text.startswith("Of the paper's 7 claims, at 50 generations per phase with 10 "
                           "replications (`ten`):")
    assert ("- **reproduced: 2** (1 after Holm):\n  - A — mA (survives Holm)\n  - F — mF\n"
            in text)
    assert "- **contradicted: 1** (0 after Holm):\n  - B — mB\n" in text
    assert "- **undecided: 2** (1 inconclusive, 1 underpowered): C; D." in text
    assert "- **not run: 1** (no data for them at this budget): E." in text
    assert "- **cannot be tested with its measure: G** — the same by construction." in text
    assert ("1 were not run (no data for them) and 1 cannot be tested with their measure (G)."
            in values["plain_names"])
    assert "OWN" not in text and "OWN" not in values["plain_names"]
    assert "reproduced 2 of the paper's claims (A; F), contradicted 1 (B)" in values["plain_names"]
    assert "Not yet" in results_docs.plain_values(
        frame.with_columns(pl.lit("not run").alias("verdict")), "ten")["plain"]


def test_the_summary_shows_the_verdicts_as_a_small_table_and_says_what_they_mean():
    """The summary's results: one row per budget linking to every claim, the codes, Holm and
    underpowered against inconclusive explained, no claim named in the table's notes."""
    text = (ROOT / results_docs.OUT / "summary.md").read_text(encoding="utf-8")
    part = text.split("## The paper's own budget")[0]
    rows = [line for line in part.splitlines() if line.startswith("| [`")]
    assert rows and all(f"]({results_docs.CLAIMS_LINK})" in row for row in rows)
    assert (ROOT / results_docs.OUT / results_docs.CLAIMS_LINK.split("#")[0]).is_file()
    assert "## Every claim at every budget" in (ROOT / "docs/results/replication.md").read_text()
    for words in ("Claim codes", "Holm's method", "Underpowered or inconclusive"):
        assert words in part, words
    # the calibration's numbers it states, recounted from the committed table
    table = pl.read_parquet(ROOT / "recordings" / "calibration" / "calibration.parquet")
    bounded = table.filter(pl.col("kind").is_in(["at most", "at least"]))
    assert (f"{int(bounded['ok'].sum())} of the {bounded.height} bounded rows"
            in " ".join(part.split()))
    worst = table.filter(pl.col("kind") == "at most")["value"].max()
    assert f"under a null is {worst:.3f}" in part
    notes = part.split("- **Claim codes:**")[1].split("\n\n")[0]
    assert "reach up" not in notes and "F4 senses differ" not in notes


def test_the_readme_is_a_front_door_not_a_progress_board():
    """The README answers in words and links the summary, where the numbers and the training's
    progress live: no generated block, no generation of a run still training, short."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 150
    assert "<!-- results" not in text and "generated by `make results`" not in text
    assert "(docs/results/summary.md)" in text
    assert "at generation" not in text
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]
    assert "gym" in extras
    assert all(f'".[{extra}]"' in text for extra in extras), "every extra in the install"


def test_the_replication_pages_named_verdicts_are_the_committed_findings():
    """The replication page's prose names F1 babbling's and F2 swipes again's verdicts and the
    contradicted claims at ten replications: recomputed from the committed findings (a claim
    renamed fails here, not silently "not run")."""
    frame = pl.read_parquet(ROOT / "recordings" / TEN / "findings.parquet")
    values = results_docs.plain_values(frame)
    rows = findings.reading(frame)
    verdict = dict(zip(rows["claim"], rows["verdict"]))
    for key, claim in results_docs.NAMED.items():
        assert values[f"plain.{key}"] == verdict[claim]
    against = rows.filter(pl.col("verdict") == "contradicted")
    assert values["plain_against"] == f"{against.height}: " + "; ".join(
        f"{c} ({m})" for c, m in zip(against["claim"], against["measured"]))
    page = " ".join((ROOT / results_docs.OUT / "replication.md").read_text().split())
    assert f"F1 babbling is {verdict['F1 babbling']}." in page
    assert f"is {verdict['F2 swipes again']} at ten replications" in page
    assert values["plain_against"] in page


def test_the_readmes_counts_are_the_committed_findings():
    """The README's sentence on what ten replications reproduced and contradicted carries the
    counts of the committed findings of `replication-50x10` (the paper's claims of its
    robots, raw and after Holm): a count out of date fails."""
    text = " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())
    found = re.search(r"(\d+) of the paper's (\d+) claims about its robots are reproduced and "
                      r"(\d+) contradicted \((\d+) and (\d+) after Holm's adjustment\)", text)
    assert found, "the README's counts sentence"
    frame = pl.read_parquet(ROOT / "recordings" / TEN / "findings.parquet")
    count = findings.summary(frame)
    assert tuple(map(int, found.groups())) == (
        count["reproduced"], findings.reading(frame).height, count["contradicted"],
        count["reproduced (Holm)"], count["contradicted (Holm)"])


def test_a_budgets_row_counts_each_verdict():
    budget = Budget("s", 50, 10, "v1")
    paper = {"runs": "r", "reproduced": 23, "reproduced (Holm)": 11, "contradicted": 3,
             "contradicted (Holm)": 1, "inconclusive": 30, "underpowered": 0, "not run": 28,
             "cannot be tested": 2}
    assert results_docs.summary_row(paper, budget) == {
        "run": f"[`r`]({results_docs.CLAIMS_LINK})",
        "generations per phase x replications": "50 x 10",
        "reproduced": "23 (11 after Holm)", "contradicted": "3 (1 after Holm)",
        "inconclusive": "30", "underpowered": "0", "not run": "28", "cannot be tested": "2"}
