"""docs/results/pre-reaching-course.md and its figures, from the full-budget run's committed
pre-reaching snapshots (``analysis.strategy_course``): where its training stands, the strategy
of every population at every snapshot, when they changed, the course of the measures,
generation 50 beside ``TEN``'s final pre-reachers and the claims of pre-reachers judged at
``runs.JUDGED``. Rendered by ``reports.results``."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import polars as pl

from dart_reach.analysis import budgets, coverage, findings, formatting, said, verdicts
from dart_reach.analysis import strategy_course as sc
from dart_reach.analysis.claims import BABBLING_BOTH
from dart_reach.analysis.figures import strategy_figure, training_by_strategy
from dart_reach.analysis.strategies import BABBLING, STILL, STILL_SHARE, trained_trials
from dart_reach.evolution import cost
from dart_reach.evolution.ga import Scheme
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.evolution.settings import SNAPSHOT_ROBOTS, snapshot_due
from dart_reach.model.world import N_SECTORS, POINTS_PER_SECTOR
from dart_reach.postevaluation import before_touch, results
from dart_reach.postevaluation.snapshots import load_development
from dart_reach.postevaluation.systematic import TESTS, load_evaluation
from dart_reach.studies import fitness_terms

from . import calibration, stillness
from .runs import FULL, JUDGED, TEN
from .text import markdown_table, training_text


#: What one trial costs is taken from the run's own records (``trial_core_s``): a
#: post-evaluation trial of a snapshot robot is the trial a training generation runs (the same
#: 200 control steps in the same world), so it costs a replication-generation's core-seconds
#: (``cost.core_seconds``: each generation's wall time on the session's workers) over the
#: trials the generation ran (lifetimes x trials). No CPU time measured once on one machine:
#: the run has moved between processors, and its records say what each session cost.
#: The generation this round of the run ends at and the snapshots' spacing.
ROUND_END, SNAPSHOT_EVERY = 250, 10
#: Trials of one robot under one sensory condition (the systematic positions), and the
#: conditions besides normal senses at a judged generation (Fig. 9's three and the ball absent).
POSITIONS, OTHER_CONDITIONS = N_SECTORS * POINTS_PER_SECTOR, len(TESTS) - 1
#: The fitness columns compared between the strategies (``course``'s: heading) and the
#: generations of each of the two windows over which growth is measured.
FITNESS = {"fitness": "post-evaluation fitness", "lifetime_fitness": "training's best"}
GROWTH_WINDOW = 10
#: A longer window beside the first look's 10 generations: the trend under the
#: generation-to-generation noise of the population's mean fitness.
LONG_WINDOW = 50


def trial_core_s(run: RunDirectory, upto: int = ROUND_END) -> tuple[float, float, float]:
    """Core-seconds of one pre-reaching trial of ``run`` (the lower quartile, median and
    upper quartile over its generations to ``upto``): each generation's core-seconds a
    replication (``cost.core_seconds``) over the trials it ran, lifetimes (twice the
    population under the steady-state scheme) x trials per lifetime."""
    ga = run.settings.ga
    lifetimes = ga.population * (2 if ga.scheme is Scheme.STEADY_STATE else 1)
    per = (cost.core_seconds(run).filter((pl.col("phase") == "pre")
                                         & (pl.col("generation") <= upto))["core_s"]
           .drop_nans().to_numpy() / (lifetimes * run.settings.trials))
    low, median, high = np.quantile(per, [0.25, 0.5, 0.75])
    return float(low), float(median), float(high)


def cost_values(run: RunDirectory, generations: int) -> dict[str, str]:
    """What post-evaluating the snapshots to ``ROUND_END`` of a pre-reaching phase of
    ``generations`` (``snapshot_due``) costs beside the training to it, at the run's own
    cost of a trial (``trial_core_s``: ``trial_core_s`` its median, ``trial_q1``, ``trial_q3``
    its quartiles): ``snapshots``, ``snapshots_core_h`` (every snapshot under normal senses),
    ``judged_core_h`` (the other conditions at the judged generations), ``terms_core_h`` (their
    robots run again for Eq. 5's terms, ``reports.stillness``), ``pre_core_s`` (the run's
    median core-seconds a pre-reaching replication-generation), ``pre_round_core_h`` (the
    training to ``ROUND_END`` at that median) and ``evaluation_share`` (the three's share of
    it)."""
    snapshots = sum(snapshot_due(g, generations, SNAPSHOT_EVERY)
                    for g in range(1, ROUND_END + 1))
    robots = SNAPSHOT_ROBOTS * run.settings.replications
    q1, trial, q3 = trial_core_s(run)
    normal = snapshots * robots * POSITIONS * trial / 3600
    judged = len(JUDGED) * OTHER_CONDITIONS * robots * POSITIONS * trial / 3600
    terms = len(JUDGED) * robots * POSITIONS * trial / 3600
    median = float(cost.core_seconds(run).filter(pl.col("phase") == "pre")["core_s"]
                   .drop_nans().median())
    training = median * ROUND_END * run.settings.replications / 3600
    return {"trial_core_s": f"{trial:.3f}", "trial_q1": f"{q1:.3f}", "trial_q3": f"{q3:.3f}",
            "snapshots": str(snapshots), "snapshots_core_h": f"{normal:.1f}",
            "judged_core_h": f"{judged:.1f}", "terms_core_h": f"{terms:.1f}",
            "pre_core_s": f"{median:.0f}", "pre_round_core_h": f"{training:.0f}",
            "evaluation_share": formatting.percent((normal + judged + terms) / training)}


def outcome(babbling: int, still: int) -> str:
    """What the populations' strategies say in plain words: which has taken over, or both."""
    if not still:
        return f"babbling has taken over (all {babbling} populations babble)"
    if not babbling:
        return f"stillness has taken over (all {still} populations are still)"
    return f"both persist ({babbling} populations babble, {still} are still)"


