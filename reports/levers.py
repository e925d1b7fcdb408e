"""The levers study's page (docs/results/levers.md, pre-registered): the screen's numbers and the
choice of the two further arms by the rule the page fixed before the screen was read, then
the trained arms against the reference.

    python -m reports.levers            # rewrites the page's generated part (below "## Results")
    python -m reports.levers --check    # exit 1 when the page differs from the tables
    python -m reports.levers --terms    # each arm's robots at 50 run again for Eq. 5's terms

``--terms`` runs the 45 systematic trials (normal senses) of the robots that an arm's
development.parquet post-evaluated at generation 50 (best 5 of 6 replications, 1,350 trials,
a few CPU-minutes per arm) and writes them to the arm's ``fitness_terms.TABLE``
(``studies.fitness_terms``, as ``reports.stillness`` does for the reference's runs); arms
already done or not yet post-evaluated at 50 are skipped.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import warnings
from pathlib import Path

import dart_reach  # noqa: F401  first: it pins numpy's kernels before numpy loads (--terms)
import polars as pl
from scipy import stats

from dart_reach.analysis.formatting import decimals
from dart_reach.analysis.profile import CRITERIA, more_than_reference, profiles, share_interval
from dart_reach.analysis.strategies import STILL, strategies
from dart_reach.postevaluation import results
from dart_reach.postevaluation.snapshots import load_development
from dart_reach.studies import fitness_terms

from .text import write_page

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "results" / "levers.md"
SCREEN = ROOT / "recordings" / "levers" / "screen.parquet"
MARK = "## Results\n"
LEVERS = ROOT / "recordings" / "levers"
#: The trained arms in the pre-registered order: name -> what it changes.
ARMS = {"far": "the ball at 0.42 m (scene beyond-arm-length)",
        "reflex-evolved": "the reflex motors' evolved inputs",
        "self-collision": "self-collision of the arm with the body (chosen by the screen)",
        "capped": "p_touch = min(n, 4) / 4 (chosen by the screen)"}
#: Generation judged, and the reference: today's model's pre-reaching at that generation.
JUDGED = 50
REFERENCE = (("standard-500x10", JUDGED), ("replication-50x10", None))
#: The decision rule's thresholds (docs/results/levers.md, "Decision rule").
RECOMMEND_AT_LEAST, RECOMMEND_P = 3, 0.05
#: The screen's candidates for the two further arms (docs/results/levers.md, "Choosing ..."):
#: name -> (screen arm whose trials it uses, fitness column scored under it).
CANDIDATES = {"binary": ("today", "fitness_binary"), "capped": ("today", "fitness_capped"),
              "start-zero": ("start-zero", "fitness_faces"),
              "self-collision": ("self-collision", "fitness_faces")}


def robot_means(screen: pl.DataFrame) -> pl.DataFrame:
    """Per arm and robot (replication, rank), the means over its normal trials of the fitness
    under each pay, the hand-shoulder distance and the babbling rate."""
    return (screen.filter(pl.col("senses") == "normal")
            .group_by("arm", "replication", "rank")
            .agg(pl.col("fitness_faces", "fitness_binary", "fitness_capped",
                        "hand_shoulder_mean").mean(),
                 pl.col("babbling").cast(pl.Float64).mean())
            .sort("arm", "replication", "rank"))


def _spearman(a, b) -> float:
    with warnings.catch_warnings():  # a constant input: undefined, NaN
        warnings.simplefilter("ignore", stats.ConstantInputWarning)
        rho = stats.spearmanr(a, b).statistic
    return float(rho) if rho == rho else math.nan


def choose_arms(screen: pl.DataFrame) -> tuple[pl.DataFrame, float, float]:
    """The pre-registered rule: per candidate, the Spearman correlation across the screened
    robots between fitness under the candidate and hand-shoulder distance (and, the tie-break,
    babbling rate), its rise over today's, and the two chosen (``chosen``)."""
    means = robot_means(screen)
    today = means.filter(pl.col("arm") == "today")
    ref_arm = _spearman(today["fitness_faces"], today["hand_shoulder_mean"])
    ref_babble = _spearman(today["fitness_faces"], today["babbling"])
    rows = []
    for name, (arm, column) in CANDIDATES.items():
        m = means.filter(pl.col("arm") == arm)
        if m.is_empty():
            continue
        # the touch pays rescore today's trials: the robots' traits are today's
        arm_rho = _spearman(m[column], m["hand_shoulder_mean"])
        babble_rho = _spearman(m[column], m["babbling"])
        rows.append({"candidate": name, "rho_arm": arm_rho, "rise_arm": arm_rho - ref_arm,
                     "rho_babbling": babble_rho, "rise_babbling": babble_rho - ref_babble})
    # an undefined correlation (a constant fitness or trait) ranks last
    table = (pl.DataFrame(rows)
             .sort(pl.col("rise_arm").fill_nan(None), pl.col("rise_babbling").fill_nan(None),
                   descending=True, nulls_last=True))
    return table.with_columns(chosen=pl.int_range(pl.len()) < 2), ref_arm, ref_babble


