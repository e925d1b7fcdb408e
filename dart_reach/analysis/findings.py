"""Each claim of ``claims.CLAIMS`` judged against runs' post-evaluation: ``findings(table,
baseline, development)`` returns one row per claim with the verdict, the effect and its
interval, p, Holm's adjusted p, whether the paper's own level is met, and beside it the
paper's own analysis with robots as units.

The unit of the headline verdict is the *replication*: a robot's value is its mean over its
post-evaluation trials, a replication's the mean over its robots (or, for the conditions of
Fig. 10, its best robot's post-evaluation fitness), and every rule works on replications
(random genomes of ``evaluate --baseline``, independent draws, are their own units). The
paper pools robots (Figs. 5-9: "50 robots ... for 45 trials"); that analysis is given as
``verdict_robots`` and never counted in the headline, because robots of one replication are
the best of one population, not independent draws (``calibration.robot_level_null``).

Multiplicity: one family per call (one budget) of the paper's claims (``own`` False); Holm's
adjustment of the p of each claim as stated (``p_holm``) and of the test of its opposite
(``p_holm_against``). The rules are calibrated by simulation (``calibration``).
"""

from __future__ import annotations

import math

import numpy as np
import polars as pl

from . import stats, summaries, verdicts
from .claims import (ABOUT_HALF, CLAIMS, RATES, SENSES, SWIPES_AFTER_MISS, SWIPES_AGAIN_UNITS,
                     Claim, Kind)
from .verdicts import ALPHA, NOT_RUN, VERDICTS, Outcome

_ROBOT = ("notation", "run", "replication", "rank")
_REPLICATION = ("notation", "run", "replication")
#: Per-robot measures computed from the sectors, not averaged over trials.
_SPREAD = ("sectors_reached", "reach_entropy")
_MEASURES = tuple(sorted({m for c in CLAIMS for m in (c.measure, c.versus_measure) if m}
                         - set(_SPREAD)))
#: Who a claim is of: the paper's robots (the headline), infants (Table I, counted apart) or
#: the project (its own reading, counted apart).
ROBOTS, INFANTS, OWN = "the paper's robots", "infants", "the project's own"
READINGS = (ROBOTS, INFANTS, OWN)
SCHEMA = {"claim": pl.Utf8, "section": pl.Utf8, "paper": pl.Utf8, "kind": pl.Utf8,
          "own": pl.Boolean, "infants": pl.Boolean,
          "measured": pl.Utf8, "test": pl.Utf8, "n": pl.Utf8,
          "effect": pl.Float64, "effect_low": pl.Float64, "effect_high": pl.Float64,
          "confidence": pl.Float64, "p": pl.Float64, "p_against": pl.Float64,
          "p_holm": pl.Float64, "p_holm_against": pl.Float64, "paper_level_met": pl.Boolean,
          "verdict": pl.Utf8, "verdict_robots": pl.Utf8, "p_robots": pl.Float64,
          "note": pl.Utf8}

