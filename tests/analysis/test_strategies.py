"""Still and babbling populations (``analysis.strategies``) on small tables worked by hand."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest

from dart_reach.analysis import strategies
from dart_reach.measures.fitness import TERMS


def evaluation(shares: dict[int, tuple[int, int]]) -> pl.DataFrame:
    """Pre-reachers' normal trials: per replication (babbling trials, trials); plus rows the
    rule must ignore (another phase, other senses, the baseline) that all babble."""
    rows = []
    for r, (babbling, n) in shares.items():
        rows += [{"phase": "pre", "senses": "normal", "baseline": False, "replication": r,
                  "babbling": i < babbling} for i in range(n)]
        rows += [{"phase": p, "senses": s, "baseline": b, "replication": r, "babbling": True}
                 for p, s, b in (("gross", "normal", False), ("pre", "no-ball", False),
                                 ("pre", "normal", True))] * 10
    return pl.DataFrame(rows)


def test_the_rule_splits_at_one_trial_in_twenty():
    found = strategies.strategies(evaluation({0: (0, 40), 1: (1, 40), 2: (2, 40), 3: (30, 40)}))
    assert found["babbling_share"].to_list() == pytest.approx([0, 1 / 40, 2 / 40, 30 / 40])
    assert found["strategy"].to_list() == ["still", "still", "babbling", "babbling"]
    assert found["trials"].to_list() == [40] * 4
    assert strategies.strategies(evaluation({0: (1, 40)}), still_share=0.02)["strategy"][0] \
        == "babbling"


def terms(replication: int, rank: int, sector: int, fitness: float, touches: int,
          sight_level: float = math.nan) -> dict:
    row = dict.fromkeys(TERMS, 0.5)
    return row | {"replication": replication, "rank": rank, "sector": sector,
                  "fitness": fitness, "touches": float(touches), "sight_level": sight_level}


def test_the_means_per_strategy_sector_and_replication():
    table = pl.DataFrame([terms(0, 0, 0, 0.02, 1, 0.4), terms(0, 1, 1, 0.0, 0),
                          terms(1, 0, 0, 0.01, 3, 0.2), terms(1, 0, 1, 0.03, 5, 0.3),
                          terms(2, 0, 0, 0.05, 2, 0.6)])
    strategy = pl.DataFrame({"replication": [0, 1, 2], "babbling_share": [0.0, 0.5, 0.4],
                             "strategy": ["still", "babbling", "babbling"]})
    trials = strategies.with_strategy(table, strategy)
    assert trials["touched"].to_list() == [1.0, 0.0, 1.0, 1.0, 1.0]
    per = strategies.by_strategy(trials)
    assert per["strategy"].to_list() == ["still", "babbling"]
    still, babbling = per.rows(named=True)
    assert (still["replications"], still["robots"], still["trials"]) == (1, 2, 2)
    assert (babbling["replications"], babbling["robots"], babbling["trials"]) == (2, 2, 3)
    assert still["fitness"] == pytest.approx(0.01)
    assert babbling["touches"] == pytest.approx(10 / 3)
    assert still["sight_level"] == pytest.approx(0.4)  # the trial without one is left out
    assert still["touched"] == pytest.approx(0.5)
    sector = strategies.by_sector(trials).filter(pl.col("sector") == 0)
    assert sector["strategy"].to_list() == ["still", "babbling"]
    assert sector["fitness"].to_list() == pytest.approx([0.02, 0.03])
    rep = strategies.by_replication(trials, strategy)
    assert rep["replication"].to_list() == [0, 1, 2]
    assert rep["fitness"].to_list() == pytest.approx([0.01, 0.02, 0.05])
    assert rep["babbling_share"].to_list() == [0.0, 0.5, 0.4]
    assert "steps in sight" in strategies.headed(per).columns


def test_a_trial_without_a_strategy_is_refused():
    table = pl.DataFrame([terms(0, 0, 0, 0.02, 1), terms(5, 0, 0, 0.02, 1)])
    strategy = pl.DataFrame({"replication": [0], "babbling_share": [0.0], "strategy": ["still"]})
    with pytest.raises(ValueError, match=r"replication\(s\) \[5\]"):
        strategies.with_strategy(table, strategy)


def test_strategies_compared_with_the_replication_as_the_unit():
    """3 against 3 apart: Mann-Whitney's exact p would be 0.1 (2 of the 20 splits as
    extreme); the gated rule gives no p there, only underpowered, with the smallest p its
    test allows, 4 / C(6, 3) = 0.2. 6 against 6 apart, still higher: reproduced at its
    smallest p, 4 / C(12, 6) = 4 / 924; babbling higher: contradicted."""
    per = pl.DataFrame({"strategy": ["still"] * 3 + ["babbling"] * 3,
                        "fitness": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
                        "touch_share": [0.5, 0.6, 0.7, 0.5, 0.6, 0.7]})
    table = strategies.compare(per, ("fitness", "touch_share"))
    fit, touch = table.rows(named=True)
    assert (fit["still"], fit["babbling"], fit["still / babbling"]) == (2.0, 5.0, 0.4)
    assert fit["still higher?"] == touch["still higher?"] == "underpowered"
    assert np.isnan(fit["p"]) and fit["smallest p"] == pytest.approx(0.2)
    assert touch["still / babbling"] == 1.0
    assert fit["factor"] == "fitness" and touch["factor"] == "steps in touch"
    six = pl.DataFrame({"strategy": ["still"] * 6 + ["babbling"] * 6,
                        "fitness": [10.0 + i for i in range(6)] + [float(i) for i in range(6)],
                        "touch_share": [float(i) for i in range(6)] + [10.0 + i for i in range(6)]})
    fit, touch = strategies.compare(six, ("fitness", "touch_share")).rows(named=True)
    assert (fit["still higher?"], fit["p"]) == ("reproduced", pytest.approx(4 / 924))
    assert (touch["still higher?"], touch["p"]) == ("contradicted", pytest.approx(4 / 924))


def test_only_the_gated_rule_says_which_strategy_is_higher():
    """``decided`` words ``compare``'s verdicts, never the means: 6 against 6 separated
    replications are "still higher" (fitness) and "babbling higher" (touch), each with its p;
    5 against 5 equally separated are underpowered, with no p, whatever the means say."""
    six = pl.DataFrame({"strategy": [strategies.BABBLING] * 6 + [strategies.STILL] * 6,
                        "fitness": [0.1 * i for i in range(12)],
                        "touch_share": [10.0 + i for i in range(6)] + [float(i) for i in range(6)]})
    assert strategies.decided(strategies.compare(six, ("fitness", "touch_share"))) == (
        "still higher: fitness (p = 0.00433); babbling higher: steps in touch (p = 0.00433) "
        "(the smallest p these numbers of replications allow: 0.00433)")
    five = six.slice(1, 10)
    assert strategies.decided(strategies.compare(five, ("fitness", "touch_share"))) == (
        "underpowered (neither a difference nor the same can be shown): fitness, steps in "
        "touch (the smallest p these numbers of replications allow: 0.0159)")
