"""The results pages, generated from the committed results (``make results``).

Every number and table of a generated page comes from the runs' committed tables under
``recordings/`` (``dart_reach.postevaluation.results``): its prose is a template,
``docs/results/templates/<page>.md``, in which ``{{ name }}`` stands for a value computed
here, and the page itself (``docs/results/<page>.md``) is the template rendered. A test renders
every template again and fails when a committed page differs: a page cannot drift from its
data, and a number typed into a page by hand has nowhere to go.

``python -m reports.results [ROOT]`` writes the pages of the repository at ROOT (default: the
current directory) and each post-evaluated replication run's findings frame
(``recordings/<run>/findings.parquet``: every claim judged at the run's budget); ``--check``
writes nothing and exits 1 naming the files that differ from their rendering.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Callable

import numpy as np
import polars as pl

from dart_reach.analysis import (budgets, coverage, findings, formatting, report, said, spreads,
                                 verdicts)
from dart_reach import integrity
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.files import write_parquet
from dart_reach.model.scenes import scene_of
from dart_reach.postevaluation import checks, results
from dart_reach.postevaluation.snapshots import load_development
from dart_reach.studies.scene_study import study_runs
from dart_reach.studies.scene_study import summary as study_summary

from . import babbling_detector, campaign, cost, pre_reaching_course, scene_study, stillness
from . import calibration as calibration_table
from .runs import REPLICATIONS, TEN
from .text import markdown_table, render, training_text

TEMPLATES = Path("docs/results/templates")
OUT = Path("docs/results")


def provenance(run_dirs) -> dict[str, str]:
    """``trained``: the revisions and dates the runs were created at (their manifests);
    ``evaluated``: the revisions and dates of the sessions that wrote their results."""
    trained, evaluated = set(), set()
    for d in map(Path, run_dirs):
        manifest = json.loads((d / "manifest.json").read_text())
        trained.add(f"{str(manifest.get('git_revision'))[:7]} ({manifest['created'][:10]})")
        for name in (results.EVALUATION, results.BASELINE, results.DEVELOPMENT):
            for e in results.sessions(d / name):
                evaluated.add(f"{str(e.get('revision'))[:7]} ({str(e.get('started'))[:10]})")
    return {"trained": ", ".join(sorted(trained)),
            "evaluated": ", ".join(sorted(evaluated)) or "unknown"}


def scene_study_values(recordings: Path) -> dict[str, str]:
    """The values of docs/results/templates/scene-study.md: ``summary`` and ``levers`` (the
    study's tables, ``reports.scene_study``), ``<scene>.<group>.<measure>`` (the summary's
    cells, ``scene_study.cell``),
    ``<scene>.wall_h`` (training wall time), the runs' ``trained`` / ``evaluated``
    provenance and the gated rules' words on the levers (``scene_study.lever_words``)."""
    runs = study_runs(recordings / "scene-study")
    summary = study_summary(runs)
    lever_table = scene_study.lever_table(runs)
    values = {"summary": scene_study.markdown(summary).rstrip("\n"),
              **scene_study.lever_words(scene_study.robots(runs),
                                        calibration_table.committed()),
              "levers": scene_study.levers_grid(lever_table).rstrip("\n"),
              "levers_full": scene_study.levers_markdown(lever_table).rstrip("\n"),
              **provenance(runs)}
    for row in summary.iter_rows(named=True):
        for measure, value in row.items():
            if isinstance(value, float):
                values[f"{row['scene']}.{row['group']}.{measure}"] = scene_study.cell(value,
                                                                                  measure)
    for d in runs:
        run = RunDirectory.open(d)
        scene = scene_of(run.settings.world.sectors) or d.name
        wall = run.status().unique(["condition", "phase"])["wall_h"].sum()
        values[f"{scene}.wall_h"] = f"{wall:.1f}"
    return values


