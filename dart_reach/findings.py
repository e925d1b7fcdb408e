"""The claims of the paper's section IV, each tested against a run's post-evaluation.

``findings(table, baseline)`` returns one row per claim: the paper's statement, the value and
the test measured here, the sample sizes, the p-value and a verdict computed from the data:

- ``reproduced``: the effect the paper reports, in its direction, at the paper's significance
  level (a claim of *no* difference: p >= 0.05);
- ``contradicted``: the opposite effect at p < 0.05 (a claim of no difference: p < 0.05);
- ``not significant at this n``: neither;
- ``not run``: the run lacks a phase, condition or sensory condition the claim needs.

Units (the paper's): a *robot* (its mean over its post-evaluation trials, normal senses unless
the claim is about senses) for the comparisons of phases (Figs. 5-9: "50 robots ... for 45
trials"); a *replication* (its best robot's post-evaluation fitness,
``metrics.replication_performance``) for the comparisons of conditions (Fig. 10). Tests are
two-tailed Mann-Whitney U unless stated (``stats``); no correction for multiple comparisons,
as in the paper. Where the paper gives no number ("about half", "large quasi-periodic
movements", "nearly constant"), the operational test is stated in the row and in
docs/analysis.md.
"""

from __future__ import annotations

import math

import numpy as np
import polars as pl
from scipy import stats as sps

from . import metrics, stats

REPRODUCED, CONTRADICTED, NOT_SIGNIFICANT, NOT_RUN = (
    "reproduced", "contradicted", "not significant at this n", "not run")
VERDICTS = (REPRODUCED, CONTRADICTED, NOT_SIGNIFICANT, NOT_RUN)

#: "About half the trials" (IV-A-1): a pre-reacher's reach rate between a third and two thirds.
ABOUT_HALF = (1 / 3, 2 / 3)
#: Significance level of the verdicts "contradicted" and of claims of no difference.
ALPHA = 0.05

_ROBOT = ("notation", "run", "replication", "rank")
_SCHEMA = {"claim": pl.Utf8, "paper": pl.Utf8, "measured": pl.Utf8, "test": pl.Utf8,
           "n": pl.Utf8, "p": pl.Float64, "verdict": pl.Utf8}
_MEASURES = ("fitness", "reached", "grasped", "speed", "straightness", "var_elbow",
             "var_shoulder", "var_trunk", "babbling_share", "sectors_reached")


# ------------------------------------------------------------------------------ units
def _with_run(table: pl.DataFrame) -> pl.DataFrame:
    return table if "run" in table.columns else table.with_columns(pl.lit("").alias("run"))


def robots(table: pl.DataFrame, senses: str = "normal") -> pl.DataFrame:
    """One row per robot (notation, run, replication, rank) of ``senses``: the mean over its
    trials of each measure (booleans: rates), and ``sectors_reached``, the number of sectors
    in which it reached the ball at least once (the spread of success, Fig. 7)."""
    table = _with_run(table).filter(pl.col("senses") == senses)
    means = metrics.robot_means(table, [m for m in _MEASURES if m != "sectors_reached"],
                                by=_ROBOT)
    spread = (table.filter(pl.col("reached")).group_by(_ROBOT)
              .agg(pl.col("sector").n_unique().cast(pl.Float64).alias("sectors_reached")))
    return (means.join(spread, on=list(_ROBOT), how="left")
            .with_columns(pl.col("sectors_reached").fill_null(0.0)))


def replications(table: pl.DataFrame, senses: str = "normal") -> pl.DataFrame:
    """One row per replication (notation, run, replication): its best robot's post-evaluation
    fitness, the unit of Fig. 10."""
    table = _with_run(table)
    if table.filter((pl.col("senses") == senses) & (pl.col("rank") == 0)).height == 0:
        return pl.DataFrame(schema={"notation": pl.Utf8, "fitness": pl.Float64})
    return metrics.replication_performance(table, senses=senses, by=("notation", "run"))


def _values(units: pl.DataFrame, group: str, measure: str) -> np.ndarray:
    v = units.filter(pl.col("notation") == group)[measure].cast(pl.Float64).to_numpy()
    return v[np.isfinite(v)]


