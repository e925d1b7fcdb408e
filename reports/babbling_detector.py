"""docs/results/babbling-detector.md: the babbling detector (``measures.kinematics``)
against paths labelled without its output (docs/model/measures.md, "Validating the
detector"): the synthetic set (``measures.babbling_synthetic``), the 40 real trials labelled
by eye (``babbling_sample``: ``SAMPLE``, ``LABELS``), the second sample with and without the
ball (``babbling_validation``), and the strategy by movement beside the strategy by rhythm at
the judged generations of ``FULL``. Rendered by ``reports.results``."""

from __future__ import annotations

from pathlib import Path

import polars as pl

from dart_reach.analysis import strategies as st
from dart_reach.analysis.formatting import percent, rate
from dart_reach.measures import babbling_synthetic as synthetic
from dart_reach.measures import kinematics as k
from dart_reach.postevaluation.snapshots import load_development

from . import babbling_validation as second
from .babbling_sample import CONDITIONS, GENERATION, LABELS, SAMPLE, SEED
from .runs import FULL, JUDGED
from .text import markdown_table

#: Paths per synthetic family.
PER_FAMILY = 200


def detect(hand) -> dict:
    """The detector's measures and verdicts on one (T, 3) hand path."""
    frequency, share = k.hand_periodicity(hand)
    amplitude, path = k.hand_amplitude(hand), k.path_length(hand)
    return {"frequency": frequency, "share": share, "amplitude": amplitude, "path": path,
            "babbling": k.is_babbling(frequency, share, amplitude),
            "moving": k.is_moving(path, amplitude)}


def synthetic_table(per_family: int = PER_FAMILY, seed: int = SEED) -> pl.DataFrame:
    """Per synthetic family: its label, paths, how many the detector calls babbling and
    which test failed where it missed (share, frequency, amplitude)."""
    rows = []
    for p in synthetic.labelled_set(per_family, seed):
        d = detect(p.hand)
        rows.append({"family": p.family, "label": p.babbling, "detected": d["babbling"],
                     "low share": d["share"] < k.BABBLING_SHARE,
                     "low frequency": d["frequency"] < k.BABBLING_MIN_HZ,
                     "small": d["amplitude"] < k.BABBLING_AMPLITUDE})
    frame = pl.DataFrame(rows)
    missed = (pl.col("detected") != pl.col("label"))
    return (frame.group_by("family", maintain_order=True)
            .agg(pl.col("label").first().alias("babbling by construction"),
                 pl.len().alias("paths"), pl.col("detected").sum().alias("called babbling"),
                 (missed & pl.col("low share")).sum().alias("missed: share < 0.4"),
                 (missed & pl.col("low frequency")).sum().alias("missed: below 0.25 Hz"),
                 (missed & pl.col("small")).sum().alias("missed: amplitude < 0.05 m")))


def real_table(root: Path) -> pl.DataFrame:
    """One row per labelled real trial: its code, condition, replication, the labels and the
    detector's measures and verdicts on its hand path."""
    paths = pl.read_parquet(root / SAMPLE)
    labels = pl.read_csv(root / LABELS)
    rows = []
    for code in sorted(paths["code"].unique()):
        p = paths.filter(pl.col("code") == code)
        first = p.row(0, named=True)
        rows.append({"code": code, "senses": first["senses"],
                     "replication": first["replication"],
                     **{f"detector {key}": value for key, value in
                        detect(p.select("x", "y", "z").to_numpy()).items()}})
    return labels.join(pl.DataFrame(rows), on="code").with_columns(
        pl.col("babbling", "moving", "unsure").cast(pl.Boolean))


def agreement(table: pl.DataFrame, label: str, detected: str) -> dict[str, int]:
    """Counts of a confusion table: true/false positives/negatives."""
    lab, det = table[label], table[detected]
    return {"tp": int((lab & det).sum()), "fn": int((lab & ~det).sum()),
            "tn": int((~lab & ~det).sum()), "fp": int((~lab & det).sum())}


def agreement_rows(real: pl.DataFrame) -> pl.DataFrame:
    """Sensitivity and specificity of the detector (babbling) and of the moving rule
    (moving) against the labels, per condition and together, with and without the trials
    labelled unsure."""
    rows = []
    for measure, label, detected in (("babbling", "babbling", "detector babbling"),
                                     ("moving", "moving", "detector moving")):
        for name, part in (*((c, real.filter(pl.col("senses") == c)) for c in CONDITIONS),
                           ("both", real), ("both, sure labels only",
                                            real.filter(~pl.col("unsure")))):
            c = agreement(part, label, detected)
            rows.append({"rule": measure, "trials": name, "n": part.height,
                         "sensitivity": rate(c["tp"], c["tp"] + c["fn"]),
                         "specificity": rate(c["tn"], c["tn"] + c["fp"])})
    return pl.DataFrame(rows)