def _post_evaluation(run_dir: Path) -> str:
    statuses = checks.table_status(run_dir)
    if not statuses:
        return "not yet"
    return "; ".join(f"{s.name.removesuffix('.parquet')} {s.trials:,} trials, "
                     + ("complete" if s.complete else "incomplete") for s in statuses)


def spreads_summary(run_dirs) -> pl.DataFrame:
    """Per post-evaluated run, the spreads of its robots against the calibration's nestings
    (``spreads.spreads`` over every phase and measure): the ratio of the within- to the
    between-replication s.d., its quartiles and largest finite value, and how often the
    replications' means vary no more than their robots would alone (between s.d. 0)."""
    rows = []
    for d in map(Path, run_dirs):
        table = results.read_table(d / results.EVALUATION)
        if table is None:
            continue
        found = spreads.spreads(table)
        ratio = found["ratio"].to_numpy()
        finite = ratio[np.isfinite(ratio)]
        q1, q2, q3 = np.quantile(finite, [0.25, 0.5, 0.75]) if finite.size else [np.nan] * 3
        rows.append({"run": f"`{d.name}`", "phases x measures": found.height,
                     "within / between: median": float(q2),
                     "quartiles": f"{formatting.number(float(q1))}–"
                                  f"{formatting.number(float(q3))}",
                     "largest finite": float(finite.max()) if finite.size else np.nan,
                     "between s.d. 0": int((~np.isfinite(ratio)).sum())})
    return pl.DataFrame(rows) if rows else pl.DataFrame({"run": ["none post-evaluated yet"]})


def replications_text(by_budget: pl.DataFrame) -> str:
    """What more replications decided at the same budget (``budgets.replications_decide``):
    the count of the paper's claims per outcome, and the claims whose verdict changed."""
    decide = budgets.replications_decide(findings.reading(by_budget))
    if decide.height == 0:
        return (f"Not yet: `{TEN}` is training. Once it is post-evaluated, this section "
                "sets its verdicts beside `replication-50`'s claim by claim.")
    counts = decide.group_by("outcome").len()
    order = pl.DataFrame({"outcome": budgets.REPLICATION_OUTCOMES})
    changed = decide.filter(pl.col("outcome").is_in([budgets.DECIDED_NOW, budgets.REVERSED,
                                                     budgets.UNDECIDED_NOW]))
    return (markdown_table(order.join(counts, on="outcome", how="left")
                           .with_columns(pl.col("len").fill_null(0).alias("claims"))
                           .drop("len"))
            + "\n\nWhere the verdict changed:\n\n"
            + (markdown_table(changed.select(
                "claim", pl.col("generations_per_phase").alias("generations per phase"),
                pl.col("replications_few").alias("replications"), pl.col("few").alias("verdict"),
                pl.col("replications_many").alias("more replications"),
                pl.col("many").alias("their verdict"), "outcome"))
               if changed.height else "none."))


