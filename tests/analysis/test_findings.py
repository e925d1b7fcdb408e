"""The findings table (``dart_reach.analysis.findings``) and its decision rules (``dart_reach.analysis.verdicts``):
small tables are built where a claim holds, where it fails and where the data cannot decide,
and the verdict must follow; a sample that could not have shown otherwise never reproduces."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest
from scipy import stats as sps

from dart_reach.analysis import findings as fd
from dart_reach.analysis import verdicts as vd

MEASURES = ("fitness", "speed", "straightness", "var_elbow", "var_shoulder", "var_trunk",
            "hand_shoulder_cv", "hand_path", "heading")


def _trials(groups: dict[str, dict], replications: int = 4, ranks: int = 2,
            senses=("normal",), seed=0, spread: float = 0.01):
    """Trials of ``replications`` x ``ranks`` robots per group, one per sector. A group's spec
    gives the mean of each measure, the reach/grasp/babbling probabilities and, per sensory
    condition, the fitness ("fitness no-sight"); every robot gets its own offset (s.d.
    ``spread``) so that samples have no ties."""
    rng = np.random.default_rng(seed)
    rows = []
    for notation, spec in groups.items():
        for r in range(replications * ranks):
            jitter = rng.normal(0, spread)
            for s in senses:
                for sector in range(9):
                    row = {"notation": notation, "senses": s, "replication": r // ranks,
                           "rank": r % ranks, "sector": sector, "lifetime_fitness": 0.0,
                           "reached": bool(rng.random() < spec.get("reach", 0.5)),
                           "grasped": bool(rng.random() < spec.get("grasp", 0.2)),
                           "babbling": bool(rng.random() < spec.get("babbling", 0.0))}
                    for m in MEASURES:
                        row[m] = spec.get(m, 0.5) + jitter + rng.normal(0, spread / 2)
                    if s != "normal":
                        row["fitness"] = spec.get(f"fitness {s}", row["fitness"]) + jitter
                    rows.append(row)
    return pl.DataFrame(rows)


def _row(found: pl.DataFrame, claim: str) -> dict:
    return found.filter(pl.col("claim") == claim).row(0, named=True)


def _verdict(found: pl.DataFrame, claim: str) -> str:
    return _row(found, claim)["verdict"]


# ------------------------------------------------------------------------------ directional
def test_a_directional_claim_is_reproduced_contradicted_or_inconclusive():
    holds = _trials({"pre": {"grasp": 0.05}, "gross": {"grasp": 0.9}})
    fails = _trials({"pre": {"grasp": 0.9}, "gross": {"grasp": 0.05}})
    neither = _trials({"pre": {"grasp": 0.5}, "gross": {"grasp": 0.5}})
    assert _verdict(fd.findings(holds), "F2 grasp up") == fd.REPRODUCED
    assert _verdict(fd.findings(fails), "F2 grasp up") == fd.CONTRADICTED
    assert _verdict(fd.findings(neither), "F2 grasp up") == fd.INCONCLUSIVE


def test_both_directions_use_one_level_and_the_papers_level_is_a_column():
    """p between 0.001 and 0.05 in the paper's direction is reproduced (at ALPHA) with the
    paper's level not met; the same p the other way is contradicted."""
    up = vd.directional([0.1, 0.2, 0.3, 0.4, 0.5], [0.6, 0.7, 0.8, 0.9, 1.0], +1, 0.001)
    assert 0.001 < up.p < 0.05 and up.verdict == vd.REPRODUCED and up.paper_level_met is False
    down = vd.directional([0.6, 0.7, 0.8, 0.9, 1.0], [0.1, 0.2, 0.3, 0.4, 0.5], +1, 0.001)
    assert down.p == up.p and down.verdict == vd.CONTRADICTED


def test_direction_comes_from_ranks_not_means():
    """b has the higher mean (one outlier) but lower ranks: the direction is the ranks'."""
    a = [1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7]
    b = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 100.0]
    assert np.mean(b) > np.mean(a)
    out = vd.directional(a, b, +1, 0.05)
    assert out.verdict == vd.CONTRADICTED and out.effect < 0  # Hodges-Lehmann shift


