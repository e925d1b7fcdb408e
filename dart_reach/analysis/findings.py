"""The claims of the paper's section IV as data, each judged against a run's post-evaluation.

A :class:`Claim` is a row of data: the paper's words and section, the measure, the groups, the
unit, the kind of claim and the paper's level. ``findings(table, baseline)`` judges every claim
of ``CLAIMS`` with the rule of its kind (``verdicts``: directional, no difference, band, every
sector, never, paired) and returns one row per claim with the verdict, the effect size and its
interval, p, Holm's adjusted p over the table, whether the paper's own level is met, and a
replication-level check.

Units: a *robot* (its mean over its post-evaluation trials) for the comparisons of phases, as
the paper's Figs. 5-9 ("50 robots ... for 45 trials"). Robots of one replication are not
independent, and the replications of gross- and fine-reaching descend from one merged
population (III-D): every robot-level claim is therefore judged again on replication means
(``p_replications``), and the note says where the two disagree. A *replication* (its best
robot's post-evaluation fitness, ``summaries.replication_performance``) for the conditions of
Fig. 10, and the replication means of robots for the band, sector and "never" claims. The rules
and their thresholds, fixed before any data was looked at, are in docs/analysis.md
("Verdicts").
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, replace

import numpy as np
import polars as pl

from . import stats, summaries, verdicts
from .verdicts import (ALPHA, CONTRADICTED, INCONCLUSIVE, NOT_RUN, REPRODUCED, UNDERPOWERED,
                       VERDICTS, Outcome)

__all__ = ["CLAIMS", "Claim", "Kind", "VERDICTS", "REPRODUCED", "CONTRADICTED", "INCONCLUSIVE",
           "UNDERPOWERED", "NOT_RUN", "findings", "summary", "robots", "replications"]

#: "About half the trials" (IV-A-1): a reach rate between a third and two thirds.
ABOUT_HALF = (1 / 3, 2 / 3)
#: The trial-level babbling measure (docs/analysis.md): F1's share of babbling trials, F7's.
BABBLING = "babbling"
#: Seed of the bootstrap intervals (a report is the same every time it is built).
BOOTSTRAP_SEED = 20131


class Kind(enum.Enum):
    DIRECTIONAL = "directional"
    NO_DIFFERENCE = "no difference"
    BAND = "band"
    EVERY_SECTOR = "every sector"
    NEVER = "never"
    PAIRED = "paired"
    SAME_PAIRED = "no change (paired)"
    CHANGE_PAIRED = "change (paired)"


@dataclass(frozen=True)
class Claim:
    """One claim: ``measure`` of group ``b`` against group ``a`` (notations; "random pre" is the
    random pre-reaching networks of ``evaluate --baseline``), higher (``sign`` +1) or lower
    (-1) for a directional claim; ``level`` the paper's significance level; ``unit`` "robots" or
    "replications"; ``senses`` the sensory condition of the trials."""

    id: str
    section: str
    paper: str
    kind: Kind
    measure: str = "fitness"
    a: str = ""
    b: str = ""
    sign: int = 0
    level: float = ALPHA
    unit: str = "robots"
    senses: str = "normal"
    #: a second post-evaluation condition: the paired claims compare ``senses`` with it in the
    #: same robots; a directional claim with it compares the per-robot drop senses - versus
    versus: str = ""
    #: "post" (the post-evaluation) or "development" (snapshots, ``development.parquet``:
    #: groups are "phase@generations", e.g. "gross@1-10", "pre@last")
    source: str = "post"


_K = Kind
_SENSES = ("normal", "no-touch", "no-sight", "nothing")


def _phase_claims() -> list[Claim]:
    claims = [
        Claim("F1 reach about half", "IV-A-1, Fig. 5",
              "pre-reachers reach (touch the ball at least once) in about half of the trials",
              _K.BAND, "reached", b="pre"),
        Claim("F1 babbling", "IV-A-1, Fig. 8",
              "pre-reachers show large quasi-periodic circular movements of the hand (motor "
              "babbling), unlike random networks", _K.DIRECTIONAL, BABBLING,
              "random pre", "pre", +1),
        Claim("F1 hand-shoulder constant vs random", "IV-A-1, Fig. 6 top",
              "pre-reachers lock the elbow: the hand-shoulder distance stays almost constant",
              _K.DIRECTIONAL, "hand_shoulder_cv", "random pre", "pre", -1),
        Claim("F1 hand-shoulder constant vs fine", "IV-A-1, IV-A-3, Fig. 6",
              "the elbow, locked in pre-reaching, is used in fine-reaching", _K.DIRECTIONAL,
              "hand_shoulder_cv", "fine", "pre", -1),
    ]
    for measure, sign, level, what in (
            ("grasped", +1, 0.001, "grasp up"), ("reached", -1, 0.001, "reach down"),
            ("straightness", +1, 0.01, "straighter"), ("speed", -1, 0.05, "slower"),
            ("var_shoulder", -1, 0.001, "shoulder variability down"),
            ("sectors_reached", -1, ALPHA, "success in fewer sectors")):
        claims.append(Claim(f"F2 {what}", "IV-A-2, Figs. 5-7",
                            f"gross- vs pre-reachers: {what}", _K.DIRECTIONAL, measure, "pre",
                            "gross", sign, level))
    for measure, sign, level, what in (
            ("reached", +1, 0.001, "reach up"), ("grasped", +1, 0.001, "grasp up"),
            ("var_elbow", +1, 0.001, "elbow variability up"),
            ("var_shoulder", +1, 0.001, "shoulder variability up"),
            ("var_trunk", +1, 0.001, "trunk variability up")):
        claims.append(Claim(f"F3 {what}", "IV-A-3, Figs. 5, 6",
                            f"fine- vs gross-reachers: {what}", _K.DIRECTIONAL, measure,
                            "gross", "fine", sign, level))
    for measure in ("speed", "straightness"):
        claims.append(Claim(f"F3 {measure} no different", "IV-A-3, Fig. 5",
                            f"fine- vs gross-reachers: no significant change in {measure}",
                            _K.NO_DIFFERENCE, measure, "gross", "fine"))
    claims.append(Claim("F3 all sectors", "IV-A-3, Fig. 7",
                        "fine-reachers reach and grasp the ball in all 9 sectors",
                        _K.EVERY_SECTOR, b="fine"))
    for phase in ("pre", "gross", "fine"):
        claims.append(Claim(f"F4 senses differ ({phase})", "IV-B, Fig. 9",
                            "performance varies across the four sensory conditions (p < 0.01)",
                            _K.PAIRED, b=phase, level=0.01))
    for s in _SENSES:
        pairs = ((("gross", "fine", +1, "fine > gross"), ("pre", "gross", +1, "gross > pre"))
                 if s in ("normal", "no-touch") else (("gross", "fine", -1, "gross > fine"),))
        for a, b, sign, what in pairs:
            claims.append(Claim(f"F4 {s}: {what}", "IV-B, Fig. 9", f"{s}: {what} (p < 0.05)",
                                _K.DIRECTIONAL, "fitness", a, b, sign, 0.05, senses=s))
    claims.append(Claim("F5 gross > gross^", "IV-C, Fig. 10",
                        "gross outperforms the non-incremental gross^ (p < 0.05)",
                        _K.DIRECTIONAL, "fitness", "gross^", "gross", +1, 0.05,
                        "replications"))
    for a, b in (("pre", "pre-h"), ("gross", "gross-h"), ("pre", "pre*"), ("gross^", "gross^*"),
                 ("fine^", "fine*"), ("fine", "fine^")):
        claims.append(Claim(f"F6 {a} vs {b}", "IV-C, Fig. 10",
                            f"{a} and {b} do not differ significantly", _K.NO_DIFFERENCE,
                            "fitness", a, b, unit="replications"))
    for g in ("fine*", "fine^", "gross^"):
        claims.append(Claim(f"F7 {g} never babbles", "IV-C",
                            f"{g} robots never display motor babbling (meaningful only where "
                            "F1 babbling is reproduced)", _K.NEVER, BABBLING, b=g))
    return claims


def _behaviour_claims() -> list[Claim]:
    """The observations of IV-A, IV-B, IV-C, V and Table I beyond F1-F7 (issue 22; the
    measures and their thresholds: docs/analysis.md, "Measures of every observation")."""
    fig8, dep, tab, ctl, dev = ("IV-A-1, Fig. 8: ball absent", "IV-B, V: deprivation",
                                "Table I, IV-A: behaviours", "IV-C: controls",
                                "V, IV-C: development")
    c = [Claim(f"A1 ball absent, pre: {m} same", fig8,
               "pre-reachers: the behaviour \"remains substantially the same ... when the "
               "target ball is absent\"", _K.SAME_PAIRED, m, b="pre", versus="no-ball")
         for m in ("babbling", "hand_amplitude", "hand_path", "var_shoulder")]
    c += [Claim(f"A2 ball absent, fine: {m} down", fig8,
                "fine-reachers, who rely on sight (IV-B), move differently without the ball",
                _K.CHANGE_PAIRED, m, b="fine", sign=-1, versus="no-ball")
          for m in ("heading", "hand_path")]
    c.append(Claim("A2 ball absent: fine's heading drop > pre's", fig8,
                   "the ball's absence changes fine-reachers more than pre-reachers",
                   _K.DIRECTIONAL, "heading", "pre", "fine", +1, versus="no-ball"))
    c += [Claim(f"A3 no sight, pre: {m} same", fig8,
                "pre-reachers: the behaviour remains the same \"in tests in which the vision "
                "system is impaired\"", _K.SAME_PAIRED, m, b="pre", versus="no-sight")
          for m in ("babbling", "hand_amplitude", "hand_path")]
    for a in ("gross", "pre"):
        c.append(Claim(f"D1 no-sight drop: fine > {a}", dep,
                       "\"the most notable effect is the strong impairment caused by the "
                       "absence of visual information in the fine-reaching phase\"",
                       _K.DIRECTIONAL, "fitness", a, "fine", +1, versus="no-sight"))
    c.append(Claim("D2 no touch, pre: fitness same", dep, "pre-reachers ignore tactile "
                   "information (V)", _K.SAME_PAIRED, "fitness", b="pre", versus="no-touch"))
    for g in ("gross", "fine"):
        c.append(Claim(f"D3 no touch, {g}: fitness down", dep, "\"the utilization of tactile "
                       "information becomes a necessary prerequisite\" after pre-reaching (V)",
                       _K.CHANGE_PAIRED, "fitness", b=g, sign=-1, versus="no-touch"))
    c.append(Claim("D3 no-touch drop: gross > pre", dep, "touch matters more to gross- than "
                   "to pre-reachers (V)", _K.DIRECTIONAL, "fitness", "pre", "gross", +1,
                   versus="no-touch"))
    c.append(Claim("T1 arm orienting", tab, "pre-reaching: \"arm orienting\" [49]: the hand "
                   "moves toward the ball more than random networks'", _K.DIRECTIONAL,
                   "heading", "random pre", "pre", +1))
    for g in ("gross", "fine"):
        c.append(Claim(f"T4 babbling reduced in {g}", tab, "\"the reduced use of motor "
                       "babbling\" after pre-reaching (III-D-2, V)", _K.DIRECTIONAL,
                       "babbling", "pre", g, -1))
    c.append(Claim("T6 anticipatory grasp", tab, "fine-reaching: \"anticipatory grasp\" "
                   "[54]: fingers closing before the palm touches", _K.DIRECTIONAL,
                   "anticipatory_grasp", "gross", "fine", +1))
    c.append(Claim("T7 smoothness no different", tab, "fine vs gross: no improvement of the "
                   "reach (IV-A-3; infants get smoother, the paper's robots do not)",
                   _K.NO_DIFFERENCE, "movement_units", "gross", "fine"))
    for m, sign, level in (("straightness_onset", +1, 0.01), ("speed_final", -1, 0.05),
                           ("speed_peak", -1, 0.05)):
        c.append(Claim(f"T8 gross vs pre: {m}", tab, "robustness of F2 straighter / slower "
                       "with the reach from movement onset", _K.DIRECTIONAL, m, "pre", "gross",
                       sign, level))
    for m in ("straightness_onset", "speed_final", "speed_peak"):
        c.append(Claim(f"T9 fine vs gross: {m} no different", tab, "robustness of F3's "
                       "claims of no difference", _K.NO_DIFFERENCE, m, "gross", "fine"))
    for m, a, b, sign in (("var_shoulder_before", "pre", "gross", -1),
                          ("var_shoulder_norm", "pre", "gross", -1),
                          ("var_elbow_before", "gross", "fine", +1),
                          ("var_elbow_norm", "gross", "fine", +1)):
        c.append(Claim(f"T10 {b} vs {a}: {m}", tab, "robustness of F2/F3's joint "
                       "variability: before the first touch, normalised by the joint's range",
                       _K.DIRECTIONAL, m, a, b, sign, 0.001))
    for a in ("pre", "fine"):
        c.append(Claim(f"T11 palm-up swipes: gross > {a}", tab, "gross-reachers \"bring their "
                       "arm on the lower part of the target area while orienting their palm up "
                       "and then produce long swipes up\" (IV-A-2)", _K.DIRECTIONAL,
                       "palm_up_swipe", a, "gross", +1))
    c.append(Claim("P1 peri-personal space shrinks in gross", tab, "the regression \"involves "
                   "a reduction of the peri-personal space\" (V)", _K.DIRECTIONAL,
                   "reach_entropy", "pre", "gross", -1))
    c.append(Claim("P2 and re-expands in fine", tab, "fine-reachers succeed \"in all areas\" "
                   "(IV-A-3)", _K.DIRECTIONAL, "reach_entropy", "gross", "fine", +1))
    for a, b, what in (("pre", "pre-h", "acuity"), ("pre", "pre*", "reflexes")):
        for m in ("babbling", "hand_amplitude", "heading", "hand_shoulder_cv"):
            c.append(Claim(f"C {b}: {m} same", ctl, f"the {what} constraint \"does not lead to "
                           "an appreciable effect on the observed behavior\"",
                           _K.NO_DIFFERENCE, m, a, b, unit="replication means"))
    c += [Claim("V1 motor suppression at the start of gross", dev, "\"initial motor "
                "suppression\" [30] (Table I): less movement in gross's first 10 generations "
                "than at the end of pre", _K.DIRECTIONAL, "hand_path", "pre@last",
                "gross@1-10", -1, source="development"),
          Claim("V2 elbow un-freezes in fine", dev, "\"the reduced use (freeze) followed by a "
                "re-extended use (un-freeze) of the distal DOFs\"", _K.DIRECTIONAL,
                "var_elbow", "fine@1-10", "fine@last", +1, source="development"),
          Claim("V3 babbling appears in pre", dev, "\"the emergence of the exploratory (motor "
                "babbling) behavior during the pre-reaching phase\"", _K.DIRECTIONAL,
                "babbling", "pre@1", "pre@last", +1, source="development"),
          Claim("V4 babbling fades in gross", dev, "\"this transient behavior is later "
                "replaced by more effective movements\"", _K.DIRECTIONAL, "babbling",
                "gross@1", "gross@last", -1, source="development")]
    c += [Claim(f"V5 {g} never babbles during development", dev, f"{g} robots \"never display "
                "such behavior during the course of their developmental process\"",
                _K.NEVER, "babbling", b=g, source="development") for g in ("fine*", "fine^")]
    return c


CLAIMS: tuple[Claim, ...] = tuple(_phase_claims() + _behaviour_claims())

_ROBOT = ("notation", "run", "replication", "rank")
#: Per-robot measures computed from the sectors, not averaged over trials.
_SPREAD = ("sectors_reached", "reach_entropy")
_MEASURES = tuple(sorted({c.measure for c in CLAIMS} - set(_SPREAD)))
_SCHEMA = {"claim": pl.Utf8, "section": pl.Utf8, "paper": pl.Utf8, "kind": pl.Utf8,
           "measured": pl.Utf8, "test": pl.Utf8, "n": pl.Utf8, "effect": pl.Float64,
           "effect_low": pl.Float64, "effect_high": pl.Float64, "p": pl.Float64,
           "p_holm": pl.Float64, "paper_level_met": pl.Boolean, "p_replications": pl.Float64,
           "p_paper_test": pl.Float64,
           "replications_agree": pl.Boolean, "verdict": pl.Utf8, "note": pl.Utf8}


# ------------------------------------------------------------------------------ units
def _with_run(table: pl.DataFrame) -> pl.DataFrame:
    return table if "run" in table.columns else table.with_columns(pl.lit("").alias("run"))


def robots(table: pl.DataFrame, senses: str = "normal") -> pl.DataFrame:
    """One row per robot (notation, run, replication, rank) of ``senses``: the mean over its
    trials of each measure (booleans: rates), and ``sectors_reached``, the number of sectors
    in which it reached the ball at least once (the spread of success, Fig. 7), and
    ``reach_entropy`` (``summaries.peripersonal_space``)."""
    table = _with_run(table).filter(pl.col("senses") == senses)
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


def _replication_means(units: pl.DataFrame, measure: str) -> pl.DataFrame:
    """Per (notation, run, replication): the mean of ``measure`` over the replication's robots."""
    return (units.filter(pl.col(measure).is_not_nan())
            .group_by("notation", "run", "replication").agg(pl.col(measure).mean())
            .sort("notation", "run", "replication"))


