"""The levers study's page (reports.levers) is its rendering from the committed tables, and its
rules are the pre-registered ones (docs/results/levers.md): the paper's pre-reacher per
replication, and the screen's choice of the two further arms."""

from __future__ import annotations

import numpy as np
import polars as pl
import pytest

from dart_reach.analysis.profile import (Criteria, more_than_reference, profiles,
                                         share_interval)
from dart_reach.postevaluation.snapshots import load_development
from reports import levers


def test_the_committed_page_is_its_rendering():
    assert levers.PAGE.read_text() == levers.page(), "run 'python -m reports.levers'"


def test_the_pre_registration_is_kept_above_the_results():
    text = levers.PAGE.read_text()
    plan = text[: text.index(levers.MARK)]
    for fixed in ("between 0.35 and 0.65", "at least 0.31 m", "below 0.05",
                  "at least half of the trials", "at least 3 of its 6", "p < 0.05",
                  "seed 2027", "50 generations x 6"):
        assert fixed in plan


def _trials(replication, reached, elbow, shoulder, trunk, hs, cv, babbling, no_ball):
    rows = []
    for k in range(20):
        rows.append({"replication": replication, "senses": "normal", "reached": k < reached,
                     "var_elbow": elbow, "var_shoulder": shoulder, "var_trunk": trunk,
                     "hand_shoulder_mean": hs, "hand_shoulder_cv": cv, "hand_path": 5.0,
                     "babbling": k < babbling, "fitness": 0.02})
        rows.append(dict(rows[-1], senses="no-ball", babbling=k < no_ball))
    return rows


def test_the_paper_pre_reacher_needs_all_four_criteria():
    paper = dict(reached=10, elbow=0.05, shoulder=0.2, trunk=0.1, hs=0.33, cv=0.02, babbling=0,
                 no_ball=12)
    one_off = [("reached", 15), ("elbow", 0.15), ("hs", 0.29), ("cv", 0.06), ("no_ball", 9)]
    rows = _trials(0, **paper)
    for r, (key, value) in enumerate(one_off, start=1):
        rows += _trials(r, **dict(paper, **{key: value}))
    prof = profiles(pl.DataFrame(rows))
    assert prof["paper"].to_list() == [True, False, False, False, False, False]
    assert prof.row(1, named=True)["is_reach"] is False  # 0.75 is outside 0.35-0.65
    assert prof.row(5, named=True)["is_babbling"] is False
    assert Criteria().reach_band == (0.35, 0.65)


def test_share_intervals_and_the_reference_test_are_the_exact_ones():
    assert share_interval(0, 6) == pytest.approx((0.0, 0.4593), abs=1e-4)
    # 3 of 6 against 0 of 20: hypergeometric tail C(6,3) / C(26,3)
    assert more_than_reference(3, 6, 0, 20) == pytest.approx(20 / 2600)
    assert more_than_reference(2, 6, 0, 20) == pytest.approx(15 / 325)
    assert more_than_reference(1, 6, 0, 20) > 0.05  # one arm's replication is not enough


def test_the_screen_rule_picks_the_levers_that_pay_the_extended_arm():
    rng = np.random.default_rng(0)
    rows = []
    extension = rng.uniform(0.2, 0.35, 20)
    for arm in ("today", "start-zero", "self-collision"):
        for robot, hs in enumerate(extension):
            for k in range(3):
                # today pays the flexed arm, self-collision the extended one, the touch pays
                # and the start nothing in particular
                faces = {"today": 0.4 - hs, "self-collision": hs, "start-zero": 0.3}[arm]
                rows.append({"arm": arm, "senses": "normal", "replication": robot // 2,
                             "rank": robot % 2, "trial": k, "hand_shoulder_mean": hs,
                             "babbling": bool(k % 2), "fitness_faces": faces + 0.001 * k,
                             "fitness_binary": 0.3 + 0.01 * rng.random(),
                             "fitness_capped": hs + 0.01 * rng.random()})
    choice, ref_arm, _ = levers.choose_arms(pl.DataFrame(rows))
    assert ref_arm < -0.9
    chosen = set(choice.filter(pl.col("chosen"))["candidate"])
    assert chosen == {"self-collision", "capped"}