#: How each kind is tested, said once (the report's table and docs/guides/analysis.md).
TESTS = {
    Kind.DIRECTIONAL.value: "two-sided studentized permutation Brunner-Munzel test on "
                            "replications (null: theta = P(b > a) = 0.5, whatever the shapes; "
                            "underpowered below 6 a group); effect: theta [nominally 95 % CI, "
                            "the test inverted: less away from 0.5 between groups of unequal "
                            "shapes, as the calibration measured]",
    Kind.NOT_BETTER.value: "non-superiority on theta = P(b better than a): upper one-sided "
                           f"95 % bound below {0.5 + verdicts.EQUIVALENCE_MARGIN:g}; "
                           "contradicted when b is better (one-sided studentized permutation "
                           "Brunner-Munzel); underpowered below 6 a group",
    Kind.NO_DIFFERENCE.value: "equivalence: two one-sided tests on theta = P(b > a) within "
                              f"0.5 +- {verdicts.EQUIVALENCE_MARGIN:g}; contradicted by a "
                              "two-sided studentized permutation Brunner-Munzel difference; "
                              "underpowered below 6 a group",
    Kind.BAND.value: f"Student's t {100 * (1 - 2 * verdicts.BAND_LEVEL):g} % interval of the "
                     "mean over replications inside the band; underpowered below "
                     f"{verdicts.BAND_MIN_UNITS} replications",
    Kind.EVERY_SECTOR.value: "every sector's reach and grasp rate: one-sided "
                             f"{100 * (1 - verdicts.SECTOR_LEVEL):g} % lower bound over "
                             f"replications above {verdicts.SECTOR_FLOOR:g}; contradicted "
                             "when a Bonferroni upper bound is below",
    Kind.AT_LEAST.value: f"one-sided {100 * (1 - verdicts.SECTOR_LEVEL):g} % lower bound of the "
                         "mean over replications above the claim's floor; contradicted when the "
                         "upper bound is below it",
    Kind.NEVER.value: "\"never\" read as less than pre-reachers: the directional test on "
                      "replications",
    Kind.PAIRED.value: f"Friedman's test at {verdicts.FRIEDMAN_LEVEL:g}, replication as block; "
                       "contradicted when every pair of "
                       "conditions is equivalent (the exact sign-flip TOST within "
                       f"+-{verdicts.PAIRED_MARGIN:.0%}, each one-sided test at "
                       f"{verdicts.PAIRED_EQUIVALENCE_LEVEL:g}; never through lopsided changes)",
    Kind.SAME_PAIRED.value: "the exact sign-flip test on replications as two one-sided tests, "
                            f"each at {verdicts.PAIRED_EQUIVALENCE_LEVEL:g}: a rate's mean "
                            f"change within +-{verdicts.RATE_MARGIN:g} (rate units; n the "
                            "replications, never the trials), another measure's mean change "
                            "relative to each replication's level within "
                            f"+-{verdicts.PAIRED_MARGIN:.0%}; never where the changes are "
                            "lopsided; contradicted by a sign-flip difference (two-tailed)",
    Kind.CHANGE_PAIRED.value: f"Wilcoxon signed-rank on replications (exact) at "
                              f"{verdicts.PAIRED_CHANGE_LEVEL:g}; effect: Hodges-Lehmann change "
                              f"[exact {100 * (1 - verdicts.PAIRED_CHANGE_LEVEL):g} % CI]",
    Kind.WITHIN.value: "Wilcoxon signed-rank on replications of one measure against another, "
                       f"at {verdicts.PAIRED_CHANGE_LEVEL:g}",
}


# ------------------------------------------------------------------------------ units
def _with_run(table: pl.DataFrame) -> pl.DataFrame:
    return table if "run" in table.columns else table.with_columns(pl.lit("").alias("run"))


def robots(table: pl.DataFrame, senses: str = "normal") -> pl.DataFrame:
    """One row per robot (notation, run, replication, rank) of ``senses``: the mean over its
    trials of each measure (booleans: rates), ``sectors_reached`` (sectors in which it reached
    the ball at least once, Fig. 7) and ``reach_entropy`` (``summaries.peripersonal_space``)."""
    table = _with_run(table).filter(pl.col("senses") == senses)
    if {"swipes", "grasped"} <= set(table.columns):
        failed = ~pl.col("grasped") & (pl.col("swipes") >= 1)
        table = table.with_columns(pl.when(failed).then(pl.col("swipes"))
                                   .otherwise(None).cast(pl.Float64).alias(SWIPES_AFTER_MISS))
    present = [m for m in _MEASURES if m in table.columns]
    means = summaries.robot_means(table, present, by=_ROBOT)
    spread = (summaries.peripersonal_space(table, by=_ROBOT)
              .select(*_ROBOT, *[pl.col(c).cast(pl.Float64) for c in _SPREAD]))
    return means.join(spread, on=list(_ROBOT), how="left", maintain_order="left")


def replications(table: pl.DataFrame, senses: str = "normal") -> pl.DataFrame:
    """One row per replication (notation, run, replication): its best robot's post-evaluation
    fitness, the unit of Fig. 10."""
    table = _with_run(table)
    if table.filter((pl.col("senses") == senses) & (pl.col("rank") == 0)).height == 0:
        return pl.DataFrame(schema={"notation": pl.Utf8, "fitness": pl.Float64})
    return summaries.replication_performance(table, senses=senses, by=("notation", "run"))