# ------------------------------------------------------------------------------ verdicts
def _row(claim, paper, measured, test, n, p, verdict) -> dict:
    return {"claim": claim, "paper": paper, "measured": measured, "test": test, "n": n,
            "p": float(p), "verdict": verdict}


def _not_run(claim: str, paper: str, missing: str) -> dict:
    return _row(claim, paper, f"not run: {missing}", "", "", math.nan, NOT_RUN)


def verdict(p: float, observed_sign: float, claimed_sign: int, level: float) -> str:
    """The verdict of a comparison: ``claimed_sign`` +1 (the paper: second group higher), -1
    (lower) or 0 (no difference); ``level``: the paper's significance level."""
    if not math.isfinite(p):
        return NOT_SIGNIFICANT
    if claimed_sign == 0:
        return CONTRADICTED if p < ALPHA else REPRODUCED
    same = np.sign(observed_sign) == claimed_sign
    if same and p < level:
        return REPRODUCED
    if not same and observed_sign != 0 and p < ALPHA:
        return CONTRADICTED
    return NOT_SIGNIFICANT


def _sign_word(sign: int) -> str:
    return {1: "higher", -1: "lower", 0: "no different"}[sign]


def compare(units: pl.DataFrame, a: str, b: str, measure: str, sign: int, level: float,
            claim: str, paper: str, unit: str = "robots") -> dict:
    """Row of a claim that ``measure`` is ``sign`` (+1 higher, -1 lower, 0 no different) in
    group ``b`` than in group ``a`` (two-tailed Mann-Whitney U over ``units``)."""
    x, y = _values(units, a, measure), _values(units, b, measure)
    if len(x) == 0 or len(y) == 0:
        lacking = " or ".join(g for g, v in ((a, x), (b, y)) if not len(v))
        return _not_run(claim, paper, f"no {unit} of {lacking} with a {measure}")
    if np.ptp(np.concatenate([x, y])) == 0:
        p = 1.0
    else:
        p = float(sps.mannwhitneyu(x, y, alternative="two-sided").pvalue)
    mx, my = float(np.mean(x)), float(np.mean(y))
    level_text = f"p < {level:g}" if sign else f"p >= {ALPHA:g}"
    return _row(claim, paper,
                f"{measure}: {b} {my:.3g} vs {a} {mx:.3g} (means over {unit})",
                f"Mann-Whitney U, two-tailed; the paper: {b} {_sign_word(sign)}, {level_text}",
                f"{len(y)} vs {len(x)} {unit}", p, verdict(p, my - mx, sign, level))


# ------------------------------------------------------------------------------ the claims
def _f1(rob: pl.DataFrame, base: pl.DataFrame | None) -> list[dict]:
    rows = []
    paper = "pre-reachers reach in about half of the trials (Fig. 5)"
    x = _values(rob, "pre", "reached")
    if len(x) == 0:
        rows.append(_not_run("F1 reach about half", paper, "no pre-reaching robots"))
    else:
        mean = float(np.mean(x))
        half = (sps.t.ppf(0.975, len(x) - 1) * np.std(x, ddof=1) / math.sqrt(len(x))
                if len(x) > 1 else math.inf)
        lo, hi = ABOUT_HALF
        if lo <= mean <= hi:
            v = REPRODUCED
        elif mean + half < lo or mean - half > hi:
            v = CONTRADICTED
        else:
            v = NOT_SIGNIFICANT
        rows.append(_row("F1 reach about half", paper,
                         f"reach rate {mean:.2f} (95% CI {mean - half:.2f}-{mean + half:.2f})",
                         f"mean in [{lo:.2f}, {hi:.2f}]: reproduced; 95% t-interval wholly "
                         "outside: contradicted", f"{len(x)} robots", math.nan, v))
    paper = ("pre-reachers show large quasi-periodic hand movements: motor babbling "
             "(Fig. 8, IV-A-1)")
    if base is None or base.height == 0:
        rows.append(_not_run("F1 babbling", paper, "no random baseline (evaluate --baseline N)"))
    else:
        both = pl.concat([rob.filter(pl.col("notation") == "pre"),
                          base.filter(pl.col("notation") == "pre")
                          .with_columns(pl.lit("random pre").alias("notation"))],
                         how="diagonal_relaxed")
        row = compare(both, "random pre", "pre", "babbling_share", +1, ALPHA,
                      "F1 babbling", paper)
        row["test"] += " (share of the hand's movement power at its dominant frequency, " \
                       "against random pre-reaching networks)"
        rows.append(row)
    paper = ("pre-reachers move the trunk and shoulder and lock the elbow: the hand-shoulder "
             "distance stays nearly constant (Fig. 6)")
    pre = rob.filter(pl.col("notation") == "pre").select("var_elbow", "var_shoulder").drop_nans()
    if pre.height < 2:
        rows.append(_not_run("F1 elbow locked", paper, "fewer than 2 pre-reaching robots"))
    else:
        e, s = pre["var_elbow"].to_numpy(), pre["var_shoulder"].to_numpy()
        p = 1.0 if np.all(e == s) else float(sps.wilcoxon(s, e).pvalue)
        rows.append(_row("F1 elbow locked", paper,
                         f"elbow variability {e.mean():.3f} vs shoulder {s.mean():.3f} rad",
                         "Wilcoxon signed-rank, two-tailed, elbow vs shoulder of the same "
                         "robots; the paper: elbow lower, p < 0.05", f"{len(e)} robots", p,
                         verdict(p, float(np.mean(e - s)), -1, ALPHA)))
    return rows


