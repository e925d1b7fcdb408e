"""``dart-reach report``: one self-contained HTML file built from a tiny real run (the
standard condition and gross^, post-evaluated under every sensory condition with a random
baseline): every section, every figure embedded, a findings row per claim."""

from __future__ import annotations

import base64
import re
import subprocess
import sys

import pytest

from dart_reach import findings, report
from dart_reach.conditions import load_condition, scaled
from dart_reach.evaluation import SENSES, evaluate_run
from dart_reach.experiment import Settings, train


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "tiny"
    train([scaled(load_condition(c), 1) for c in ("standard", "gross-hat")],
          Settings(replications=2, trials=1, steps=6, seed=2), out, workers=1)
    evaluate_run(out, senses=SENSES, robots=2, workers=1, baseline=2)
    return out


def test_the_report_holds_every_section_figure_and_claim(tiny_run, tmp_path):
    path = report.build([tiny_run], tmp_path / "r.html")
    text = path.read_text()
    for anchor in ("findings", "provenance", "training", "baseline", "figures", "fig10",
                   "statistics"):
        assert f'<section id="{anchor}">' in text, anchor
    images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)
    # training, Figs. 5, 6, 7, 8 (paths and babbling), 9, Table I behaviours, 10 (the tiny
    # run keeps neither snapshots nor best-of-generation recordings: no development figures)
    assert len(images) == 9
    assert "Table I: the behaviours of each phase" in text
    assert "Development over generations" not in text
    assert all(base64.b64decode(i)[:8] == b"\x89PNG\r\n\x1a\n" for i in images)
    assert "not drawn" not in text
    assert "src=\"http" not in text and "<script" not in text  # nothing fetched: offline
    rows = re.findall(r'<tr class="[^"]+"><td>(F\d[^<]*)</td>(?:(?!</tr>).)*?'
                      r'<td class="verdict">([^<]+)', text)
    claims = [c for c, _ in rows]
    assert len(claims) == len(set(claims)) >= 30
    assert {v for _, v in rows} <= set(findings.VERDICTS)
    # the tiny run has what F5 needs (gross and gross^) but not F6's pre-h
    verdicts = dict(rows)
    assert verdicts["F5 gross &gt; gross^"] != findings.NOT_RUN
    assert verdicts["F6 pre vs pre-h"] == findings.NOT_RUN
    assert "random pre" in text and "git revision" in text


def test_cli_writes_the_report_and_never_overwrites_a_foreign_file(tiny_run, tmp_path):
    def cli(*args):
        return subprocess.run([sys.executable, "-m", "dart_reach.cli", "report", *args],
                              capture_output=True, text=True, timeout=300)

    r = cli(str(tiny_run))
    assert r.returncode == 0, r.stderr
    assert (tiny_run / "report.html").is_file() and str(tiny_run / "report.html") in r.stdout
    assert cli(str(tiny_run)).returncode == 0  # its own report is rebuilt
    foreign = tmp_path / "notes.html"
    foreign.write_text("<p>my notes</p>")
    r = cli(str(tiny_run), "--out", str(foreign))
    assert r.returncode == 2 and "not a dart_reach report" in r.stderr
    assert foreign.read_text() == "<p>my notes</p>"
    r = cli(str(tmp_path / "none"))
    assert r.returncode == 2 and "no such run directory" in r.stderr
    r = cli(str(tiny_run), "--out", str(tmp_path / "r.pdf"))
    assert r.returncode == 2 and ".html" in r.stderr


def test_report_reads_at_100_percent_and_states_its_corrections(tiny_run, tmp_path):
    import polars as pl

    from dart_reach.evaluation import run_phases

    text = report.build([tiny_run], tmp_path / "r.html").read_text()
    import html

    assert html.escape(report.TRAINING_NOTE) in text
    assert text.count(html.escape(report.HOLM_NOTE)) == 2  # Figs. 9 and 10
    assert "p_holm" in text
    stats = pl.read_parquet(tiny_run / "generations.parquet")
    summary = report.training_summary(stats, run_phases(tiny_run))
    phases = summary.select("condition", "phase").unique(maintain_order=True).rows()
    assert phases == [("standard", "pre"), ("standard", "gross"), ("standard", "fine"),
                      ("gross-hat", "gross-hat")]
    assert report.DPI >= 100