def replication_means(units: pl.DataFrame, *measures: str) -> pl.DataFrame:
    """Per (notation, run, replication): the mean of each measure over its robots (NaN robots
    left out)."""
    return (units.group_by(*_REPLICATION)
            .agg(*[pl.col(m).filter(pl.col(m).is_not_nan()).mean() for m in measures])
            .sort(*_REPLICATION))


def _values(units: pl.DataFrame, group: str, measure: str) -> np.ndarray:
    if measure not in units.columns or "notation" not in units.columns:
        return np.zeros(0)
    v = units.filter(pl.col("notation") == group)[measure].cast(pl.Float64).to_numpy()
    return v[np.isfinite(v)]


def _window(group: str, generations: pl.Series) -> tuple[str, int, int]:
    """"phase@start" / "phase@end": the first / last tenth (at least one generation) of the
    phase's generations; windows never overlap."""
    phase, where = group.split("@")
    last = int(generations.max())
    tenth = max(1, math.ceil(last / 10))
    return (phase, 1, tenth) if where == "start" else (phase, last - tenth + 1, last)


class _Data:
    """The tables a claim is judged on, built once per ``findings`` call."""

    def __init__(self, table, baseline, development):
        self.table = _with_run(table)
        self.development = _with_run(development) if development is not None else None
        self._robots: dict[str, pl.DataFrame] = {}
        # random pre-reaching networks: independent robots, their own units
        self.baseline = (robots(baseline).filter(pl.col("notation") == "pre")
                         .with_columns(pl.lit("random pre").alias("notation"))
                         if baseline is not None and baseline.height else None)
        self.replications = replications(table)

    def robots(self, senses: str) -> pl.DataFrame:
        if senses not in self._robots:
            self._robots[senses] = robots(self.table, senses)
        return self._robots[senses]

    def two_groups(self, claim: Claim) -> tuple[pl.DataFrame, pl.DataFrame | None]:
        """(replication units, robot units or None) of a two-group claim's measure."""
        if claim.unit == "replications":
            return self.replications, None
        if claim.measure not in self.table.columns and claim.measure not in _SPREAD:
            empty = pl.DataFrame(schema={"notation": pl.Utf8, claim.measure: pl.Float64})
            return empty, empty
        if claim.versus:
            rob = self.drops(claim)
        else:
            rob = self.robots(claim.senses)
        if claim.measure not in rob.columns:
            return rob, rob
        reps = replication_means(rob, claim.measure)
        if "random pre" in (claim.a, claim.b) and self.baseline is not None:
            reps = pl.concat([reps, self.baseline.select("notation", claim.measure)],
                             how="diagonal_relaxed")
            rob = pl.concat([rob, self.baseline], how="diagonal_relaxed")
        return reps, rob

    def drops(self, claim: Claim) -> pl.DataFrame:
        """Per robot: ``measure`` under ``senses`` minus under ``versus``."""
        ref, new = (self.robots(s).select(*_ROBOT, pl.col(claim.measure).alias(name))
                    for s, name in ((claim.senses, "ref"), (claim.versus, "new")))
        return (ref.join(new, on=list(_ROBOT), how="inner", maintain_order="left")
                .with_columns((pl.col("ref") - pl.col("new")).alias(claim.measure)))

    def development_units(self, claim: Claim, group: str) -> pl.DataFrame:
        """Replications of the development table in the window ``group``: each replication's
        robots averaged over the window's snapshots and trials."""
        dev = self.development
        phase, first, upto = _window(group, dev.filter(pl.col("notation") == group.split("@")[0])
                                     ["generation"])
        sub = dev.filter((pl.col("notation") == phase)
                         & pl.col("generation").is_between(first, upto))
        rob = summaries.robot_means(sub, [claim.measure], by=_ROBOT)
        return replication_means(rob, claim.measure)


# ------------------------------------------------------------------------------ judging
def _row(claim: Claim, out: Outcome, measured: str, n: str, robots_out: Outcome | None = None
         ) -> dict:
    note = out.note
    return {"claim": claim.id, "section": claim.section, "paper": claim.paper,
            "kind": claim.kind.value, "own": claim.own, "infants": claim.infants,
            "measured": measured,
            "test": TESTS[claim.kind.value], "n": n, "effect": out.effect,
            "effect_low": out.low, "effect_high": out.high, "confidence": out.confidence,
            "p": out.p, "p_against": out.p_against, "p_holm": math.nan,
            "p_holm_against": math.nan, "paper_level_met": out.paper_level_met,
            "verdict": out.verdict,
            "verdict_robots": robots_out.verdict if robots_out is not None else None,
            "p_robots": robots_out.p if robots_out is not None else math.nan, "note": note}


