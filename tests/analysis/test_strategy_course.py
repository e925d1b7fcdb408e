"""The course of the two pre-reaching strategies (``analysis/strategy_course.py``):
strategies per snapshot by the stillness rule, their changes, the claims of pre-reachers
judged per generation."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest

from dart_reach.analysis import strategy_course as sc
from dart_reach.analysis import verdicts as v
from dart_reach.analysis.findings import UNTESTABLE
from dart_reach.analysis.figures import (STRATEGY_PANELS, TRAINING_PANELS, strategy_figure,
                                         training_by_strategy)
from dart_reach.analysis.strategies import BABBLING, STILL, STILL_SHARE


def _development(babbling_by: dict[tuple[int, int], float], trials: int = 20) -> pl.DataFrame:
    """Two robots per (replication, generation), ``trials`` normal trials each, a share
    ``babbling_by[(replication, generation)]`` of which babble; each measure from the
    trial's index so that the means are known; rank 0's lifetime fitness = generation / 100."""
    rows = []
    for (r, g), share in babbling_by.items():
        n = round(share * 2 * trials)
        for rank in (0, 1):
            for k in range(trials):
                i = rank * trials + k
                rows.append({"condition": "standard", "offset": 0,
                             "phase": "pre", "notation": "pre", "senses": "normal",
                             "replication": r, "rank": rank, "generation": g, "trial": k,
                             "lifetime_fitness": g / 100 if rank == 0 else -1.0,
                             "babbling": i < n, "hand_path": float(rank), "reached": k % 2 == 0,
                             "grasped": False, "fitness": 0.01 * rank,
                             "contact_after_first": 0.5 if k % 2 == 0 else math.nan})
            rows.append(dict(rows[-1], senses="no-ball", babbling=True, hand_path=99.0))
    return pl.DataFrame(rows)


def test_a_populations_strategy_at_each_snapshot_and_its_measures():
    dev = _development({(0, 1): 0.5, (0, 10): 0.0, (0, 20): 0.4, (1, 1): 0.02, (1, 10): 0.0})
    c = sc.course(dev)
    assert c.select("replication", "generation").rows() == [(0, 1), (0, 10), (0, 20),
                                                           (1, 1), (1, 10)]
    assert c["strategy"].to_list() == [BABBLING, STILL, BABBLING, STILL, STILL]
    assert c["babbling_share"].to_list() == pytest.approx([0.5, 0.0, 0.4, 0.025, 0.0])
    assert 0.025 < STILL_SHARE  # one babbling trial in 40 is still still
    row = c.row(0, named=True)  # normal trials only: the no-ball rows change nothing
    assert row["robots"] == 2 and row["trials"] == 40
    assert row["babbling"] == pytest.approx(0.5) and row["hand_path"] == pytest.approx(0.5)
    assert row["reached"] == pytest.approx(0.5) and row["grasped"] == 0.0
    assert row["contact_after_first"] == pytest.approx(0.5)  # trials with a touch only
    assert row["fitness"] == pytest.approx(0.005) and row["lifetime_fitness"] == 0.01


def test_changes_of_strategy_and_coming_back():
    dev = _development({(0, 1): 0.5, (0, 10): 0.0, (0, 20): 0.4, (0, 30): 0.3,
                        (1, 1): 0.0, (1, 10): 0.0, (2, 1): 0.6, (2, 10): 0.0, (2, 20): 0.0})
    turns = sc.switches(sc.course(dev))
    rows = {r["replication"]: r for r in turns.iter_rows(named=True)}
    assert rows[0] == {"replication": 0, "first": BABBLING, "last": BABBLING,
                       "generations": "1-30", "changes": 2, "changed_at": "10, 20",
                       "came_back": True, "last_change": 20}
    assert rows[1]["changes"] == 0 and rows[1]["changed_at"] == "–" and not rows[1]["came_back"]
    assert rows[1]["last_change"] is None
    assert rows[2]["changes"] == 1 and rows[2]["last"] == STILL and not rows[2]["came_back"]


def test_how_many_would_be_still_were_the_line_elsewhere():
    # 40 trials a (replication, generation): shares 0, 1/40, 3/40, 5/40 and 0.3
    dev = _development({(0, 1): 0.0, (1, 1): 0.025, (2, 1): 0.075, (3, 1): 0.125, (4, 1): 0.3,
                        (0, 10): 0.3})
    lines = sc.still_by_line(sc.course(dev), (0.01, STILL_SHARE, 0.1, 0.2))
    assert lines.columns == ["generation", "below 1 %", "below 5 %", "below 10 %", "below 20 %"]
    assert lines.row(0) == (1, 1, 2, 3, 4) and lines.row(1) == (10, 0, 0, 0, 0)
    rule = sc.course(dev).filter(pl.col("generation") == 1)
    assert lines["below 5 %"][0] == (rule["strategy"] == STILL).sum()


def test_the_claims_of_pre_reachers_alone():
    ids = [c.id for c in sc.claims_of_pre()]
    assert "F1 reach about half" in ids and "T1 arm orienting" in ids
    assert "V3 babbling appears in pre" in ids
    assert {i for i in ids if i.startswith("A1")} and {i for i in ids if i.startswith("A3")}
    for other in ("F1 hand-shoulder constant vs fine", "V1 motor suppression at the start of "
                  "gross", "F2 grasp up", "T4 babbling reduced in gross"):
        assert other not in ids  # they need another phase
    assert all(not c.own and not c.infants for c in sc.claims_of_pre())


def test_claims_are_judged_at_the_generations_there_and_on_their_conditions():
    """Each judged generation is one family on its own snapshot: a condition evaluated there
    (no-ball) is judged, one that is not (no-sight) is not run; a generation without a
    snapshot gives no row; the verdicts differ where the snapshots do; a claim its measure
    cannot test is never judged, and says so."""
    shares = {(r, g): (0.6 if g == 50 else 0.0) for r in range(8) for g in (1, 2, 5, 50, 100)}
    dev = _development(shares)
    dev = dev.with_columns(pl.lit(0).alias("sector"))
    found = sc.judged(dev, None, generations=(50, 100, 150))
    assert found["generation"].unique().sort().to_list() == [50, 100]
    per = {(r["generation"], r["claim"]): r for r in found.iter_rows(named=True)}
    assert per[(50, "A3 no sight, pre: babbling same")]["verdict"] == "not run"
    assert per[(50, "A1 ball absent, pre: hand_path same")]["verdict"] != "not run"
    # babbling without the ball: judged on babbling before the touch (validated with and
    # without the ball), which snapshots' tables do not hold: not run, saying which measure
    babbling = per[(50, "A1 ball absent, pre: babbling same")]
    assert babbling["verdict"] == "not run"
    assert babbling["measured"] == "not run: no babbling_before_touch"
    # without sight: a measure not evaluated there is not run; babbling, which no measure
    # validated without sight can see, cannot be tested whatever the data (said as such)
    assert per[(50, "A3 no sight, pre: hand_path same")]["verdict"] == "not run"
    assert not per[(50, "A3 no sight, pre: hand_path same")]["measured"].startswith(UNTESTABLE)
    assert per[(50, "A3 no sight, pre: babbling same")]["measured"].startswith(UNTESTABLE)
    # V3: babbling at the end of the snapshots up to 50 (generation 50) above the start's
    assert per[(50, "V3 babbling appears in pre")]["verdict"] == "reproduced"
    assert per[(100, "V3 babbling appears in pre")]["verdict"] != "reproduced"


def test_a_generation_beside_another_runs_final_populations():
    """Generation 50 of the full run beside a 50-generation run's final pre-reachers: each
    population once, its strategy by the same rule; the other run's baseline and other
    phases and conditions left out."""
    full = sc.course(_development({(0, 50): 0.5, (1, 50): 0.0, (0, 40): 0.0}))
    other = _development({(0, 50): 0.0, (1, 50): 0.0, (2, 50): 0.3}).drop("generation")
    other = pl.concat([other.with_columns(pl.lit(False).alias("baseline")),
                       other.with_columns(pl.lit(True).alias("baseline"), babbling=True),
                       other.with_columns(pl.lit(False).alias("baseline"), phase=pl.lit("gross"),
                                          babbling=True)])
    side = sc.at_budget(full, 50, other, ("full @50", "other"))
    assert side.select("run", "replication", "strategy").rows() == [
        ("full @50", 0, BABBLING), ("full @50", 1, STILL),
        ("other", 0, STILL), ("other", 1, STILL), ("other", 2, BABBLING)]
    assert side.filter(pl.col("run") == "other")["babbling_share"].to_list() == pytest.approx(
        [0.0, 0.0, 0.3])


def test_the_figure_draws_each_population_with_its_strategy():
    c = sc.course(_development({(0, 1): 0.5, (0, 10): 0.0, (0, 20): 0.4,
                                (1, 1): 0.02, (1, 10): 0.3}))
    fig = strategy_figure(c, STILL_SHARE)
    for ax, column in zip(fig.axes, STRATEGY_PANELS):
        lines = {line.get_label(): line for line in ax.get_lines()}
        for r in (0, 1):
            mine = c.filter(pl.col("replication") == r)
            x, y = lines[f"rep {r}"].get_data()
            assert list(x) == mine["generation"].to_list()
            assert list(y) == pytest.approx(mine[column].to_list())
        # per replication: the babbling snapshots filled, the still ones open
        filled = [pc.get_offsets().tolist() for pc in ax.collections[0::2]]
        hollow = [pc.get_offsets().tolist() for pc in ax.collections[1::2]]
        assert [len(f) for f in filled] == [2, 1] and [len(h) for h in hollow] == [1, 1]
        assert hollow[0][0][0] == 10 and hollow[1][0][0] == 1
    assert fig.axes[0].get_lines()[-1].get_ydata()[0] == STILL_SHARE


def test_the_training_figure_draws_running_means_marked_by_strategy():
    rng = np.random.default_rng(7)
    stats = pl.DataFrame([{"phase": "pre", "replication": r, "generation": g,
                           "best": float(rng.random()), "mean": float(rng.random())}
                          for r in (0, 1) for g in range(1, 16)]
                         + [{"phase": "gross", "replication": 0, "generation": 1,
                             "best": 9.0, "mean": 9.0}])
    fig = training_by_strategy(stats, {0: BABBLING, 1: STILL}, STILL, window=4)
    for ax, column in zip(fig.axes, TRAINING_PANELS):
        thick = {line.get_label(): line for line in ax.get_lines()
                 if not line.get_label().startswith("_")}
        assert set(thick) == {f"rep 0 ({BABBLING})", f"rep 1 ({STILL})"}
        for r, label in enumerate(sorted(thick)):
            raw = stats.filter((pl.col("replication") == r) & (pl.col("phase") == "pre"))
            x, y = thick[label].get_data()
            assert list(x) == list(range(4, 16))  # from the window-th generation on
            assert list(y) == pytest.approx(np.convolve(raw[column], np.ones(4) / 4, "valid"))
        assert thick[f"rep 0 ({BABBLING})"].get_linestyle() == "-"
        assert thick[f"rep 1 ({STILL})"].get_linestyle() == "--"


def test_the_verdicts_that_changed_between_judged_generations():
    found = pl.DataFrame({"generation": [50, 50, 100, 100, 150],
                          "claim": ["a", "b", "a", "b", "b"],
                          "verdict": ["inconclusive", "reproduced", "contradicted",
                                      "reproduced", "inconclusive"]})
    changed = sc.verdict_changes(found)
    assert changed.rows() == [("a", 50, 100, "inconclusive", "contradicted"),
                              ("b", 100, 150, "reproduced", "inconclusive")]
    assert sc.verdict_changes(found.filter(pl.col("generation") == 50)).height == 0


def test_babbling_under_each_condition_by_strategy():
    """Replication 0 babbles under normal senses (half its trials) and in every no-ball trial;
    replication 1 is still under normal senses and babbles in its no-ball trials too, which
    shows as the still populations' highest rate; generation 1 has normal senses only."""
    dev = _development({(0, 50): 0.5, (1, 50): 0.0, (0, 1): 0.5, (1, 1): 0.0})
    dev = dev.filter((pl.col("generation") == 50) | (pl.col("senses") == "normal"))
    rates = sc.babbling_by_condition(dev, sc.course(dev))
    assert rates.select("generation", "senses").rows() == [(50, "no-ball"), (50, "normal")]
    normal, no_ball = (rates.filter(pl.col("senses") == s).row(0, named=True)
                       for s in ("normal", "no-ball"))
    assert normal["babbling"] == 1 and normal["median"] == pytest.approx(0.5)
    assert normal["still_high"] == 0.0
    assert no_ball["median"] == 1.0 and no_ball["still_high"] == 1.0
    # by another measure (A1's babbling before the touch) where it is measured: the rates
    # are that column's, and a table without it has no rows
    touch = dev.with_columns((~pl.col("babbling")).alias("babbling_before_touch"))
    other = sc.babbling_by_condition(touch, sc.course(dev), measure="babbling_before_touch")
    normal = other.filter(pl.col("senses") == "normal").row(0, named=True)
    assert normal["median"] == pytest.approx(0.5) and normal["still_high"] == 1.0
    assert sc.babbling_by_condition(dev, sc.course(dev),
                                    measure="babbling_before_touch").height == 0