def _values(units: pl.DataFrame, group: str, measure: str) -> np.ndarray:
    if measure not in units.columns or "notation" not in units.columns:
        return np.zeros(0)
    v = units.filter(pl.col("notation") == group)[measure].cast(pl.Float64).to_numpy()
    return v[np.isfinite(v)]


class _Data:
    """The tables a claim is judged on, built once per ``findings`` call."""

    def __init__(self, table: pl.DataFrame, baseline: pl.DataFrame | None,
                 development: pl.DataFrame | None = None):
        self.table = _with_run(table)
        self.development = _with_run(development) if development is not None else None
        self._robots = {}
        # the random networks of the pre-reaching phase (their notation is the phase's)
        self.baseline = (robots(baseline).filter(pl.col("notation") == "pre")
                         .with_columns(pl.lit("random pre").alias("notation"))
                         if baseline is not None and baseline.height else None)
        self.replications = replications(table)

    def robots(self, senses: str) -> pl.DataFrame:
        if senses not in self._robots:
            self._robots[senses] = robots(self.table, senses)
        return self._robots[senses]

    def pairs(self, claim: Claim) -> pl.DataFrame:
        """Group ``b``'s robots under ``senses`` (column ``ref``) and ``versus`` (``new``),
        and the drop ref - new as ``claim.measure``: one row per robot present under both."""
        if claim.measure not in self.table.columns:
            return pl.DataFrame(schema={"notation": pl.Utf8, "ref": pl.Float64,
                                        "new": pl.Float64, claim.measure: pl.Float64})
        ref, new = (self.robots(s).select(*_ROBOT, pl.col(claim.measure).alias(name))
                    for s, name in ((claim.senses, "ref"), (claim.versus, "new")))
        return (ref.join(new, on=list(_ROBOT), how="inner", maintain_order="left")
                .with_columns((pl.col("ref") - pl.col("new")).alias(claim.measure)))

    def development_units(self, claim: Claim) -> pl.DataFrame:
        """Robots of the development table in the generation windows ``a`` and ``b``
        ("phase@last", "phase@first-last", "phase@g"), each window's robot (replication,
        rank) averaged over its generations and trials, ``notation`` = the window's name."""
        dev, out = self.development, []
        if dev is None or claim.measure not in dev.columns:
            return pl.DataFrame(schema={"notation": pl.Utf8, claim.measure: pl.Float64})
        for group in (claim.a, claim.b):
            phase, spec = group.split("@")
            sub = dev.filter(pl.col("notation") == phase)
            if sub.height == 0:
                continue
            last = int(sub["generation"].max())
            lo, _, hi = spec.partition("-")
            first = last if lo == "last" else int(lo)
            upto = last if (hi or lo) == "last" else int(hi or lo)
            sub = sub.filter(pl.col("generation").is_between(first, upto))
            out.append(summaries.robot_means(sub, [claim.measure], by=_ROBOT[1:])
                       .with_columns(pl.lit(group).alias("notation")))
        return (pl.concat(out, how="diagonal_relaxed") if out
                else pl.DataFrame(schema={"notation": pl.Utf8, claim.measure: pl.Float64}))

    def units(self, claim: Claim) -> pl.DataFrame:
        if claim.source == "development":
            return self.development_units(claim)
        if claim.unit == "replications":
            return self.replications
        if claim.versus:
            return self.pairs(claim)
        units = self.robots(claim.senses)
        if claim.unit == "replication means":
            return _replication_means(units, claim.measure) if claim.measure in units.columns \
                else units
        if "random pre" in (claim.a, claim.b) and self.baseline is not None:
            units = pl.concat([units, self.baseline], how="diagonal_relaxed")
        return units


