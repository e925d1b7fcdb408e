"""``dart-reach report``: one self-contained HTML file built from a tiny real run (the
standard condition and gross^, post-evaluated under every sensory condition with a random
baseline): every section, every figure embedded, a findings row per claim; beside it a run of
the standard condition at another budget (2 generations per phase): the two budgets are judged
apart and set side by side."""

from __future__ import annotations

import base64
import html
import re
import shutil
import subprocess
import sys
from pathlib import Path

import polars as pl
from polars.testing import assert_frame_equal
import pytest

from dart_reach.analysis import (answers, budgets, counts, figures, findings, report, tables,
                                  verdicts)
from dart_reach.analysis.claims import CLAIMS
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.postevaluation.systematic import SENSES, evaluate_run
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train
from dart_reach.model.versions import CURRENT_MODEL_VERSION, model_version

ROOT = Path(__file__).resolve().parents[2]

#: the scene of the version new runs use, which the tiny runs here are trained under
NEW_SCENE = model_version(CURRENT_MODEL_VERSION).scene


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "tiny"
    train([scaled(load_condition(c), 1) for c in ("standard", "gross-hat")],
          Settings(replications=2, trials=1, steps=6, seed=2), out, workers=1)
    evaluate_run(out, senses=SENSES, robots=2, workers=1, baseline=2)
    return out


def _report_process(*args, cwd) -> subprocess.CompletedProcess:
    """``dart-reach report ARGS`` in a process of its own, in ``cwd``."""
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", "report", *map(str, args)],
                          capture_output=True, text=True, timeout=600, cwd=cwd)


@pytest.fixture(scope="module")
def built(tiny_run, tmp_path_factory) -> tuple[Path, subprocess.CompletedProcess]:
    """The report of ``tiny_run`` alone, built once by ``dart-reach report`` in a process of
    its own with every default (in the current directory, the folder returned), for the tests
    that read it and the test of the command."""
    cwd = tmp_path_factory.mktemp("built")
    return cwd, _report_process(tiny_run, cwd=cwd)


@pytest.fixture(scope="module")
def tiny_report(built) -> str:
    cwd, result = built
    assert result.returncode == 0, result.stderr
    return (cwd / "tiny-report.html").read_text()


@pytest.fixture(scope="module")
def other_budget(tmp_path_factory):
    """The standard condition at 2 generations per phase (``tiny_run``: 1), same scene."""
    out = tmp_path_factory.mktemp("report") / "tiny-2"
    train([scaled(load_condition("standard"), 2)],
          Settings(replications=2, trials=1, steps=6, seed=3), out, workers=1)
    evaluate_run(out, senses=SENSES, robots=2, workers=1, baseline=2)
    return out


def test_the_report_holds_every_section_figure_and_claim(tiny_report):
    text = tiny_report
    for anchor in ("findings", "provenance", "training", "baseline", "figures", "fig10",
                   "statistics"):
        assert f'<section id="{anchor}">' in text, anchor
    images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)
    # the summary's forest, training, Figs. 5, 6, 7, 8 (paths and babbling), 9, Table I
    # behaviours, 10 (the tiny run keeps neither snapshots nor best-of-generation recordings:
    # no development figures)
    assert len(images) == 10
    assert text.index('id="summary"') < text.index('id="findings"')
    assert "Table I: the behaviours of each phase" in text
    assert "Development over generations" not in text
    assert all(base64.b64decode(i)[:8] == b"\x89PNG\r\n\x1a\n" for i in images)
    assert "not drawn" not in text
    assert "src=\"http" not in text and "<script" not in text  # nothing fetched: offline
    rows = re.findall(r'<tr class="[^"]+"><td>(F\d[^<]*)</td>(?:(?!</tr>).)*?'
                      r'<td class="verdict">([^<]+)', text)
    claims = [c for c, _ in rows]
    assert len(claims) == len(set(claims)) >= 30
    assert {v for _, v in rows} <= set(verdicts.VERDICTS)
    # the tiny run has what F5 needs (gross and gross^) but not F6's pre-h
    by_claim = dict(rows)
    assert by_claim["F5 gross &gt; gross^"] != verdicts.NOT_RUN
    assert by_claim["F6 pre not better than pre-h"] == verdicts.NOT_RUN
    assert "random pre" in text and "git revision" in text
    # one budget: its findings as ever, no comparison of budgets
    assert "findings budgets" not in text and "as the budget grows" not in text
    assert html.escape(report.BUDGET_FIGURE_NOTE) not in text


