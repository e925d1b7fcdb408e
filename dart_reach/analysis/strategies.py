"""The two pre-reaching strategies, still and babbling, told apart by one rule, and Eq. 5's
fitness taken apart per strategy (what each strategy earns).

Trained for some generations, some pre-reaching populations babble and some hold the hand
still; ``strategies`` tells them apart from a post-evaluation table by a rule fixed before
their fitness was compared, and ``by_strategy``, ``by_sector`` and ``by_replication`` average
the per-trial factors of the fitness (``measures.fitness.fitness_terms``: one row per trial of
a table such as ``studies.fitness_terms``'s) over each strategy's trials.

The rule (``STILL_SHARE``): a replication is *still* when fewer than 1 in 20 of its
pre-reaching robots' post-evaluation trials under normal senses babble (``babbling``, the
measure of IV-A-1 in ``measures.kinematics``), *babbling* otherwise. Populations are one kind
or the other: a babbling one babbles in a large share of its trials (random networks already
do in some), a still one in none; the margin lets a still population have a stray babbling
trial without changing kind.
"""

from __future__ import annotations

import polars as pl

from . import formatting, verdicts
from ..measures.kinematics import BABBLING_AMPLITUDE, MOVING_PATH

#: A replication babbling in fewer than this share of its trials is still.
STILL_SHARE = 0.05
STILL, BABBLING = "still", "babbling"
#: The columns ``by_strategy`` and the others average, with their headings.
COLUMNS = {
    "fitness": "fitness",
    "sight_share": "steps in sight",
    "sight_level": "p_sight in sight",
    "touch_share": "steps in touch",
    "touch_level": "p_touch in touch",
    "scoring_share": "steps scoring",
    "scoring_level": "p_multimodal scoring",
    "touch_limits": "touch the min",
    "touched": "trials with a touch",
    "touches": "touches per trial",
    "contact_after_first": "in touch after 1st",
    "contact_bout_s": "touch length (s)",
}


def trained_trials(table: pl.DataFrame, phase: str = "pre", senses: str = "normal"
                   ) -> pl.DataFrame:
    """The trials of ``phase`` under ``senses`` in a post-evaluation or development table,
    the trained robots' only (not the random baseline's, where the table holds it)."""
    rows = table.filter((pl.col("phase") == phase) & (pl.col("senses") == senses))
    return rows.filter(~pl.col("baseline")) if "baseline" in rows.columns else rows


def strategies(evaluation: pl.DataFrame, phase: str = "pre", senses: str = "normal",
               still_share: float = STILL_SHARE, by: tuple[str, ...] = ("replication",)
               ) -> pl.DataFrame:
    """Per replication of ``phase`` in a post-evaluation table (trained robots, not the
    baseline; ``by``: per replication and generation of a development table, say):
    ``trials``, ``babbling_share`` (the share of its trials under ``senses`` that babble) and
    ``strategy``: ``STILL`` below ``still_share``, else ``BABBLING``."""
    return (trained_trials(evaluation, phase, senses).group_by(*by)
            .agg(pl.len().alias("trials"),
                 pl.col("babbling").cast(pl.Float64).mean().alias("babbling_share"))
            .with_columns(pl.when(pl.col("babbling_share") < still_share).then(pl.lit(STILL))
                          .otherwise(pl.lit(BABBLING)).alias("strategy"))
            .sort(*by))


#: The strategy by movement (``movement``): a replication moving in fewer than
#: ``STILL_SHARE`` of its trials is still by movement.
MOVES = "moves"


def movement(evaluation: pl.DataFrame, phase: str = "pre", senses: str = "normal",
             still_share: float = STILL_SHARE, by: tuple[str, ...] = ("replication",)
             ) -> pl.DataFrame:
    """The strategy by the movement's amount and size, beside ``strategies``'s by rhythm:
    per replication (``by``), ``trials``, ``moving_share`` (the share of its trials under
    ``senses`` whose hand path is at least ``MOVING_PATH`` m and amplitude at least
    ``BABBLING_AMPLITUDE`` m, ``kinematics.is_moving``) and ``movement``: ``STILL`` below
    ``still_share``, else ``MOVES``."""
    moving = ((pl.col("hand_path") >= MOVING_PATH)
              & (pl.col("hand_amplitude") >= BABBLING_AMPLITUDE)).fill_null(False)
    return (trained_trials(evaluation, phase, senses).group_by(*by)
            .agg(pl.len().alias("trials"), moving.cast(pl.Float64).mean().alias("moving_share"))
            .with_columns(pl.when(pl.col("moving_share") < still_share).then(pl.lit(STILL))
                          .otherwise(pl.lit(MOVES)).alias("movement"))
            .sort(*by))


def with_strategy(terms: pl.DataFrame, strategy: pl.DataFrame) -> pl.DataFrame:
    """``terms`` (one row per trial, with ``replication``) with its replication's strategy
    and ``touched`` (1.0 when the trial has a touch); every trial's replication must have
    one."""
    out = terms.join(strategy.select("replication", "strategy"), on="replication", how="left")
    if out["strategy"].null_count():
        missing = sorted(set(out.filter(pl.col("strategy").is_null())["replication"]))
        raise ValueError(f"no strategy for replication(s) {missing}")
    return out.with_columns((pl.col("touches") > 0).cast(pl.Float64).alias("touched"))