def test_each_arms_eq5_table_is_its_robots_at_50_with_their_post_evaluated_fitness():
    """An arm's robots at 50 run again under the arm's own levers (read from its manifest):
    every robot its development.parquet post-evaluated there, on every position, with the
    fitness it stored there, to the last bit (the far arm's would differ under today's scene);
    and every arm post-evaluated at 50 has its table."""
    from dart_reach.postevaluation import results
    from dart_reach.studies import fitness_terms

    keys = ["generation", "replication", "rank", "trial", "sector"]
    checked = 0
    for arm in levers.ARMS:
        run_dir = levers.LEVERS / arm
        assert fitness_terms.missing(run_dir, (levers.JUDGED,)) == [], \
            f"run 'python -m reports.levers --terms' ({arm})"
        table = results.read_table(run_dir / fitness_terms.TABLE)
        if table is None:
            continue
        assert table["generation"].unique().to_list() == [levers.JUDGED]
        assert (sorted(table.select("replication", "rank").unique().iter_rows())
                == fitness_terms.snapshot_pre(run_dir, levers.JUDGED))
        development = load_development(run_dir)
        joined = table.join(development.select(*keys, pl.col("fitness").alias("evaluated")),
                            on=keys)
        assert joined.height == table.height == 45 * 30
        assert (joined["fitness"] == joined["evaluated"]).all()
        checked += 1
    assert checked >= 1


def test_the_pre_reaching_phase_taken_apart_is_the_runs_own(tmp_path):
    """The levers arms train the condition ``pre-only``, the reference's runs the standard
    one: each run's one pre-reaching phase (conditions sharing it count once); a run with two
    different ones is refused unless the condition is named."""
    from dart_reach.evolution.conditions import load_condition
    from dart_reach.evolution.rundir import RunDirectory
    from dart_reach.evolution.settings import Settings
    from dart_reach.studies import fitness_terms

    far = RunDirectory.open(levers.LEVERS / "far")
    assert [c.name for c in far.conditions] == ["pre-only"]
    assert fitness_terms.pre_phase_key(far) == far.conditions[0].phases[0].key
    standard = load_condition("standard")
    pre_only = far.conditions[0]
    both = RunDirectory(tmp_path / "both", [pre_only, standard], Settings())
    assert fitness_terms.pre_phase_key(both, "standard") == standard.phases[0].key
    with pytest.raises(ValueError, match="name the condition"):
        fitness_terms.pre_phase_key(both)
    text = (levers.ROOT / "docs" / "learning-check.toml").read_text()
    other = tmp_path / "other.toml"
    other.write_text(text.replace('name = "pre-only"', 'name = "pre-other"'))
    two = RunDirectory(tmp_path / "two", [pre_only, load_condition(str(other))], Settings())
    with pytest.raises(ValueError, match="no single pre-reaching phase.*'pre-only', 'pre-other'"):
        fitness_terms.pre_phase_key(two)
    assert fitness_terms.pre_phase_key(two, "pre-only") == pre_only.phases[0].key
    with pytest.raises(ValueError, match="'standard' has no pre-reaching phase"):
        fitness_terms.pre_phase_key(two, "standard")


def test_the_decision_rule_is_the_pre_registered_one():
    """At least 3 of 6 and Fisher's p < 0.05 against the reference's 0 of 20; the larger
    share among those that qualify; on a tie (every arm changes one lever) the earlier arm."""
    def verdict(arm, k, n=6, k_ref=0, n_ref=20):
        return arm, k, n, more_than_reference(k, n, k_ref, n_ref)

    assert levers.recommended([verdict("far", 2), verdict("capped", 1)]) is None  # p 0.046, k 2
    assert levers.recommended([verdict("far", 3), verdict("capped", 2)]) == "far"
    assert levers.recommended([verdict("far", 3), verdict("capped", 4)]) == "capped"
    assert levers.recommended([verdict("far", 4), verdict("capped", 4)]) == "far"
    # 3 of 6 is not enough against a reference that has them too
    assert levers.recommended([verdict("far", 3, k_ref=8)]) is None
    assert levers.recommended([]) is None


def test_the_page_says_the_decision_is_the_pre_registered_raw_fisher_rule():
    """The sentence under the decision names the rule (raw Fisher, not a gated rule) and
    carries each arm's count and p as ``recommended`` took them: a wrong p or count fails."""
    text = levers.PAGE.read_text()
    ref = levers.reference_profiles()
    k_ref, n_ref = int(ref["paper"].sum()), ref.height
    judged = []
    for arm in levers.ARMS:
        at = levers.arm_profiles(arm).filter(pl.col("generation") == levers.JUDGED)
        k, n = int(at["paper"].sum()), at.height
        judged.append((arm, k, n, more_than_reference(k, n, k_ref, n_ref)))
    sentence = levers.decision_basis(judged, k_ref, n_ref)
    assert sentence in text
    assert "raw one-sided Fisher exact test" in sentence and "not one of" in sentence
    for arm, k, n, p in judged:
        assert f"`{arm}` {k} of {n}, p = {p:.3f}" in sentence
    assert ("none qualifies." in sentence) == (levers.recommended(judged) is None)