def test_the_report_opens_on_its_answers_and_reads_on_a_phone(tiny_report):
    """A run of 2 replications decides nothing: the first section says so, every phenomenon
    "not yet testable"; the forest's caption says what its scale is; the page has a viewport
    and every table scrolls in its own box instead of widening the page."""
    text = tiny_report
    assert '<meta name="viewport" content="width=device-width, initial-scale=1">' in text
    sections = re.findall(r'<section id="([^"]+)">', text)
    assert sections[:2] == ["answers", "summary"]
    first = text[text.index('<section id="answers">'):text.index('<section id="summary">')]
    assert "class='answers too-small'" in first and "too small to test the paper" in first
    cells = re.findall(r"<td class='(\w+)'>([^<]+)</td>", first)
    assert len(cells) == len(answers.PHENOMENA)
    assert set(cells) == {("untestable", answers.NOT_TESTABLE)}
    summary = text[text.index('<section id="summary">'):text.index('<section id="findings">')]
    assert "<b>The scale</b>" in summary and "divided by the largest" in summary
    assert "Labels that read against the axis" in summary
    assert "better means a lower speed" in summary  # F3 speed not better, drawn at this run
    assert text.count("<table") == text.count('<div class="scroll"><table') \
        + text.count("<div class='scroll'><table") > 10


def test_cli_writes_the_report_and_never_overwrites_a_foreign_file(tiny_run, built, tmp_path,
                                                                  in_process):
    """The build is ``built``'s, which the other tests read; a report of ours is built over
    in test_a_report_of_two_budgets_sets_them_side_by_side. The refusals here come before
    any build."""
    def process(*args):
        return _report_process(*args, cwd=tmp_path)

    def cli(*args):  # the rest in this process: the same command, without a process's imports
        return in_process("report", *args, cwd=tmp_path)

    cwd, r = built  # by default in the current directory, never in the run
    assert r.returncode == 0, r.stderr
    assert (cwd / "tiny-report.html").is_file() and "tiny-report.html" in r.stdout
    assert not (tiny_run / "report.html").exists()
    for inside in ("--out", "--findings"):
        name = "r.html" if inside == "--out" else "f.parquet"
        r = cli(str(tiny_run), inside, str(tiny_run / "phases" / name))
        assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
        assert "inside the run" in r.stderr and inside in r.stderr
        assert not (tiny_run / "phases" / name).exists()
    foreign = tmp_path / "notes.html"
    foreign.write_text("<p>my notes</p>")
    r = process(str(tiny_run), "--out", str(foreign))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    assert "not a dart_reach report" in r.stderr
    assert foreign.read_text() == "<p>my notes</p>"
    r = cli(str(tmp_path / "none"))
    assert r.returncode == 2 and "no such run directory" in r.stderr
    r = cli(str(tiny_run), "--out", str(tmp_path / "r.pdf"))
    assert r.returncode == 2 and ".html" in r.stderr
    r = cli(str(tiny_run), "--findings", str(foreign))
    assert r.returncode == 2 and "give a name ending in .parquet" in r.stderr
    mine = tmp_path / "mine.parquet"
    mine.write_bytes(b"my table")
    r = cli(str(tiny_run), "--findings", str(mine))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "mine.parquet exists" in r.stderr
    assert foreign.read_text() == "<p>my notes</p>" and mine.read_bytes() == b"my table"


def _contents(directory: Path) -> dict:
    """Every file and folder under ``directory`` with its bytes (folders: None)."""
    return {p.relative_to(directory): (p.read_bytes() if p.is_file() else None)
            for p in sorted(directory.rglob("*"))}