def test_sizes_that_cannot_reach_the_level_are_underpowered_before_any_test():
    assert vd.smallest_mann_whitney_p(2, 2) == pytest.approx(1 / 3)
    assert vd.smallest_mann_whitney_p(3, 4) == pytest.approx(2 / 35)
    assert vd.smallest_mann_whitney_p(4, 4) == pytest.approx(2 / 70)
    perfect = vd.directional([0.0, 0.1, 0.2], [1.0, 1.1, 1.2], +1, 0.05)
    assert perfect.verdict == vd.UNDERPOWERED and math.isnan(perfect.p)
    # the scipy test agrees that complete separation of 3 vs 3 cannot reach 0.05
    assert sps.mannwhitneyu([1.0, 1.1, 1.2], [0.0, 0.1, 0.2]).pvalue == pytest.approx(0.1)


def test_hodges_lehmann_shift_and_interval():
    shift, low, high = vd.hodges_lehmann(np.arange(10.0), np.arange(10.0) + 3)
    assert shift == 3.0 and low < 3.0 < high
    assert vd.hodges_lehmann([0.0, 1.0], [2.0, 3.0])[1:] == (-math.inf, math.inf)


# ------------------------------------------------------------------------------ no difference
def test_a_two_versus_two_no_difference_claim_is_never_reproduced():
    table = _trials({"pre": {}, "pre-h": {}}, replications=2, ranks=1)
    assert _verdict(fd.findings(table), "F6 pre vs pre-h") == fd.UNDERPOWERED
    assert vd.equivalent([0.5, 0.51], [0.5, 0.51]).verdict == vd.UNDERPOWERED


def test_equal_valued_groups_are_not_evidence_of_equivalence():
    out = vd.equivalent(np.zeros(40), np.zeros(40))
    assert out.verdict == vd.INCONCLUSIVE and "no evidence" in out.note


def test_equivalence_is_shown_refuted_or_left_open():
    rng = np.random.default_rng(3)
    same = vd.equivalent(rng.normal(0, 1, 400), rng.normal(0, 1, 400))
    apart = vd.equivalent(rng.normal(0, 1, 40), rng.normal(2, 1, 40))
    small = vd.equivalent(rng.normal(0, 1, 30), rng.normal(0.3, 1, 30))
    assert same.verdict == vd.REPRODUCED and abs(same.effect - 0.5) < 0.05
    assert apart.verdict == vd.CONTRADICTED
    assert small.verdict == vd.INCONCLUSIVE
    assert not vd.equivalence_reachable(10, 10) and vd.equivalence_reachable(50, 50)


def test_the_probabilistic_index_matches_scipys_brunner_munzel():
    rng = np.random.default_rng(1)
    a, b = rng.normal(0, 1, 7), rng.normal(0.5, 1.3, 9)
    theta, se, df = vd.probabilistic_index(a, b)
    res = sps.brunnermunzel(a, b)
    assert (theta - 0.5) / se == pytest.approx(res.statistic)
    assert 2 * sps.t(df).sf(abs(theta - 0.5) / se) == pytest.approx(res.pvalue)
    assert theta == pytest.approx(np.mean(b[None, :] > a[:, None]))


def test_f3_no_difference_claims_on_tables():
    same = _trials({"gross": {"speed": 0.3}, "fine": {"speed": 0.3}}, replications=25,
                   spread=0.05)
    apart = _trials({"gross": {"speed": 0.3}, "fine": {"speed": 0.6}}, replications=8)
    assert _verdict(fd.findings(same), "F3 speed no different") == fd.REPRODUCED
    assert _verdict(fd.findings(apart), "F3 speed no different") == fd.CONTRADICTED