# ------------------------------------------------------------------------------ judging
def _row(claim: Claim, out: Outcome, measured: str, test: str, n: str,
         p_rep: float = math.nan, agree: bool | None = None,
         p_paper_test: float = math.nan) -> dict:
    return {"claim": claim.id, "section": claim.section, "paper": claim.paper,
            "kind": claim.kind.value, "measured": measured, "test": test, "n": n,
            "effect": out.effect, "effect_low": out.low, "effect_high": out.high, "p": out.p,
            "p_holm": math.nan, "paper_level_met": out.paper_level_met,
            "p_replications": p_rep, "replications_agree": agree,
            "p_paper_test": p_paper_test, "verdict": out.verdict,
            "note": out.note}


def _not_run(claim: Claim, missing: str) -> dict:
    return _row(claim, Outcome(NOT_RUN), f"not run: {missing}", "", "")


def _two_groups(claim: Claim, data: _Data) -> dict:
    units = data.units(claim)
    x, y = _values(units, claim.a, claim.measure), _values(units, claim.b, claim.measure)
    if len(x) == 0 or len(y) == 0:
        lacking = " or ".join(g for g, v in ((claim.a, x), (claim.b, y)) if not len(v))
        return _not_run(claim, f"no {claim.unit} of {lacking} with a {claim.measure}")
    directional = claim.kind is Kind.DIRECTIONAL
    judge = ((lambda u, v: verdicts.directional(u, v, claim.sign, claim.level)) if directional
             else verdicts.equivalent)
    out = judge(x, y)
    if directional:
        word = "higher" if claim.sign > 0 else "lower"
        test = (f"Mann-Whitney U, two-tailed, p < {ALPHA:g}; direction from U; effect: "
                f"Hodges-Lehmann shift {claim.b} - {claim.a} [95% CI]; the paper: {claim.b} "
                f"{word}, p < {claim.level:g}")
    else:
        test = (f"equivalence: two one-sided tests, theta = P({claim.b} > {claim.a}) within "
                f"0.5 +- {verdicts.EQUIVALENCE_MARGIN:g} (Brunner-Munzel s.e.), p < {ALPHA:g}; "
                f"effect: theta [90% CI]")
    measured = (f"{claim.measure}: {claim.b} {np.mean(y):.3g} vs {claim.a} {np.mean(x):.3g} "
                f"(means over {claim.unit})")
    n = f"{len(y)} vs {len(x)} {claim.unit}"
    p_rep, agree = math.nan, None
    if claim.unit == "robots" and "random pre" not in (claim.a, claim.b) and "replication" \
            in units.columns:
        reps = _replication_means(units, claim.measure)
        rx, ry = _values(reps, claim.a, claim.measure), _values(reps, claim.b, claim.measure)
        at_reps = judge(rx, ry)
        p_rep, agree = at_reps.p, at_reps.verdict == out.verdict
        n += f" ({len(ry)} vs {len(rx)} replications)"
        if not agree:
            out = replace(out, note="; ".join(filter(None, [
                out.note, f"replication means: {at_reps.verdict}"
                          + (f" (p = {at_reps.p:.2g})" if math.isfinite(at_reps.p) else "")])))
    return _row(claim, out, measured, test, n, p_rep, agree)


