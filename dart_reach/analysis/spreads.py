"""How a run's values spread within and between its replications, against the calibration's
``Nesting`` (``calibration.RUN_RATIOS`` spans the committed runs' ratios; docs/results/
replication.md): the spreads of the robots about their replication's mean and of the
replications' effects, per phase and measure."""

from __future__ import annotations

import math

import numpy as np
import polars as pl

from . import summaries

#: The measures whose spreads ``spreads`` estimates: those most claims judge.
SPREAD_MEASURES = ("fitness", "reached", "grasped", "speed", "straightness", "var_elbow",
                   "var_shoulder", "var_trunk", "hand_shoulder_cv", "babbling")


def spreads(table: pl.DataFrame, measures=SPREAD_MEASURES, senses: str = "normal"
            ) -> pl.DataFrame:
    """The spreads of a run's post-evaluation against the calibration's ``Nesting``: per
    phase (``notation``) and measure, from the robots' means under ``senses``
    (``summaries.robot_means``), ``within_sd`` (the pooled s.d. of robots around their
    replication's mean), ``between_sd`` (the s.d. of replication effects: the variance of the
    replication means less within_sd² / robots, 0 when that is negative) and ``ratio`` =
    within / between (inf where between is 0). The calibration simulates ``RUN_RATIOS``."""
    normal = table.filter(pl.col("senses") == senses)
    names = [m for m in measures if m in normal.columns]
    robots_ = summaries.robot_means(normal, names, by=("notation", "replication", "rank"))
    rows = []
    for (notation,), group in robots_.group_by("notation", maintain_order=True):
        for m in names:
            per = [g[m].drop_nans().to_numpy() for _, g in group.group_by("replication",
                                                                          maintain_order=True)]
            per = [x for x in per if len(x) >= 2]
            if len(per) < 2:
                continue
            within = math.sqrt(sum(((x - x.mean()) ** 2).sum() for x in per)
                               / sum(len(x) - 1 for x in per))
            k = np.mean([len(x) for x in per])
            var_means = float(np.var([x.mean() for x in per], ddof=1))
            between = math.sqrt(max(var_means - within ** 2 / k, 0.0))
            rows.append({"phase": notation, "measure": m, "replications": len(per),
                         "robots": float(k), "between_sd": between, "within_sd": within,
                         "ratio": within / between if between > 0 else math.inf})
    return pl.DataFrame(rows)