# ------------------------------------------------------------------------------ intervals
def test_about_half_needs_its_interval_inside_the_band():
    rng = np.random.default_rng(0)
    assert vd.in_band([0.45, 0.5, 0.55, 0.5, 0.48], fd.ABOUT_HALF, rng).verdict == vd.REPRODUCED
    assert vd.in_band([0.9, 0.95, 0.85, 0.92], fd.ABOUT_HALF, rng).verdict == vd.CONTRADICTED
    wide = vd.in_band([0.1, 0.9, 0.2, 0.8], fd.ABOUT_HALF, rng)  # mean 0.5, wide interval
    assert wide.verdict == vd.INCONCLUSIVE and wide.low < 1 / 3 and 0 <= wide.low
    assert vd.in_band([0.5, 0.5, 0.5], fd.ABOUT_HALF, rng).verdict == vd.UNDERPOWERED
    half = _trials({"pre": {"reach": 0.5}}, replications=6, ranks=5)
    rarely = _trials({"pre": {"reach": 0.02}}, replications=6, ranks=5)
    assert _verdict(fd.findings(half), "F1 reach about half") == fd.REPRODUCED
    assert _verdict(fd.findings(rarely), "F1 reach about half") == fd.CONTRADICTED


def test_all_sectors_needs_reach_and_grasp_above_the_floor_everywhere():
    good = _trials({"fine": {"reach": 0.9, "grasp": 0.8}}, replications=5, ranks=5)
    no_grasp = _trials({"fine": {"reach": 0.9, "grasp": 0.0}}, replications=5, ranks=5)
    assert _verdict(fd.findings(good), "F3 all sectors") == fd.REPRODUCED
    row = _row(fd.findings(no_grasp), "F3 all sectors")
    assert row["verdict"] == fd.CONTRADICTED and "grasp in sector" in row["note"]
    # one touch per sector pooled over every trial is not enough any more
    rare = _trials({"fine": {"reach": 0.03, "grasp": 0.03}}, replications=5, ranks=5)
    assert _verdict(fd.findings(rare), "F3 all sectors") != fd.REPRODUCED


def test_never_is_an_upper_bound_and_is_conditional_on_babbling_existing():
    never = _trials({"fine*": {"babbling": 0.0}}, replications=5)
    often = _trials({"fine*": {"babbling": 0.6}}, replications=5)
    assert _verdict(fd.findings(never), "F7 fine* never babbles") == fd.REPRODUCED
    assert _verdict(fd.findings(often), "F7 fine* never babbles") == fd.CONTRADICTED
    assert "F1 babbling" in _row(fd.findings(never), "F7 fine* never babbles")["paper"]


# ------------------------------------------------------------------------------ paired senses
def test_senses_are_tested_with_the_robot_as_block():
    spec = {p: {"fitness": f, "fitness no-touch": f * 0.9, "fitness no-sight": f * 0.3,
                "fitness nothing": f * 0.2} for p, f in (("pre", 0.1), ("gross", 0.3),
                                                          ("fine", 0.6))}
    spec["fine"].update({"fitness no-sight": 0.02, "fitness nothing": 0.01})
    senses = ("normal", "no-touch", "no-sight", "nothing")
    found = fd.findings(_trials(spec, senses=senses))
    for claim in ("F4 senses differ (pre)", "F4 senses differ (fine)",
                  "F4 normal: fine > gross", "F4 normal: gross > pre",
                  "F4 no-sight: gross > fine", "F4 nothing: gross > fine"):
        assert _verdict(found, claim) == fd.REPRODUCED, claim
    kw = _row(found, "F4 senses differ (pre)")
    assert "Kruskal-Wallis" in kw["test"] and 0 <= kw["p_paper_test"] < 0.01
    only_normal = fd.findings(_trials(spec))
    assert _verdict(only_normal, "F4 senses differ (pre)") == fd.NOT_RUN
    two = fd.findings(_trials(spec, replications=1, senses=senses))  # 2 robots as blocks
    assert _verdict(two, "F4 senses differ (pre)") == fd.UNDERPOWERED
    assert vd.smallest_friedman_p(3, 4) < 0.05 < vd.smallest_friedman_p(2, 4)


# ------------------------------------------------------------------------------ units, table
def test_robot_level_and_replication_level_disagreement_is_said():
    """Many robots per replication make robot-level p small (120 vs 120 robots, each gross
    replication a little above its pre counterpart); the 4 vs 4 replication means overlap, the
    replication-level check disagrees, and the note says so."""
    rng = np.random.default_rng(5)
    rows = []
    for notation, offsets in (("pre", (0.0, 0.3, 0.6, 0.9)), ("gross", (0.15, 0.45, 0.75, 1.1))):
        for rep, off in enumerate(offsets):
            for rank in range(30):
                rows.append({"notation": notation, "senses": "normal", "replication": rep,
                             "rank": rank, "sector": rank % 9, "lifetime_fitness": 0.0,
                             "reached": True, "grasped": True, "fitness": 0.1,
                             "var_shoulder": 1.0,
                             "straightness": off + rng.normal(0, 0.02)})
    row = _row(fd.findings(pl.DataFrame(rows)), "F2 straighter")
    assert row["verdict"] == fd.REPRODUCED and row["replications_agree"] is False
    assert "replication means: inconclusive" in row["note"]
    assert row["n"] == "120 vs 120 robots (4 vs 4 replications)"