def settled(turns: pl.DataFrame, generations: list[int]) -> str:
    """The last change of strategy in plain words, from ``strategy_course.switches``'s table
    and the snapshots' ``generations`` (ascending): when it came, in which replications, and
    how many snapshots since found every population where it was."""
    last = turns["last_change"].max()
    if last is None:
        return "No population changed strategy between snapshots."
    replications = turns.filter(pl.col("last_change") == last)["replication"].sort().to_list()
    text = (f"The last change came at generation {last} (replication"
            f"{'s' if len(replications) > 1 else ''} {', '.join(map(str, replications))})")
    since = [g for g in generations if g > last]
    if not since:
        return text + ", the last snapshot."
    return (text + f"; at the {len(since)} snapshot{'s' if len(since) > 1 else ''} since "
            f"({since[0]}-{since[-1]}) every population kept its strategy.")


def still_to_know(last: int, of: int) -> str:
    """When the question is next answered, given the ``last`` snapshot post-evaluated and the
    phase's ``of`` generations: at ``ROUND_END`` (this round's end) and at ``of``,
    or, past ``ROUND_END``, at ``of`` alone."""
    if last < ROUND_END:
        return (f"Whether this holds is known at generation {ROUND_END} (this round's end) "
                f"and at {of}.")
    return f"Whether it holds to generation {of} is known when pre-reaching ends there."


def kinds(table: pl.DataFrame) -> tuple[int, int]:
    """(babbling, still) populations of a table with a ``strategy`` column."""
    return tuple(table.filter(pl.col("strategy") == k).height for k in (BABBLING, STILL))


def with_terms(run_dir: Path, evaluation: pl.DataFrame) -> pl.DataFrame:
    """A run's ``evaluation`` table (``load_evaluation(run_dir)``) as it is, or, when it
    predates ``contact_after_first``, its pre-reachers' normal trials given that measure from
    the run's Eq. 5 table (``fitness_terms.TABLE``: the same robots' same trials run again)."""
    if "contact_after_first" in evaluation.columns:
        return evaluation
    keys = ["phase", "replication", "rank", "trial"]
    terms = results.read_table(run_dir / fitness_terms.TABLE).select(*keys, "contact_after_first")
    joined = trained_trials(evaluation).join(terms, on=keys, how="left")
    if joined["contact_after_first"].is_null().any():
        raise ValueError(f"{run_dir / fitness_terms.TABLE}: not every pre-reacher's trial of "
                         f"{run_dir / results.EVALUATION} (python -m reports.stillness)")
    return joined


