"""The findings table (``dart_reach.analysis.findings``) on small constructed post-evaluations:
each claim's verdict follows the data, with the replication as the unit of the headline and
the robots beside it as the paper's analysis; samples that could not have shown otherwise never
reproduce; Holm's family is the paper's claims; every claim carries the paper's words."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest

from dart_reach.analysis import findings as fd
from dart_reach.analysis import verdicts as vd
from dart_reach.analysis.claims import CLAIMS, Kind

MEASURES = ("fitness", "speed", "straightness", "var_elbow", "var_shoulder", "var_trunk",
            "var_elbow_norm", "var_shoulder_norm", "var_trunk_norm", "hand_shoulder_cv",
            "hand_shoulder_mean", "hand_path", "heading", "movement_units", "first_touch_s")


def _trials(groups: dict[str, dict], replications: int = 10, ranks: int = 3,
            senses=("normal",), seed=0, between: float = 0.02, within: float = 0.005):
    """Trials of ``replications`` x ``ranks`` robots per group, one per sector. A group's spec
    gives each measure's mean, the reach/grasp/babbling probabilities and per sensory condition
    the fitness ("fitness no-sight"); each replication has its own offset (s.d. ``between``),
    each robot its own around it (``within``), so that samples have no ties."""
    rng = np.random.default_rng(seed)
    rows = []
    for notation, spec in groups.items():
        for rep in range(replications):
            rep_offset = rng.normal(0, between)
            for rank in range(ranks):
                jitter = rep_offset + rng.normal(0, within)
                for s in senses:
                    for sector in range(9):
                        row = {"notation": notation, "senses": s, "replication": rep,
                               "rank": rank, "sector": sector, "lifetime_fitness": 0.0,
                               "reached": bool(rng.random() < spec.get("reach", 0.5)),
                               "grasped": bool(rng.random() < spec.get("grasp", 0.2)),
                               "babbling": bool(rng.random() < spec.get("babbling", 0.0))}
                        for m in MEASURES:
                            row[m] = spec.get(m, 0.5) + jitter + rng.normal(0, within / 2)
                        if s != "normal" and f"fitness {s}" in spec:
                            row["fitness"] = spec[f"fitness {s}"] + jitter
                            row["reached"] = bool(rng.random() < spec.get(f"reach {s}",
                                                                          spec.get("reach", .5)))
                        rows.append(row)
    return pl.DataFrame(rows)


def _row(found: pl.DataFrame, claim: str) -> dict:
    return found.filter(pl.col("claim") == claim).row(0, named=True)


def _verdict(found: pl.DataFrame, claim: str) -> str:
    return _row(found, claim)["verdict"]


def test_every_claim_carries_the_papers_words_and_has_a_row():
    assert len({c.id for c in CLAIMS}) == len(CLAIMS)
    for c in CLAIMS:
        assert c.section and c.paper, c.id
    found = fd.findings(_trials({"pre": {}}, replications=4))
    assert found["claim"].to_list() == [c.id for c in CLAIMS]
    assert set(found["verdict"]) <= set(vd.VERDICTS)
    assert found["kind"].is_in([k.value for k in Kind]).all()
    assert found.filter(pl.col("own"))["claim"].to_list() == [c.id for c in CLAIMS if c.own]


def test_a_directional_claim_is_judged_on_replications():
    holds = _trials({"pre": {"grasp": 0.05}, "gross": {"grasp": 0.9}})
    fails = _trials({"pre": {"grasp": 0.9}, "gross": {"grasp": 0.05}})
    neither = _trials({"pre": {"grasp": 0.5}, "gross": {"grasp": 0.5}}, seed=3)
    assert _verdict(fd.findings(holds), "F2 grasp up") == vd.REPRODUCED
    assert _verdict(fd.findings(fails), "F2 grasp up") == vd.CONTRADICTED
    assert _verdict(fd.findings(neither), "F2 grasp up") == vd.INCONCLUSIVE
    assert _row(fd.findings(holds), "F2 grasp up")["n"] == "10 replications vs 10 replications"


def test_robots_as_units_are_beside_the_headline_never_in_it():
    """Three replications per group: a shift the 30 robots show (robot-level reproduced) is
    underpowered with the replication as the unit (3 vs 3: the smallest p is 0.1)."""
    trials = _trials({"pre": {"straightness": 0.4}, "gross": {"straightness": 0.6}},
                     replications=3, ranks=10, between=0.01)
    found = fd.findings(trials)
    row = _row(found, "F2 straighter")
    assert row["verdict"] == vd.UNDERPOWERED
    assert row["verdict_robots"] == vd.REPRODUCED
    reproduced = found.filter(~pl.col("own") & (pl.col("verdict") == vd.REPRODUCED))
    assert "F2 straighter" not in reproduced["claim"].to_list()
    assert fd.summary(found)[vd.REPRODUCED] == reproduced.height


def test_random_genomes_are_units_of_their_own():
    trials = _trials({"pre": {"babbling": 0.8, "hand_shoulder_cv": 0.1}})
    baseline = _trials({"pre": {"babbling": 0.05, "hand_shoulder_cv": 0.5}}, replications=10,
                       ranks=1, seed=1)
    found = fd.findings(trials, baseline)
    assert _verdict(found, "F1 babbling") == vd.REPRODUCED
    assert _verdict(found, "F1 hand-shoulder constant vs random") == vd.REPRODUCED
    assert _row(found, "F1 babbling")["n"] == "10 replications vs 10 random genomes"
    assert _verdict(fd.findings(trials), "F1 babbling") == vd.NOT_RUN


def test_not_better_is_one_sided():
    """F3: fine is "not significantly better" than gross in straightness: a worse fine
    reproduces it, a better one contradicts it."""
    worse = _trials({"gross": {"straightness": 0.6}, "fine": {"straightness": 0.4}})
    better = _trials({"gross": {"straightness": 0.4}, "fine": {"straightness": 0.6}})
    assert _verdict(fd.findings(worse), "F3 straightness not better") == vd.REPRODUCED
    assert _verdict(fd.findings(better), "F3 straightness not better") == vd.CONTRADICTED
    # speed: lower is better (more direct reaches, IV-A-2)
    assert _verdict(fd.findings(worse.with_columns(pl.col("speed") * -1)),
                    "F3 speed not better") in (vd.INCONCLUSIVE, vd.REPRODUCED)


def test_about_half_needs_its_interval_inside_the_band():
    half = _trials({"pre": {"reach": 0.5}}, ranks=5)
    most = _trials({"pre": {"reach": 0.95}}, ranks=5)
    few = _trials({"pre": {"reach": 0.5}}, replications=2)
    assert _verdict(fd.findings(half), "F1 reach about half") == vd.REPRODUCED
    assert _verdict(fd.findings(most), "F1 reach about half") == vd.CONTRADICTED
    assert _verdict(fd.findings(few), "F1 reach about half") == vd.UNDERPOWERED


def test_all_sectors_and_zero_spread():
    good = _trials({"fine": {"reach": 0.7, "grasp": 0.6}}, ranks=5)
    bad = _trials({"fine": {"reach": 0.7, "grasp": 0.0}}, ranks=5)
    assert _verdict(fd.findings(good), "F3 all sectors") == vd.REPRODUCED
    # every grasp rate is 0 in every replication: no spread, no evidence either way
    assert _verdict(fd.findings(bad), "F3 all sectors") == vd.INCONCLUSIVE


def test_never_means_less_than_pre():
    still = _trials({"pre": {"babbling": 0.6}, "fine*": {"babbling": 0.02}})
    babbles = _trials({"pre": {"babbling": 0.6}, "fine*": {"babbling": 0.6}}, seed=2)
    assert _verdict(fd.findings(still), "F7 fine* never babbles") == vd.REPRODUCED
    assert _verdict(fd.findings(babbles), "F7 fine* never babbles") != vd.REPRODUCED
    # without pre-reachers that babble there is nothing to compare with
    assert _verdict(fd.findings(still.filter(pl.col("notation") != "pre")),
                    "F7 fine* never babbles") == vd.NOT_RUN


def test_senses_are_tested_with_the_replication_as_block():
    senses = ("normal", "no-touch", "no-sight", "nothing")
    differ = _trials({"fine": {"fitness": 0.8, "fitness no-touch": 0.6, "fitness no-sight": 0.3,
                               "fitness nothing": 0.1}}, senses=senses)
    same = _trials({"fine": {"fitness": 0.5}}, senses=senses, within=0.02)
    assert _verdict(fd.findings(differ), "F4 senses differ (fine)") == vd.REPRODUCED
    assert _row(fd.findings(differ), "F4 senses differ (fine)")["n"] == \
        "10 replications x 4 conditions"
    assert _verdict(fd.findings(same), "F4 senses differ (fine)") == vd.CONTRADICTED


def test_conditions_compare_replications_best_robots():
    trials = _trials({"gross": {"fitness": 0.8}, "gross^": {"fitness": 0.3}})
    row = _row(fd.findings(trials), "F5 gross > gross^")
    assert row["verdict"] == vd.REPRODUCED and row["verdict_robots"] is None
    row = _row(fd.findings(_trials({"pre": {"fitness": 0.2}, "pre-h": {"fitness": 0.8}})),
               "F6 pre not better than pre-h")
    assert row["verdict"] == vd.REPRODUCED  # the standard is worse: certainly not better


def test_paired_claims_pair_each_replication_with_itself():
    senses = ("normal", "no-touch", "no-ball")
    trials = _trials({"pre": {"reach no-touch": 0.5},
                      "gross": {"fitness": 0.8, "fitness no-touch": 0.4}}, senses=senses,
                     ranks=5)
    found = fd.findings(trials)
    assert _verdict(found, "D3 no touch, gross: fitness down") == vd.REPRODUCED
    assert _row(found, "D3 no touch, gross: fitness down")["n"] == "10 replications"


def test_a_claim_its_measure_cannot_test_says_so_and_is_never_judged():
    """D2's reach is a first touch, and every touch sensor is silent until it: a trial
    reaches under no touch exactly when it does under normal senses, so even reach rates
    that differ (here 0.9 and 0.3) leave it untested, not contradicted. A3's babbling has no
    measure validated without sight: untested too, and both counted apart."""
    trials = _trials({"pre": {"reach": 0.9, "reach no-touch": 0.3}},
                     senses=("normal", "no-touch"), ranks=5)
    row = _row(fd.findings(trials), "D2 no touch, pre: reach same")
    assert row["verdict"] == vd.NOT_RUN and math.isnan(row["effect"])
    assert row["measured"].startswith(fd.UNTESTABLE + "a trial reaches")
    assert [c.id for c in CLAIMS if c.untestable] == ["A3 no sight, pre: babbling same",
                                                      "D2 no touch, pre: reach same"]
    babbling = _row(fd.findings(trials), "A3 no sight, pre: babbling same")
    assert babbling["measured"].startswith(fd.UNTESTABLE + "no babbling measure is validated")
    counts = fd.summary(fd.findings(trials))
    assert counts[fd.CANNOT] == 2
    assert counts[vd.NOT_RUN] == fd.reading(fd.findings(trials)).filter(
        (pl.col("verdict") == vd.NOT_RUN)
        & ~pl.col("measured").str.starts_with(fd.UNTESTABLE)).height


def test_the_elbow_is_locked_against_the_same_robots_shoulder():
    locked = _trials({"pre": {"var_elbow_norm": 0.1, "var_shoulder_norm": 0.5,
                              "var_trunk_norm": 0.4}})
    free = _trials({"pre": {"var_elbow_norm": 0.6, "var_shoulder_norm": 0.2,
                            "var_trunk_norm": 0.2}})
    assert _verdict(fd.findings(locked), "F1 elbow locked: elbow < shoulder") == vd.REPRODUCED
    assert _verdict(fd.findings(free), "F1 elbow locked: elbow < trunk") == vd.CONTRADICTED


def test_development_windows_do_not_overlap_and_pair_one_phase():
    rows = []
    for gen in (1, 2, 5, 10, 15, 20):
        t = _trials({"pre": {"babbling": 0.02 if gen <= 2 else 0.7}}, seed=gen)
        rows.append(t.with_columns(pl.lit(gen).alias("generation")))
    development = pl.concat(rows)
    found = fd.findings(_trials({"pre": {}}), development=development)
    row = _row(found, "V3 babbling appears in pre")
    assert row["verdict"] == vd.REPRODUCED and row["n"] == "10 replications, paired"
    assert fd._window("pre@start", development["generation"]) == ("pre", 1, 2)
    assert fd._window("pre@end", development["generation"]) == ("pre", 19, 20)
    assert _verdict(found, "V4 babbling fades in gross") == vd.NOT_RUN


def test_holm_family_is_the_papers_claims_and_the_summary_counts_it():
    trials = _trials({"pre": {"grasp": 0.05, "straightness": 0.3},
                      "gross": {"grasp": 0.9, "straightness": 0.7}})
    found = fd.findings(trials)
    assert found.filter(pl.col("own") | pl.col("infants"))["p_holm"].is_nan().all()
    headline = fd.reading(found).filter(pl.col("p").is_not_nan())
    assert (headline["p_holm"] >= headline["p"]).all()
    counts = fd.summary(found)
    assert counts[vd.REPRODUCED] >= counts["reproduced (Holm)"] >= 1
    assert sum(counts[v] for v in fd.COUNTED) == found.filter(
        ~pl.col("own") & ~pl.col("infants")).height
    for who, rows in ((fd.OWN, found.filter(pl.col("own"))),
                      (fd.INFANTS, found.filter(~pl.col("own") & pl.col("infants")))):
        assert rows.height > 0 and sum(fd.summary(found, who)[v] for v in fd.COUNTED) \
            == rows.height
    assert set(fd.reading(found, fd.INFANTS)["claim"]) == {
        "T2 reach onset", "T6 anticipatory grasp", "T7 smoother reach (infants)",
        "V1 motor suppression at the start of gross"}
    with pytest.raises(ValueError, match="reading"):
        fd.reading(found, "robots")


def _with_swipes(trials: pl.DataFrame, swipes_of) -> pl.DataFrame:
    """``trials`` with ``swipes`` per trial from ``swipes_of(replication, rank, sector)``."""
    return trials.with_columns(pl.struct("replication", "rank", "sector").map_elements(
        lambda r: swipes_of(r["replication"], r["rank"], r["sector"]),
        return_dtype=pl.Int64).alias("swipes"))


def test_swipes_again_is_conditional_on_a_failed_swipe():
    """Gross-reachers that almost never swipe cannot test "when they don't grasp the ball they
    try again" (underpowered, the counts said), however low their swipes per ungrasped trial;
    with failed swipes in every replication the at-least rule decides on those trials only."""
    base = _trials({"gross": {"grasp": 0.0}, "pre": {}})
    rare = fd.findings(_with_swipes(base, lambda rep, rank, sector: int(
        rep < 2 and rank == 0 and sector == 0)))
    row = _row(rare, "F2 swipes again")
    assert row["verdict"] == vd.UNDERPOWERED
    assert "cannot be tested at this n" in row["note"] and "in 2 replications" in row["note"]
    again = fd.findings(_with_swipes(base, lambda rep, rank, sector: 3 if sector < 2 else 0))
    assert _verdict(again, "F2 swipes again") == vd.INCONCLUSIVE  # 3 everywhere: no spread
    varied = fd.findings(_with_swipes(base, lambda rep, rank, sector: (
        (3 + (rep + rank) % 2) if sector < 2 else 0)))
    assert _verdict(varied, "F2 swipes again") == vd.REPRODUCED
    once = fd.findings(_with_swipes(base, lambda rep, rank, sector: (
        1 + (sector == 0 and rank == 0 and rep % 2 == 0) if sector < 3 else 0)))
    assert _verdict(once, "F2 swipes again") == vd.CONTRADICTED


def test_smoothness_not_better_is_the_projects_reading():
    """The paper never measures the robots' smoothness: T7's not-better row is the project's,
    the infants' smoother reach the infants'; neither is in the headline."""
    by_id = {c.id: c for c in CLAIMS}
    assert by_id["T7 smoothness not better"].own
    assert by_id["T7 smoother reach (infants)"].infants
    assert not any(c.id.startswith("T7") for c in CLAIMS if not (c.own or c.infants))


def test_a1_babbling_is_judged_on_babbling_before_the_touch():
    """A1's babbling uses the measure validated with and without the ball
    (``babbling_before_touch``), not the detector on the whole trial; a table without it
    leaves the claim not run, saying which measure it lacks."""
    trials = _trials({"pre": {"babbling": 0.5}}, senses=("normal", "no-ball"), ranks=5)
    row = _row(fd.findings(trials), "A1 ball absent, pre: babbling same")
    assert row["verdict"] == vd.NOT_RUN
    assert row["measured"] == "not run: no babbling_before_touch"
    rng = np.random.default_rng(1)
    both = trials.with_columns(pl.Series("babbling_before_touch",
                                         rng.random(trials.height) < 0.5))
    row = _row(fd.findings(both), "A1 ball absent, pre: babbling same")
    assert row["verdict"] != vd.NOT_RUN
    assert row["measured"].startswith("babbling_before_touch: normal")