def _f2_f3(rob: pl.DataFrame, table: pl.DataFrame) -> list[dict]:
    rows = []
    for measure, sign, level, what in (
            ("grasped", +1, 0.001, "grasp up"), ("reached", -1, 0.001, "reach down"),
            ("straightness", +1, 0.01, "straighter"), ("speed", -1, 0.05, "slower"),
            ("var_shoulder", -1, 0.001, "shoulder variability down"),
            ("sectors_reached", -1, 0.05, "success in fewer sectors")):
        rows.append(compare(rob, "pre", "gross", measure, sign, level, f"F2 {what}",
                            f"gross- vs pre-reachers: {what} (p < {level:g}; Figs. 5-7)"))
    for measure, sign, level, what in (
            ("reached", +1, 0.001, "reach up"), ("grasped", +1, 0.001, "grasp up"),
            ("var_elbow", +1, 0.001, "elbow variability up"),
            ("var_shoulder", +1, 0.001, "shoulder variability up"),
            ("var_trunk", +1, 0.001, "trunk variability up"),
            ("speed", 0, ALPHA, "speed no different"),
            ("straightness", 0, ALPHA, "straightness no different")):
        paper = (f"fine- vs gross-reachers: {what}"
                 + (f" (p < {level:g})" if sign else " (not significant)") + " (Figs. 5, 6)")
        rows.append(compare(rob, "gross", "fine", measure, sign, level, f"F3 {what}", paper))
    paper = "fine-reachers succeed in all 9 sectors (Fig. 7)"
    fine = _with_run(table).filter((pl.col("notation") == "fine")
                                   & (pl.col("senses") == "normal"))
    if fine.height == 0:
        rows.append(_not_run("F3 all sectors", paper, "no fine-reaching robots"))
    else:
        per = fine.group_by("sector").agg(pl.col("reached").mean()).sort("sector")
        rates = dict(zip(per["sector"].to_list(), per["reached"].to_list()))
        empty = [k for k in range(9) if rates.get(k, 0.0) == 0.0]
        rows.append(_row("F3 all sectors", paper,
                         f"sectors without a reach: {empty or 'none'}; lowest sector rate "
                         f"{min(rates.get(k, 0.0) for k in range(9)):.2f}",
                         "every sector reached in at least one trial: reproduced; else "
                         "contradicted", f"{fine['replication'].n_unique()} replications, "
                         f"{fine.height} trials", math.nan,
                         REPRODUCED if not empty else CONTRADICTED))
    return rows