def test_a_rates_same_claim_is_never_at_a_scale_end():
    """At generation 50 replication 1 is still and babbles in every no-ball trial (0 against
    1), replication 2 babbles in 1 normal trial of 40 and in no no-ball trial (0.025 against
    0): on the relative scale both were at its end (2 and -2, ``verdicts.relative_changes``);
    babbling is a rate, judged on its own scale, so no babbling claim is listed."""
    dev = _development({(0, 50): 0.5, (1, 50): 0.0, (2, 50): 0.025, (1, 10): 0.0})
    dev = dev.with_columns(pl.when((pl.col("senses") == "no-ball") & (pl.col("replication") == 2))
                           .then(False).otherwise(pl.col("babbling")).alias("babbling"),
                           (pl.col("trial") % 9).alias("sector"))  # the robots' means need it
    pairs = [(0.0, 1.0), (0.025, 0.0)]
    assert list(np.abs(v.relative_changes(*zip(*pairs)))) == [2.0, 2.0]
    assert sc.scale_ends(dev, (10, 50)).height == 0


def _course(rows: list[tuple[int, int, str, float]]) -> pl.DataFrame:
    """A ``course`` table of (generation, replication, strategy, fitness) rows; the training's
    best fitness is twice the post-evaluation's."""
    g, r, s, f = zip(*rows)
    return pl.DataFrame({"generation": g, "replication": r, "strategy": s, "fitness": f,
                         "lifetime_fitness": [2 * x for x in f]})