def test_the_report_leaves_the_runs_it_reads_untouched(tmp_path):
    """Committed results hold no recording: the trials of Figs. 6 and 8 are recorded again,
    beside the report, never in the run (byte for byte the same after the report)."""
    run = tmp_path / "runs" / "near"
    shutil.copytree(ROOT / "recordings" / "scene-study" / "near", run)
    before = _contents(run)
    (tmp_path / "out").mkdir()
    r = subprocess.run([sys.executable, "-m", "dart_reach.cli", "report", str(run)],
                       capture_output=True, text=True, timeout=600, cwd=tmp_path / "out")
    assert r.returncode == 0, r.stderr
    assert _contents(run) == before  # every file's bytes (so its hash) unchanged, none added
    made = sorted((tmp_path / "out" / "near-report-recordings" / "near").rglob("*.rrd"))
    assert made and all(p.stat().st_size > 0 for p in made)
    # and says so: the folder beside the report, its trials, those recorded by this build
    assert (f"near-report-recordings/ holds the {len(made)} trials" in r.stdout
            and f"{len(made)} recorded now" in r.stdout), r.stdout
    assert (tmp_path / "out" / "near-report-recordings" / "near" / "evaluation"
            / "trial.rbl").is_file()
    text = (tmp_path / "out" / "near-report.html").read_text()
    assert "Fig. 8" in text and "no recording" not in text
    assert report.recordings_dir(tmp_path / "r.html", [run, tmp_path / "near"]) == {
        run: tmp_path / "r-recordings" / "near-0",
        tmp_path / "near": tmp_path / "r-recordings" / "near-1"}
    help_text = subprocess.run([sys.executable, "-m", "dart_reach.cli", "report", "--help"],
                               capture_output=True, text=True).stdout
    assert "The runs are only read" in " ".join(help_text.split())


def test_report_reads_at_100_percent_and_states_its_corrections(tiny_run, tiny_report):
    from dart_reach.postevaluation.systematic import run_phases

    text = tiny_report
    assert html.escape(report.TRAINING_NOTE) in text
    assert text.count(html.escape(report.HOLM_NOTE)) == 2  # Figs. 9 and 10
    assert "p_holm" in text
    stats = pl.read_parquet(tiny_run / "generations.parquet")
    summary = report.training_summary(stats, run_phases(tiny_run))
    phases = summary.select("condition", "phase").unique(maintain_order=True).rows()
    assert phases == [("standard", "pre"), ("standard", "gross"), ("standard", "fine"),
                      ("gross-hat", "gross-hat")]
    assert report.DPI >= 100


def _alone(run_dirs) -> pl.DataFrame:
    """The findings of runs pooled, as ``report.build`` judged every run given before budgets
    were told apart."""
    from dart_reach.postevaluation.snapshots import load_development
    from dart_reach.postevaluation.systematic import load_evaluation

    baseline = pl.concat([load_evaluation(d, baseline=True).with_columns(
        pl.lit(d.name).alias("run")) for d in run_dirs], how="diagonal_relaxed")
    developments = [dev for d in run_dirs if (dev := load_development(d)) is not None]
    return findings.findings(tables.load_runs(run_dirs), baseline,
                             development=pl.concat(developments) if developments else None)


def _same(a: pl.DataFrame, b: pl.DataFrame) -> bool:
    """Equal to the last bit, except the sign of a zero (a median of differences can be -0.0
    in one computation and 0.0 in another)."""
    def canonical(df: pl.DataFrame) -> pl.DataFrame:
        return df.select(sorted(b.columns)).with_columns(pl.col(pl.Float64) + 0.0)
    try:  # NaN equals NaN here (a claim not run has a NaN effect in both)
        assert_frame_equal(canonical(a), canonical(b), check_exact=True)
    except AssertionError:
        return False
    return True


def test_budgets_are_never_pooled_and_runs_of_one_budget_are(tiny_run, other_budget, tmp_path):
    by_budget = budgets.findings_by_budget([other_budget, tiny_run])
    assert by_budget.select("generations_per_phase", "runs").unique(maintain_order=True).rows() \
        == [(1, "tiny"), (2, "tiny-2")]
    assert set(by_budget["scene"]) == {NEW_SCENE}
    for gens, run in ((1, tiny_run), (2, other_budget)):
        block = by_budget.filter(pl.col("generations_per_phase") == gens)
        assert block.height == len(CLAIMS)
        assert _same(block.drop(budgets.KEY_COLUMNS), _alone([run]))
    # the same data, the same findings to the last bit, every time (group orders, bootstrap
    # draws): this caught sums over polars groups taken in a random order
    for _ in range(4):
        assert _same(budgets.findings_by_budget([other_budget, tiny_run]), by_budget)
    # pooling both would have judged other samples (the test can fail)
    both = _alone([tiny_run, other_budget])
    assert both["n"].to_list() != by_budget.filter(
        pl.col("generations_per_phase") == 1)["n"].to_list()
    # a copy of a run is a second run of the same budget: pooled with it
    twin = tmp_path / "tiny-twin"
    shutil.copytree(tiny_run, twin, ignore=shutil.ignore_patterns("*.rrd", "report.html"))
    pooled = budgets.findings_by_budget([tiny_run, twin])
    assert pooled["runs"].unique().to_list() == ["tiny, tiny-twin"]
    assert _same(pooled.drop(budgets.KEY_COLUMNS), _alone([tiny_run, twin]))