def fitness_summary(fit: pl.DataFrame, table: pl.DataFrame) -> str:
    """The page's words on the strategies' fitness from ``strategy_course.fitness_by_strategy``'s
    table ``fit``, each from the project's gated rules (``verdicts.directional``: a strategy
    fitter; ``verdicts.equivalent``: the same), never from a raw test: the snapshots the rules
    could judge (at least 6 populations a strategy), what they found there, and the last
    snapshot's n, smallest p and theta, with its interval where the rule is not gated,
    labelled with the coverage measured for it (``coverage.label`` on the calibration
    ``table``)."""
    if not fit.height:
        return "no snapshot has populations of both strategies"
    judged = fit.filter(pl.col("verdict_fitness") != verdicts.UNDERPOWERED)
    last = fit.tail(1).to_dicts()[0]
    gated = last["verdict_fitness"] == verdicts.UNDERPOWERED
    interval = coverage.label(table, last["babbling"], last["still"])
    parts = []
    for column, heading in FITNESS.items():
        theta = f"θ = P(babbling > still) = {formatting.number(last[f'theta_{column}'])}"
        if not gated:
            theta += (f" [{formatting.number(last[f'theta_{column}_low'])}, "
                      f"{formatting.number(last[f'theta_{column}_high'])}], {interval}")
        words = []
        for verdict, field, what in (
                (verdicts.REPRODUCED, "verdict", "the babbling populations fitter"),
                (verdicts.CONTRADICTED, "verdict", "the still ones fitter"),
                (verdicts.REPRODUCED, "same", "the two the same")):
            at = judged.filter(pl.col(f"{field}_{column}") == verdict)["generation"].to_list()
            if at:
                words.append(f"{what} at generation(s) {', '.join(map(str, at))}")
        found = ("; ".join(words) if words else "neither a difference nor the same shown at any")
        at_last = (last[f"verdict_{column}"] if gated else
                   f"p = {formatting.number(last[f'p_{column}'])}")
        parts.append(f"the {heading}: {found} (at {last['generation']}: {at_last}, {theta})"
                     if judged.height else f"the {heading}: {theta} at {last['generation']}")
    sizes = (f"n = {last['babbling']} babbling vs {last['still']} still populations at "
             f"{last['generation']}, the smallest p possible there "
             f"{formatting.number(last['smallest_p'])}")
    if not judged.height:
        return (f"at every one of the {fit.height} snapshots at which both strategies have a "
                f"population, one strategy has fewer than 6 ({sizes}): below that the project's "
                f"rule (`verdicts.directional`, gated below 6 a group) can show neither a "
                f"difference nor the same, so nothing is said of which is fitter; "
                + "; ".join(parts))
    return (f"of the {fit.height} snapshots at which both strategies have a population, the "
            f"rule could judge {judged.height} (at least 6 populations a strategy; {sizes}): "
            + "; ".join(parts))


def fitness_values(course: pl.DataFrame, stats: pl.DataFrame) -> dict[str, str]:
    """The page's "Are the two strategies equally fit?": the strategies' fitness per snapshot
    (``strategy_course.fitness_by_strategy``) and the populations' growth over the last 20
    generations trained and over the last 2 x ``LONG_WINDOW`` (``strategy_course.growth`` on
    the run's ``stats``), with the strategy of each population at the last snapshot."""
    fit = sc.fitness_by_strategy(course)
    table = calibration.committed()
    summary = fitness_summary(fit, table)
    headings = {"babbling": "babbling populations", "still": "still populations",
                **{f"{c}_{k}": f"{h}: {k}" for c, h in FITNESS.items() for k in (BABBLING, STILL)},
                **{f"verdict_{c}": f"{h}: babbling fitter?" for c, h in FITNESS.items()},
                **{f"same_{c}": f"{h}: the same?" for c, h in FITNESS.items()},
                **{f"p_{c}": f"{h}: p" for c, h in FITNESS.items()},
                **{f"theta_{c}{e}": f"{h}: θ{w}" for c, h in FITNESS.items()
                   for e, w in (("", ""), ("_low", " low"), ("_high", " high"))},
                "smallest_p": "smallest p possible"}
    rising = sc.growth(stats, window=GROWTH_WINDOW)
    rising = rising.join(sc.last_strategies(course), on="replication", how="left")
    up = rising.filter(pl.col("ratio") > 1)
    end = int(rising["last"].min())
    long_ = f"now / before over {LONG_WINDOW}"
    if end >= 2 * LONG_WINDOW:
        longer = sc.growth(stats, window=LONG_WINDOW)
        rising = rising.join(longer.select("replication", pl.col("ratio").alias(long_)),
                             on="replication", how="left")
        long_summary = (f"; over generations {end - 2 * LONG_WINDOW + 1}-{end - LONG_WINDOW} "
                        f"and {end - LONG_WINDOW + 1}-{end}, {(longer['ratio'] > 1).sum()} of "
                        f"{longer.height} rose (x{longer['ratio'].min():.2f}-"
                        f"{longer['ratio'].max():.2f}; column '{long_}')")
    else:
        rising = rising.with_columns(pl.lit(None, pl.Float64).alias(long_))
        long_summary = f"; {2 * LONG_WINDOW} generations are not yet trained for the longer view"
    return {
        "fitness_summary": summary, "fitness_table": markdown_table(fit.rename(headings)),
        "theta_coverage": coverage.label(table, 10, 10),
        "growth_window": f"{end - 2 * GROWTH_WINDOW + 1}-{end - GROWTH_WINDOW} and "
                         f"{end - GROWTH_WINDOW + 1}-{end}",
        "growth_summary": f"{up.height} of {rising.height} populations' mean fitness rose "
                          f"(x{rising['ratio'].min():.2f}-{rising['ratio'].max():.2f} over "
                          f"all {rising.height}){long_summary}",
        "growth_table": markdown_table(rising.select(
            "replication", "strategy", pl.col("mean_before").alias("mean fitness before"),
            pl.col("mean_now").alias("mean fitness now"), pl.col("ratio").alias("now / before"),
            long_)),
    }


