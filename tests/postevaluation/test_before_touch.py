"""A run's babbling before the touch, measured again (``postevaluation.before_touch``): the
column joins the run's final robots' trials by their keys, and a run without it is left as
it is."""

from __future__ import annotations

import polars as pl

from dart_reach.postevaluation import before_touch as bt


def _table() -> pl.DataFrame:
    return pl.DataFrame({"phase_key": ["p"] * 3, "senses": ["normal", "normal", "no-ball"],
                         "replication": [0, 0, 1], "rank": [0, 0, 2], "trial": [3, 4, 3],
                         "babbling": [False, True, True]})


def test_attach_joins_the_final_robots_rows_and_leaves_others_null(tmp_path):
    assert bt.attach(_table(), tmp_path).equals(_table())  # no table: unchanged
    stored = pl.DataFrame({"phase_key": ["p", "p", "p"], "generation": [None, None, 50],
                           "senses": ["normal", "no-ball", "normal"], "replication": [0, 1, 0],
                           "rank": [0, 2, 0], "trial": [3, 3, 4],
                           bt.COLUMN: [True, False, True]},
                          schema_overrides={"generation": pl.Int64})
    stored.write_parquet(tmp_path / bt.TABLE)
    out = bt.attach(_table(), tmp_path)
    assert out[bt.COLUMN].to_list() == [True, None, False]  # the snapshot's row is not final
    assert out.drop(bt.COLUMN).equals(_table())