def _paired_change(claim: Claim, data: _Data) -> dict:
    pairs = data.pairs(claim).filter(pl.col("notation") == claim.b)
    if pairs.height == 0:
        return _not_run(claim, f"no {claim.b} robots with {claim.measure} under both "
                               f"{claim.senses} and {claim.versus} (evaluate --sensors all)")
    if claim.kind is Kind.SAME_PAIRED:
        judge = verdicts.paired_equivalent
        test = (f"paired equivalence: two one-sided paired t-tests, mean change within +-"
                f"{verdicts.PAIRED_MARGIN:.0%} of the median under {claim.senses}, p < {ALPHA:g}"
                "; effect: mean change [90% CI]")
    else:
        def judge(ref, new):
            return verdicts.paired_directional(ref, new, claim.sign, claim.level)
        test = (f"Wilcoxon signed-rank, two-tailed, p < {ALPHA:g}; effect: median change "
                f"({claim.versus} - {claim.senses}); the paper: "
                f"{'higher' if claim.sign > 0 else 'lower'} under {claim.versus}")
    out = judge(pairs["ref"].to_numpy(), pairs["new"].to_numpy())
    reps = (pairs.group_by("run", "replication").agg(pl.col("ref").mean(), pl.col("new").mean())
            .sort("run", "replication"))
    at_reps = judge(reps["ref"].to_numpy(), reps["new"].to_numpy())
    agree = at_reps.verdict == out.verdict
    if not agree:
        out = replace(out, note="; ".join(filter(None, [
            out.note, f"replication means: {at_reps.verdict}"])))
    return _row(claim, out, f"{claim.measure}: {claim.senses} {pairs['ref'].mean():.3g}, "
                            f"{claim.versus} {pairs['new'].mean():.3g} (means over robots)",
                test, f"{pairs.height} robots ({reps.height} replications)", at_reps.p, agree)


