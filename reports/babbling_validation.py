"""The second validation of the babbling measures (docs/model/measures.md, "The second
validation sample"): the detector (``kinematics.is_babbling`` on the whole trial) and the
candidate for claim A1 (``kinematics.babbling_before_touch``) against the labels of
``babbling_second_sample``'s trials, per condition, and the pre-registered rule that says
whether a measure is validated with and without the ball. Rendered into
docs/results/babbling-detector.md by ``reports.babbling_detector``."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import polars as pl
from scipy.stats import binomtest

from dart_reach.measures import kinematics as k

from . import babbling_second_sample as second
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


def lower_limit(hits: int, n: int, confidence: float = RULE.confidence) -> float:
    """One-sided Clopper-Pearson lower confidence limit of a proportion hits / n (the lower
    end of the two-sided interval at 1 - 2 (1 - ``confidence``)); NaN when n = 0."""
    if n == 0:
        return float("nan")
    two_sided = 1 - 2 * (1 - confidence)
    return float(binomtest(hits, n).proportion_ci(two_sided, method="exact").low)


def trials(root: Path) -> pl.DataFrame:
    """One row per trial of the second sample: its code, condition, generation,
    replication, the two labels (``YES``, ``NO``, ``UNSURE``), the first touch's row (-1:
    none), and per measure of ``MEASURES`` and the moving rule its verdict; with the
    detector's frequency (Hz), share, amplitude (m) and path (m)."""
    paths = pl.read_parquet(root / second.SAMPLE)
    labels = pl.read_csv(root / second.LABELS, schema_overrides={"babbling": pl.String,
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


def _rate(hit: int, n: int) -> str:
    return f"{hit}/{n} ({hit / n:.0%})" if n else "–"


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
        for senses in second.CONDITIONS:
            part = table.filter(pl.col("senses") == senses)
            for unsure in (None, YES, NO):
                c = counts(part, label, verdict, unsure)
                pos, neg = c["tp"] + c["fn"], c["tn"] + c["fp"]
                rows.append({
                    "measure": name, "label": label, "senses": senses,
                    "unsure labels": {None: "left out", YES: "as yes", NO: "as no"}[unsure],
                    "trials": pos + neg, "sensitivity": _rate(c["tp"], pos),
                    "sensitivity lower limit": lower_limit(c["tp"], pos, rule.confidence),
                    "specificity": _rate(c["tn"], neg),
                    "specificity lower limit": lower_limit(c["tn"], neg, rule.confidence),
                    "meets the rule": ("yes" if passes(c, rule) else "no")
                    if unsure is None and label == "babbling" else ""})
    return pl.DataFrame(rows)


def validated(table: pl.DataFrame, measure: str, rule: Acceptance = RULE) -> dict[str, bool]:
    """Per condition, whether ``measure`` (a key of ``MEASURES``) meets ``rule`` on the sure
    babbling labels."""
    return {s: passes(counts(table.filter(pl.col("senses") == s), "babbling",
                             MEASURES[measure]), rule) for s in second.CONDITIONS}


def label_counts(table: pl.DataFrame) -> pl.DataFrame:
    """Per condition: trials, and how many labels of each question are yes, no, unsure,
    and how many trials are labelled moving but not babbling."""
    rows = []
    for senses in second.CONDITIONS:
        part = table.filter(pl.col("senses") == senses)
        row = {"senses": senses, "trials": part.height}
        for label in ("babbling", "moving"):
            for answer, name in ((YES, "yes"), (NO, "no"), (UNSURE, "unsure")):
                row[f"{label} {name}"] = int((part[label] == answer).sum())
        row["moving, not babbling"] = int(((part["moving"] == YES)
                                           & (part["babbling"] == NO)).sum())
        rows.append(row)
    return pl.DataFrame(rows)


#: How the page names each condition.
WHERE = {"normal": "with the ball (normal senses)", "no-ball": "with the ball absent"}


def words(table: pl.DataFrame, rule: Acceptance = RULE) -> str:
    """The page's words on the second sample, every number counted from ``table``
    (``trials``): per condition what each measure finds of the trials labelled babbling and
    which it misses, what it calls babbling against the label, which measure meets ``rule``
    where, how often the labels tell babbling from moving, and the decision for claim A1."""
    parts = []
    for senses in second.CONDITIONS:
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
    verdicts = []
    for m, where in met.items():
        verdicts.append(f"the {m.split(' (')[0]} meets it "
                        + ("in both conditions" if len(where) == len(second.CONDITIONS) else
                           "only " + " and ".join(WHERE[s] for s in where) if where else
                           "in neither condition"))
    apart = table.filter((pl.col("babbling") != pl.col("moving"))
                         & pl.col("babbling").is_in([YES, NO])
                         & pl.col("moving").is_in([YES, NO])).height
    unsure = table.filter((pl.col("babbling") == UNSURE) | (pl.col("moving") == UNSURE)).height
    ok = len(met[CANDIDATE]) == len(second.CONDITIONS)
    text = (" ".join(parts) + " By the rule, " + "; ".join(verdicts) + ". "
            + f"The sure labels tell babbling from moving on {apart} of the "
            f"{table.height} trials ({unsure} with an unsure answer to either question): "
            + ("no trial is labelled moving but not babbling, so this sample cannot tell the "
               "two apart either. " if apart == 0 else
               f"{apart} trials are labelled one and not the other. "))
    over = table.filter((pl.col("moving") == NO) & pl.col("detector moving"))["code"]
    sure_still = table.filter(pl.col("moving") == NO).height
    text += (f"The moving rule calls moving {len(over)} of the {sure_still} trials labelled "
             "not moving" + (f" ({', '.join(over)}). " if len(over) else ". "))
    text += ("The candidate is validated with and without the ball: claim A1's babbling can "
             "be judged with it." if ok else
             "The candidate is not validated in both conditions, so claim A1's babbling stays "
             "\"cannot be tested\".")
    return text


def values(root: Path) -> dict[str, str]:
    """The page's values of the second sample (docs/results/templates/babbling-detector.md)."""
    table = trials(root)
    return {
        "second_labels": second.LABELS, "second_sample": second.SAMPLE,
        "second_seed": str(second.SEED), "second_trials": str(table.height),
        "second_label_counts": markdown_table(label_counts(table)),
        "second_validation": markdown_table(validation(table)),
        "second_rule": (f"sensitivity and specificity each at least {RULE.rate:g}, with a "
                        f"one-sided {RULE.confidence:.0%} Clopper-Pearson lower limit of each at "
                        f"least {RULE.lower:g}, from at least {RULE.trials} trials on each side "
                        "of the label, in each condition"),
        "second_words": words(table),
        "second_table": markdown_table(table.sort("code")),
    }
