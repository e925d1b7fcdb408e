"""The second and third validations of the babbling measures (docs/model/measures.md, "The
second validation sample", "The third validation sample"): the detector
(``kinematics.is_babbling`` on the whole trial), the candidate for claim A1
(``kinematics.babbling_before_touch``) and the moving rule (``kinematics.is_moving``) against
the labels of a sample's trials (``SECOND``: ``babbling_second_sample``'s, ``THIRD``:
``babbling_third_sample``'s), per condition, and the pre-registered rule that says whether a
measure is validated in a condition. Rendered into docs/results/babbling-detector.md by
``reports.babbling_detector``."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import polars as pl
from scipy.stats import binomtest

from dart_reach.analysis.formatting import percent, rate
from dart_reach.measures import kinematics as k

from . import babbling_second_sample as second
from . import babbling_third_sample as third
from .text import markdown_table

#: The measures validated: the page's name of each and its column in ``trials``.
MEASURES = {"detector (whole trial)": "detector babbling",
            "candidate (before the touch)": "before-touch babbling"}
#: The candidate for A1 (the key of ``MEASURES``).
CANDIDATE = "candidate (before the touch)"
#: A label's three answers in the labels file.
YES, NO, UNSURE = "1", "0", "unsure"


@dataclass(frozen=True)
class Acceptance:
    """The pre-registered rule "validated in both conditions": in each condition, on the
    trials whose label is sure, sensitivity and specificity each at least ``rate``, with a
    one-sided ``confidence`` Clopper-Pearson lower limit of each at least ``lower``, from at
    least ``trials`` trials on each side of the label."""

    rate: float = 0.8
    lower: float = 0.6
    confidence: float = 0.95
    trials: int = 15


RULE = Acceptance()


@dataclass(frozen=True)
class Sample:
    """A labelled sample: its table of hand paths and its labels (paths from the repository's
    root; its conditions are its table's, ``conditions``)."""

    sample: str
    labels: str


SECOND = Sample(second.SAMPLE, second.LABELS)
THIRD = Sample(third.SAMPLE, third.LABELS)


def lower_limit(hits: int, n: int, confidence: float = RULE.confidence) -> float:
    """One-sided Clopper-Pearson lower confidence limit of a proportion hits / n (the lower
    end of the two-sided interval at 1 - 2 (1 - ``confidence``)); NaN when n = 0."""
    if n == 0:
        return float("nan")
    two_sided = 1 - 2 * (1 - confidence)
    return float(binomtest(hits, n).proportion_ci(two_sided, method="exact").low)


def trials(root: Path, sample: Sample = SECOND) -> pl.DataFrame:
    """One row per trial of ``sample``: its code, condition, generation, replication, the two
    labels (``YES``, ``NO``, ``UNSURE``), the first touch's time (s; null: none), and per
    measure of ``MEASURES`` and the moving rule its verdict; with the detector's frequency
    (Hz), share, amplitude (m) and path (m)."""
    paths = pl.read_parquet(root / sample.sample)
    labels = pl.read_csv(root / sample.labels, schema_overrides={"babbling": pl.String,
                                                               "moving": pl.String})
    rows = []
    for code in sorted(paths["code"].unique()):
        p = paths.filter(pl.col("code") == code).sort("step")
        hand = p.select("x", "y", "z").to_numpy()
        touched = p["touched"].to_numpy()
        end = int(np.argmax(touched)) if touched.any() else -1
        frequency, share = k.hand_periodicity(hand)
        amplitude, length = k.hand_amplitude(hand), k.path_length(hand)
        first = p.row(0, named=True)
        rows.append({"code": code, "senses": first["senses"],
                     "generation": first["generation"], "replication": first["replication"],
                     "first touch (s)": end * k.DT if end >= 0 else None,
                     "Hz": frequency, "share": share, "amplitude (m)": amplitude,
                     "path (m)": length,
                     "detector babbling": k.is_babbling(frequency, share, amplitude),
                     "before-touch babbling": k.babbling_before_touch(hand, end),
                     "detector moving": k.is_moving(length, amplitude)})
    table = labels.join(pl.DataFrame(rows), on="code", how="right")
    missing = table.filter(pl.col("babbling").is_null() | pl.col("moving").is_null())
    if missing.height:
        raise ValueError(f"trials without labels: {missing['code'].to_list()}")
    bad = table.filter(~pl.col("babbling").is_in([YES, NO, UNSURE])
                       | ~pl.col("moving").is_in([YES, NO, UNSURE]))
    if bad.height:
        raise ValueError(f"labels other than {YES}, {NO}, {UNSURE}: {bad['code'].to_list()}")
    return table.select("code", "senses", "generation", "replication", "babbling", "moving",
                        *(c for c in table.columns if c not in (
                            "code", "senses", "generation", "replication", "babbling",
                            "moving")))


def counts(part: pl.DataFrame, label: str, verdict: str, unsure: str | None = None
           ) -> dict[str, int]:
    """Confusion counts of ``verdict`` against ``label`` on ``part``: the sure labels only
    (``unsure`` None) or the unsure counted as ``YES`` or ``NO``."""
    lab = part[label].replace({UNSURE: unsure} if unsure else {})
    keep = lab.is_in([YES, NO])
    lab, det = (lab.filter(keep) == YES), part[verdict].filter(keep)
    return {"tp": int((lab & det).sum()), "fn": int((lab & ~det).sum()),
            "tn": int((~lab & ~det).sum()), "fp": int((~lab & det).sum())}


def passes(c: dict[str, int], rule: Acceptance = RULE) -> bool:
    """Whether confusion counts ``c`` meet ``rule`` (``Acceptance``)."""
    pos, neg = c["tp"] + c["fn"], c["tn"] + c["fp"]
    if pos < rule.trials or neg < rule.trials:
        return False
    return (c["tp"] / pos >= rule.rate and c["tn"] / neg >= rule.rate
            and lower_limit(c["tp"], pos, rule.confidence) >= rule.lower
            and lower_limit(c["tn"], neg, rule.confidence) >= rule.lower)


def validation(table: pl.DataFrame, rule: Acceptance = RULE) -> pl.DataFrame:
    """Per measure of ``MEASURES`` (babbling label) and the moving rule (moving label), per
    condition: trials with a sure label, sensitivity and specificity with their one-sided
    Clopper-Pearson lower limits, and (babbling measures) whether ``rule`` is met; then the
    same with the unsure labels counted as yes and as no (sensitivity and specificity
    only)."""
    rows = []
    for name, verdict, label in (*((n, v, "babbling") for n, v in MEASURES.items()),
                                 ("moving rule", "detector moving", "moving")):
        for senses in conditions(table):
            part = table.filter(pl.col("senses") == senses)
            for unsure in (None, YES, NO):
                c = counts(part, label, verdict, unsure)
                pos, neg = c["tp"] + c["fn"], c["tn"] + c["fp"]
                rows.append({
                    "measure": name, "label": label, "senses": senses,
                    "unsure labels": {None: "left out", YES: "as yes", NO: "as no"}[unsure],
                    "trials": pos + neg, "sensitivity": rate(c["tp"], pos),
                    "sensitivity lower limit": lower_limit(c["tp"], pos, rule.confidence),
                    "specificity": rate(c["tn"], neg),
                    "specificity lower limit": lower_limit(c["tn"], neg, rule.confidence),
                    "meets the rule": ("yes" if passes(c, rule) else "no")
                    if unsure is None else ""})
    return pl.DataFrame(rows)


def validated(table: pl.DataFrame, measure: str, rule: Acceptance = RULE) -> dict[str, bool]:
    """Per condition, whether ``measure`` (a key of ``MEASURES``) meets ``rule`` on the sure
    babbling labels."""
    return {s: passes(counts(table.filter(pl.col("senses") == s), "babbling",
                             MEASURES[measure]), rule) for s in conditions(table)}


def sensitivity_lower_limit(table: pl.DataFrame, measure: str, senses: str,
                            rule: Acceptance = RULE) -> float:
    """The one-sided ``rule.confidence`` lower limit of ``measure``'s sensitivity (a key of
    ``MEASURES``) under ``senses``, on the sure babbling labels of ``table``."""
    c = counts(table.filter(pl.col("senses") == senses), "babbling", MEASURES[measure])
    return lower_limit(c["tp"], c["tp"] + c["fn"], rule.confidence)


def label_counts(table: pl.DataFrame) -> pl.DataFrame:
    """Per condition: trials, and how many labels of each question are yes, no, unsure,
    and how many trials are labelled moving but not babbling."""
    rows = []
    for senses in conditions(table):
        part = table.filter(pl.col("senses") == senses)
        row = {"senses": senses, "trials": part.height}
        for label in ("babbling", "moving"):
            for answer, name in ((YES, "yes"), (NO, "no"), (UNSURE, "unsure")):
                row[f"{label} {name}"] = int((part[label] == answer).sum())
        row["moving, not babbling"] = int(((part["moving"] == YES)
                                           & (part["babbling"] == NO)).sum())
        rows.append(row)
    return pl.DataFrame(rows)


#: How the page names each condition, in the page's order.
WHERE = {"normal": "with the ball (normal senses)", "no-ball": "with the ball absent",
         "no-sight": "without sight"}


def conditions(table: pl.DataFrame) -> tuple[str, ...]:
    """The conditions of a sample's ``table``, in ``WHERE``'s order."""
    return tuple(c for c in WHERE if c in set(table["senses"]))


def _where(met: list[str], of: tuple[str, ...]) -> str:
    return ("in every condition" if len(met) == len(of) else
            "only " + " and ".join(WHERE[s] for s in met) if met else "in no condition")


def words(table: pl.DataFrame, rule: Acceptance = RULE) -> str:
    """The page's words on a sample, every number counted from ``table`` (``trials``): per
    condition what each measure finds of the trials labelled babbling and which it misses,
    what it calls babbling against the label, which measure meets ``rule`` where, how often
    the labels tell babbling from moving, and what the moving rule calls moving against the
    moving label."""
    parts = []
    for senses in conditions(table):
        part = table.filter(pl.col("senses") == senses)
        found = []
        for name, column in MEASURES.items():
            c = counts(part, "babbling", column)
            missed = part.filter((pl.col("babbling") == YES) & ~pl.col(column))["code"]
            wrong = part.filter((pl.col("babbling") == NO) & pl.col(column))["code"]
            found.append(f"the {name.split(' (')[0]} finds {c['tp']} of the "
                         f"{c['tp'] + c['fn']} trials labelled babbling"
                         + (f" (misses {', '.join(missed)})" if c["fn"] else "")
                         + f" and calls babbling {c['fp']} of the {c['tn'] + c['fp']} labelled "
                         "not babbling" + (f" ({', '.join(wrong)})" if c["fp"] else ""))
        parts.append(f"{WHERE[senses].capitalize()}, {'; '.join(found)}.")
    met = {m: [s for s, ok in validated(table, m, rule).items() if ok] for m in MEASURES}
    verdicts = [f"the {m.split(' (')[0]} meets it {_where(where, conditions(table))}"
                for m, where in met.items()]
    apart = table.filter((pl.col("babbling") != pl.col("moving"))
                         & pl.col("babbling").is_in([YES, NO])
                         & pl.col("moving").is_in([YES, NO])).height
    unsure = table.filter((pl.col("babbling") == UNSURE) | (pl.col("moving") == UNSURE)).height
    text = (" ".join(parts) + " By the rule, " + "; ".join(verdicts) + ". "
            + f"The sure labels tell babbling from moving on {apart} of the "
            f"{table.height} trials ({unsure} with an unsure answer to either question): "
            + ("no trial is labelled moving but not babbling, so this sample cannot tell the "
               "two apart. " if apart == 0 else
               f"{apart} trials are labelled one and not the other. "))
    over = table.filter((pl.col("moving") == NO) & pl.col("detector moving"))["code"]
    under = table.filter((pl.col("moving") == YES) & ~pl.col("detector moving"))["code"]
    sure_still = table.filter(pl.col("moving") == NO).height
    sure_moving = table.filter(pl.col("moving") == YES).height
    text += (f"The moving rule calls moving {len(over)} of the {sure_still} trials labelled "
             "not moving" + (f" ({', '.join(over)})" if len(over) else "")
             + f" and not moving {len(under)} of the {sure_moving} labelled moving"
             + (f" ({', '.join(under)})" if len(under) else "") + "; it "
             + ("meets" if all(passes(counts(table.filter(pl.col("senses") == s), "moving",
                                             "detector moving"), rule)
                               for s in conditions(table)) else "does not meet")
             + " the rule in every condition.")
    return text


def a1_decision(table: pl.DataFrame, rule: Acceptance = RULE) -> str:
    """What the second sample decides for claim A1 (its protocol): the candidate validated
    with and without the ball, or A1's babbling "cannot be tested"."""
    if all(validated(table, CANDIDATE, rule).values()):
        return ("The candidate is validated with and without the ball: claim A1's babbling "
                "can be judged with it.")
    return ("The candidate is not validated in both conditions, so claim A1's babbling stays "
            "\"cannot be tested\".")


def third_decision(table: pl.DataFrame, second_table: pl.DataFrame,
                   rule: Acceptance = RULE) -> str:
    """What the third sample decides (its protocol), beside the second sample's
    ``second_table``: whether a measure is validated both without sight (here) and with the
    ball (on the second sample, the runs' robots: A3's reference), a condition for judging
    claim A3's babbling with it (which also needs the runs' trials measured for it; until
    both, A3's babbling stays "cannot be tested"); and, with and without the ball, the second
    sample's result checked on other robots."""
    both = [m.split(" (")[0] for m in MEASURES
            if validated(table, m, rule)["no-sight"]
            and validated(second_table, m, rule)["normal"]]
    sight = (f"The {both[0]} is validated without sight here and with the ball on the second "
             "sample: A3's babbling can be judged with it once the runs' trials are measured "
             "for it (not yet done, so it stays \"cannot be tested\")." if both else
             "No measure is validated both without sight (here) and with the ball (on the "
             "second sample, A3's reference), so A3's babbling stays \"cannot be tested\".")
    met = validated(table, CANDIDATE, rule)
    ball = ("normal", "no-ball")
    held = [s for s in ball if met[s]]
    return (sight + " With and without the ball, on these robots (model version 3, "
            f"generations {', '.join(map(str, third.GENERATIONS))}), the candidate meets the "
            f"rule {_where(held, ball)}" + (
                "." if len(held) == len(ball) else
                ": the second sample's result (validated in both, on which A1 is judged) does "
                "not carry over to them. A1 is not re-decided on this sample (its protocol); "
                "its babbling verdicts rest on the second sample alone."))


def rule_words(rule: Acceptance = RULE) -> str:
    return (f"sensitivity and specificity each at least {rule.rate:g}, with a one-sided "
            f"{percent(rule.confidence)} Clopper-Pearson lower limit of each at least "
            f"{rule.lower:g}, from at least {rule.trials} trials on each side of the label, "
            "in each condition")


def values(root: Path) -> dict[str, str]:
    """The page's values of the second and third samples
    (docs/results/templates/babbling-detector.md)."""
    out = {"second_seed": str(second.SEED), "third_seed": str(third.SEED),
           "rule": rule_words(), "third_generations": ", ".join(map(str, third.GENERATIONS)),
           "third_run": third.RUN}
    second_table = trials(root, SECOND)
    for key, sample, decision in (("second", SECOND, a1_decision),
                                  ("third", THIRD, lambda t: third_decision(t, second_table))):
        table = second_table if sample is SECOND else trials(root, sample)
        out.update({
            f"{key}_labels": sample.labels, f"{key}_sample": sample.sample,
            f"{key}_trials": str(table.height),
            f"{key}_label_counts": markdown_table(label_counts(table)),
            f"{key}_validation": markdown_table(validation(table)),
            f"{key}_words": words(table) + " " + decision(table),
            f"{key}_table": markdown_table(table.sort("code"))})
    return out