def test_whether_the_strategies_are_equally_fit():
    """At generation 10 every babbling population out-earns every still one, 4 against 3:
    below the gate of 6 a group, so the rule says underpowered and gives no p and no
    interval (the smallest p of its test there: 4 / C(7, 3) = 4 / 35); at 20 they interleave;
    at 30 no population is still, so the generation has no row."""
    rows = ([(10, r, BABBLING, 0.1 + r) for r in range(4)]
            + [(10, r, STILL, 0.01 * r) for r in range(4, 7)]
            + [(20, r, BABBLING if r % 2 else STILL, float(r)) for r in range(7)]
            + [(30, r, BABBLING, 1.0) for r in range(7)])
    fit = sc.fitness_by_strategy(_course(rows))
    assert fit["generation"].to_list() == [10, 20]
    at10, at20 = fit.row(0, named=True), fit.row(1, named=True)
    assert (at10["babbling"], at10["still"]) == (4, 3)
    assert at10["smallest_p"] == pytest.approx(4 / 35)
    for column in ("fitness", "lifetime_fitness"):
        assert at10[f"verdict_{column}"] == v.UNDERPOWERED
        assert at10[f"same_{column}"] == v.UNDERPOWERED
        assert np.isnan(at10[f"p_{column}"]) and np.isnan(at10[f"theta_{column}_low"])
        assert at10[f"theta_{column}"] == 1.0  # every babbling population above every still
    assert at10["fitness_babbling"] == pytest.approx(1.6)  # median of 0.1, 1.1, 2.1, 3.1
    assert at10["fitness_still"] == pytest.approx(0.05)
    assert at10["lifetime_fitness_still"] == pytest.approx(0.1)
    assert (at20["babbling"], at20["still"]) == (3, 4)
    assert at20["verdict_fitness"] == v.UNDERPOWERED
    assert at20["theta_fitness"] == pytest.approx(6 / 12)  # 1, 3, 5 above 0, 2, 4, 6: 6 of 12