def plain_values(by_budget: pl.DataFrame, run: str = TEN) -> dict[str, str]:
    """The paper's claims at ``run``'s budget in plain words, the replication as the unit.
    ``plain``: the reproduced and the contradicted, each with what was measured and whether
    it survives Holm's adjustment, then the names of those left undecided (inconclusive or
    underpowered), of those not run (no data: a condition the run did not train, or a
    table not committed) and, apart, of those their measure cannot test (``Claim.untestable``,
    with why); ``plain_names``: one sentence naming the decided ones, for the
    summary; ``plain_against``: the contradicted ones with what was measured, and
    ``plain.<key>`` the verdict of each of ``NAMED``'s claims, for the replication page's
    prose."""
    rows = findings.reading(by_budget.filter(pl.col("runs") == run))
    if rows.filter(pl.col("verdict") != verdicts.NOT_RUN).height == 0:
        text = f"Not yet: `{run}` has not been post-evaluated."
        return {"plain": text, "plain_names": text, "plain_against": text,
                **{f"plain.{key}": verdicts.NOT_RUN for key in NAMED}}
    count = findings.summary(rows)
    holm = {verdicts.REPRODUCED: "p_holm", verdicts.CONTRADICTED: "p_holm_against"}

    def of(*chosen: str) -> pl.DataFrame:
        return rows.filter(pl.col("verdict").is_in(chosen))

    def names(*chosen: str) -> str:
        return "; ".join(of(*chosen)["claim"]) or "none"

    def listed(verdict: str) -> str:
        return "".join(f"\n  - {r['claim']} — {r['measured']}"
                       + (" (survives Holm)" if r[holm[verdict]] < findings.ALPHA else "")
                       for r in of(verdict).iter_rows(named=True)) or " none"

    undecided = (verdicts.INCONCLUSIVE, verdicts.UNDERPOWERED)
    budget = (f"{rows['generations_per_phase'][0]} generations per phase with "
              f"{rows['replications'][0]} replications (`{run}`)")
    lines = [f"Of the paper's {rows.height} claims, at {budget}:", ""]
    for verdict in holm:
        lines.append(f"- **{verdict}: {count[verdict]}** ({count[verdict + ' (Holm)']} after "
                     f"Holm):{listed(verdict)}")
    lines.append(f"- **undecided: {of(*undecided).height}** ({count[undecided[0]]} "
                 f"inconclusive, {count[undecided[1]]} underpowered): {names(*undecided)}.")
    cannot = of(verdicts.NOT_RUN).filter(pl.col("measured").str.starts_with(findings.UNTESTABLE))
    no_data = of(verdicts.NOT_RUN).filter(~pl.col("claim").is_in(cannot["claim"].implode()))
    lines.append(f"- **not run: {no_data.height}** (no data for them at this budget"
                 f"): {'; '.join(no_data['claim']) or 'none'}.")
    lines += [f"- **cannot be tested with its measure: {r['claim']}** — "
              f"{r['measured'].removeprefix(findings.UNTESTABLE)}."
              for r in cannot.iter_rows(named=True)]
    sentence = (f"At {budget}, with the replication as the unit: reproduced "
                f"{count[verdicts.REPRODUCED]} of the paper's claims "
                f"({names(verdicts.REPRODUCED)}), contradicted {count[verdicts.CONTRADICTED]} "
                f"({names(verdicts.CONTRADICTED)}); {of(*undecided).height} stay undecided at "
                f"this budget, {no_data.height} were not run (no data for them)"
                + (f" and {cannot.height} cannot be tested with their measure "
                   f"({'; '.join(cannot['claim'])})" if cannot.height else "") + ".")
    verdict_of = dict(zip(rows["claim"], rows["verdict"]))
    against = of(verdicts.CONTRADICTED)
    return {"plain": "\n".join(lines), "plain_names": sentence,
            "plain_against": f"{against.height}" + "".join(
                f"{'; ' if i else ': '}{r['claim']} ({r['measured']})"
                for i, r in enumerate(against.iter_rows(named=True))),
            **{f"plain.{key}": verdict_of.get(claim, verdicts.NOT_RUN)
               for key, claim in NAMED.items()}}


#: The claims whose verdicts the replication page's prose names (``plain_values``): key ->
#: the claim.
NAMED = {"babbling": "F1 babbling", "swipes_again": "F2 swipes again"}


#: Where the summary's table of verdicts links (from docs/results/): every claim at every
#: budget.
CLAIMS_LINK = "replication.md#every-claim-at-every-budget"


def summary_row(paper: dict, budget: budgets.Budget) -> dict[str, str]:
    """The summary's row of a budget: its runs (linked to every claim at every budget) and the
    paper's claims by verdict (``findings.summary``; those their measure cannot test apart
    from those not run), the decided ones with how many survive Holm's adjustment."""
    return {"run": f"[`{paper['runs']}`]({CLAIMS_LINK})",
            "generations per phase x replications":
                f"{budget.generations_per_phase} x {budget.replications}",
            **{v: (f"{paper[v]} ({paper[f'{v} (Holm)']} after Holm)" if f"{v} (Holm)" in paper
                   else str(paper[v])) for v in findings.COUNTED}}