def test_a_report_of_two_budgets_sets_them_side_by_side(tiny_run, other_budget, built,
                                                        tmp_path):
    # built over a report of ours (the tiny run's): a report is rebuilt where one was
    shutil.copy(built[0] / "tiny-report.html", tmp_path / "r.html")
    text = report.build([tiny_run, other_budget], tmp_path / "r.html",
                        findings_out=tmp_path / "found.parquet").read_text()
    assert text != (built[0] / "tiny-report.html").read_text()
    # the findings as data: the frame the table is drawn from, every claim at both budgets
    found_data = pl.read_parquet(tmp_path / "found.parquet")
    assert _same(found_data, budgets.findings_by_budget([tiny_run, other_budget]))
    assert found_data.group_by("generations_per_phase").len().sort(
        "generations_per_phase").rows() == [(1, len(CLAIMS)), (2, len(CLAIMS))]
    with pytest.raises(ValueError, match="found.parquet' exists"):
        report.build([tiny_run], tmp_path / "r2.html", findings_out=tmp_path / "found.parquet")
    assert not (tmp_path / "r2.html").exists()
    start, end = text.index('<section id="findings">'), text.index('<section id="provenance">')
    found = text[start:end]
    table = re.search(r'<table class="findings budgets">.*?</table>', found).group(0)
    head = re.findall(r"<th>([^<]*)</th>", table.split("</thead>")[0])
    assert head == ["claim", "kind", *[f"{g} gen/phase: {c}" for g in (1, 2)
                                       for c in ("effect [CI]", "verdict", "robots as units")],
                    budgets.MOVEMENT_COLUMN]
    rows = re.findall(r"<tr><td>([^<]*)</td>", table)
    assert len(rows) == len(CLAIMS) == len(set(rows))
    moves = re.findall(r"<td>([^<]*)</td></tr>", table)  # no colour: it states no result
    assert len(moves) == len(CLAIMS) and set(moves) <= set(budgets.MOVEMENTS)
    # the figure of the effects against the budget, then each budget's own table
    assert re.search(r'<img alt="figure" src="data:image/png;base64,[A-Za-z0-9+/=]+">'
                     + re.escape(f"<p>{html.escape(report.BUDGET_FIGURE_NOTE)}</p>"), found)
    assert found.count('<table class="findings">') == 2
    assert f"<h3>{NEW_SCENE}, 1 generation per phase, 2 replications: tiny</h3>" in found
    assert f"<h3>{NEW_SCENE}, 2 generations per phase, 2 replications: tiny-2</h3>" in found
    assert "scenes" not in found.split("<table")[0]  # one scene: no notice
    # Fig. 10 per budget, never pooled: each budget's own heading and its own figure or reason
    fig10 = text.split('<section id="fig10">')[1].split("</section>")[0]
    assert fig10.count("<h3>") == 2
    for gens in ("1 generation", "2 generations"):
        assert f"<h3>{NEW_SCENE}, {gens} per phase, 2 replications</h3>" in fig10