def _f4(table: pl.DataFrame) -> list[dict]:
    rows = []
    senses = ("normal", "no-touch", "no-sight", "nothing")
    per = {s: robots(table, s) for s in senses}
    paper = ("performance differs across the four sensory conditions (p < 0.01, "
             "Kruskal-Wallis; Fig. 9)")
    present = [s for s in senses if per[s].height]
    if len(present) < 4:
        rows.append(_not_run("F4 senses differ", paper,
                             f"sensory conditions evaluated: {', '.join(present) or 'none'} "
                             "(evaluate --sensors all)"))
    else:
        units = pl.concat([per[s].filter(pl.col("notation").is_in(["pre", "gross", "fine"]))
                           .with_columns(pl.lit(s).alias("senses")) for s in senses])
        kw = stats.kruskal_wallis(units, "fitness", "senses").row(0, named=True)
        means = ", ".join(f"{s} {units.filter(pl.col('senses') == s)['fitness'].mean():.3g}"
                          for s in senses)
        rows.append(_row("F4 senses differ", paper, f"fitness: {means}",
                         "Kruskal-Wallis across the four sensory conditions, the robots of "
                         "the three phases pooled; the paper: p < 0.01",
                         f"{kw['n']} robot-conditions", kw["p"],
                         REPRODUCED if kw["p"] < 0.01 else NOT_SIGNIFICANT))
    for s in senses:
        if s in ("normal", "no-touch"):
            pairs = (("gross", "fine", +1, "fine > gross"), ("pre", "gross", +1, "gross > pre"))
        else:
            pairs = (("gross", "fine", -1, "gross > fine"),)
        for a, b, sign, what in pairs:
            paper = f"{s}: {what} (p < 0.05; Fig. 9)"
            if not per[s].height:
                rows.append(_not_run(f"F4 {s}: {what}", paper, f"senses {s} not evaluated"))
            else:
                rows.append(compare(per[s], a, b, "fitness", sign, 0.05,
                                    f"F4 {s}: {what}", paper))
    return rows


def _f5_f6(reps: pl.DataFrame) -> list[dict]:
    rows = [compare(reps, "gross^", "gross", "fitness", +1, 0.05, "F5 gross > gross^",
                    "gross outperforms the non-incremental gross^ (p < 0.05, two-tailed "
                    "Mann-Whitney; Fig. 10)", unit="replications")]
    for a, b in (("pre", "pre-h"), ("gross", "gross-h"), ("pre", "pre*"),
                 ("gross^", "gross^*"), ("fine^", "fine*"), ("fine", "fine^")):
        rows.append(compare(reps, a, b, "fitness", 0, ALPHA, f"F6 {a} vs {b}",
                            f"{a} and {b} do not differ significantly (Fig. 10)",
                            unit="replications"))
    return rows


def _f7(rob: pl.DataFrame) -> list[dict]:
    return [compare(rob, "pre", g, "babbling_share", -1, ALPHA, f"F7 {g} no babbling",
                    f"{g} robots never show motor babbling (IV-C): their quasi-periodic "
                    "movement below the pre-reachers'")
            for g in ("fine*", "fine^")]


def findings(table: pl.DataFrame, baseline: pl.DataFrame | None = None) -> pl.DataFrame:
    """Every claim of section IV (F1-F7) against the post-evaluation ``table`` (one or several
    runs' trials with columns notation, senses, replication, rank, sector and the measures of
    ``metrics.trial_metrics``; ``figures.load_runs`` gives several runs') and ``baseline``
    (random genomes' trials, ``load_evaluation(run, baseline=True)``; None: none).

    Columns: claim, paper, measured, test, n, p (NaN where the test has none), verdict (one
    of ``VERDICTS``). Phases are told apart by their notation (pre, gross, fine, gross^, ...).
    """
    missing = [c for c in ("notation", "senses", "replication", "rank", "sector", *_MEASURES)
               if c not in table.columns and c != "sectors_reached"]
    if missing:
        raise ValueError(f"the post-evaluation table lacks columns {missing}")
    rob = robots(table)
    base = robots(baseline) if baseline is not None and baseline.height else None
    rows = [*_f1(rob, base), *_f2_f3(rob, table), *_f4(table), *_f5_f6(replications(table)),
            *_f7(rob)]
    return pl.DataFrame(rows, schema=_SCHEMA)


def summary(found: pl.DataFrame) -> dict[str, int]:
    """How many claims got each verdict."""
    counts = dict(found.group_by("verdict").len().iter_rows())
    return {v: int(counts.get(v, 0)) for v in VERDICTS}