def _pre_replications(table: pl.DataFrame | None) -> tuple[str, str, str]:
    """A run's pre-reachers replication by replication (``report.replication_table``), how
    many of its replications had no robot babble in any trial, and the mean fitness of those
    still replications beside the babbling ones' with what their test allows to say
    (``said.two_groups``)."""
    if table is None:
        return ("not post-evaluated yet",) * 3
    pre = report.replication_table(table, "pre")
    is_still = pre["babbling rate"] == 0
    fit = {name: pre.filter(rows)["fitness"] for name, rows in
           (("still", is_still), ("babbling", ~is_still))}
    fitness = "; ".join(f"{name} {formatting.number(float(f.mean()))} ({f.len()})"
                        if f.len() else f"{name}: none" for name, f in fit.items())
    fitness += ", " + said.two_groups(fit["still"].to_numpy(), fit["babbling"].to_numpy(),
                                      "still", "babbling", calibration_table.committed())
    return markdown_table(pre), f"{int(is_still.sum())} of {pre.height}", fitness


def calibration_values(table: pl.DataFrame) -> dict[str, str]:
    """What the calibration shows, in the words of the summary and the replication page, from
    the committed calibration ``table`` (``calibration_table.held``, ``coverage.label``), so that
    no page states it as fixed text: ``calibration`` (how many bounded rows are met, the
    highest rate of a wrong decision under a null, the lowest coverage and theta's reported
    coverage), ``theta_coverage`` (the label of theta's interval at 10 vs 10),
    ``paired_interval`` (the level of a paired claim of no change's interval),
    ``band_interval``, ``sector_interval`` and ``change_interval`` (the coverage measured of a
    band's interval, every sector's weakest cell's and a paired change's,
    ``coverage.shaped_label``), and
    ``smallest_p_4`` / ``smallest_p_10`` (the smallest p of the directional rule's test at 4
    and 10 replications a group, ``verdicts.smallest_directional_p``)."""
    held = calibration_table.held(table)
    sizes = " and ".join(map(str, table["replications"].unique().sort().to_list()))
    shortfall = held["bounded"] - held["met"]
    rules = ", ".join(table.filter(pl.col("kind").is_in(["at most", "at least"]))["rule"]
                      .unique(maintain_order=True).to_list())
    text = (f"{held['met']} of the {held['bounded']} bounded rows of the rules ({rules}: rates "
            f"of a wrong decision under a null, at {sizes} replications and with the groups' "
            f"shapes unequal, and coverages) are met within Monte-Carlo error"
            + (f" and **{shortfall} are not**" if shortfall else "")
            + f"; the highest rate of a wrong decision under a null is "
            f"{held['highest_error']:.3f} (its bound {held['error_bound']:g}), the lowest "
            f"coverage of an interval held to its level {held['lowest_coverage']:.3f}")
    if held["reported_low"] == held["reported_low"]:
        text += (f"; θ's interval away from θ = 0.5 between groups of unequal shapes, only "
                 f"reported, covers {held['reported_low']:.2f}-{held['reported_high']:.2f}")
    if held["unbounded_high"] == held["unbounded_high"]:
        text += (f"; where a rule's error rate is only reported ({held['unbounded']}), it "
                 f"decides wrongly up to {held['unbounded_high']:.2f} of the time")
    return {"calibration": text, "theta_coverage": coverage.label(table, 10, 10),
            "paired_interval": calibration_table.paired_interval(table),
            "band_interval": coverage.shaped_label(table, "band"),
            "sector_interval": coverage.shaped_label(table, "sector"),
            "change_interval": coverage.shaped_label(table, "change"),
            "smallest_p_4": formatting.significant(verdicts.smallest_directional_p(4, 4)),
            "smallest_p_10": formatting.significant(verdicts.smallest_directional_p(10, 10))}