def _not_run(claim: Claim, missing: str) -> dict:
    return _row(claim, Outcome(NOT_RUN), f"not run: {missing}", "")


#: The ``measured`` of a claim its measure cannot test (``Claim.untestable``): never judged,
#: its verdict "not run", counted apart from those without data.
UNTESTABLE = "cannot be tested with this measure: "
#: The count of such claims (``summary``), apart from those not run for want of data.
CANNOT = "cannot be tested"
#: What ``summary`` counts, in order: every verdict, then the claims that cannot be tested.
COUNTED = VERDICTS + (CANNOT,)


def _judge_two(claim: Claim):
    if claim.kind in (Kind.DIRECTIONAL, Kind.NEVER):
        return lambda a, b: verdicts.directional(a, b, claim.sign, claim.level)
    if claim.kind is Kind.NOT_BETTER:
        return lambda a, b: verdicts.not_better(a, b, claim.sign)
    return verdicts.equivalent


def _two_groups(claim: Claim, data: _Data) -> dict:
    reps, rob = data.two_groups(claim)
    x, y = _values(reps, claim.a, claim.measure), _values(reps, claim.b, claim.measure)
    if len(x) == 0 or len(y) == 0:
        lacking = " or ".join(g for g, v in ((claim.a, x), (claim.b, y)) if not len(v))
        return _not_run(claim, f"no units of {lacking} with a {claim.measure}")
    judge = _judge_two(claim)
    out = judge(x, y)
    robots_out = (judge(_values(rob, claim.a, claim.measure), _values(rob, claim.b, claim.measure))
                  if rob is not None else None)
    unit = "random genomes" if claim.a == "random pre" else "replications"
    return _row(claim, out, f"{claim.measure}: {claim.b} {np.mean(y):.3g} vs {claim.a} "
                            f"{np.mean(x):.3g} (means over replications)",
                f"{len(y)} replications vs {len(x)} {unit}", robots_out)


def _never(claim: Claim, data: _Data) -> dict:
    if claim.source == "post":
        return _two_groups(claim, data)
    dev = data.development
    if dev is None or claim.measure not in dev.columns:
        return _not_run(claim, f"no {claim.measure} in the development table "
                               "(evaluate --development)")
    # each replication's highest rate over the snapshots of its course
    per = (dev.filter(pl.col("notation").is_in([claim.a, claim.b]))
           .group_by(*_REPLICATION, "generation")
           .agg(pl.col(claim.measure).cast(pl.Float64).mean())
           .group_by(*_REPLICATION).agg(pl.col(claim.measure).max()))
    x, y = _values(per, claim.a, claim.measure), _values(per, claim.b, claim.measure)
    if len(x) == 0 or len(y) == 0:
        return _not_run(claim, f"no snapshots of {claim.a if not len(x) else claim.b}")
    out = verdicts.directional(x, y, claim.sign, claim.level)
    return _row(claim, out, f"highest {claim.measure} over the snapshots: {claim.b} "
                            f"{y.mean():.3f} vs {claim.a} {x.mean():.3f}",
                f"{len(y)} vs {len(x)} replications")


def _development(claim: Claim, data: _Data) -> dict:
    dev = data.development
    if dev is None or claim.measure not in dev.columns:
        return _not_run(claim, f"no {claim.measure} in the development table "
                               "(evaluate --development)")
    phases = {g.split("@")[0] for g in (claim.a, claim.b)}
    if not phases <= set(dev["notation"].unique()):
        return _not_run(claim, f"no snapshots of {', '.join(sorted(phases))}")
    a, b = (data.development_units(claim, g) for g in (claim.a, claim.b))
    if len(phases) == 1:  # the same replications at two moments: paired
        pairs = a.join(b, on=["run", "replication"], suffix="_b")
        out = verdicts.paired_directional(pairs[claim.measure].to_numpy(),
                                          pairs[f"{claim.measure}_b"].to_numpy(), claim.sign,
                                          claim.level)
        n = f"{pairs.height} replications, paired"
    else:  # different phases: different populations
        out = verdicts.directional(a[claim.measure].to_numpy(), b[claim.measure].to_numpy(),
                                   claim.sign, claim.level)
        n = f"{b.height} vs {a.height} replications"
    return _row(claim, out, f"{claim.measure}: {claim.b} {b[claim.measure].mean():.3g} vs "
                            f"{claim.a} {a[claim.measure].mean():.3g}", n)