def test_the_summary_opens_on_the_counts_per_budget_then_a_forest_by_section():
    """The first screen: the paper's claims by verdict at each budget (totals that add up,
    the project's own claims apart), by section folded, then the forest: one panel per
    section, labels of 10 points, a marker for every claim that was run (one without an
    interval in its own column), the claims no budget ran left out and listed."""
    nan = float("nan")
    rows = [{"scene": "s", "generations_per_phase": g, "replications": 4, "model": "v1",
             "runs": f"r{g}",
             "sign": 1, "claim": c, "section": sec, "kind": kind, "own": own, "effect": e,
             "effect_low": e - 0.1 if kind == "directional" else nan,
             "effect_high": e + 0.1 if kind == "directional" else nan, "verdict": v,
             "p_holm": ph, "p_holm_against": 1.0, "note": ""}
            for g in (10, 50)
            for c, sec, kind, own, e, v, ph in (
                ("a", "IV-A-2, Fig. 5", "directional", False, 0.3, verdicts.REPRODUCED, 0.01),
                ("b", "IV-A-2, Fig. 6", "directional", False, 0.3, verdicts.REPRODUCED, 0.2),
                ("c", "IV-C: controls", "directional", False, 0.0, verdicts.INCONCLUSIVE, 0.9),
                ("w", "IV-B, Fig. 9", "senses differ", False, 0.9, verdicts.REPRODUCED,
                 0.01),
                ("gone", "IV-C", "directional", False, nan, verdicts.NOT_RUN, nan),
                ("d", "IV-A-2", "directional", True, 0.5, verdicts.REPRODUCED, nan))]
    frame = pl.DataFrame(rows)
    by_section = counts.section_counts(frame)
    row = by_section.filter((pl.col("section") == "IV-A-2")
                            & (pl.col("budget") == "10 gen/phase")).row(0, named=True)
    assert row["claims"] == 2 and row[verdicts.REPRODUCED] == 2
    assert row["decided after Holm"] == 1
    assert by_section["claims"].sum() == 10  # the project's own claim is not counted
    answer = counts.budget_counts(frame)
    assert answer["budget"].to_list() == ["10 gen/phase x 4 replications",
                                          "50 gen/phase x 4 replications"]
    assert answer["runs"].to_list() == ["r10", "r50"] and (answer["claims"] == 5).all()
    assert (answer.select(list(verdicts.VERDICTS)).sum_horizontal() == answer["claims"]).all()
    assert answer[verdicts.NOT_RUN].to_list() == [1, 1]
    assert counts.never_run(frame)["claim"].to_list() == ["gone"]

    text = report.summary_html(frame)
    assert text.count("<img") == 1 and "directional" in text
    assert text.index("counts answer") < text.index("<img")  # the answer first
    assert "1 claims not run at any budget" in text and "<td>gone</td>" in text

    fig = figures.forest_figure(frame)
    fig.canvas.draw()
    panels = {ax.get_title(loc="left"): [t.get_text() for t in ax.get_yticklabels()]
              for ax in fig.axes}
    assert panels == {"IV-A-2": ["a", "b"], "IV-C": ["c"], "IV-B": ["w"]}
    sizes = [t.get_fontsize() for ax in fig.axes
             for t in ax.get_yticklabels() + ax.get_xticklabels()]
    assert min(sizes) >= 10
    for ax in fig.axes:  # one marker per budget for every claim that was run
        markers = [line for line in ax.get_lines() if line.get_marker() not in ("None", "")]
        assert len(markers) == 2 * len(panels[ax.get_title(loc="left")])
    w = next(ax for ax in fig.axes if ax.get_title(loc="left") == "IV-B")
    xs = {float(line.get_xdata()[0]) for line in w.get_lines() if line.get_marker() != "None"}
    assert xs == {figures.forest.NO_INTERVAL_X}  # Kendall's W: no interval, still a marker


def test_a_replication_is_the_mean_of_its_robots_means():
    """report.replication_table: per replication of the phase asked, normal senses only, the
    mean over robots of each robot's mean over its trials (not the mean over all trials)."""
    rows = []
    for replication, rank, trials, reached in ((0, 0, 1, [True]), (0, 1, 3, [False] * 3),
                                               (1, 0, 2, [True, False])):
        for t in range(trials):
            rows.append({"phase": "pre", "senses": "normal", "replication": replication,
                         "rank": rank, "fitness": 0.1 * (t + 1), "reached": reached[t],
                         "babbling": False, "hand_path": 2.0 * replication})
    noise = [dict(r, senses="nothing", fitness=9.0) for r in rows] + \
            [dict(r, phase="gross", fitness=9.0) for r in rows]
    table = report.replication_table(pl.DataFrame(rows + noise), "pre")
    assert table["replication"].to_list() == [0, 1]
    assert table["robots"].to_list() == [2, 1]
    assert table["reach rate"].to_list() == [0.5, 0.5]  # robots 1 and 0; trials would give 0.25
    assert table["fitness"].to_list() == pytest.approx([(0.1 + 0.2) / 2, 0.15])
    assert table["hand path (m)"].to_list() == [0.0, 2.0]
    assert table["babbling rate"].to_list() == [0.0, 0.0]