def replication_values(recordings: Path) -> dict[str, str]:
    """The values of docs/results/templates/replication.md: ``runs`` (what each run is and
    where it stands), ``counts`` (the paper's claims by verdict at each budget, the replication
    as the unit, raw and Holm-surviving; ``own_counts`` the project's own; ``answer`` the
    summary's, ``summary_row``), ``sections`` (by
    section of the paper), ``claims`` (every claim side by side, ``budgets.side_by_side``),
    ``movement_note`` (the legend of its intervals as the budget grows),
    and per run ``<run>.measures`` (means over robots beside the random baseline) and
    ``<run>.status`` (training, ``dart-reach status --markdown``)."""
    dirs = [recordings / name for name in REPLICATIONS]
    judged = [d for d in dirs if results.exists(d / results.EVALUATION)]
    by_budget = budgets.findings_by_budget(judged)
    values = {"sections": markdown_table(report.section_counts(by_budget)),
              "claims": markdown_table(budgets.side_by_side(by_budget)),
              "movement_note": budgets.MOVEMENT_NOTE,
              "by_replications": replications_text(by_budget),
              **plain_values(by_budget)}
    rows, infants, own, answer = [], [], [], []
    named = budgets.labels(budgets.budgets(by_budget))  # the model named only where several
    for block in by_budget.partition_by(*budgets.BUDGET_COLUMNS, maintain_order=True):
        budget = budgets.Budget(*block.select(budgets.BUDGET_COLUMNS).row(0))
        for target, who in ((rows, findings.ROBOTS), (infants, findings.INFANTS),
                            (own, findings.OWN)):
            target.append({"budget": named[budget], "runs": block["runs"][0],
                           **findings.summary(block, who)})
        paper = rows[-1]
        answer.append(summary_row(paper, budget))
    values["counts"] = markdown_table(pl.DataFrame(rows))
    values["infant_counts"] = markdown_table(pl.DataFrame(infants))
    values["answer"] = markdown_table(pl.DataFrame(answer))
    values["own_counts"] = markdown_table(pl.DataFrame(own))
    described = []
    for d in dirs:
        run = RunDirectory.open(d)
        manifest = json.loads((d / "manifest.json").read_text())
        described.append({
            "run": f"`{d.name}`", "conditions": ", ".join(c.name for c in run.conditions),
            "generations per phase": budgets.generations_per_phase(run)[0],
            "replications": run.settings.replications, "seed": run.settings.seed,
            "scene": scene_of(run.settings.world.sectors) or "custom",
            "created": manifest["created"][:10], "training": training_text(run),
            "post-evaluation": _post_evaluation(d)})
        table = results.read_table(d / results.EVALUATION)
        values[f"{d.name}.measures"] = "not post-evaluated yet" if table is None else \
            markdown_table(report.baseline_table(
                table, results.read_table(d / results.BASELINE)))
        (values[f"{d.name}.pre"], values[f"{d.name}.pre_still"],
         values[f"{d.name}.pre_fitness"]) = _pre_replications(table)
        status = run.status().with_columns(
            pl.format("{} / {}", "generations", "of").alias("generations")).drop("of")
        values[f"{d.name}.status"] = markdown_table(status)
        values[f"{d.name}.training"] = training_text(run)
    values["runs"] = markdown_table(pl.DataFrame(described))
    values["spreads"] = markdown_table(spreads_summary(dirs))
    values.update(calibration_values(calibration_table.committed()))
    return values