def _pairs(data: _Data, claim: Claim) -> tuple[pl.DataFrame, pl.DataFrame]:
    """A paired claim's robots of ``claim.b`` (``_Data.drops``) and their replications' means
    (``ref`` under ``claim.senses``, ``new`` under ``claim.versus``)."""
    drops = data.drops(claim).filter(pl.col("notation") == claim.b)
    return drops, replication_means(drops, "ref", "new")


def paired_replications(table: pl.DataFrame, claim: Claim) -> pl.DataFrame:
    """The replications a paired claim (``claim.versus`` set) is judged on: per replication
    of ``claim.b`` in ``table`` (post-evaluation trials), the mean over its robots of
    ``claim.measure`` under ``claim.senses`` (``ref``) and under ``claim.versus`` (``new``)."""
    return _pairs(_Data(table, None, None), claim)[1]


def _paired_change(claim: Claim, data: _Data) -> dict:
    if claim.measure not in data.table.columns:
        return _not_run(claim, f"no {claim.measure}")
    drops, reps = _pairs(data, claim)
    if drops.height == 0:
        return _not_run(claim, f"no {claim.b} robots under both {claim.senses} and "
                               f"{claim.versus} (evaluate --sensors all)")
    if claim.kind is Kind.SAME_PAIRED and claim.measure in RATES:
        judge = verdicts.paired_rate_equivalent
    elif claim.kind is Kind.SAME_PAIRED:
        def judge(ref, new):
            return verdicts.paired_equivalent(ref, new, relative=True)
    else:
        def judge(ref, new):
            return verdicts.paired_directional(ref, new, claim.sign, claim.level)
    out = judge(reps["ref"].to_numpy(), reps["new"].to_numpy())
    robots_out = judge(drops["ref"].to_numpy(), drops["new"].to_numpy())
    return _row(claim, out, f"{claim.measure}: {claim.senses} {reps['ref'].mean():.3g}, "
                            f"{claim.versus} {reps['new'].mean():.3g} (means over "
                            "replications)", f"{reps.height} replications", robots_out)


def _within(claim: Claim, data: _Data) -> dict:
    rob = data.robots(claim.senses).filter(pl.col("notation") == claim.b)
    if rob.height == 0 or not {claim.measure, claim.versus_measure} <= set(rob.columns):
        return _not_run(claim, f"no {claim.b} robots with {claim.measure} and "
                               f"{claim.versus_measure}")
    reps = replication_means(rob, claim.measure, claim.versus_measure)
    out = verdicts.paired_directional(reps[claim.versus_measure].to_numpy(),
                                      reps[claim.measure].to_numpy(), claim.sign, claim.level)
    robots_out = verdicts.paired_directional(rob[claim.versus_measure].to_numpy(),
                                             rob[claim.measure].to_numpy(), claim.sign,
                                             claim.level)
    return _row(claim, out, f"{claim.b}: {claim.measure} {reps[claim.measure].mean():.3g} vs "
                            f"{claim.versus_measure} {reps[claim.versus_measure].mean():.3g}",
                f"{reps.height} replications", robots_out)


def _band(claim: Claim, data: _Data) -> dict:
    reps = replication_means(data.robots(claim.senses), claim.measure) \
        .filter(pl.col("notation") == claim.b)
    if reps.height == 0:
        return _not_run(claim, f"no {claim.b} robots")
    out = verdicts.in_band(reps[claim.measure].to_numpy(), ABOUT_HALF)
    return _row(claim, out, f"{claim.measure} rate {out.effect:.2f}",
                f"{reps.height} replications")


