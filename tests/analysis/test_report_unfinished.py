"""``dart-reach report`` of an unfinished run: a tiny real run stopped at
generation 2 of 3 of pre-reaching, its snapshots post-evaluated (``evaluate --development
--finished-only``) and judged in the report, which says at its top where the run stands; the
run is only read. Without a post-evaluated snapshot the report is refused in one line naming
the command that works on an unfinished run."""

from __future__ import annotations

import hashlib
import html
from pathlib import Path

import polars as pl
import pytest

from dart_reach.analysis import unfinished
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train

TINY = Settings(replications=2, trials=1, steps=4, seed=5)


def _hashes(directory: Path) -> dict:
    return {p.relative_to(directory): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(directory.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def stopped(tmp_path_factory) -> Path:
    """The standard condition at 3 generations per phase, stopped after pre-reaching's second
    (a snapshot after every generation): pre at 2 of 3, gross and fine not run."""
    out = tmp_path_factory.mktemp("unfinished") / "stopped"

    def stop_after_second(progress):
        if progress.done_generations == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        train([scaled(load_condition("standard"), 3)], TINY, out, workers=1,
              progress=stop_after_second, snapshot_every=1)
    return out


def test_an_unfinished_run_is_reported_from_its_snapshots(stopped, tmp_path, in_process):
    before = _hashes(stopped)
    refused = in_process("report", stopped, "--out", tmp_path / "r.html")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1, refused.stderr
    assert "--development 5 --development-sensors all --finished-only" in refused.stderr
    assert _hashes(stopped) == before and not (tmp_path / "r.html").exists()

    done = in_process("evaluate", stopped, "--development", "1", "--development-sensors",
                      "normal,no-ball", "--finished-only", "--workers", "1", "--record", "none")
    assert done.returncode == 0, done.stderr
    snapshots = unfinished.snapshot_trials(stopped)
    assert snapshots["generation"].unique().to_list() == [2]  # the latest, not generation 1
    assert snapshots["notation"].unique().to_list() == ["pre"]
    assert snapshots.height == 2 * 2 * 45  # replications x senses x positions

    before = _hashes(stopped)
    made = in_process("report", stopped, "--out", tmp_path / "r.html")
    assert made.returncode == 0, made.stderr
    assert _hashes(stopped) == before  # nothing in the run changed, nothing added
    text = html.unescape((tmp_path / "r.html").read_text())
    stands = ("stopped is unfinished: standard: pre at generation 2 of 3, gross, fine not run. "
              "Judged here in place of final populations: its latest post-evaluated snapshots, "
              "pre at generation 2 (2 robots of 2 replications; senses normal, no-ball)")
    assert stands in text
    assert text.index(stands) < text.index('id="answers"')  # at the top
    # the pre-reaching claims judged on the snapshot, the later phases' not run
    found = pl.read_parquet(_findings(stopped, tmp_path, in_process))
    assert found.filter(pl.col("verdict") != "not run").height > 0
    assert found.filter(pl.col("claim").str.contains("(?i)fine")
                        & (pl.col("verdict") != "not run")).height == 0


def _findings(run: Path, tmp_path: Path, in_process) -> Path:
    path = tmp_path / "findings.parquet"
    result = in_process("report", run, "--out", tmp_path / "again.html", "--findings", path)
    assert result.returncode == 0, result.stderr
    return path