#: How the page names each condition of the sample.
WHERE = {"normal": "under normal senses", "no-ball": "with the ball absent"}


def _trials(n: int) -> str:
    return f"{n} trial{'' if n == 1 else 's'}"


def agreement_words(real: pl.DataFrame) -> str:
    """The page's words on the labelled trials, every number counted from them (``real``,
    ``real_table``): per condition what the detector finds of the trials labelled babbling
    and which it misses, how many it calls babbling that the eye does not, what the moving
    rule finds and which it calls moving against the eye, and on how many trials the labels
    themselves tell babbling from moving. A consequence is said only where its count is not
    0."""
    parts, misses = [], {}
    for senses in CONDITIONS:
        part = real.filter(pl.col("senses") == senses)
        c = agreement(part, "babbling", "detector babbling")
        missed = part.filter(pl.col("babbling") & ~pl.col("detector babbling"))["code"]
        misses[senses] = c["fn"]
        parts.append(f"{WHERE[senses]} it finds {c['tp']} of the "
                     f"{_trials(c['tp'] + c['fn'])} labelled babbling"
                     + (f" (misses: {', '.join(missed.to_list())})" if c["fn"] else ""))
    wrong = agreement(real, "babbling", "detector babbling")["fp"]
    text = (f"Against the eye: {'; '.join(parts)}. It calls {_trials(wrong)} babbling that "
            "the eye does not.")
    if any(misses.values()):
        text += (" A trial missed undercounts its population's babbling share under its "
                 "condition, so a change in babbling between normal senses and the ball absent "
                 f"(claims A1, A3) carries the detector's misses ({misses['normal']} with the "
                 f"ball present, {misses['no-ball']} with it absent) as well as the robots'.")
    m = agreement(real, "moving", "detector moving")
    over = real.filter(~pl.col("moving") & pl.col("detector moving"))["code"].to_list()
    text += (f" The moving rule (path ≥ 1 m and amplitude ≥ 5 cm, fixed before labelling) "
             f"finds {m['tp']} of the {_trials(m['tp'] + m['fn'])} labelled moving and calls "
             f"moving {m['fp']} of the {_trials(m['tn'] + m['fp'])} labelled not moving"
             + (f" ({', '.join(over)})" if over else "") + ".")
    apart = int((real["babbling"] != real["moving"]).sum())
    text += (f" The labels tell babbling from moving on {apart} of the {_trials(real.height)}"
             + (": the sample cannot separate the two." if apart == 0 else "."))
    return text


#: The labeller's note on the labelled trials (by eye, from their sheets, once the detector
#: had been run on them): a description of the committed sample's trials, not a measure, and
#: the trials it was written on: those the detector misses, those the moving rule calls
#: moving against the eye (``labeller_note`` refuses a sample whose trials differ).
NOTE = ("the trials the detector misses ({missed}) are sweeps that stop or change at the "
        "ball, or that turn irregular after a touch; those the moving rule calls moving "
        "against the eye ({over}; path {path} m) move only in the first second's swing from "
        "the home posture or jitter at the ball")
NOTE_ON = (("T03", "T07", "T08", "T13", "T18", "T22", "T35"), ("T14", "T17", "T26", "T28"))


def labeller_note(real: pl.DataFrame) -> str:
    """``NOTE`` as the page says it, marked as the labeller's note on this sample, with the
    trials it describes and their paths counted from ``real`` (``real_table``); an error when
    they are no longer ``NOTE_ON``'s (the note would describe other trials)."""
    missed = real.filter(pl.col("babbling") & ~pl.col("detector babbling"))["code"].sort()
    over = real.filter(~pl.col("moving") & pl.col("detector moving")).sort("code")
    now = (tuple(missed.to_list()), tuple(over["code"].to_list()))
    if now != NOTE_ON:
        raise ValueError(f"the labeller's note was written on the trials {NOTE_ON}, the "
                         f"detector and the moving rule now disagree with the eye on {now}: "
                         f"look at their sheets and rewrite reports.babbling_detector.NOTE")
    paths = over["detector path"]
    return ("The labeller's note, by eye from the sheets of this committed sample "
            f"(`{LABELS}`), a description and not a measure: "
            + NOTE.format(missed=", ".join(now[0]), over=", ".join(now[1]),
                          path=f"{paths.min():.2f}-{paths.max():.2f}") + ".")