def _at_least(claim: Claim, data: _Data) -> dict:
    if claim.measure not in data.robots(claim.senses).columns:
        return _not_run(claim, f"no {claim.measure}")
    reps = replication_means(data.robots(claim.senses), claim.measure) \
        .filter((pl.col("notation") == claim.b) & pl.col(claim.measure).is_not_nan())
    if claim.measure == SWIPES_AFTER_MISS:
        return _swipes_again(claim, data, reps)
    if reps.height == 0:
        return _not_run(claim, f"no {claim.b} robots with a {claim.measure}")
    out = verdicts.at_least({claim.b: reps[claim.measure].to_numpy()}, claim.floor)
    return _row(claim, out, f"{claim.measure} {out.effect:.3g} (mean over replications)",
                f"{reps.height} replications")


def _swipes_again(claim: Claim, data: _Data, reps: pl.DataFrame) -> dict:
    """F2 "when they don't grasp the ball they try again": conditional on a failed swipe, so
    judged on the replications that have one; fewer than ``SWIPES_AGAIN_UNITS`` and it cannot
    be tested at this n (underpowered), whatever the mean."""
    trials = data.table.filter((pl.col("notation") == claim.b)
                               & (pl.col("senses") == claim.senses))
    if trials.height == 0 or "swipes" not in trials.columns:
        return _not_run(claim, f"no {claim.b} trials with swipes")
    failed = trials.filter(~pl.col("grasped") & (pl.col("swipes") >= 1)).height
    counted = (f"{failed} of {trials.height} trials with a failed swipe, in {reps.height} "
               "replications")
    if reps.height < SWIPES_AGAIN_UNITS:
        out = verdicts.Outcome(verdicts.UNDERPOWERED, note=(
            f"cannot be tested at this n: {counted} (at least {SWIPES_AGAIN_UNITS} needed)"))
        return _row(claim, out, f"{claim.measure}: {counted}", f"{reps.height} replications")
    out = verdicts.at_least({claim.b: reps[claim.measure].to_numpy()}, claim.floor)
    return _row(claim, out, f"{claim.measure} {out.effect:.3g} (mean over replications; "
                            f"{counted})", f"{reps.height} replications")


def _every_sector(claim: Claim, data: _Data) -> dict:
    trials = data.table.filter((pl.col("notation") == claim.b)
                               & (pl.col("senses") == claim.senses))
    if trials.height == 0:
        return _not_run(claim, f"no {claim.b} robots")
    per = (trials.group_by("run", "replication", "sector")
           .agg(pl.col("reached").cast(pl.Float64).mean(),
                pl.col("grasped").cast(pl.Float64).mean())
           .sort("run", "replication", "sector"))
    cells = {f"{what} in sector {k}": per.filter(pl.col("sector") == k)[col].to_numpy()
             for k in range(9) for col, what in (("reached", "reach"), ("grasped", "grasp"))}
    out = verdicts.at_least(cells, verdicts.SECTOR_FLOOR)
    return _row(claim, out, f"lowest sector rate {out.effect:.2f}",
                f"{per.select('run', 'replication').n_unique()} replications")


def _senses(claim: Claim, data: _Data) -> dict:
    per = [data.robots(s).filter(pl.col("notation") == claim.b)
           .select(*_ROBOT, pl.col("fitness").alias(s)) for s in SENSES]
    if any(p.height == 0 for p in per):
        evaluated = [s for s, p in zip(SENSES, per) if p.height]
        return _not_run(claim, f"{claim.b} evaluated under {', '.join(evaluated) or 'none'} "
                               "(evaluate --sensors all)")
    wide = per[0]
    for p in per[1:]:
        wide = wide.join(p, on=list(_ROBOT), how="inner", maintain_order="left")
    reps = replication_means(wide, *SENSES)
    out = verdicts.senses_differ(reps.select(SENSES).to_numpy(), claim.level)
    robots_out = verdicts.senses_differ(wide.select(SENSES).to_numpy(), claim.level)
    means = ", ".join(f"{s} {reps[s].mean():.3g}" for s in SENSES)
    return _row(claim, out, f"fitness: {means}", f"{reps.height} replications x 4 conditions",
                robots_out)