def _band(claim: Claim, data: _Data) -> dict:
    robots_ = data.robots(claim.senses)
    reps = _replication_means(robots_, claim.measure).filter(pl.col("notation") == claim.b)
    if reps.height == 0:
        return _not_run(claim, f"no {claim.b} robots")
    out = verdicts.in_band(reps[claim.measure].to_numpy(), ABOUT_HALF,
                           np.random.default_rng(BOOTSTRAP_SEED))
    lo, hi = ABOUT_HALF
    ci = f" (95% CI {out.low:.2f}-{out.high:.2f})" if math.isfinite(out.low) else ""
    return _row(claim, out, f"{claim.measure} rate {out.effect:.2f}{ci}",
                f"percentile bootstrap over replications of their robots' mean rate: interval "
                f"inside [{lo:.2f}, {hi:.2f}]: reproduced; wholly outside: contradicted",
                f"{reps.height} replications, {_values(robots_, claim.b, claim.measure).size} "
                "robots")


def _every_sector(claim: Claim, data: _Data) -> dict:
    trials = data.table.filter((pl.col("notation") == claim.b)
                               & (pl.col("senses") == claim.senses))
    if trials.height == 0:
        return _not_run(claim, f"no {claim.b} robots")
    per = (trials.group_by("run", "replication", "sector")
           .agg(pl.col("reached").cast(pl.Float64).mean(),
                pl.col("grasped").cast(pl.Float64).mean())
           .sort("run", "replication", "sector"))  # the bootstrap's draws: the same every time
    cells = {f"{what} in sector {k}": per.filter(pl.col("sector") == k)[col].to_numpy()
             for k in range(9) for col, what in (("reached", "reach"), ("grasped", "grasp"))}
    out = verdicts.at_least(cells, verdicts.SECTOR_FLOOR, np.random.default_rng(BOOTSTRAP_SEED))
    ci = f" (95% CI {out.low:.2f}-{out.high:.2f})" if math.isfinite(out.low) else ""
    return _row(claim, out, f"lowest sector rate {out.effect:.2f}{ci}",
                f"each sector's reach and grasp rate, bootstrap over replications: every lower "
                f"bound > {verdicts.SECTOR_FLOOR:g}: reproduced; an upper bound below: "
                "contradicted", f"{per.select('run', 'replication').n_unique()} replications, "
                                f"{trials.height} trials")