def campaign_values(recordings: Path) -> dict[str, str]:
    """The campaign's judgement so far, for the summary (docs/results/campaign.md has it
    whole): the paper's pre-reacher at the judged generations post-evaluated, described at the
    last, and the paper's claims of the phases finished and post-evaluated, counted. Neither
    changes while a phase trains."""
    run_dir = recordings / campaign.CAMPAIGN.relative_to(campaign.ROOT / "recordings")
    started = (run_dir / "manifest.json").exists()
    judged = campaign.judged_snapshots(load_development(run_dir, senses=None)
                                       if started else None)
    word = {True: "met", False: "not met"}
    if judged:
        g, j, _ = judged[-1]
        found = [str(g) for g, j, _ in judged if j["paper"]]
        pre = (f"the paper's pre-reacher, every criterion at once, is found at "
               f"{', '.join(found) or 'none'} of its judged pre-reaching generations "
               f"post-evaluated ({', '.join(str(g) for g, _, _ in judged)}); at {g}: reach "
               f"{formatting.decimals(j['reach'], 2)} (A1 {word[j['A1']]}; the scene is "
               f"calibrated on it), elbow SD {formatting.decimals(j['elbow_sd'])} against the "
               f"shoulder's {formatting.decimals(j['shoulder_sd'])} and the trunk's "
               f"{formatting.decimals(j['trunk_sd'])} (A2 {word[j['A2']]}), the best robot's "
               f"hand {formatting.decimals(j['hand_shoulder_m'])} m from the shoulder, CV "
               f"{formatting.decimals(j['hand_shoulder_cv'])} (A3 {word[j['A3']]}), "
               f"{j['babbling_robots']} of {j['robots']} best robots babbling without the "
               f"ball (A4 {campaign.a4_word(j)}), {j['still']} of {j['replications']} "
               f"replications still")
    else:
        pre = (f"none of its judged pre-reaching generations "
               f"({', '.join(map(str, campaign.CAMPAIGN_JUDGED))}) is post-evaluated yet")
    phases = campaign.judged_phases(run_dir)  # none without a post-evaluation
    if phases:
        c = findings.summary(campaign.phase_claims(run_dir))
        names = ", ".join(campaign.PHASE_NAMES.get(p.name, p.name) for p in phases)
        claims = (f"Of the paper's claims, those its finished and post-evaluated phases "
                  f"({names}) can judge: " + ", ".join(
                      f"{v} {c[v]}" for v in findings.VERDICTS if v != verdicts.NOT_RUN)
                  + f" (after Holm's adjustment reproduced {c['reproduced (Holm)']}, "
                  f"contradicted {c['contradicted (Holm)']}); {c[verdicts.NOT_RUN]} not run (a "
                  f"phase they need has not finished and been post-evaluated yet), "
                  f"{c[findings.CANNOT]} cannot be tested")
    else:
        claims = "No phase has finished and been post-evaluated yet: no phase claim is judged"
    return {"pre_reacher": pre, "claims": claims}


def stillness_values(recordings: Path) -> dict[str, str]:
    """The values of docs/results/templates/stillness.md (``stillness.values``)."""
    return stillness.values(recordings, markdown_table)


#: Each doc rendered from a template: its name and the functions of the recordings directory
#: giving its values, each under a prefix of its keys (``course.outcome``:
#: ``pre_reaching_course.values``'s ``outcome``).
DOCS: dict[str, dict[str, Callable[[Path], dict[str, str]]]] = {
    "scene-study.md": {"": scene_study_values},
    "replication.md": {"": replication_values},
    "summary.md": {"": replication_values, "course.": pre_reaching_course.values,
                   "campaign.": campaign_values},
    "stillness.md": {"": stillness_values},
    "pre-reaching-course.md": {"": pre_reaching_course.values},
    "babbling-detector.md": {"": babbling_detector.values},
    "calibration.md": {"": calibration_table.values}}


#: Each figure of the results docs: its path under docs/results and the function of the
#: recordings directory giving its PNG bytes. Written by ``main``; not part of ``--check`` (a
#: figure's bytes depend on matplotlib's version; its data are the doc's tables).
FIGURES: dict[str, Callable[[Path], bytes]] = {
    "pre-reaching-course.png": pre_reaching_course.figure,
    "pre-reaching-training.png": pre_reaching_course.training_figure}