def test_the_strategies_fitness_is_judged_once_both_have_6_populations():
    """6 babbling populations above 6 still ones: the rule decides "babbling fitter" at the
    smallest p its permutation test has at 6 vs 6, 4 / C(12, 6) = 4 / 924 (both complete
    separations and the two splits one pair short of them); the still ones above: "still
    fitter" (contradicted); interleaved and close (0.0, 0.1, ... against 0.05, 0.15, ...): no
    difference, nor the same at 6 a group."""
    ahead = ([(10, r, BABBLING, 10.0 + r) for r in range(6)]
             + [(10, r, STILL, float(r - 6)) for r in range(6, 12)])
    behind = ([(20, r, BABBLING, float(r)) for r in range(6)]
              + [(20, r, STILL, 10.0 + r) for r in range(6, 12)])
    mixed = ([(30, r, BABBLING, 0.1 * r) for r in range(6)]
             + [(30, r, STILL, 0.1 * (r - 6) + 0.05) for r in range(6, 12)])
    fit = sc.fitness_by_strategy(_course(ahead + behind + mixed))
    at10, at20, at30 = fit.iter_rows(named=True)
    assert at10["smallest_p"] == pytest.approx(4 / 924)
    assert (at10["verdict_fitness"], at10["p_fitness"]) == (v.REPRODUCED, pytest.approx(4 / 924))
    assert at10["theta_fitness_low"] > 0.5
    assert (at20["verdict_fitness"], at20["p_fitness"]) == (v.CONTRADICTED,
                                                            pytest.approx(4 / 924))
    assert at20["theta_fitness_high"] < 0.5
    assert at30["verdict_fitness"] == v.INCONCLUSIVE and at30["p_fitness"] > 0.5
    assert at30["same_fitness"] != v.REPRODUCED


def test_whether_the_fitness_is_still_rising():
    """Replication 0's mean fitness doubles from generations 11-20 to 21-30, replication 1's
    stays; generations 1-10 weigh nothing; fewer than 20 generations cannot say."""
    def stats(last: int) -> pl.DataFrame:
        return pl.DataFrame([{"phase": "pre", "replication": r, "generation": g,
                              "mean": (2.0 if r == 0 and g > last - 10 else 1.0)
                              * (100.0 if g <= last - 20 else 1.0)}
                             for r in (0, 1) for g in range(1, last + 1)]
                            + [{"phase": "gross", "replication": 0, "generation": 1,
                                "mean": 50.0}])
    rising = sc.growth(stats(30))
    assert rising.select("replication", "last").rows() == [(0, 30), (1, 30)]
    assert rising["mean_before"].to_list() == [1.0, 1.0]
    assert rising["ratio"].to_list() == [2.0, 1.0]
    assert sc.growth(stats(20))["ratio"].to_list() == [2.0, 1.0]
    with pytest.raises(ValueError, match="needs 20 generations"):
        sc.growth(stats(19))