def screen_profiles(screen: pl.DataFrame) -> pl.DataFrame:
    """Per screen arm, the pre-reacher's profile over the screened robots' trials (every robot
    of every replication pooled per replication, then the replications' mean) and the share of
    replications meeting each criterion."""
    per = profiles(screen, by=("arm", "replication"))
    return (per.group_by("arm")
            .agg(pl.col("reach", "elbow_sd", "shoulder_sd", "trunk_sd", "hand_shoulder_m",
                        "hand_shoulder_cv", "hand_path_m", "babbling", "babbling_no_ball",
                        "fitness").mean(),
                 *[pl.col(f"is_{c}").mean() for c in CRITERIA], pl.col("paper").mean(),
                 pl.len().alias("replications"))
            .sort("arm"))


def screen_section(screen: pl.DataFrame) -> str:
    prof = screen_profiles(screen)
    choice, ref_arm, ref_babble = choose_arms(screen)
    n_robots = screen.filter(pl.col("arm") == "today").select("replication", "rank").unique().height
    lines = [
        "### The screen (no training)",
        "",
        f"Generated by `python -m reports.levers` from `recordings/levers/screen.parquet` "
        f"(`make levers-screen`): the best 2 robots of each of the 10 replications of "
        f"`standard-500x10` at generation {int(screen['generation'][0])} ({n_robots} robots), "
        f"45 positions, normal senses and ball absent, under each arm. Profile means over the "
        f"replications (each replication's 90 normal trials pooled); the criteria columns are "
        f"the share of replications meeting each criterion of the paper's pre-reacher.",
        "",
        "| arm | reach | elbow SD | shoulder SD | trunk SD | hand-shoulder (m) | CV | hand "
        "path (m) | babbling | babbling, no ball | fitness | reach ok | elbow locked | arm "
        "extended | babbling ok | paper's |",
        "|---|" + "---:|" * 15,
    ]
    for r in prof.iter_rows(named=True):
        cells = [r["arm"], decimals(r["reach"], 2), decimals(r["elbow_sd"]),
                 decimals(r["shoulder_sd"]), decimals(r["trunk_sd"]),
                 decimals(r["hand_shoulder_m"]), decimals(r["hand_shoulder_cv"]),
                 decimals(r["hand_path_m"], 2), decimals(r["babbling"], 2),
                 decimals(r["babbling_no_ball"], 2), decimals(r["fitness"], 4),
                 *(decimals(r[f"is_{c}"], 1) for c in CRITERIA), decimals(r["paper"], 1)]
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "Fitness of the screened robots under each touch pay (today's trials scored "
              "again; mean over the robots' normal trials):", "",
              "| pay | fitness |", "|---|---:|"]
    today = screen.filter((pl.col("arm") == "today") & (pl.col("senses") == "normal"))
    for pay in ("faces", "binary", "capped"):
        lines.append(f"| {pay} | {decimals(today[f'fitness_{pay}'].mean(), 4)} |")
    lines += ["", "**The two further arms, by the pre-registered rule** (Spearman correlation, "
              f"across the {n_robots} robots, of fitness under the candidate with the "
              f"hand-shoulder distance; today's: {decimals(ref_arm)}; with the babbling rate, the "
              f"tie-break; today's: {decimals(ref_babble)}):", "",
              "| candidate | rho, arm extension | rise | rho, babbling | rise | trained |",
              "|---|---:|---:|---:|---:|---|"]
    for r in choice.iter_rows(named=True):
        lines.append(f"| {r['candidate']} | {decimals(r['rho_arm'])} | {decimals(r['rise_arm'])} | "
                     f"{decimals(r['rho_babbling'])} | {decimals(r['rise_babbling'])} | "
                     f"{'yes' if r['chosen'] else 'no'} |")
    lines += ["", "What each screen predicts (robots evolved without the lever, run under it; a "
              "prediction of where training under it starts, not its result):", ""]
    at = {r["arm"]: r for r in prof.iter_rows(named=True)}
    base = at["today"]
    for arm, r in at.items():
        if arm == "today":
            continue
        lines.append(f"- `{arm}`: reach {decimals(base['reach'], 2)} -> "
                     f"{decimals(r['reach'], 2)}, fitness "
                     f"{decimals(base['fitness'], 4)} -> {decimals(r['fitness'], 4)} "
                     f"({r['fitness'] / base['fitness'] - 1:+.0%}), hand-shoulder "
                     f"{decimals(base['hand_shoulder_m'])} -> "
                     f"{decimals(r['hand_shoulder_m'])} m, babbling "
                     f"without the ball {decimals(base['babbling_no_ball'], 2)} -> "
                     f"{decimals(r['babbling_no_ball'], 2)}.")
    for r in choice.iter_rows(named=True):
        if r["candidate"] in ("binary", "capped"):
            paid = today[f"fitness_{r['candidate']}"].mean()
            lines.append(f"- `{r['candidate']}` touch pay: fitness "
                         f"{decimals(today['fitness_faces'].mean(), 4)} -> "
                         f"{decimals(paid, 4)}; among the robots it pays the extended arm "
                         f"{'more' if r['rise_arm'] > 0 else 'less'} than today's pay (rho "
                         f"{decimals(r['rho_arm'])} against {decimals(ref_arm)}).")
    return "\n".join(lines) + "\n"