def still_at_50(recordings: Path) -> dict[str, str]:
    """How many of the stillness page's pre-reaching populations are still (``reports.stillness``'s
    run, its ``strategies.strategies`` rule): ``stillness_generations`` (its generations per
    phase), ``still_at_50`` ("k of the N") and ``still_rule`` (the rule's line)."""
    t = stillness.tables(recordings)
    still = t["strategy"].filter(pl.col("strategy") == STILL).height
    run = RunDirectory.open(recordings / stillness.RUN)
    return {"stillness_generations": str(budgets.generations_per_phase(run)[0]),
            "still_at_50": f"{still} of the {t['strategy'].height}",
            "still_rule": formatting.percent(STILL_SHARE)}


def fit_at_50(recordings: Path) -> str:
    """The still populations' fitness against the babbling ones' in the stillness page's run
    (``reports.stillness``, 50 generations), the replication as the unit, worded from its
    test (``said.two_groups``)."""
    by_replication = stillness.tables(recordings)["by_replication"]
    fit = {s: by_replication.filter(pl.col("strategy") == s)["fitness"].to_numpy()
           for s in (STILL, BABBLING)}
    return said.two_groups(fit[STILL], fit[BABBLING], STILL, BABBLING, calibration.committed())


def babbling_words(development: pl.DataFrame, recordings: Path) -> dict[str, str]:
    """Two of the page's statements on babbling, counted: ``random_babbling``, how many of
    ``TEN``'s random pre-reaching genomes babble in any normal trial and in what share of
    their trials; ``no_ball_alike``, how many of the robots of ``FULL``'s judged snapshots
    (``development``) babble without the ball in all their trials or in none, and only when
    all do, that the populations' rates (each the mean of ``SNAPSHOT_ROBOTS`` robots) move
    in steps of 1 / ``SNAPSHOT_ROBOTS`` there."""
    baseline = results.read_table(recordings / TEN / results.BASELINE)
    random = (baseline.filter((pl.col("phase") == "pre") & (pl.col("senses") == "normal"))
              .group_by("replication", "rank").agg(pl.col("babbling").cast(pl.Float64).mean()))
    robots = (trained_trials(development.filter(pl.col("generation").is_in(JUDGED)), "pre",
                             "no-ball").group_by("generation", "replication", "rank")
              .agg(pl.col("babbling").cast(pl.Float64).mean()))
    alike = int(robots["babbling"].is_in([0.0, 1.0]).sum())
    return {"random_babbling": (
                f"{int((random['babbling'] > 0).sum())} of the {random.height} random "
                f"pre-reaching genomes of `{TEN}` babble in some of their normal trials, in "
                f"{formatting.percent(random['babbling'].mean())} of those trials together"),
            "no_ball_alike": (
                f"{alike} of the {robots.height} robots of these snapshots babble in all "
                f"their trials or in none"
                + (f", so there the rates move in steps of 1/{SNAPSHOT_ROBOTS}"
                   if alike == robots.height else ""))}


