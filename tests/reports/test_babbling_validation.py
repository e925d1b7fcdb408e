"""The second and third validations of the babbling measures (``reports.babbling_validation``):
each sample is the draw its protocol describes (the second's trials are the committed ones;
the third's were never measured), every trial is labelled, the page's counts are the labels
against the measures recomputed here, and the acceptance rule says what it was written to
say."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import polars as pl
import pytest
from scipy.stats import beta

from dart_reach.measures import kinematics as k
from dart_reach.postevaluation.snapshots import load_development
from reports import babbling_sample as first
from reports import babbling_second_sample as second
from reports import babbling_third_sample as third
from reports import babbling_validation as page
from reports.runs import FULL, JUDGED

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def trials() -> pl.DataFrame:
    return page.trials(ROOT)


@pytest.fixture(scope="module")
def paths() -> pl.DataFrame:
    return pl.read_parquet(ROOT / second.SAMPLE)


def test_the_sample_is_one_trial_per_condition_generation_and_replication(paths):
    keys = paths.group_by("code").agg(pl.col("senses", "generation", "replication", "rank",
                                             "trial").first())
    assert keys.height == 100
    assert keys.select("senses", "generation", "replication").n_unique() == 100
    assert set(keys["generation"]) == set(JUDGED)
    # the draw, made again, is the committed sample, codes and all
    old = pl.read_parquet(ROOT / first.SAMPLE).select("senses", "replication", "rank",
                                                      "trial").unique()
    drawn = second.draw(ROOT / "recordings" / FULL, old)
    assert drawn.select("code", "senses", "generation", "replication", "rank", "trial").sort(
        "code").equals(keys.select(drawn.columns[-1], "senses", "generation", "replication",
                                   "rank", "trial").sort("code"))
    # no normal trial of the first sample again
    again = keys.filter((pl.col("generation") == first.GENERATION)
                        & (pl.col("senses") == "normal")).join(
        old.filter(pl.col("senses") == "normal"), on=["replication", "rank", "trial"])
    assert again.height == 0


def test_each_trial_run_again_is_the_committed_trial(paths):
    dev = load_development(ROOT / "recordings" / FULL, senses=None).filter(
        pl.col("generation").is_in(JUDGED))
    for code, part in paths.group_by("code"):
        row = part.row(0, named=True)
        committed = dev.filter((pl.col("generation") == row["generation"])
                               & (pl.col("senses") == row["senses"])
                               & (pl.col("replication") == row["replication"])
                               & (pl.col("rank") == row["rank"])
                               & (pl.col("trial") == row["trial"])).row(0, named=True)
        hand = part.sort("step").select("x", "y", "z").to_numpy()
        assert k.path_length(hand) == pytest.approx(committed["hand_path"], rel=1e-6), code
        touched = part.sort("step")["touched"].to_numpy()
        touch = np.argmax(touched) * k.DT if touched.any() else float("nan")
        assert np.isnan(touch) == np.isnan(committed["first_touch_s"]), code
        if touched.any():
            assert touch == pytest.approx(committed["first_touch_s"]), code
        if row["senses"] == "no-ball":
            assert not touched.any()


def test_every_trial_is_labelled_apart_for_babbling_and_moving(trials):
    assert trials.height == 100
    assert set(trials["babbling"]) <= {page.YES, page.NO, page.UNSURE}
    assert set(trials["moving"]) <= {page.YES, page.NO, page.UNSURE}
    # a trial labelled babbling is labelled moving (the protocol's definitions)
    assert trials.filter((pl.col("babbling") == page.YES) & (pl.col("moving") != page.YES)
                         ).height == 0


def _before_touch_by_hand(part: pl.DataFrame) -> bool:
    """The candidate written out again from its definition: the detector on rows
    0 .. max(first touch, 100) - 1, the whole trial without a touch."""
    part = part.sort("step")
    touched = part["touched"].to_numpy()
    rows = max(int(np.argmax(touched)), 100) if touched.any() else part.height
    hand = part.select("x", "y", "z").to_numpy()[:rows]
    f, share = k.hand_periodicity(hand)
    return bool(share >= 0.4 and f >= 0.25 and k.hand_amplitude(hand) >= 0.05)


def test_the_pages_counts_are_the_labels_against_the_measures(trials, paths):
    by_hand = {code: _before_touch_by_hand(part) for (code,), part in
               paths.group_by("code")}
    assert {c: v for c, v in trials.select("code", "before-touch babbling").iter_rows()} \
        == by_hand
    table = page.validation(trials)
    for senses in second.CONDITIONS:
        part = trials.filter(pl.col("senses") == senses)
        yes, no = part.filter(pl.col("babbling") == "1"), part.filter(pl.col("babbling") == "0")
        for name, found in (("candidate (before the touch)",
                             [by_hand[c] for c in yes["code"]]),
                            ("detector (whole trial)", yes["detector babbling"].to_list())):
            row = table.filter((pl.col("measure") == name) & (pl.col("senses") == senses)
                               & (pl.col("unsure labels") == "left out")).row(0, named=True)
            assert row["sensitivity"].startswith(f"{sum(found)}/{yes.height} ")
            assert row["trials"] == yes.height + no.height
        row = table.filter((pl.col("measure") == "candidate (before the touch)")
                           & (pl.col("senses") == senses)
                           & (pl.col("unsure labels") == "left out")).row(0, named=True)
        correct = sum(not by_hand[c] for c in no["code"])
        assert row["specificity"].startswith(f"{correct}/{no.height} ")
    words = page.words(trials)
    for senses in second.CONDITIONS:
        yes = trials.filter((pl.col("senses") == senses) & (pl.col("babbling") == "1"))
        found = sum(by_hand[c] for c in yes["code"])
        assert f"the candidate finds {found} of the {yes.height} trials labelled babbling" \
            in words
    # one trial's output otherwise: the words change with it
    flipped = trials.with_columns(pl.when(pl.col("code") == "U001")
                                  .then(~pl.col("before-touch babbling"))
                                  .otherwise(pl.col("before-touch babbling"))
                                  .alias("before-touch babbling"))
    assert page.words(flipped) != words


def test_the_committed_page_is_the_rendering_of_the_labels():
    values = page.values(ROOT)
    text = (ROOT / "docs/results/babbling-detector.md").read_text(encoding="utf-8")
    for key in ("second_label_counts", "second_validation", "second_words",
                "third_label_counts", "third_validation", "third_words"):
        assert values[key] in text, key


@pytest.mark.parametrize("hits, n", [(0, 5), (16, 20), (28, 32), (32, 32)])
def test_the_lower_limit_is_clopper_pearsons(hits, n):
    expected = 0.0 if hits == 0 else beta.ppf(0.05, hits, n - hits + 1)
    assert page.lower_limit(hits, n) == pytest.approx(expected, abs=1e-9)


def test_the_rule_needs_both_sides_each_large_and_bounded():
    ok = {"tp": 17, "fn": 3, "tn": 15, "fp": 0}  # 0.85 of 20 and 1.0 of 15
    assert page.passes(ok)
    assert not page.passes({**ok, "tn": 14})  # 14 trials labelled not babbling: too few
    assert not page.passes({**ok, "tp": 15, "fn": 5})  # 0.75 < 0.8
    assert not page.passes({**ok, "tp": 16, "fn": 4})  # 0.8, but a lower limit of 0.599
    # 12 of 15 is 0.8, but its lower limit (0.56) is under 0.6
    assert page.lower_limit(12, 15) < 0.6
    assert not page.passes({"tp": 12, "fn": 3, "tn": 15, "fp": 0})


# ------------------------------------------------------------------------------ third sample
@pytest.fixture(scope="module")
def third_trials() -> pl.DataFrame:
    return page.trials(ROOT, page.THIRD)


def test_the_third_sample_is_its_draw_forty_a_condition(third_trials):
    """The draw made again is the committed sample, codes and all: 40 trials under each
    condition, 40 distinct (generation, replication) units each, from the protocol's
    snapshots, no genome drawn twice without the ball."""
    paths = pl.read_parquet(ROOT / third.SAMPLE)
    keys = paths.group_by("code").agg(pl.col("senses", "generation", "replication", "rank",
                                             "trial").first())
    drawn = third.draw(ROOT / "recordings" / third.RUN)
    columns = ["code", "senses", "generation", "replication", "rank", "trial"]
    assert drawn.select(columns).sort("code").equals(keys.select(columns).sort("code"))
    for senses in third.CONDITIONS:
        part = keys.filter(pl.col("senses") == senses)
        assert part.height == third.PER_CONDITION
        assert part.select("generation", "replication").n_unique() == third.PER_CONDITION
    assert set(keys["generation"]) <= set(third.GENERATIONS)
    assert third_trials.height == len(third.CONDITIONS) * third.PER_CONDITION
    assert third_trials.filter((pl.col("babbling") == page.YES)
                               & (pl.col("moving") != page.YES)).height == 0


def test_the_third_samples_counts_are_the_labels_against_the_measures(third_trials):
    """Sensitivity and specificity of the candidate and of the moving rule per condition,
    counted here from the labels and the measures written out again from their definitions
    (the moving rule: a path of at least 1.0 m and an amplitude of at least 0.05 m)."""
    paths = pl.read_parquet(ROOT / third.SAMPLE)
    before = {code: _before_touch_by_hand(part) for (code,), part in paths.group_by("code")}
    moving = {}
    for (code,), part in paths.group_by("code"):
        hand = part.sort("step").select("x", "y", "z").to_numpy()
        moving[code] = bool(k.path_length(hand) >= 1.0 and k.hand_amplitude(hand) >= 0.05)
    table = page.validation(third_trials)
    for senses in third.CONDITIONS:
        part = third_trials.filter(pl.col("senses") == senses)
        for name, label, measure in (("candidate (before the touch)", "babbling", before),
                                     ("moving rule", "moving", moving)):
            yes = part.filter(pl.col(label) == page.YES)["code"]
            no = part.filter(pl.col(label) == page.NO)["code"]
            row = table.filter((pl.col("measure") == name) & (pl.col("senses") == senses)
                               & (pl.col("unsure labels") == "left out")).row(0, named=True)
            assert row["sensitivity"].startswith(f"{sum(measure[c] for c in yes)}/{len(yes)} ")
            assert row["specificity"].startswith(
                f"{sum(not measure[c] for c in no)}/{len(no)} ")
    apart = third_trials.filter((pl.col("moving") == page.YES)
                                & (pl.col("babbling") == page.NO)).height
    assert apart > 0  # this sample tells babbling from moving
    assert f"{apart} trials are labelled one and not the other" in page.words(third_trials)


def test_the_campaigns_a4_reads_the_detectors_no_ball_sensitivity_on_this_sample(third_trials):
    """The lower limit that reads the campaign's A4 (docs/results/campaign.md, "Addendum") is
    Clopper-Pearson's on the detector's hits among the sure babbling labels without the ball,
    counted here from the labels and the detector's verdicts."""
    from reports.campaign import a4_sensitivity

    part = third_trials.filter((pl.col("senses") == "no-ball")
                               & (pl.col("babbling") == page.YES))
    hits, n = int(part["detector babbling"].sum()), part.height
    assert 0 < hits < n  # the detector misses some: the reading matters
    assert a4_sensitivity() == pytest.approx(beta.ppf(0.05, hits, n - hits + 1), abs=1e-9)
