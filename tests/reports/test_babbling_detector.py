"""The babbling detector's page (``reports.babbling_detector``): its real trials are the
committed ones (the sample run again reproduces each trial's committed hand path and
babbling), every trial drawn is labelled, and the agreement it states is recomputed here
from the labels and the committed trials with plain polars."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import polars as pl
import pytest

from dart_reach.postevaluation.snapshots import load_development
from reports import babbling_detector as page
from reports import babbling_sample as sample
from reports.runs import FULL

ROOT = Path(__file__).resolve().parents[2]


def _committed() -> pl.DataFrame:
    """Each sampled trial's committed row (snapshot 250) beside its label."""
    paths = pl.read_parquet(ROOT / sample.SAMPLE)
    keys = paths.group_by("code").agg(pl.col("senses", "replication", "rank", "trial").first())
    dev = load_development(ROOT / "recordings" / FULL, senses=None).filter(
        pl.col("generation") == sample.GENERATION)
    return (keys.join(dev, on=["senses", "replication", "rank", "trial"])
            .join(pl.read_csv(ROOT / sample.LABELS), on="code", suffix="_label"))


def test_every_drawn_trial_is_labelled_and_is_the_committed_trial():
    paths = pl.read_parquet(ROOT / sample.SAMPLE)
    rows = _committed()
    assert rows.height == 2 * sample.PER_CONDITION == paths["code"].n_unique()
    assert sorted(rows["senses"].unique()) == sorted(sample.CONDITIONS)
    for code, committed in rows.select("code", "hand_path").iter_rows():
        hand = paths.filter(pl.col("code") == code).select("x", "y", "z").to_numpy()
        length = float(np.linalg.norm(np.diff(hand, axis=0), axis=1).sum())
        assert abs(length - committed) < 1e-6 * max(1.0, committed), code


def test_the_stated_agreement_is_the_labels_against_the_committed_babbling():
    rows = _committed().with_columns(pl.col("babbling_label").cast(pl.Boolean))
    table = page.agreement_rows(page.real_table(ROOT))
    for senses in (*sample.CONDITIONS, "both"):
        part = rows if senses == "both" else rows.filter(pl.col("senses") == senses)
        labelled = part.filter(pl.col("babbling_label"))
        found = int(labelled["babbling"].sum())
        still = part.filter(~pl.col("babbling_label"))
        correct = int((~still["babbling"]).sum())
        row = table.filter((pl.col("rule") == "babbling") & (pl.col("trials") == senses)).row(
            0, named=True)
        assert row["sensitivity"].startswith(f"{found}/{labelled.height} ")
        assert row["specificity"].startswith(f"{correct}/{still.height} ")


def test_the_pages_words_are_the_counts_of_the_labels_and_the_committed_babbling():
    rows = _committed().with_columns(pl.col("babbling_label", "moving").cast(pl.Boolean))
    real = page.real_table(ROOT)
    words = page.agreement_words(real)
    for senses in sample.CONDITIONS:
        labelled = rows.filter((pl.col("senses") == senses) & pl.col("babbling_label"))
        assert (f"{page.WHERE[senses]} it finds {int(labelled['babbling'].sum())} of the "
                f"{labelled.height} trials labelled babbling") in words
    wrong = rows.filter(~pl.col("babbling_label") & pl.col("babbling")).height
    assert f"It calls {wrong} trial{'' if wrong == 1 else 's'} babbling that the eye does not" \
        in words
    apart = int((rows["babbling_label"] != rows["moving"]).sum())
    assert f"The labels tell babbling from moving on {apart} of the 40 trials" in words
    # one trial's output otherwise: the words change with it
    first = real["code"][0]
    flipped = real.with_columns(pl.when(pl.col("code") == first)
                                .then(~pl.col("detector babbling"))
                                .otherwise(pl.col("detector babbling")).alias("detector babbling"))
    assert page.agreement_words(flipped) != words


def test_the_labellers_note_is_marked_and_tied_to_the_trials_it_describes():
    """The note names the committed misses (the labels against the committed babbling, plain
    polars) and is marked as the labeller's; a sample whose misses differ is refused."""
    rows = _committed().with_columns(pl.col("babbling_label").cast(pl.Boolean))
    missed = sorted(rows.filter(pl.col("babbling_label") & ~pl.col("babbling"))["code"])
    real = page.real_table(ROOT)
    note = page.labeller_note(real)
    assert note.startswith("The labeller's note") and "not a measure" in note
    assert f"({', '.join(missed)})" in note
    first = real.filter(pl.col("babbling") & pl.col("detector babbling"))["code"][0]
    flipped = real.with_columns(pl.when(pl.col("code") == first).then(False)
                                .otherwise(pl.col("detector babbling")).alias("detector babbling"))
    with pytest.raises(ValueError, match="rewrite reports.babbling_detector.NOTE"):
        page.labeller_note(flipped)


def test_the_synthetic_misses_are_counted_from_the_detector_not_stated():
    """Why the synthetic babbling paths are missed is the table's count of each failed test
    (a path may fail several), and the page says what the table says."""
    families = pl.DataFrame({"paths": [10, 10], "called babbling": [7, 10],
                             "missed: amplitude < 0.05 m": [2, 0], "missed: share < 0.4": [2, 0],
                             "missed: below 0.25 Hz": [0, 0]})
    assert page.misses(families) == ("3 missed: 2 with an RMS amplitude below 0.05 m, 2 with a "
                                      "rhythm share below 0.4")
    assert page.misses(families[1:]) == "none missed"
    syn = page.synthetic_table(per_family=20)
    babbling = syn.filter(pl.col("babbling by construction"))
    missed = int((babbling["paths"] - babbling["called babbling"]).sum())
    assert page.misses(babbling).startswith(f"{missed} missed" if missed else "none")
    text = " ".join((ROOT / "docs" / "results" / "babbling-detector.md").read_text().split())
    full = page.synthetic_table().filter(pl.col("babbling by construction"))
    interrupted = full.filter(pl.col("family").str.contains("interrupted"))
    assert page.misses(interrupted) in text