def test_conditions_compare_replications():
    holds = _trials({"gross": {"fitness": 0.6}, "gross^": {"fitness": 0.2}}, replications=8)
    fails = _trials({"gross": {"fitness": 0.2}, "gross^": {"fitness": 0.6}}, replications=8)
    for table, expected in ((holds, fd.REPRODUCED), (fails, fd.CONTRADICTED)):
        row = _row(fd.findings(table), "F5 gross > gross^")
        assert row["verdict"] == expected and row["n"] == "8 vs 8 replications"


def test_hand_shoulder_constancy_and_babbling_against_the_baseline():
    table = _trials({"pre": {"hand_shoulder_cv": 0.01, "babbling": 0.8},
                     "fine": {"hand_shoulder_cv": 0.05}})
    base = _trials({"pre": {"hand_shoulder_cv": 0.04, "babbling": 0.1},
                    "gross": {"hand_shoulder_cv": 0.0, "babbling": 0.9}}, seed=1)
    found = fd.findings(table, base)
    assert _verdict(found, "F1 hand-shoulder constant vs random") == fd.REPRODUCED
    assert _verdict(found, "F1 hand-shoulder constant vs fine") == fd.REPRODUCED
    assert _verdict(found, "F1 babbling") == fd.REPRODUCED
    assert _verdict(fd.findings(table), "F1 babbling") == fd.NOT_RUN  # no baseline


def test_holm_and_every_claim_has_a_row():
    assert np.allclose(vd.holm([0.01, 0.04, math.nan, 0.03]), [0.03, 0.06, math.nan, 0.06],
                       equal_nan=True)
    found = fd.findings(_trials({"pre": {}, "gross": {"grasp": 0.9}}))
    assert found.height == len(set(found["claim"])) == len(fd.CLAIMS) >= 30
    assert set(found["verdict"]) <= set(fd.VERDICTS)
    tested = found.filter(pl.col("p").is_not_nan())
    assert (tested["p_holm"] >= tested["p"]).all()
    assert _verdict(found, "F6 fine vs fine^") == fd.NOT_RUN
    assert found.filter(pl.col("verdict") == fd.NOT_RUN)["measured"].str.starts_with(
        "not run").all()
    assert sum(fd.summary(found).values()) == found.height
    with pytest.raises(ValueError, match="lacks columns"):
        fd.findings(pl.DataFrame({"notation": ["pre"]}))


# ------------------------------------------------------------------------------ paired samples
def test_paired_directional_claims_flip_and_small_samples_are_underpowered():
    rng = np.random.default_rng(2)
    ref = rng.normal(1.0, 0.2, 20)
    assert vd.paired_directional(ref, ref - 0.3 + rng.normal(0, 0.05, 20), -1, 0.05).verdict \
        == vd.REPRODUCED
    assert vd.paired_directional(ref, ref + 0.3 + rng.normal(0, 0.05, 20), -1, 0.05).verdict \
        == vd.CONTRADICTED
    assert vd.paired_directional(ref, ref + rng.normal(0, 0.05, 20), -1, 0.05).verdict \
        == vd.INCONCLUSIVE
    assert vd.smallest_signed_rank_p(5) > 0.05 > vd.smallest_signed_rank_p(6)
    four = vd.paired_directional([1, 2, 3, 4], [0, 1, 2, 3], -1, 0.05)  # 4 replications
    assert four.verdict == vd.UNDERPOWERED