def _never(claim: Claim, data: _Data) -> dict:
    source = data.development if claim.source == "development" else data.table
    if source is None or claim.measure not in source.columns:
        return _not_run(claim, f"no {claim.measure} in the "
                               + ("development table (evaluate --development)"
                                  if claim.source == "development" else "post-evaluation"))
    trials = source.filter(pl.col("notation") == claim.b)
    if claim.source == "post":
        trials = trials.filter(pl.col("senses") == claim.senses)
        reps = (trials.group_by("run", "replication")
                .agg(pl.col(claim.measure).cast(pl.Float64).mean().alias("value")))
    else:  # the highest rate over the snapshots of the course
        reps = (trials.group_by("run", "replication", "generation")
                .agg(pl.col(claim.measure).cast(pl.Float64).mean().alias("value"))
                .group_by("run", "replication").agg(pl.col("value").max()))
    reps = reps.sort("run", "replication")  # the bootstrap's draws: the same every time
    if reps.height == 0:
        return _not_run(claim, f"no {claim.b} robots")
    eps = verdicts.NEVER_EPSILON
    out = verdicts.at_most(reps["value"].to_numpy(), eps, np.random.default_rng(BOOTSTRAP_SEED))
    bound = f" (upper 95% bound {out.high:.3f})" if math.isfinite(out.high) else ""
    return _row(claim, out, f"{claim.measure} {out.effect:.3f}{bound}",
                f"bootstrap over replications: upper bound <= {eps:g}: reproduced; lower bound "
                f"> {eps:g}: contradicted", f"{reps.height} replications")