def values(recordings: Path) -> dict[str, str]:
    """The values of docs/results/templates/pre-reaching-course.md: the full-budget run's
    pre-reaching snapshots (``strategy_course``), where training stands, the strategies per
    replication and snapshot, their changes, the course of the measures, generation 50
    beside ``TEN``'s populations and the claims of pre-reachers at ``runs.JUDGED``."""
    directory = recordings / FULL
    run = RunDirectory.open(directory)
    pre = run.status().filter(pl.col("phase") == "pre")
    trained = int(pre["generations"].min())
    out = {"run": FULL, "training": training_text(run), "pre_trained": str(trained),
           "pre_of": str(int(pre["of"].max())), "still_share": formatting.percent(STILL_SHARE),
           "judged": ", ".join(map(str, JUDGED)), "ten": TEN,
           "judged_list": ",".join(map(str, JUDGED)),
           **cost_values(run, int(pre["of"].max())), "fit_at_50": fit_at_50(recordings),
           **still_at_50(recordings)}
    development = load_development(directory, senses=None)
    if development is None or not development.filter(pl.col("phase") == "pre").height:
        raise ValueError(f"{directory}: no pre-reaching snapshot post-evaluated (dart-reach "
                         f"evaluate COPY --finished-only --development 5)")
    out.update(babbling_words(development, recordings))
    development = before_touch.attach(development, directory)  # A1's babbling, where measured
    course = sc.course(development)
    conditions = (development.filter(pl.col("phase") == "pre").group_by("generation")
                  .agg(pl.col("senses").unique().sort()).sort("generation"))
    out["evaluated"] = "; ".join(
        f"{g} ({', '.join(s)})" for g, s in conditions.iter_rows())
    generations = course["generation"].unique().sort().to_list()
    last = generations[-1]
    out["last"] = str(last)
    matrix = (course.with_columns(
        (pl.col("strategy").str.slice(0, 1).str.to_uppercase() + pl.lit(" ")
         + (pl.col("babbling_share") * 100).round(0).cast(pl.Int64).cast(pl.Utf8)
         + pl.lit(" %")).alias("cell"))
        .pivot(on="replication", index="generation", values="cell", sort_columns=True)
        .sort("generation"))
    out["matrix"] = markdown_table(matrix.rename(
        {c: f"rep {c}" for c in matrix.columns if c != "generation"}))
    out["lines"] = markdown_table(sc.still_by_line(course).rename(
        {f"below {STILL_SHARE * 100:g} %": f"below {STILL_SHARE * 100:g} % (the rule)"}))
    turns = sc.switches(course)
    out["switches"] = markdown_table(turns)
    medians = (course.group_by("generation")
               .agg((pl.col("strategy") == BABBLING).sum().alias("babbling populations"),
                    (pl.col("strategy") == STILL).sum().alias("still populations"),
                    *[pl.col(m).median() for m in sc.MEASURES])
               .sort("generation").rename(sc.MEASURES))
    out["medians"] = markdown_table(medians)
    out.update(fitness_values(course, run.stats))
    babbling, still = kinds(course.filter(pl.col("generation") == last))
    out["outcome"] = outcome(babbling, still)
    out["changed"] = str(int((turns["changes"] > 0).sum()))
    out["came_back"] = str(int(turns["came_back"].sum()))
    out["settled"] = settled(turns, generations)
    out["still_to_know"] = still_to_know(last, int(pre["of"].max()))
    ten = recordings / TEN
    if 50 in generations and results.exists(ten / results.EVALUATION):
        evaluation = load_evaluation(ten)
        measured = with_terms(ten, evaluation)
        side = sc.at_budget(course, 50, measured, (f"{FULL} @50", TEN))
        out["at50"] = markdown_table(side.drop("babbling_share").rename(sc.MEASURES))
        full50, other = (side.filter(pl.col("run") == r) for r in side["run"].unique(
            maintain_order=True))
        b, s_ = kinds(side)
        out["at50_summary"] = (f"of the {side.height} populations trained for 50 generations, "
                               f"{b} babble and {s_} are still ({kinds(full50)[1]} of "
                               f"{full50.height} in this run, {kinds(other)[1]} of "
                               f"{other.height} in {TEN})")
        if measured is not evaluation:
            out["at50_summary"] += (f"; {TEN}'s evaluation table predates the measure "
                                    f"'{sc.MEASURES['contact_after_first']}' "
                                    f"(contact_after_first), which comes from its "
                                    f"{fitness_terms.TABLE} (the same robots' same trials run "
                                    f"again)")
    else:
        out["at50"] = "(generation 50 not yet post-evaluated)"
        out["at50_summary"] = "generation 50 is not yet post-evaluated"
    baseline = (load_evaluation(directory, baseline=True)
                if results.exists(directory / results.BASELINE) else None)
    found = sc.judged(development, baseline, JUDGED)
    claims = [c.id for c in sc.claims_of_pre()]
    grid = pl.DataFrame({"claim": claims})
    for g in found["generation"].unique().sort().to_list():
        cells = {r["claim"]: "cannot be tested with this measure (replication.md says why)"
                 if r["measured"].startswith(findings.UNTESTABLE) else f"{r['verdict']}: "
                 + formatting.effect(r["effect"], r["effect_low"], r["effect_high"])
                 + (f", p {formatting.number(r['p'])}" if r["p"] == r["p"] else "")
                 + (f" ({r['note']})" if r["note"] else "")
                 for r in found.filter(pl.col("generation") == g).iter_rows(named=True)}
        grid = grid.with_columns(pl.Series(f"gen {g}", [cells[c] for c in claims]))
    waiting = [g for g in JUDGED if g not in set(found["generation"])]
    why = {g: "not yet trained" if g > trained else "not yet evaluated" for g in waiting}
    out["claims_waiting"] = ("" if not waiting else "Not yet judged: generation(s) "
                             + ", ".join(f"{g} ({why[g]})" for g in waiting) + ". ")
    if grid.width == 1:
        grid = grid.with_columns(pl.lit("–").alias("verdict"))
    out["claims"] = markdown_table(grid)
    changed = sc.verdict_changes(found)
    out["verdict_changes"] = "; ".join(
        f"{r['claim']} ({r['before']}: {r['was']}, {r['after']}: {r['now']})"
        for r in changed.iter_rows(named=True)) or "none"
    ends = sc.scale_ends(development, JUDGED)
    out["rate_margin"] = f"{verdicts.RATE_MARGIN:g}"
    out["equivalence_level"] = f"{verdicts.PAIRED_EQUIVALENCE_LEVEL:g}"
    out["paired_interval"] = calibration.paired_interval(calibration.committed())
    out["band_interval"] = coverage.shaped_label(calibration.committed(), "band")
    out["change_interval"] = coverage.shaped_label(calibration.committed(), "change")
    out["sector_interval"] = coverage.shaped_label(calibration.committed(), "sector")
    out["theta_margin"] = f"{verdicts.EQUIVALENCE_MARGIN:g}"
    out["scale_ends"] = ("none." if not ends.height else "\n\n" + markdown_table(ends.rename(
        {"senses": "condition", "reference": "value", "versus": "against",
         "changed": "value there"})))
    for key, measure in (("by_condition", "babbling"), ("by_condition_touch", BABBLING_BOTH)):
        rates = sc.babbling_by_condition(development, course, measure=measure)
        out[key] = markdown_table(rates.select(
            "generation", pl.col("senses").alias("condition"),
            pl.col("babbling").alias("babbling populations"),
            pl.col("median").alias("their babbling rate: median"),
            pl.col("babbling_low").alias("lowest"), pl.col("babbling_high").alias("highest"),
            pl.col("still_high").alias("still populations: highest rate"))
        ) if rates.height or measure != BABBLING_BOTH else (
            f"(not yet measured: `python -m reports.babbling_before_touch . --runs {FULL}`)")
    return out


def _png(fig) -> bytes:
    """A figure as PNG bytes, no software version written (the same data on the same
    matplotlib give the same bytes)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90, metadata={"Software": None})
    return buffer.getvalue()


def figure(recordings: Path) -> bytes:
    """docs/results/pre-reaching-course.png: the full-budget run's pre-reaching strategies over
    its post-evaluated snapshots (``figures.strategy_figure``), as PNG bytes."""
    return _png(strategy_figure(sc.course(load_development(recordings / FULL)), STILL_SHARE))


def training_figure(recordings: Path) -> bytes:
    """docs/results/pre-reaching-training.png: the full-budget run's pre-reaching fitness in
    training, every generation, each replication marked by its strategy at the last
    post-evaluated snapshot (``figures.training_by_strategy``), as PNG bytes."""
    directory = recordings / FULL
    course = sc.course(load_development(directory))
    strategies = dict(sc.last_strategies(course).iter_rows())
    return _png(training_by_strategy(RunDirectory.open(directory).stats, strategies, STILL,
                                     window=GROWTH_WINDOW))