def reference_profiles() -> pl.DataFrame:
    """Today's model at generation 50, one row per population (20): ``standard-500x10``'s
    snapshot at 50 and ``replication-50x10``'s trained pre-reaching phase."""
    parts = []
    for run, generation in REFERENCE:
        path = ROOT / "recordings" / run
        if generation is None:
            from dart_reach.postevaluation.systematic import load_evaluation
            table = load_evaluation(path).filter(pl.col("phase") == "pre")
        else:
            table = (load_development(path, senses=None)
                     .filter((pl.col("phase") == "pre") & (pl.col("generation") == generation)
                             & ~pl.col("baseline")))
        parts.append(_with_strategy(profiles(table), table).with_columns(run=pl.lit(run)))
    return pl.concat(parts)


def _with_strategy(prof: pl.DataFrame, table: pl.DataFrame,
                   by: tuple[str, ...] = ("replication",)) -> pl.DataFrame:
    return prof.join(strategies(table, by=by).select(*by, "strategy"), on=list(by))


def arm_profiles(arm: str) -> pl.DataFrame | None:
    """An arm's profiles per replication and snapshot generation, or None before its first
    post-evaluated snapshot."""
    table = load_development(LEVERS / arm, senses=None)
    if table is None:
        return None
    table = table.filter((pl.col("phase") == "pre") & ~pl.col("baseline"))
    by = ("generation", "replication")
    return _with_strategy(profiles(table, by=by), table, by)


def _progress(arm: str) -> str:
    stats_path = LEVERS / arm / "generations.parquet"
    if not stats_path.exists():
        return "not started"
    g = pl.read_parquet(stats_path).group_by("replication").agg(pl.col("generation").max())
    manifest = json.loads((LEVERS / arm / "manifest.json").read_text())
    revision = str(manifest.get("git_revision"))[:7] + (" (dirty)" if manifest.get("git_dirty")
                                                        else "")
    return (f"{int(g['generation'].min())} of {JUDGED} generations in all "
            f"{g.height} replications, revision {revision}")