def movement_table(recordings: Path) -> pl.DataFrame:
    """Per replication at each judged generation: babbling share and strategy by rhythm
    (``strategies.strategies``) beside moving share and strategy by movement
    (``strategies.movement``), normal senses."""
    dev = load_development(recordings / FULL).filter(pl.col("generation").is_in(JUDGED))
    by = ("generation", "replication")
    table = st.strategies(dev, by=by).join(st.movement(dev, by=by), on=list(by))
    return table.select("generation", "replication", "babbling_share", "strategy",
                        "moving_share", "movement").sort(*by)


#: The reasons a babbling path is missed, as ``synthetic_table`` counts them, in words.
MISSED = {"missed: amplitude < 0.05 m": "an RMS amplitude below 0.05 m",
          "missed: share < 0.4": "a rhythm share below 0.4",
          "missed: below 0.25 Hz": "a rhythm below 0.25 Hz"}


def misses(families: pl.DataFrame) -> str:
    """Why the detector missed the babbling paths of ``families`` (rows of
    ``synthetic_table``): "N missed: A with ..., B with ..." (a path may fail several tests),
    or "none missed"."""
    missed = int((families["paths"] - families["called babbling"]).sum())
    if not missed:
        return "none missed"
    why = [f"{int(families[col].sum())} with {words}" for col, words in MISSED.items()
           if families[col].sum()]
    return f"{missed} missed: " + ", ".join(why)


def values(recordings: Path) -> dict[str, str]:
    root = recordings.parent
    syn = synthetic_table()
    real = real_table(root)
    moves = movement_table(recordings)
    pos = syn.filter(pl.col("babbling by construction"))
    neg = syn.filter(~pl.col("babbling by construction"))
    last = moves.filter(pl.col("generation") == max(JUDGED))
    rhythm_still = last.filter(pl.col("strategy") == st.STILL)
    wide = moves.pivot("generation", index="replication", values="moving_share").sort(
        "replication")
    return {
        **second.values(root),
        "run": FULL, "generation": str(GENERATION), "seed": str(SEED),
        "per_family": str(PER_FAMILY), "labels": LABELS, "sample": SAMPLE,
        "synthetic_table": markdown_table(syn),
        "synthetic_sensitivity": rate(int(pos["called babbling"].sum()),
                                       int(pos["paths"].sum())),
        "synthetic_specificity": rate(int((neg["paths"] - neg["called babbling"]).sum()),
                                       int(neg["paths"].sum())),
        "interrupted": rate(int(pos.filter(pl.col("family").str.contains("interrupted"))
                                 ["called babbling"].sum()),
                             int(pos.filter(pl.col("family").str.contains("interrupted"))
                                 ["paths"].sum())),
        "uninterrupted": rate(int(pos.filter(~pl.col("family").str.contains("interrupted"))
                                   ["called babbling"].sum()),
                               int(pos.filter(~pl.col("family").str.contains("interrupted"))
                                   ["paths"].sum())),
        "uninterrupted_misses": misses(pos.filter(~pl.col("family").str.contains(
            "interrupted"))),
        "interrupted_misses": misses(pos.filter(pl.col("family").str.contains("interrupted"))),
        "wander": rate(int(neg.filter(pl.col("family") == "wander")["called babbling"].sum()),
                        int(neg.filter(pl.col("family") == "wander")["paths"].sum())),
        "other_still": str(int(neg.filter(pl.col("family") != "wander")["called babbling"]
                               .sum())),
        "agreement_table": markdown_table(agreement_rows(real)),
        "agreement_words": agreement_words(real),
        "labeller_note": labeller_note(real),
        "unsure": str(int(real["unsure"].sum())),
        "real_table": markdown_table(real.select(
            "code", "senses", "replication", "babbling", "unsure", "detector babbling",
            pl.col("detector frequency").alias("Hz"), pl.col("detector share").alias("share"),
            pl.col("detector amplitude").alias("amplitude (m)"),
            pl.col("detector path").alias("path (m)"), "moving", "detector moving")),
        "moving_wide": markdown_table(wide.rename({str(g): f"moving share at {g}"
                                                   for g in JUDGED})),
        "last_table": markdown_table(last.drop("generation")),
        "last": str(max(JUDGED)),
        "rhythm_still": ", ".join(map(str, rhythm_still["replication"].to_list())) or "none",
        "rhythm_still_moving": ", ".join(f"{r} ({percent(m)})" for r, m in zip(
            rhythm_still["replication"], rhythm_still["moving_share"])) or "none",
        "still_by_movement": "; ".join(
            f"at {g}: replication{'s' if len(r) > 1 else ''} {', '.join(map(str, r))}"
            for g, r in moves.filter(pl.col("movement") == st.STILL)
            .group_by("generation", maintain_order=True).agg("replication").iter_rows())
        or "none",
    }
