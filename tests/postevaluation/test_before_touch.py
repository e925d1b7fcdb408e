"""A run's babbling before the touch, measured again (``postevaluation.before_touch``): the
column joins the run's final robots' trials by their keys, and a development table (the
snapshots') by their keys and generation; a run without it is left as it is."""

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


def test_attach_joins_the_snapshots_rows_to_a_development_table(tmp_path):
    """A development table (its trials carry their snapshot's ``generation``) takes the
    stored rows of the same generation, never a final robot's nor another snapshot's."""
    stored = pl.DataFrame({"phase_key": ["p"] * 4, "generation": [None, 50, 100, 50],
                           "senses": ["normal"] * 4, "replication": [0] * 4, "rank": [0] * 4,
                           "trial": [3, 3, 3, 4], bt.COLUMN: [True, False, True, True]},
                          schema_overrides={"generation": pl.Int64})
    stored.write_parquet(tmp_path / bt.TABLE)
    development = pl.DataFrame({"phase_key": ["p"] * 3, "generation": [50, 100, 150],
                                "senses": ["normal"] * 3, "replication": [0] * 3,
                                "rank": [0] * 3, "trial": [3, 3, 3]},
                               schema_overrides={"generation": pl.Int32})
    out = bt.attach(development, tmp_path)
    assert out[bt.COLUMN].to_list() == [False, True, None]
    assert out.drop(bt.COLUMN).equals(development)