def course_lines(ref: pl.DataFrame) -> list[str]:
    """Each arm's course over its post-evaluated snapshots beside the reference at 50: the
    means over the replications, how many meet each criterion and all four, and how many
    are still (the split between the strategies)."""
    head = ["", "The course over the snapshots (means over the replications; the criteria as "
            "counts of replications):", "",
            "| arm | generation | replications | reach | elbow SD | shoulder SD | trunk SD | "
            "hand-shoulder (m) | CV | babbling | babbling, no ball | fitness | "
            + " | ".join(CRITERIA) + " | paper's | still |", "|---|" + "---:|" * 17]
    # the paper's pre-reacher (IV-A-1) as the pre-registered criteria read it
    rows = ["| the paper (IV-A-1) | | | about half (0.35-0.65) | below shoulder's and trunk's "
            "| | | at least 0.31 (arm extended) | below 0.05 | yes (quasi-periodic) | yes | | "
            + " | ".join("" for _ in CRITERIA) + " | | |"]
    tables = [("reference", ref.with_columns(generation=pl.lit(JUDGED)))]
    tables += [(arm, p) for arm in ARMS if (p := arm_profiles(arm)) is not None]
    for arm, prof in tables:
        for g in sorted(prof["generation"].unique()):
            at = prof.filter(pl.col("generation") == g)
            m = {c: at[c].mean() for c in ("reach", "elbow_sd", "shoulder_sd", "trunk_sd",
                                           "hand_shoulder_m", "hand_shoulder_cv", "babbling",
                                           "babbling_no_ball", "fitness")}
            rows.append(f"| {arm} | {g} | {at.height} | {decimals(m['reach'], 2)} | "
                        f"{decimals(m['elbow_sd'])} | {decimals(m['shoulder_sd'])} | "
                        f"{decimals(m['trunk_sd'])} | "
                        f"{decimals(m['hand_shoulder_m'])} | {decimals(m['hand_shoulder_cv'])} | "
                        f"{decimals(m['babbling'], 2)} | {decimals(m['babbling_no_ball'], 2)} | "
                        f"{decimals(m['fitness'], 4)} | "
                        + " | ".join(str(int(at[f"is_{c}"].sum())) for c in CRITERIA)
                        + f" | {int(at['paper'].sum())} | "
                        f"{int((at['strategy'] == STILL).sum())} |")
    return head + rows if len(tables) > 1 else []


def arms_section() -> str:
    ref = reference_profiles()
    k_ref, n_ref = int(ref["paper"].sum()), ref.height
    lines = ["### The trained arms", "",
             f"Generated by `python -m reports.levers` from each arm's committed "
             f"`recordings/levers/ARM/development.parquet` (`make levers-evaluate`). The "
             f"reference: today's model at generation {JUDGED}, {n_ref} populations "
             f"(`standard-500x10` at 50, `replication-50x10`): {k_ref} of {n_ref} are the "
             f"paper's pre-reacher; still: {int((ref['strategy'] == STILL).sum())} of {n_ref}. "
             f"Every arm trains from the one pinned revision its manifest names, in a checkout "
             f"of it (`make levers-train`, resumable, with the four arms' `LEVER_ARMS` of this "
             f"Makefile); `make levers-state LEVERS_FROM=that-checkout` copies their compact "
             f"state here to commit.",
             "", "| arm | training | judged at 50: paper's pre-reacher | 95 % interval | "
             "Fisher p vs reference | reach ok | elbow locked | arm extended | babbling ok | "
             "still |", "|---|---|---:|---|---:|---:|---:|---:|---:|---:|"]
    verdicts, met = [], []  # per judged arm: the verdict; the replications meeting each criterion
    for arm, what in ARMS.items():
        prof = arm_profiles(arm)
        at = None if prof is None else prof.filter(pl.col("generation") == JUDGED)
        if at is None or at.is_empty():
            lines.append(f"| {arm}: {what} | {_progress(arm)} | not yet | | | | | | | |")
            continue
        k, n = int(at["paper"].sum()), at.height
        low, high = share_interval(k, n)
        p = more_than_reference(k, n, k_ref, n_ref)
        met.append([int(at[f"is_{c}"].sum()) for c in CRITERIA])
        lines.append(f"| {arm}: {what} | {_progress(arm)} | {k} of {n} | {low:.2f}-{high:.2f} "
                     f"| {p:.3f} | " + " | ".join(map(str, met[-1]))
                     + f" | {int((at['strategy'] == STILL).sum())} |")
        verdicts.append((arm, k, n, p))
    lines += course_lines(ref)
    lines += ["", "Editorial, not a departure: the module the plan names for the strategy, "
              "`analysis.stillness`, has since been renamed `analysis.strategies`; its rule is "
              "unchanged.", ""]
    if len(verdicts) < len(ARMS):
        lines.append("**Decision: not yet.** The rule is applied when every arm has been "
                     f"post-evaluated at generation {JUDGED}.")
    else:
        chosen = recommended(verdicts)
        lines.append(f"**Decision: spend the paper's budget on `{chosen}`.**" if chosen else
                     "**Decision: none of these levers gives the paper's pre-reacher at "
                     f"{JUDGED} generations**, so the model's default stays as it is (the "
                     "rule changes it only on a recommendation).")
        lines += ["", decision_basis(verdicts, k_ref, n_ref), "",
                  _criteria_sentence(met, sum(v[2] for v in verdicts), ref)]
    return "\n".join(lines) + "\n"


