"""The course of the two pre-reaching strategies over generations.

Trained for some generations, some pre-reaching populations babble and some hold the hand
still (``strategies``). A run that keeps snapshots of its best robots
(``--snapshot-every``) and post-evaluates them (``evaluate --finished-only --development 5``:
the 45 systematic positions, normal senses, and other conditions at the generations to judge)
gives the development table this module reads:

- ``course``: per replication and snapshot, the means of ``MEASURES`` over the best robots'
  trials and the population's strategy by ``strategies.strategies``'s rule (still when fewer
  than ``still_share`` of the trials babble);
- ``switches``: per replication, when the strategy changed and whether it came back;
  ``still_by_line``: how many would be still were the rule's line elsewhere;
- ``claims_of_pre`` and ``judged``: the claims of section IV-A-1 about pre-reachers alone
  (F1, A1, A3, D2, T1, V3: those whose groups are pre-reachers and random networks) judged on
  the snapshots of the given generations as if each were the phase's end, the replication as
  the unit, one Holm family per generation;
- ``verdict_changes`` and ``babbling_by_condition``: which verdicts changed between judged
  generations, and how much the babbling and the still populations babble under each
  condition evaluated there; ``scale_ends``: the replications whose relative change in a
  "same" claim is at the scale's end (a still population's one babbling trial);
- ``fitness_by_strategy`` and ``growth``: whether the two strategies are equally fit at each
  snapshot, and whether the populations' fitness is still rising;
- ``at_budget``: a generation of one run beside another run's final pre-reachers trained for
  as many generations.

Which generations to judge is the caller's choice: every function that judges takes them.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
import polars as pl

from . import findings, strategies, verdicts
from ..postevaluation import snapshots
from .claims import CLAIMS, RATES, Claim, Kind
from .strategies import BABBLING, STILL

#: The measures followed (column: heading): booleans are rates; ``contact_after_first`` is
#: the mean over the trials with a touch.
MEASURES = {"babbling": "babbling rate", "hand_path": "hand path (m)",
            "reached": "reach rate", "grasped": "grasp rate",
            "contact_after_first": "in touch after 1st", "fitness": "fitness"}
#: Lines either side of the rule's 5 % at which ``still_by_line`` counts the still
#: populations: how the count moves with the one lever the rule sets.
LINES = (0.01, 0.05, 0.10, 0.20)
_GROUPS = {"", "pre", "random pre"}


def course(development: pl.DataFrame, phase: str = "pre",
           still_share: float = strategies.STILL_SHARE) -> pl.DataFrame:
    """Per (replication, generation) of ``phase`` in a development table
    (``snapshots.load_development(run, senses=None)`` or its normal trials): ``robots``,
    ``trials``, each of ``MEASURES`` as ``snapshots.course`` gives it (each robot's mean over
    its normal trials, then the mean over the robots; NaN where none has one),
    ``lifetime_fitness`` (the best robot's), the ``babbling_share`` and the ``strategy``
    (``strategies.strategies``). Sorted by replication and generation."""
    rows = development.filter((pl.col("phase") == phase) & (pl.col("senses") == "normal"))
    keys = ["replication", "generation"]
    means = snapshots.course(rows, tuple(MEASURES)).select(
        *keys, "robots", *[m for m in MEASURES if m in rows.columns])
    best = (rows.filter(pl.col("rank") == 0).group_by(keys)
            .agg(pl.col("lifetime_fitness").first()))
    kinds = strategies.strategies(rows, phase, still_share=still_share, by=tuple(keys))
    out = means.join(best, on=keys).join(kinds, on=keys)
    missing = [pl.lit(float("nan")).alias(m) for m in MEASURES if m not in out.columns]
    return (out.with_columns(*missing)
            .select(*keys, "robots", "trials", *MEASURES, "lifetime_fitness",
                    "babbling_share", "strategy")
            .sort(keys))


def switches(course_table: pl.DataFrame) -> pl.DataFrame:
    """Per replication of ``course``'s table: its strategy at the first and at the last
    snapshot, ``changes`` (how many times it changed between consecutive snapshots),
    ``changed_at`` (the generations of the first snapshot after each change, as text),
    ``came_back`` (it returned to a strategy it had left) and ``last_change`` (the generation
    of the last change; null without one)."""
    rows = []
    for (replication,), sub in course_table.sort("generation").group_by(
            "replication", maintain_order=True):
        kinds, generations = sub["strategy"].to_list(), sub["generation"].to_list()
        at = [g for g, k, before in zip(generations[1:], kinds[1:], kinds) if k != before]
        left: set[str] = set()
        came_back = False
        for k, before in zip(kinds[1:], kinds):
            if k != before:
                left.add(before)
                came_back |= k in left
        rows.append({"replication": replication, "first": kinds[0], "last": kinds[-1],
                     "generations": f"{generations[0]}-{generations[-1]}",
                     "changes": len(at), "changed_at": ", ".join(map(str, at)) or "–",
                     "came_back": came_back, "last_change": at[-1] if at else None})
    return pl.DataFrame(rows, schema={"replication": pl.Int64, "first": pl.Utf8,
                                      "last": pl.Utf8, "generations": pl.Utf8,
                                      "changes": pl.Int64, "changed_at": pl.Utf8,
                                      "came_back": pl.Boolean, "last_change": pl.Int64})


def last_strategies(course_table: pl.DataFrame) -> pl.DataFrame:
    """``replication`` and ``strategy`` at the last snapshot of ``course``'s table."""
    return (course_table.filter(pl.col("generation") == pl.col("generation").max())
            .select("replication", "strategy"))


def still_by_line(course_table: pl.DataFrame, lines: Sequence[float] = LINES
                  ) -> pl.DataFrame:
    """Per snapshot of ``course``'s table, how many populations would be still were the
    rule's line (``strategies.STILL_SHARE``) at each of ``lines``: a column ``below L %`` per
    line counts the replications whose ``babbling_share`` is under it."""
    return (course_table.group_by("generation")
            .agg(*[(pl.col("babbling_share") < line).sum().cast(pl.Int64)
                   .alias(f"below {line * 100:g} %") for line in lines])
            .sort("generation"))


def _of_pre(c: Claim) -> bool:
    if c.own or c.infants:
        return False
    if c.source == "development":  # a course within pre-reaching (V3), not across phases
        return c.kind is not Kind.NEVER and {g.split("@")[0] for g in (c.a, c.b)} == {"pre"}
    return c.unit == "robots" and {c.a, c.b} <= _GROUPS and "pre" in (c.a, c.b)


def claims_of_pre(claims: Sequence[Claim] = CLAIMS) -> tuple[Claim, ...]:
    """The paper's claims of its robots (not ``own``, not ``infants``) about pre-reachers
    alone: a post-evaluation claim on robots whose groups are pre-reachers and random
    networks, and a course within pre-reaching (V3: babbling appears)."""
    return tuple(c for c in claims if _of_pre(c))


def judged(development: pl.DataFrame, baseline: pl.DataFrame | None,
           generations: Sequence[int], phase: str = "pre") -> pl.DataFrame:
    """``claims_of_pre`` judged at each of ``generations`` that the development table holds
    (``findings.findings``, one Holm family per generation): the snapshot's robots and
    trials, every condition it was evaluated under, stand for the phase's final
    post-evaluation, and V3 compares the first and last tenth of the snapshots up to that
    generation. ``baseline``: the random networks' trials (``load_evaluation(run,
    baseline=True)``). ``findings.SCHEMA``'s columns with ``generation`` first; empty when no
    generation is there."""
    rows = development.filter(pl.col("phase") == phase)
    claims = claims_of_pre()
    frames = []
    for g in generations:
        at = rows.filter(pl.col("generation") == g)
        if not at.height:
            continue
        upto = rows.filter((pl.col("generation") <= g) & (pl.col("senses") == "normal"))
        found = findings.findings(at, baseline, claims, development=upto)
        frames.append(found.with_columns(pl.lit(g).alias("generation")))
    if not frames:
        return pl.DataFrame(schema={"generation": pl.Int32, **findings.SCHEMA})
    return pl.concat(frames).select("generation", *findings.SCHEMA)


def at_budget(course_table: pl.DataFrame, generation: int, evaluation: pl.DataFrame,
              labels: tuple[str, str]) -> pl.DataFrame:
    """The populations at ``generation`` of the full run (``course``'s table) beside another
    run's final pre-reachers trained for that many generations (its ``evaluation``, the
    trained robots' trials): per population, ``run`` (``labels``: the full run's, the
    other's), replication, babbling_share, strategy and the means of ``MEASURES``."""
    full = (course_table.filter(pl.col("generation") == generation)
            .select("replication", "babbling_share", "strategy", *MEASURES)
            .with_columns(pl.lit(labels[0]).alias("run")))
    other_rows = strategies.trained_trials(evaluation)
    other = course(other_rows.with_columns(pl.lit(generation).alias("generation"),
                                           pl.lit(0).alias("offset"),
                                           pl.lit(float("nan")).alias("lifetime_fitness")))
    other = (other.select("replication", "babbling_share", "strategy", *MEASURES)
             .with_columns(pl.lit(labels[1]).alias("run")))
    return pl.concat([full, other]).select("run", "replication", "babbling_share",
                                           "strategy", *MEASURES)


def verdict_changes(found: pl.DataFrame) -> pl.DataFrame:
    """The claims whose verdict differs between consecutive judged generations of ``judged``'s
    table: ``claim``, ``before`` and ``after`` (the generations), ``was`` and ``now`` (the
    verdicts), in the claims' order within each pair of generations."""
    generations = found["generation"].unique().sort().to_list()
    verdict = {(r["generation"], r["claim"]): r["verdict"] for r in found.iter_rows(named=True)}
    claims = found["claim"].unique(maintain_order=True).to_list()
    rows = [{"claim": c, "before": a, "after": b, "was": verdict[a, c], "now": verdict[b, c]}
            for a, b in zip(generations, generations[1:]) for c in claims
            if (a, c) in verdict and (b, c) in verdict and verdict[a, c] != verdict[b, c]]
    return pl.DataFrame(rows, schema={"claim": pl.Utf8, "before": pl.Int64, "after": pl.Int64,
                                      "was": pl.Utf8, "now": pl.Utf8})


def scale_ends(development: pl.DataFrame, generations: Sequence[int],
               phase: str = "pre") -> pl.DataFrame:
    """The replications at the end of the scale of a "same" claim of ``claims_of_pre``
    (``Kind.SAME_PAIRED``: each replication's change relative to its own level,
    ``verdicts.relative_changes``, from -2 to 2) at each of ``generations`` the development
    table holds under the claim's two conditions: a value of 0 under one and any other under
    the other is at +-2 however small it is (one babbling trial of a still population's 225),
    and one such unit widens the interval of the mean change by itself. Only the claims still
    judged on that scale are listed: a rate's (``claims.RATES``: babbling, reach) is judged
    on its own scale (``verdicts.paired_rate_equivalent``), where 0 is a level like any
    other. ``generation``,
    ``claim``, ``replication``, ``senses`` and ``reference`` (the claim's first condition and
    the replication's value there), ``versus`` and ``changed`` (its second)."""
    rows = development.filter(pl.col("phase") == phase)
    same = [c for c in claims_of_pre() if c.kind is Kind.SAME_PAIRED and c.measure not in RATES]
    frames = [pl.DataFrame(schema={"generation": pl.Int64, "claim": pl.Utf8,
                                   "replication": pl.Int64, "senses": pl.Utf8,
                                   "reference": pl.Float64, "versus": pl.Utf8,
                                   "changed": pl.Float64})]
    for g in generations:
        at = rows.filter(pl.col("generation") == g)
        senses = set(at["senses"].unique())
        for claim in same:
            if not {claim.senses, claim.versus} <= senses or claim.measure not in at.columns:
                continue
            pairs = findings.paired_replications(at, claim)
            ends = np.abs(verdicts.relative_changes(pairs["ref"], pairs["new"])) == 2
            frames.append(pairs.filter(pl.Series(ends)).select(
                pl.lit(g, pl.Int64).alias("generation"), pl.lit(claim.id).alias("claim"),
                pl.col("replication").cast(pl.Int64), pl.lit(claim.senses).alias("senses"),
                pl.col("ref").alias("reference"), pl.lit(claim.versus).alias("versus"),
                pl.col("new").alias("changed")))
    return pl.concat(frames)


def babbling_by_condition(development: pl.DataFrame, course_table: pl.DataFrame,
                          phase: str = "pre", measure: str = "babbling") -> pl.DataFrame:
    """Per generation evaluated under more than normal senses and per condition (``senses``):
    how much the populations babble, each population's babbling rate being the share of its
    best robots' trials that babble by ``measure`` (the detector on the whole trial, or
    ``claims.BABBLING_BOTH``: before the first touch, conditions where it is measured only),
    grouped by its strategy under normal senses (``course``'s table): ``babbling`` (how many
    populations babble), ``median`` (of their rates), ``babbling_low``-``babbling_high``
    (their range) and ``still_high`` (the highest rate of the still populations)."""
    rows = development.filter(pl.col("phase") == phase)
    if measure not in rows.columns:
        return pl.DataFrame(schema={"generation": pl.Int64, "senses": pl.String,
                                    "babbling": pl.UInt32, "median": pl.Float64,
                                    "babbling_low": pl.Float64, "babbling_high": pl.Float64,
                                    "still_high": pl.Float64})
    rows = rows.filter(pl.col(measure).is_not_null())
    several = (rows.group_by("generation").agg(pl.col("senses").n_unique().alias("n"))
               .filter(pl.col("n") > 1)["generation"])
    keys = ["replication", "generation"]
    rates = (rows.filter(pl.col("generation").is_in(several.implode()))
             .group_by(*keys, "senses").agg(pl.col(measure).mean().alias("rate"))
             .join(course_table.select(*keys, "strategy"), on=keys))
    babbles = pl.col("strategy") == BABBLING
    rate = pl.col("rate").filter(babbles)
    return (rates.group_by("generation", "senses")
            .agg(babbles.sum().alias("babbling"), rate.median().alias("median"),
                 rate.min().alias("babbling_low"), rate.max().alias("babbling_high"),
                 pl.col("rate").filter(~babbles).max().alias("still_high"))
            .sort("generation", "senses"))


def fitness_by_strategy(course_table: pl.DataFrame,
                        columns: Sequence[str] = ("fitness", "lifetime_fitness")) -> pl.DataFrame:
    """Are the two strategies equally fit? Per generation of ``course``'s table at which both
    strategies have a population: how many populations ``babbling`` and ``still``, and per
    column (``fitness``: the mean over the best robots' post-evaluation trials;
    ``lifetime_fitness``: the best robot's fitness in training) the median of each strategy's
    populations (``<column>_babbling``, ``<column>_still``) and what the project's gated rules
    say of them, the replication as the unit (section IV-A-1's populations; DESIGN.md,
    "Findings as data"): ``verdict_<column>``, ``verdicts.directional``'s verdict of "the
    babbling populations are fitter" (reproduced: babbling fitter; contradicted: still fitter;
    underpowered below 6 populations a strategy, whatever the data) with ``p_<column>``, its
    two-sided studentized permutation Brunner-Munzel p (NaN where gated); ``same_<column>``,
    ``verdicts.equivalent``'s verdict of "equally fit" (theta within 0.5 +-
    ``verdicts.EQUIVALENCE_MARGIN``); ``theta_<column>`` = P(babbling > still) + P(=) / 2
    and, where the rule is not gated, its interval (``theta_<column>_low``, ``_high``: the
    permutation test inverted, nominally 95 %; ``coverage.label`` says what it covers);
    ``smallest_p``, the smallest p of the directional rule at these sizes
    (``verdicts.smallest_directional_p``)."""
    rows = []
    for (generation,), at in course_table.group_by("generation", maintain_order=True):
        n = {s: at.filter(pl.col("strategy") == s).height for s in (BABBLING, STILL)}
        if not all(n.values()):
            continue
        row = {"generation": generation, "babbling": n[BABBLING], "still": n[STILL]}
        for column in columns:
            for s in (BABBLING, STILL):
                row[f"{column}_{s}"] = at.filter(pl.col("strategy") == s)[column].median()
            still_, babbling_ = (at.filter(pl.col("strategy") == s)[column].to_numpy()
                                 for s in (STILL, BABBLING))
            fitter = verdicts.directional(still_, babbling_, +1)
            gated = fitter.verdict == verdicts.UNDERPOWERED
            row[f"verdict_{column}"] = fitter.verdict
            row[f"p_{column}"] = math.nan if gated else min(fitter.p, fitter.p_against)
            row[f"same_{column}"] = verdicts.equivalent(still_, babbling_).verdict
            row[f"theta_{column}"] = fitter.effect
            row[f"theta_{column}_low"] = math.nan if gated else fitter.low
            row[f"theta_{column}_high"] = math.nan if gated else fitter.high
        row["smallest_p"] = verdicts.smallest_directional_p(n[STILL], n[BABBLING])
        rows.append(row)
    keys = ["generation", "babbling", "still"]
    schema = {**{k: pl.Int64 for k in keys},
              **{f"{c}_{s}": pl.Float64 for c in columns for s in (BABBLING, STILL)},
              **{f"{w}_{c}": pl.Utf8 for c in columns for w in ("verdict", "same")},
              **{f"p_{c}": pl.Float64 for c in columns},
              **{f"theta_{c}{e}": pl.Float64 for c in columns for e in ("", "_low", "_high")},
              "smallest_p": pl.Float64}
    return pl.DataFrame(rows, schema=schema).sort("generation")


def growth(generations: pl.DataFrame, phase: str = "pre", window: int = 10) -> pl.DataFrame:
    """Is the population's fitness still rising? Per replication of a run's generation table
    (``generations.parquet``: one row per replication and generation trained, ``mean`` the
    population's mean fitness), over the last ``window`` generations of ``phase`` and the
    ``window`` before them: ``last`` (the last generation trained), ``mean_before`` and
    ``mean_now`` (the means of the population's mean fitness) and ``ratio`` (now / before):
    at 50 generations and ``window`` 10, generations 41-50 against 31-40. ValueError when fewer than
    2 × ``window`` generations are trained."""
    rows = generations.filter(pl.col("phase") == phase)
    last = rows.group_by("replication").agg(pl.col("generation").max().alias("last"))
    if not rows.height or int(last["last"].min()) < 2 * window:
        raise ValueError(f"growth over {window} generations needs {2 * window} generations of "
                         f"{phase!r} in every replication")
    ago = pl.col("last") - pl.col("generation")
    return (rows.join(last, on="replication")
            .group_by("replication", "last")
            .agg(pl.col("mean").filter(ago.is_between(window, 2 * window - 1)).mean()
                 .alias("mean_before"),
                 pl.col("mean").filter(ago < window).mean().alias("mean_now"))
            .with_columns((pl.col("mean_now") / pl.col("mean_before")).alias("ratio"))
            .sort("replication"))