#: Each doc that is a table alone: its path under docs/results and the function of the
#: recordings directory giving its text.
TABLES: dict[str, Callable[[Path], str]] = {
    "scene-study/scene-study.md":
        lambda recordings: scene_study.tables_text(study_runs(recordings / "scene-study"))}


#: Generated parts of other pages: the page (from the root), the template rendered between
#: its ``BEGIN`` and ``END`` lines, and the functions giving the values, as ``DOCS``'s.
PARTS: dict[str, tuple[str, dict[str, Callable[[Path], dict[str, str]]]]] = {
    "docs/results/benchmarks.md": ("benchmarks-cost.md", {"": cost.values})}
BEGIN = "<!-- results: generated by `make results` from docs/results/templates/{} -->"
END = "<!-- /results -->"


def generate(root: Path) -> dict[Path, str]:
    """Every generated doc of the repository at ``root``: path -> its text."""
    recordings = root / "recordings"
    out = {root / OUT / name: text(recordings) for name, text in TABLES.items()}
    cache: dict[Callable, dict[str, str]] = {}

    def values(function):
        if function not in cache:
            cache[function] = function(recordings)
        return cache[function]

    def merged(functions) -> dict[str, str]:
        return {prefix + key: value for prefix, function in functions.items()
                for key, value in values(function).items()}

    for name, functions in DOCS.items():
        template = (root / TEMPLATES / name).read_text(encoding="utf-8")
        out[root / OUT / name] = render(template, merged(functions), name)
    for page, (name, functions) in PARTS.items():
        text = (root / page).read_text(encoding="utf-8")
        begin = BEGIN.format(name)
        if text.count(begin) != 1 or text.count(END) != 1:
            raise ValueError(f"{root / page}: expected one '{begin}' line and one '{END}' line")
        head, rest = text.split(begin + "\n", 1)
        _, tail = rest.split(END, 1)
        part = render((root / TEMPLATES / name).read_text(encoding="utf-8"), merged(functions),
                      name)
        out[root / page] = head + begin + "\n" + part + END + tail
    return out


def findings_frames(root: Path) -> dict[Path, pl.DataFrame]:
    """The findings frame of each post-evaluated replication run at its own budget
    (``budgets.findings_by_budget``), committed as ``recordings/<run>/findings.parquet``."""
    out = {}
    for name in REPLICATIONS:
        run = root / "recordings" / name
        if results.exists(run / results.EVALUATION):
            out[run / "findings.parquet"] = budgets.findings_by_budget([run])
    return out


def _same_frame(path: Path, frame: pl.DataFrame) -> bool:
    if not path.is_file():
        return False
    stored = pl.read_parquet(path)
    return stored.schema == frame.schema and stored.equals(frame)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m reports.results",
                                     description="write the results docs from the committed "
                                                 "results")
    parser.add_argument("root", nargs="?", type=Path, default=Path("."),
                        help="the repository (default: the current directory)")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 naming the docs that differ")
    args = parser.parse_args(argv)
    if not (args.root / TEMPLATES).is_dir():
        print(f"{args.root / TEMPLATES}: no such directory (give the repository's root)",
              file=sys.stderr)
        return 2
    docs = generate(args.root)
    frames = findings_frames(args.root)
    stale = [p for p, text in docs.items()
             if not p.is_file() or p.read_text(encoding="utf-8") != text]
    stale += [p for p, frame in frames.items() if not _same_frame(p, frame)]
    if args.check:
        for p in stale:
            print(f"{p}: differs from its rendering (make results)", file=sys.stderr)
        return 1 if stale else 0
    for p in stale:
        if p in frames:  # in its run's ledger (integrity), with page checksums
            integrity.write(p, lambda tmp, p=p: write_parquet(frames[p], tmp))
        else:
            p.write_text(docs[p], encoding="utf-8")
        print(f"wrote {p}")
    for name, figure in FIGURES.items():
        path, png = args.root / OUT / name, figure(args.root / "recordings")
        if not path.is_file() or path.read_bytes() != png:
            path.write_bytes(png)
            print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