def decision_basis(verdicts: list[tuple[str, int, int, float]], k_ref: int, n_ref: int) -> str:
    """What the decision rests on, in words: the pre-registered rule (``recommended``: a raw
    one-sided Fisher exact test of each arm's count of replications that are the paper's
    pre-reacher against the reference's, not one of the gated rules of
    ``analysis.verdicts``), why it stands, and each arm's count and p (``verdicts``: as
    ``recommended`` takes them) against the rule's thresholds."""
    qualify = [v[0] for v in verdicts if v[1] >= RECOMMEND_AT_LEAST and v[3] < RECOMMEND_P]
    arms = "; ".join(f"`{arm}` {k} of {n}, p = {p:.3f}" for arm, k, n, p in verdicts)
    return (f"This decision is the pre-registered rule (\"Decision rule\" above), applied "
            f"as written: at least {RECOMMEND_AT_LEAST} replications of an arm that are the "
            f"paper's pre-reacher and a raw one-sided Fisher exact test of that count against "
            f"the reference's ({k_ref} of {n_ref}) at p < {RECOMMEND_P:g}. It is not one of "
            f"the project's gated rules (`analysis.verdicts`, which every other verdict of "
            f"these pages comes from), and it stands because it was fixed, with its test and "
            f"its level, before any arm was trained: changing it after the results would "
            f"choose the rule by its outcome. Its test counts replications, one yes or no "
            f"each, the unit the gated rules use too. The arms: {arms}; "
            + (f"qualifying: {', '.join(f'`{a}`' for a in qualify)}." if qualify
               else "none qualifies."))


def _criteria_sentence(met: list[list[int]], reps: int, ref: pl.DataFrame) -> str:
    """How many of the judged arms' ``reps`` replications meet each criterion at ``JUDGED``
    (``met``: per arm, per criterion), beside the reference's, and the one met least."""
    totals = [sum(counts) for counts in zip(*met)]
    ref_counts = [int(ref[f"is_{c}"].sum()) for c in CRITERIA]
    least = CRITERIA[totals.index(min(totals))]
    return (f"Replications meeting each criterion at {JUDGED}, over the {reps} of the "
            f"{len(met)} arms (the reference's {ref.height} in brackets): "
            + ", ".join(f"{c.replace('_', ' ')} {t} ({r})"
                        for c, t, r in zip(CRITERIA, totals, ref_counts))
            + f"; the one met least: {least.replace('_', ' ')}.")


def recommended(verdicts: list[tuple[str, int, int, float]]) -> str | None:
    """The pre-registered decision rule (docs/results/levers.md, "Decision rule") on each
    arm's (name, replications that are the paper's pre-reacher, replications, Fisher p
    against the reference), in the pre-registered order: an arm qualifies with at least
    ``RECOMMEND_AT_LEAST`` and p < ``RECOMMEND_P``; of those, the larger share; on a tie the
    one that changes fewer levers from version 1 (every arm here changes one: then the
    earlier); None when no arm qualifies."""
    good = [v for v in verdicts if v[1] >= RECOMMEND_AT_LEAST and v[3] < RECOMMEND_P]
    return max(good, key=lambda v: v[1] / v[2], default=(None,))[0]


#: Eq. 5's terms the page shows (``measures.fitness.fitness_terms``), with their headings.
TERMS = {"fitness": "fitness", "sight_share": "in sight", "touch_share": "in touch",
         "touch_level": "touch level", "scoring_share": "scoring", "touch_limits":
         "touch limits", "contact_after_first": "in touch after first"}