def _means(table: pl.DataFrame, by: list[str]) -> pl.DataFrame:
    """Mean of each of ``COLUMNS`` over the trials of each group of ``by`` (a level or a
    duration over the trials that have one), with the group's robots and trials."""
    return (table.group_by(by)
            .agg(pl.struct("replication", "rank").n_unique().alias("robots"),
                 pl.len().alias("trials"),
                 *[pl.col(c).fill_nan(None).mean().alias(c) for c in COLUMNS])
            .sort(by, descending=[c == "strategy" for c in by]))


def by_strategy(table: pl.DataFrame) -> pl.DataFrame:
    """Per strategy (``with_strategy``'s table): its replications, robots and trials, and
    the mean of each factor of the fitness over its trials; still first."""
    reps = table.group_by("strategy").agg(pl.col("replication").n_unique().alias("replications"))
    return (_means(table, ["strategy"]).join(reps, on="strategy")
            .select("strategy", "replications", "robots", "trials", *COLUMNS)
            .sort("strategy", descending=True))


def by_sector(table: pl.DataFrame) -> pl.DataFrame:
    """Per strategy and sector (0-8, ``World.sector_point``'s numbering): the factors' means
    over the strategy's trials in the sector."""
    return _means(table, ["strategy", "sector"]).select("strategy", "sector", "trials", *COLUMNS)


def by_replication(table: pl.DataFrame, strategy: pl.DataFrame) -> pl.DataFrame:
    """Per replication: its strategy, babbling share (``strategies``) and the factors' means
    over its robots' trials."""
    return (_means(table, ["replication"]).drop("strategy", strict=False)
            .join(strategy.select("replication", "babbling_share", "strategy"),
                  on="replication")
            .select("replication", "strategy", "babbling_share", "robots", "trials", *COLUMNS)
            .sort("replication"))


def headed(table: pl.DataFrame) -> pl.DataFrame:
    """``table`` with the factors' columns under their headings (``COLUMNS``)."""
    return table.rename({k: v for k, v in COLUMNS.items() if k in table.columns})


def compare(per_replication: pl.DataFrame, columns=("fitness", "touch_share", "touch_level",
                                                    "scoring_share", "scoring_level",
                                                    "sight_share", "sight_level",
                                                    "contact_after_first")) -> pl.DataFrame:
    """Still against babbling with the replication as the unit (``by_replication``'s
    table): per factor, each strategy's median over its replications, the ratio still /
    babbling of the medians, and what the project's gated rule says (``verdicts.directional``
    of "still higher than babbling"; DESIGN.md, "Findings as data"): ``verdict``
    (reproduced: still higher; contradicted: babbling higher; underpowered below 6
    replications a strategy, whatever the data), ``p`` (its two-sided studentized permutation
    Brunner-Munzel p; NaN where gated) and ``smallest p`` (the smallest its test allows at
    these sizes, ``verdicts.smallest_directional_p``)."""
    rows = []
    for column in columns:
        group = {s: per_replication.filter(pl.col("strategy") == s)[column].to_numpy()
                 for s in (STILL, BABBLING)}
        medians = {s: per_replication.filter(pl.col("strategy") == s)[column].median()
                   for s in (STILL, BABBLING)}
        rule = verdicts.directional(group[BABBLING], group[STILL], +1)
        gated = rule.verdict == verdicts.UNDERPOWERED
        rows.append({"factor": COLUMNS[column], "still": medians[STILL],
                     "babbling": medians[BABBLING],
                     "still / babbling": medians[STILL] / medians[BABBLING]
                     if medians[BABBLING] else float("nan"),
                     "still higher?": rule.verdict,
                     "p": float("nan") if gated else min(rule.p, rule.p_against),
                     "smallest p": verdicts.smallest_directional_p(
                         *(len(verdicts.finite(group[s])) for s in (BABBLING, STILL)))})
    return pl.DataFrame(rows)


#: ``compare``'s verdict of "still higher" in the page's words: the only words that say which
#: strategy is higher (docs/results/stillness.md, "In plain words"; the means never do).
WORDS = {verdicts.REPRODUCED: "still higher", verdicts.CONTRADICTED: "babbling higher",
         verdicts.INCONCLUSIVE: "no difference detected",
         verdicts.UNDERPOWERED: "underpowered (neither a difference nor the same can be shown)"}


def decided(compared: pl.DataFrame) -> str:
    """What the gated rule says of each factor of ``compare``'s table, in ``WORDS``: the
    factors grouped by verdict, each decided one with its p, in the table's order; the
    smallest p the two strategies' numbers of replications allow at the end."""
    said: dict[str, list[str]] = {}
    for row in compared.iter_rows(named=True):
        gated = row["still higher?"] == verdicts.UNDERPOWERED
        p = "" if gated else f" (p = {formatting.significant(row['p'])})"
        said.setdefault(WORDS[row["still higher?"]], []).append(f"{row['factor']}{p}")
    smallest = formatting.significant(compared["smallest p"][0])
    return ("; ".join(f"{word}: {', '.join(factors)}" for word, factors in said.items())
            + f" (the smallest p these numbers of replications allow: {smallest})")