def _paired(claim: Claim, data: _Data) -> dict:
    per = [data.robots(s).filter(pl.col("notation") == claim.b)
           .select(*_ROBOT[1:], pl.col("fitness").alias(s)) for s in _SENSES]
    if any(p.height == 0 for p in per):
        evaluated = [s for s, p in zip(_SENSES, per) if p.height]
        return _not_run(claim, f"{claim.b} evaluated under {', '.join(evaluated) or 'none'} "
                               "(evaluate --sensors all)")
    wide = per[0]
    for p in per[1:]:
        wide = wide.join(p, on=list(_ROBOT[1:]), how="inner", maintain_order="left")
    out = verdicts.paired(wide.select(_SENSES).to_numpy(), claim.level)
    long = pl.concat([p.rename({s: "fitness"}).with_columns(pl.lit(s).alias("senses"))
                      for s, p in zip(_SENSES, per)])
    kw = (stats.kruskal_wallis(long, "fitness", "senses")["p"].item()
          if long["fitness"].n_unique() > 1 else 1.0)
    means = ", ".join(f"{s} {wide[s].mean():.3g}" for s in _SENSES)
    return _row(claim, out, f"fitness: {means}",
                f"Friedman, robot as block, p < {ALPHA:g}; effect: Kendall's W; the paper: "
                f"Kruskal-Wallis p < {claim.level:g} (here, as independent groups: p = "
                f"{kw:.2g})", f"{wide.height} robots x 4 conditions", p_paper_test=kw)