def build_terms(progress=print) -> list[str]:
    """Eq. 5's terms of every arm's robots at ``JUDGED`` (``fitness_terms.build``) where the
    arm's development.parquet has them and its table does not yet; the arms done."""
    done = []
    for arm in ARMS:
        run_dir = LEVERS / arm
        if fitness_terms.missing(run_dir, (JUDGED,)) != [JUDGED]:
            continue
        rows = fitness_terms.build(run_dir, progress=lambda m: progress(f"{arm}: {m}"),
                                   generation=JUDGED).to_dicts()
        path = run_dir / fitness_terms.TABLE
        results.save_table(path, results.read_table(path), rows, fitness_terms.SNAPSHOT_KEY,
                           results.session())
        done.append(arm)
    return done


def _terms_by_replication(terms: pl.DataFrame, strategy: pl.DataFrame) -> pl.DataFrame:
    """Per replication: the means of ``TERMS`` over its trials (a level over the trials that
    have one), with its strategy."""
    return (terms.group_by("replication")
            .agg(*[pl.col(c).fill_nan(None).mean() for c in TERMS])
            .join(strategy.select("replication", "strategy"), on="replication"))


def terms_section() -> str:
    """What each arm does to what Eq. 5 pays: the means over the replications (of the means
    over each replication's trials) at generation 50, beside the reference's."""
    ref_terms = []
    for run, generation in REFERENCE:
        table = results.read_table(ROOT / "recordings" / run / fitness_terms.TABLE)
        if generation is not None:
            table = table.filter(pl.col("generation") == generation)
        prof = reference_profiles().filter(pl.col("run") == run)
        ref_terms.append(_terms_by_replication(table, prof))
    rows = [("reference", pl.concat(ref_terms))]
    for arm in ARMS:
        table = results.read_table(LEVERS / arm / fitness_terms.TABLE)
        prof = arm_profiles(arm)
        if table is None or prof is None:
            continue
        table = table.filter(pl.col("generation") == JUDGED)
        rows.append((arm, _terms_by_replication(
            table, prof.filter(pl.col("generation") == JUDGED))))
    lines = ["### What each lever does to what Eq. 5 pays", "",
             f"At generation {JUDGED}, generated from each arm's `{fitness_terms.TABLE}` "
             "(`make levers-terms`: its post-evaluated robots' 45 normal trials run again), "
             "and the reference's; means over the replications "
             "of each one's trial means (`measures.fitness.fitness_terms`). In sight, in touch "
             "and scoring are shares of the steps; touch level is the mean p_touch over the "
             "steps in touch (n/16 under today's pay, min(n, 4)/4 under `capped`); touch "
             "limits is the share of scoring steps on which touch, not sight, sets the score.",
             "", "| arm | replications | still | " + " | ".join(TERMS.values()) + " |",
             "|---|---:|---:|" + "---:|" * len(TERMS)]
    for arm, by_rep in rows:
        still = int((by_rep["strategy"] == STILL).sum())
        lines.append(f"| {arm} | {by_rep.height} | {still} | " + " | ".join(
            decimals(by_rep[c].mean(), 4 if c == "fitness" else 3) for c in TERMS) + " |")
    return "\n".join(lines) + "\n" if len(rows) > 1 else ""


def page() -> str:
    text = PAGE.read_text()
    head = text[: text.index(MARK) + len(MARK)]
    parts = []
    if SCREEN.exists():
        parts.append(screen_section(pl.read_parquet(SCREEN)))
    else:
        parts.append("Not yet: the screen and the training follow the pre-registration.\n")
    parts.append(arms_section())
    parts.append(terms_section())
    return head + "\n" + "\n".join(parts)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m reports.levers", description=__doc__)
    p.add_argument("--check", action="store_true", help="exit 1 when the page is stale")
    p.add_argument("--terms", action="store_true",
                   help=f"run each arm's robots at {JUDGED} again for Eq. 5's terms first")
    args = p.parse_args(argv)
    if args.terms:
        print(f"Eq. 5's terms at {JUDGED}: {', '.join(build_terms()) or 'no arm missing'}")
    return write_page(PAGE, page(), args.check)


if __name__ == "__main__":
    sys.exit(main())