_JUDGES = {Kind.DIRECTIONAL: _two_groups, Kind.NOT_BETTER: _two_groups,
           Kind.NO_DIFFERENCE: _two_groups, Kind.BAND: _band, Kind.EVERY_SECTOR: _every_sector,
           Kind.NEVER: _never, Kind.PAIRED: _senses, Kind.SAME_PAIRED: _paired_change,
           Kind.AT_LEAST: _at_least,
           Kind.CHANGE_PAIRED: _paired_change, Kind.WITHIN: _within}


def _judge(claim: Claim, data: _Data) -> dict:
    if claim.untestable:
        return _row(claim, Outcome(NOT_RUN), UNTESTABLE + claim.untestable, "")
    if claim.source == "development" and claim.kind is not Kind.NEVER:
        return _development(claim, data)
    return _JUDGES[claim.kind](claim, data)


def findings(table: pl.DataFrame, baseline: pl.DataFrame | None = None,
             claims: tuple[Claim, ...] = CLAIMS,
             development: pl.DataFrame | None = None) -> pl.DataFrame:
    """Every claim (default: the paper's) judged against the post-evaluation ``table`` (one or
    several runs' trials: notation, senses, replication, rank, sector and the measures of
    ``metrics.trial_metrics``; ``tables.load_runs`` gives several runs'), ``baseline`` (random
    genomes' trials, ``load_evaluation(run, baseline=True)``; None: none) and ``development``
    (the snapshots' post-evaluation, ``snapshots.load_development``; None: those claims are
    not run). Columns: ``SCHEMA``; ``verdict`` is one of ``VERDICTS``."""
    missing = [c for c in ("notation", "senses", "replication", "rank", "sector", "fitness",
                           "reached", "grasped") if c not in table.columns]
    if missing:
        raise ValueError(f"the post-evaluation table lacks columns {missing}")
    data = _Data(table, baseline, development)
    found = pl.DataFrame([_judge(c, data) for c in claims], schema=SCHEMA)
    headline = (~found["own"] & ~found["infants"]).to_numpy()
    adjusted = {}
    for column in ("p", "p_against"):
        p = np.where(headline, found[column].to_numpy(), np.nan)
        adjusted[column.replace("p", "p_holm", 1)] = stats.holm_adjusted(p)
    return found.with_columns(pl.Series("p_holm", adjusted["p_holm"]),
                              pl.Series("p_holm_against", adjusted["p_holm_against"]))


def reading(found: pl.DataFrame, who: str = ROBOTS) -> pl.DataFrame:
    """The rows of ``found`` whose claims are ``who``'s (``READINGS``): the paper's of its
    robots (the headline), the paper's of infants, or the project's own."""
    if who not in READINGS:
        raise ValueError(f"unknown reading {who!r}; known: {READINGS}")
    own = pl.col("own")
    infants = (pl.col("infants").fill_null(False) if "infants" in found.columns  # a frame of
               else pl.lit(False))  # findings without claims of infants
    return found.filter(~own & ~infants if who == ROBOTS else
                        ~own & infants if who == INFANTS else own)


def summary(found: pl.DataFrame, who: str = ROBOTS) -> dict[str, int]:
    """How many of ``who``'s claims (``reading``; default the paper's of its robots, the
    headline) got each verdict (``COUNTED``: "not run" is the claims without data, those their
    measure cannot test, ``UNTESTABLE``, are counted apart as ``CANNOT``), and how many decided
    ones survive Holm's adjustment (``reproduced (Holm)``, ``contradicted (Holm)``; claims
    without a p, the band and every-sector rules, count as surviving only raw; Holm's family is
    the headline, so the other readings have none)."""
    rows = reading(found, who)
    counts = dict(rows.group_by("verdict").len().iter_rows())
    out = {v: int(counts.get(v, 0)) for v in VERDICTS}
    cannot = rows.filter((pl.col("verdict") == NOT_RUN)
                         & pl.col("measured").str.starts_with(UNTESTABLE)).height
    out[NOT_RUN] -= cannot
    out[CANNOT] = cannot
    out["reproduced (Holm)"] = rows.filter((pl.col("verdict") == verdicts.REPRODUCED)
                                           & (pl.col("p_holm") < ALPHA)).height
    out["contradicted (Holm)"] = rows.filter((pl.col("verdict") == verdicts.CONTRADICTED)
                                             & (pl.col("p_holm_against") < ALPHA)).height
    return out