_JUDGES = {Kind.DIRECTIONAL: _two_groups, Kind.NO_DIFFERENCE: _two_groups, Kind.BAND: _band,
           Kind.EVERY_SECTOR: _every_sector, Kind.NEVER: _never, Kind.PAIRED: _paired,
           Kind.SAME_PAIRED: _paired_change, Kind.CHANGE_PAIRED: _paired_change}


def findings(table: pl.DataFrame, baseline: pl.DataFrame | None = None,
             claims: tuple[Claim, ...] = CLAIMS,
             development: pl.DataFrame | None = None) -> pl.DataFrame:
    """Every claim (default: section IV's) judged against the post-evaluation ``table`` (one or
    several runs' trials: notation, senses, replication, rank, sector and the measures of
    ``metrics.trial_metrics``; ``figures.load_runs`` gives several runs') and ``baseline``
    (random genomes' trials, ``load_evaluation(run, baseline=True)``; None: none) and
    ``development`` (the snapshots' post-evaluation, ``development.load_development``, for the
    claims about the course of training; None: they are not run).

    Columns: claim, section, paper, kind, measured, test, n, effect, effect_low, effect_high,
    p, p_holm (Holm over the table's p), paper_level_met, p_replications, replications_agree,
    p_paper_test (the paper's own test where ours differs: F4's Kruskal-Wallis), verdict (one
    of ``VERDICTS``), note.
    """
    missing = [c for c in ("notation", "senses", "replication", "rank", "sector", "fitness",
                           "reached", "grasped") if c not in table.columns]
    if missing:
        raise ValueError(f"the post-evaluation table lacks columns {missing}")
    data = _Data(table, baseline, development)
    rows = [_JUDGES[c.kind](c, data) for c in claims]
    found = pl.DataFrame(rows, schema=_SCHEMA)
    return found.with_columns(pl.Series("p_holm", verdicts.holm(found["p"].to_numpy())))


def summary(found: pl.DataFrame) -> dict[str, int]:
    """How many claims got each verdict."""
    counts = dict(found.group_by("verdict").len().iter_rows())
    return {v: int(counts.get(v, 0)) for v in VERDICTS}
