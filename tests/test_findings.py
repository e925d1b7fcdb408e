"""The findings table (``dart_reach.findings``): each claim's verdict follows the data. Small
tables are built where a claim holds and where it fails, and the verdict must flip."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest

from dart_reach import findings as fd

MEASURES = ("fitness", "speed", "straightness", "var_elbow", "var_shoulder", "var_trunk",
            "babbling_share")


def _trials(groups: dict[str, dict], robots: int = 8, senses=("normal",), seed=0):
    """Trials of ``robots`` robots (4 replications x 2 ranks) per group, 9 sectors each. A
    group's spec gives the mean of each measure and the reach/grasp probabilities; every robot
    gets its own small offset so that samples have no ties."""
    rng = np.random.default_rng(seed)
    rows = []
    for notation, spec in groups.items():
        for s in senses:
            for r in range(robots):
                jitter = rng.normal(0, 0.01)
                for sector in range(9):
                    row = {"notation": notation, "senses": s, "replication": r // 2,
                           "rank": r % 2, "sector": sector, "lifetime_fitness": 0.0,
                           "reached": bool(rng.random() < spec.get("reach", 0.5)),
                           "grasped": bool(rng.random() < spec.get("grasp", 0.2))}
                    for m in MEASURES:
                        row[m] = spec.get(m, 0.5) + jitter + rng.normal(0, 0.005)
                    if s != "normal":
                        row["fitness"] = spec.get(f"fitness {s}", row["fitness"])
                    rows.append(row)
    return pl.DataFrame(rows)


def _verdict(found: pl.DataFrame, claim: str) -> str:
    return found.filter(pl.col("claim") == claim)["verdict"].item()


def test_a_directional_claim_is_reproduced_contradicted_or_not_significant():
    holds = _trials({"pre": {"grasp": 0.05, "reach": 0.5}, "gross": {"grasp": 0.9, "reach": 0.5}})
    fails = _trials({"pre": {"grasp": 0.9}, "gross": {"grasp": 0.05}})
    neither = _trials({"pre": {"grasp": 0.5}, "gross": {"grasp": 0.5}}, robots=4)
    assert _verdict(fd.findings(holds), "F2 grasp up") == fd.REPRODUCED
    assert _verdict(fd.findings(fails), "F2 grasp up") == fd.CONTRADICTED
    assert _verdict(fd.findings(neither), "F2 grasp up") == fd.NOT_SIGNIFICANT


def test_the_papers_level_is_required_for_reproduced():
    # p < 0.05 but not < 0.001 with 4 vs 4 robots (the smallest two-sided p is 0.029)
    few = _trials({"pre": {"grasp": 0.0}, "gross": {"grasp": 1.0}}, robots=4)
    row = fd.findings(few).filter(pl.col("claim") == "F2 grasp up").row(0, named=True)
    assert 0.001 < row["p"] < 0.05 and row["verdict"] == fd.NOT_SIGNIFICANT


def test_a_claim_of_no_difference_flips_with_a_difference():
    same = _trials({"gross": {"speed": 0.3}, "fine": {"speed": 0.3}})
    apart = _trials({"gross": {"speed": 0.3}, "fine": {"speed": 0.6}})
    assert _verdict(fd.findings(same), "F3 speed no different") == fd.REPRODUCED
    assert _verdict(fd.findings(apart), "F3 speed no different") == fd.CONTRADICTED


def test_conditions_compare_replications():
    holds = _trials({"gross": {"fitness": 0.6}, "gross^": {"fitness": 0.2}}, robots=16)
    fails = _trials({"gross": {"fitness": 0.2}, "gross^": {"fitness": 0.6}}, robots=16)
    for table, expected in ((holds, fd.REPRODUCED), (fails, fd.CONTRADICTED)):
        row = fd.findings(table).filter(pl.col("claim") == "F5 gross > gross^").row(0, named=True)
        assert row["verdict"] == expected and row["n"] == "8 vs 8 replications"


def test_about_half_and_all_sectors():
    half = _trials({"pre": {"reach": 0.5}, "fine": {"reach": 0.9}})
    rarely = _trials({"pre": {"reach": 0.02}, "fine": {"reach": 0.0}})
    assert _verdict(fd.findings(half), "F1 reach about half") == fd.REPRODUCED
    assert _verdict(fd.findings(rarely), "F1 reach about half") == fd.CONTRADICTED
    assert _verdict(fd.findings(half), "F3 all sectors") == fd.REPRODUCED
    assert _verdict(fd.findings(rarely), "F3 all sectors") == fd.CONTRADICTED


def test_elbow_locked_and_babbling_against_the_baseline():
    pre = {"var_elbow": 0.1, "var_shoulder": 0.5, "babbling_share": 0.8}
    table = _trials({"pre": pre})
    base = _trials({"pre": {"babbling_share": 0.3}}, seed=1)
    found = fd.findings(table, base)
    assert _verdict(found, "F1 elbow locked") == fd.REPRODUCED
    assert _verdict(found, "F1 babbling") == fd.REPRODUCED
    assert _verdict(fd.findings(table), "F1 babbling") == fd.NOT_RUN  # no baseline
    swapped = _trials({"pre": {"var_elbow": 0.5, "var_shoulder": 0.1}})
    assert _verdict(fd.findings(swapped), "F1 elbow locked") == fd.CONTRADICTED


def test_senses_claims_need_every_sensory_condition():
    spec = {"pre": {"fitness": 0.1, "fitness no-sight": 0.05, "fitness nothing": 0.05},
            "gross": {"fitness": 0.3, "fitness no-sight": 0.2, "fitness nothing": 0.2},
            "fine": {"fitness": 0.6, "fitness no-sight": 0.02, "fitness nothing": 0.02}}
    every = _trials(spec, senses=("normal", "no-touch", "no-sight", "nothing"))
    found = fd.findings(every)
    for claim in ("F4 senses differ", "F4 normal: fine > gross", "F4 normal: gross > pre",
                  "F4 no-sight: gross > fine", "F4 nothing: gross > fine"):
        assert _verdict(found, claim) == fd.REPRODUCED, claim
    only_normal = fd.findings(_trials(spec))
    assert _verdict(only_normal, "F4 senses differ") == fd.NOT_RUN
    assert _verdict(only_normal, "F4 no-sight: gross > fine") == fd.NOT_RUN


def test_every_claim_has_a_row_and_missing_conditions_are_not_run():
    found = fd.findings(_trials({"pre": {}}))
    assert found.height == len(set(found["claim"])) >= 30
    assert set(found["verdict"]) <= set(fd.VERDICTS)
    assert _verdict(found, "F6 fine vs fine^") == fd.NOT_RUN
    assert found.filter(pl.col("verdict") == fd.NOT_RUN)["measured"].str.starts_with(
        "not run").all()
    assert sum(fd.summary(found).values()) == found.height
    with pytest.raises(ValueError, match="lacks columns"):
        fd.findings(pl.DataFrame({"notation": ["pre"]}))


def test_verdict_rule():
    assert fd.verdict(0.0005, +0.2, +1, 0.001) == fd.REPRODUCED
    assert fd.verdict(0.0005, -0.2, +1, 0.001) == fd.CONTRADICTED
    assert fd.verdict(0.01, +0.2, +1, 0.001) == fd.NOT_SIGNIFICANT
    assert fd.verdict(0.2, -0.2, +1, 0.001) == fd.NOT_SIGNIFICANT
    assert fd.verdict(0.2, 0.1, 0, 0.05) == fd.REPRODUCED
    assert fd.verdict(0.01, 0.1, 0, 0.05) == fd.CONTRADICTED
    assert fd.verdict(math.nan, 0.1, +1, 0.05) == fd.NOT_SIGNIFICANT