def test_paired_sameness_is_shown_by_equivalence_not_by_absence_of_a_difference():
    rng = np.random.default_rng(4)
    ref = rng.normal(1.0, 0.2, 30)
    assert vd.paired_equivalent(ref, ref + rng.normal(0, 0.02, 30)).verdict == vd.REPRODUCED
    assert vd.paired_equivalent(ref, ref * 0.5 + rng.normal(0, 0.02, 30)).verdict \
        == vd.CONTRADICTED
    noisy = vd.paired_equivalent(ref[:6], ref[:6] + rng.normal(0, 0.5, 6))
    assert noisy.verdict == vd.INCONCLUSIVE
    assert vd.paired_equivalent(ref, ref).verdict == vd.REPRODUCED  # every robot unchanged
    assert vd.paired_equivalent(np.zeros(10), np.zeros(10)).verdict == vd.INCONCLUSIVE  # floor
    assert vd.paired_equivalent(ref[:2], ref[:2]).verdict == vd.UNDERPOWERED


# ------------------------------------------------------------------------------ issue 22's claims
def test_ball_absent_and_deprivation_claims_pair_each_robot_with_itself():
    senses = ("normal", "no-touch", "no-sight", "nothing", "no-ball")
    same = {"pre": {"hand_path": 2.0, "fitness": 0.1}, "fine": {"fitness": 0.6}}
    same["fine"].update({"fitness no-sight": 0.05, "fitness no-ball": 0.0,
                         "fitness no-touch": 0.4})
    same["pre"].update({"fitness no-sight": 0.1, "fitness no-touch": 0.1,
                        "fitness no-ball": 0.0})
    found = fd.findings(_trials(same, replications=5, senses=senses))
    # every robot's hand path is its own under the ball's absence (the jitter is per robot)
    assert _verdict(found, "A1 ball absent, pre: hand_path same") == fd.REPRODUCED
    assert _verdict(found, "D1 no-sight drop: fine > pre") == fd.REPRODUCED
    assert _verdict(found, "D2 no touch, pre: fitness same") == fd.REPRODUCED
    assert _verdict(found, "D3 no touch, fine: fitness down") == fd.REPRODUCED
    moved = {"pre": dict(same["pre"])}
    table = _trials(moved, replications=5, senses=senses)
    table = table.with_columns(pl.when(pl.col("senses") == "no-ball")
                               .then(pl.col("hand_path") * 0.3).otherwise(pl.col("hand_path"))
                               .alias("hand_path"))
    assert _verdict(fd.findings(table), "A1 ball absent, pre: hand_path same") \
        == fd.CONTRADICTED
    assert _verdict(fd.findings(_trials(same)), "A1 ball absent, pre: hand_path same") \
        == fd.NOT_RUN  # no ball-absent trials


def test_development_claims_compare_generation_windows():
    rng = np.random.default_rng(8)
    rows = []
    for notation, gens, path in (("pre", (1, 5, 10), 2.0), ("gross", (1, 5, 10), 1.0)):
        for g in gens:
            for rep in range(4):
                for rank in range(5):
                    value = (0.5 if (notation, g) in (("gross", 1), ("gross", 5)) else path)
                    rows.append({"notation": notation, "generation": g, "replication": rep,
                                 "rank": rank, "hand_path": value + rng.normal(0, 0.05),
                                 "babbling": float(rng.random() < 0.02)})
    dev = pl.DataFrame(rows)
    table = _trials({"pre": {}})
    found = fd.findings(table, development=dev)
    row = _row(found, "V1 motor suppression at the start of gross")
    assert row["verdict"] == fd.REPRODUCED  # 20 robots each side
    assert row["n"] == "20 vs 20 robots (4 vs 4 replications)"
    assert _verdict(fd.findings(table), "V1 motor suppression at the start of gross") \
        == fd.NOT_RUN
    star = dev.with_columns(pl.lit("fine*").alias("notation"))
    assert _verdict(fd.findings(table, development=pl.concat([dev, star])),
                    "V5 fine* never babbles during development") != fd.CONTRADICTED


def test_control_behaviour_claims_are_judged_on_replications():
    table = _trials({"pre": {"heading": 0.3}, "pre-h": {"heading": 0.3}})
    row = _row(fd.findings(table), "C pre-h: heading same")
    assert row["verdict"] == fd.UNDERPOWERED and row["n"] == "4 vs 4 replication means"
