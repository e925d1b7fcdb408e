"""The replication report (``dart-reach report RUN [RUN ...]``): one self-contained HTML file.

What a reviewer of a replication wants to read, in this order: an answer per phenomenon of the
paper (``answers``), the claims by verdict and their forest (``summary_html``), the findings
table (every claim of section IV against the data, ``findings``), provenance (command,
conditions, budgets, seeds, revision, versions, machine, physics step, wall time), training
(curves and the numbers at the start and end of each phase), the measures of Figs. 5-6 beside
the random baseline, the figures (5-10, drawn by ``figures`` as the notebooks draw them) and the
statistics behind them. Figures are matplotlib PNGs embedded as data URIs, tables plain HTML,
the page a ``string.Template`` (``templates/report.html``): it opens offline in any browser.

Runs trained at different budgets (scene, generations per phase, replications, model version
and variant: ``budgets``) are judged apart: the findings of each budget, and, when there are
several, the claims side by side with how their intervals lie as the budget grows (a
description, not a test) and the figure of their effects against the budget. The provenance
of each run names its model version and variant (``run_provenance``).

Every number in it is computed from the run directories when the report is built; the runs
are only read. The trials Figs. 6 and 8 draw that have no recording are run again and recorded
in a folder beside the report (``recordings_dir``: ``<name>-recordings/<run>/`` for
``<name>.html``), kept there for the next build.
"""

from __future__ import annotations

import base64
import html
import io
import time
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from string import Template

import polars as pl

from . import answers, budgets, counts, figures, findings, formatting, summaries, verdicts
from . import unfinished
from .run_provenance import provenance
from ..errors import UsageError
from ..postevaluation import results
from ..postevaluation import snapshots as development
from ..postevaluation.systematic import run_phases
from .counts import section_counts  # noqa: F401 - the report's counts, as results_docs reads them
from .stats import fig9_statistics, fig10_statistics, phase_statistics
from .tables import condition_trials, sector_config
from ..evolution.rundir import RunDirectory, RunError
from ..files import atomic_write

#: Pixels per inch of the figures: their 9-point labels are 12.5 px at 100 % zoom.
DPI = 100
#: Under the training curves: why the best fitness of a generation can fall.
TRAINING_NOTE = (
    "The best fitness of a generation can fall: a genotype's fitness is its mean over new "
    "random trials (ball positions) every generation, and the parents kept from one generation "
    "to the next are evaluated again on new trials (steady state, section III-C), so a lucky "
    "parent's score regresses toward its true mean. The curves are the best of each "
    "generation's evaluations, not a record that can only rise.")
#: Beside the pairwise tests of Figs. 9 and 10.
HOLM_NOTE = (
    "p: each pair's two-tailed Mann-Whitney test, uncorrected, as the paper reports them; "
    "p_holm: corrected for the number of pairs compared (Holm's step-down method, which keeps "
    "the chance of any false positive among them below alpha). The matrices draw black where "
    "p_holm < 0.05 and grey where only the uncorrected p is.")
#: Marks the files this module writes: only those are ever overwritten.
GENERATOR = '<meta name="generator" content="dart_reach report">'
#: Measures of the baseline table (Figs. 5, 6 and the babbling measure), with their labels.
#: ``babbling_share`` is the share of the hand's spectral power at its dominant frequency (a
#: spectral concentration, one of the inputs of the babbling measure, high for any movement
#: at one rhythm, random networks' too), not babbling, which is ``babbling``'s rate.
MEASURES = (("fitness", "fitness"), ("reached", "reach rate"), ("grasped", "grasp rate"),
            ("speed", "speed (m/s)"), ("straightness", "straightness"),
            ("var_elbow", "elbow var. (rad)"), ("var_shoulder", "shoulder var. (rad)"),
            ("var_trunk", "trunk var. (rad)"), ("elbow_freezing", "hand-shoulder s.d. (m)"),
            ("babbling", "babbling rate"), ("babbling_share", "spectral concentration"))


# ------------------------------------------------------------------------------ pieces
def _figure(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    return f'<img alt="figure" src="data:image/png;base64,{data}">'


def _cell(value) -> str:
    if isinstance(value, float):
        return formatting.number(value)
    if isinstance(value, bool):
        return "■" if value else ""
    return html.escape(str(value))


def table_html(df: pl.DataFrame, css: str = "", group: str | None = None,
               cell_class=None) -> str:
    """A polars table as a plain HTML table (floats to 3 significant digits). ``group``: a
    column whose value heads each run of equal values (a row of its own) instead of being a
    column; ``cell_class(column, value)``: the CSS class of a cell ("" for none)."""
    columns = [c for c in df.columns if c != group]
    head = "".join(f"<th>{html.escape(c)}</th>" for c in columns)
    rows, current = [], None
    for row in df.iter_rows(named=True):
        if group is not None and row[group] != current:
            current = row[group]
            rows.append(f'<tr class="group"><th colspan="{len(columns)}">'
                        f"{html.escape(str(current))}</th></tr>")
        cells = []
        for c in columns:
            css_ = cell_class(c, row[c]) if cell_class is not None else ""
            cells.append(f'<td class="{css_}">{_cell(row[c])}</td>' if css_
                         else f"<td>{_cell(row[c])}</td>")
        rows.append(f"<tr>{''.join(cells)}</tr>")
    return (f'<div class="scroll"><table class="{css}"><thead><tr>{head}</tr></thead>'
            f'<tbody>{"".join(rows)}</tbody></table></div>')


def _effect(r: dict) -> str:
    return html.escape(formatting.effect(r["effect"], r["effect_low"], r["effect_high"]))


def _findings_html(found: pl.DataFrame) -> str:
    """The findings, grouped by the paper's section and figure, in the table's order."""
    head = ("<tr><th>claim</th><th>the paper</th><th>measured here</th><th>kind (test: see "
            "the summary)</th><th>n</th>"
            "<th>effect [CI]</th><th>p</th><th>Holm p</th><th>paper's level met</th>"
            "<th>verdict (replications)</th><th>the paper's analysis: robots as units</th>"
            "</tr>")
    rows, section = [], None
    for r in found.iter_rows(named=True):
        if r["section"] != section:
            section = r["section"]
            rows.append(f'<tr class="group"><th colspan="11">{html.escape(section)}</th></tr>')
        met = {True: "yes", False: "no", None: "–"}[r["paper_level_met"]]
        note = f'<br><small>{html.escape(r["note"])}</small>' if r["note"] else ""
        rows.append(
            f'<tr class="{r["verdict"].split()[0]}"><td>{html.escape(r["claim"])}</td>'
            f'<td>{html.escape(r["paper"])}</td><td>{html.escape(r["measured"])}</td>'
            f'<td>{html.escape(r["kind"])}</td><td>{html.escape(r["n"])}</td>'
            f'<td>{_effect(r)}</td><td>{_cell(r["p"])}</td><td>{_cell(r["p_holm"])}</td>'
            f'<td>{met}</td><td class="verdict">{html.escape(r["verdict"])}{note}</td>'
            f'<td>{html.escape(r["verdict_robots"] or "–")}</td></tr>')
    return (f'<div class="scroll"><table class="findings"><thead>{head}</thead><tbody>'
            f'{"".join(rows)}</tbody></table></div>')


def budget_text(run_dirs: Sequence[Path], table: pl.DataFrame | None) -> str:
    """What the runs' budget can test: generations per phase, replications and robots per
    replication post-evaluated."""
    parts = []
    for d in run_dirs:
        run = RunDirectory.open(d)
        gens = budgets.generations_per_phase(run)
        parts.append(f"{d.name}: {'/'.join(map(str, gens))} generations per phase "
                     f"({gens[-1] / 500:.0%} of the paper's 500), "
                     f"{run.settings.replications} replications (the paper: 10)")
    if table is not None and table.height:
        robots_ = table.group_by("notation", "replication").agg(pl.col("rank").n_unique())
        parts.append(f"{robots_['rank'].max()} robots per replication post-evaluated "
                     "(the paper: 5)")
    return "; ".join(parts)


def training_summary(stats: pl.DataFrame, phases: pl.DataFrame | None = None) -> pl.DataFrame:
    """Best and mean fitness at the first and last generation of each phase, per condition,
    phase and replication (from ``generations.parquet``), conditions in the order of the run
    and phases in training order (``phases``: ``evaluation.run_phases`` of the run; default:
    the order of the table)."""
    keys = ["condition", "phase", "replication"]
    order = (phases.select("condition", "phase") if phases is not None
             else stats.select("condition", "phase")).unique(maintain_order=True)
    s = (stats.join(order.with_row_index("_order"), on=["condition", "phase"], how="left")
         .sort(["_order", "replication", "generation"], nulls_last=True).drop("_order"))
    return (s.group_by(keys, maintain_order=True)
            .agg(pl.col("generation").last().alias("generations"),
                 pl.col("best").first().alias("best_first"),
                 pl.col("best").last().alias("best_last"),
                 pl.col("best").max().alias("best_max"),
                 pl.col("mean").first().alias("mean_first"),
                 pl.col("mean").last().alias("mean_last")))


def baseline_table(table: pl.DataFrame, baseline: pl.DataFrame | None) -> pl.DataFrame:
    """Mean over robots of each measure (``MEASURES``) per phase, normal senses, with the
    random genomes of that phase (``evaluate --baseline``) as rows ``random <phase>``."""
    parts = [table.filter(pl.col("senses") == "normal")]
    if baseline is not None and baseline.height:
        parts.append(baseline.filter(pl.col("senses") == "normal")
                     .with_columns(pl.format("random {}", "notation").alias("notation")))
    both = pl.concat(parts, how="diagonal_relaxed")
    if both.height == 0:
        return pl.DataFrame({"phase": []})
    names = [m for m, _ in MEASURES]
    robots = summaries.robot_means(both, names, by=("notation", "replication", "rank"))
    order = {n: i for i, n in enumerate(dict.fromkeys(both["notation"].to_list()))}
    out = (robots.group_by("notation", maintain_order=True)
           .agg(pl.len().alias("robots"), *[pl.col(m).mean() for m in names])
           .with_columns(pl.col("notation").replace_strict(order, return_dtype=pl.Int64)
                         .alias("_o"))
           .sort("_o").drop("_o"))
    return out.rename({"notation": "phase", **{m: label for m, label in MEASURES}})


#: The measures of ``replication_table``: what a phase's replications differ in.
REPLICATION_MEASURES = (("fitness", "fitness"), ("reached", "reach rate"),
                        ("babbling", "babbling rate"), ("hand_path", "hand path (m)"))


def replication_table(table: pl.DataFrame, phase: str) -> pl.DataFrame:
    """One row per replication of ``phase`` (its name), normal senses: the mean over its
    robots of each robot's mean over its trials (``REPLICATION_MEASURES``), the unit of every
    verdict (docs/model/claims.md, "Verdicts")."""
    rows = table.filter((pl.col("phase") == phase) & (pl.col("senses") == "normal"))
    names = [m for m, _ in REPLICATION_MEASURES]
    robots = summaries.robot_means(rows, names, by=("replication", "rank"))
    return (robots.group_by("replication").agg(pl.len().alias("robots"),
                                               *[pl.col(m).mean() for m in names])
            .sort("replication").rename(dict(REPLICATION_MEASURES)))


def _section(title: str, body: str, anchor: str) -> str:
    return f'<section id="{anchor}"><h2>{html.escape(title)}</h2>{body}</section>'


def _try(draw, *args, **kwargs) -> str:
    """A figure, or a line saying why it could not be drawn (missing data)."""
    try:
        return _figure(draw(*args, **kwargs))
    except (ValueError, RunError, KeyError, pl.exceptions.PolarsError) as exc:
        return f'<p class="missing">not drawn: {html.escape(str(exc))}</p>'


#: Above the findings: what the verdicts mean.
VERDICTS_NOTE = (
    "<i>Underpowered</i>: even the most favourable data could not reach p &lt; 0.05 at this n "
    "(decided from the sizes before any test; a directional claim also below 6 replications a "
    "group, where no rank test holds its level when the groups' shapes differ); "
    "<i>inconclusive</i>: the data cannot decide; a "
    "claim of no difference is <i>reproduced</i> only by an equivalence test.")
#: Under the figure of the effects against the budget.
BUDGET_FIGURE_NOTE = (
    "Each claim's effect at each budget, on a scale where up is the paper's direction (the "
    "claim's own units: theta - 0.5 for a directional claim, 0.15 - |theta - 0.5| for a claim of "
    "no difference, the depth inside the band, the weakest sector's rate above the floor, ...; "
    "docs/model/claims.md, \"Several budgets\"), with its interval; hollow: no interval or an "
    "unbounded one. The dashed line is 0: no effect, or the claim's boundary. Only the claims "
    "with an effect at two budgets or more are drawn; the words under each panel are the "
    "intervals as the budget grows of the table above: a description, not a test.")


def _baseline_html(label: str, pooled_, heading: bool) -> str:
    """The measures beside the random baseline of one budget's runs (budgets never pooled),
    under ``label`` (``budgets.labels``)."""
    return ((f"<h3>{html.escape(label)}</h3>" if heading else "")
            + table_html(baseline_table(pooled_.table, pooled_.baseline)))


def _counts(found: pl.DataFrame) -> str:
    """The headline: the paper's claims of its robots by verdict, the replication as the unit
    (raw and Holm-surviving); its claims of infants (Table I) and the project's own apart."""
    def line(who: str) -> str:
        return " · ".join(f"{v}: <b>{n}</b>" for v, n in findings.summary(found, who).items())
    return (f'<p class="counts">The paper\'s claims of its robots, replications as units: '
            f'{line(findings.ROBOTS)}</p>'
            f'<p class="counts">The paper\'s claims of infants (Table I): '
            f'{line(findings.INFANTS)}</p>'
            f'<p class="counts">The project\'s own claims: {line(findings.OWN)}</p>')


def summary_html(by_budget: pl.DataFrame) -> str:
    """The first screen: the answer (the paper's claims by verdict at each budget, with
    totals; by section folded under it), then the forest of every claim's effect grouped by
    section, the claims no budget ran apart, and what each kind of test is."""
    answer = counts.budget_counts(by_budget)
    n = findings.reading(by_budget)["claim"].n_unique()
    never = counts.never_run(by_budget)
    tests = pl.DataFrame({"kind": list(findings.TESTS), "test": list(findings.TESTS.values())})
    verdict_cell = (lambda column, value: column.split()[0]
                    if column in verdicts.VERDICTS and value else "")
    return (f"<p class='answer'>The paper's {n} claims of its robots at each budget, the "
            "replication as the unit of every verdict (its claims of infants and the "
            "project's own are counted apart, in each budget's findings):</p>"
            + table_html(answer, "counts answer", cell_class=verdict_cell)
            + "<p><i>Not run</i>: no data for them at that budget. <i>Decided after "
              "Holm</i>: the reproduced and contradicted claims that stay below p = 0.05 once "
              "Holm's method corrects for the number of claims tested at the budget. "
            + VERDICTS_NOTE + "</p>"
            + "<details><summary>The same by section of the paper</summary>"
            + table_html(section_counts(by_budget), "counts", cell_class=verdict_cell)
            + "</details>"
            + _try(figures.forest_figure, by_budget) + figures.forest_caption(by_budget)
            + "<details><summary>Each row's effect, in its own units, and its 1 on the "
              "axis</summary>" + table_html(figures.scale_table(by_budget)) + "</details>"
            + ("" if never.is_empty() else
               f"<details><summary>{never.height} claims not run at any budget (left out of "
               "the figure)</summary>" + table_html(never) + "</details>")
            + "<details><summary>The tests of each kind of claim</summary>"
            + table_html(tests, "tests") + "</details>")


def _verdict_class(column: str, value) -> str:
    """The CSS class of a cell of ``budgets.side_by_side``: its verdict (the intervals as the
    budget grows get none: they state no result)."""
    return value.split()[0] if column.endswith(": verdict") else ""


def _findings_body(blocks: list, by_budget: pl.DataFrame) -> str:
    """The findings of each budget (``budgets``: runs of one scene, generations per phase,
    replications and model are pooled, others never): for one budget, its table as ever; for
    several, the claims side by side with their intervals as the budget grows, the figure of
    the effects against the budget, then each budget's table under its heading (its model
    named where the runs are of several, ``budgets.labels``)."""
    named = budgets.labels([budget for budget, *_ in blocks])

    def block_html(budget, dirs, pooled_, found, heading):
        head = (f"<h3>{html.escape(named[budget])}: "
                f"{html.escape(', '.join(d.name for d in dirs))}</h3>" if heading else "")
        return (head + _counts(found) + "<p>What the budget can test: "
                + html.escape(budget_text(dirs, pooled_.table)) + f". {VERDICTS_NOTE}</p>"
                + _findings_html(found))

    if len(blocks) == 1:
        return block_html(*blocks[0], heading=False)
    scenes = list(dict.fromkeys(budget.scene for budget, *_ in blocks))
    parts = []
    if len(scenes) > 1:
        parts.append(f"<p class='missing'>These runs were trained on {len(scenes)} scenes "
                     f"({html.escape(', '.join(scenes))}): each scene's runs are compared as "
                     "separate groups, never pooled, and the intervals are compared within a "
                     "scene.</p>")
    models = list(dict.fromkeys(budget.model for budget, *_ in blocks))
    if len(models) > 1:
        parts.append(f"<p class='missing'>These runs were trained under {len(models)} models "
                     f"({html.escape(', '.join(models))}; model versions and variants, "
                     "docs/model/levers.md): each model's runs are separate groups, never "
                     "pooled, and the intervals are compared within a model.</p>")
    parts.append(
        f"<p>{len(blocks)} budgets: "
        + html.escape("; ".join(f"{named[b]} ({', '.join(d.name for d in dirs)})"
                                for b, dirs, *_ in blocks))
        + ". The runs of one budget (scene, generations per phase, replications and model) are "
          "pooled and judged together; runs of different budgets never are. "
        + html.escape(budgets.MOVEMENT_NOTE) + " See docs/model/claims.md, \"Several budgets\". "
          "Verdicts take the replication as the unit; the paper's own analysis, robots as "
          "units, is the column beside them.</p>")
    parts.append(table_html(budgets.side_by_side(by_budget), "findings budgets",
                            group="section", cell_class=_verdict_class))
    parts.append(_try(figures.budget_figure, by_budget)
                 + f"<p>{html.escape(BUDGET_FIGURE_NOTE)}</p>")
    parts += [block_html(*block, heading=True) for block in blocks]
    return "".join(parts)


# ------------------------------------------------------------------------------ the report
def recordings_dir(out: Path, run_dirs: Sequence[Path]) -> dict[Path, Path]:
    """Where the report ``out`` keeps the trials it records again, per run: beside it, in
    ``<name>-recordings/<run name>/`` (a run's position in ``run_dirs`` added where two runs
    share a name)."""
    out = Path(out)
    names = [d.name for d in run_dirs]
    base = out.parent / f"{out.stem}-recordings"
    return {d: base / (d.name if names.count(d.name) == 1 else f"{d.name}-{i}")
            for i, d in enumerate(run_dirs)}


def default_name(run_dir: Path) -> str:
    """The report's file name by default, in the current directory: ``<run>-report.html``."""
    return f"{Path(run_dir).resolve().name}-report.html"


def _check_outside(out: Path, run_dirs: Sequence[Path], option: str) -> None:
    """``UsageError`` when ``out`` (and so what is written beside it) lies inside a run."""
    for d in run_dirs:
        if d.resolve() in (out.resolve().parent, *out.resolve().parent.parents):
            text = f"{out}: inside the run {d}, which the report only reads; write it elsewhere"
            raise UsageError(f"{text} ({option}=...)", cli=f"{text} (--{option.split('_')[0]})")


def build(run_dirs: Sequence, out=None, findings_out=None) -> Path:
    """Write the report of ``run_dirs`` to ``out`` (default ``<first run's name>-report.html``
    in the current directory) and return its path. The runs are only read, and ``out`` may not
    lie inside one of them (nothing is ever written into a run the report reads): the trials
    that Figs. 6 and 8 draw and that have no recording are recorded again in ``recordings_dir``
    beside ``out``. An unfinished run is judged on its post-evaluated snapshots
    (``unfinished``), where it stands said at the top. Runs without a post-evaluation get
    provenance and training only, their claims "not run".
    ``findings_out``: also write the findings the report shows, every claim at every budget
    (``budgets.findings_by_budget``'s frame), to this parquet file, a new one."""
    run_dirs = [Path(d) for d in run_dirs]
    if not run_dirs:
        raise ValueError("the report needs at least one run directory")
    for d in run_dirs:
        RunDirectory.open(d).verify()  # one clear error for a path not a run, or damaged
    out = Path(out) if out is not None else Path(default_name(run_dirs[0]))
    _check_outside(out, run_dirs, "out")
    if findings_out is not None:
        _check_outside(Path(findings_out), run_dirs, "findings_out")
    if out.suffix.lower() not in (".html", ".htm"):
        raise ValueError(f"{out}: the report is an HTML file; give a name ending in .html")
    if not out.parent.is_dir():
        raise UsageError(f"{out.parent}: no such directory (out={str(out)!r}); create it first",
                         cli=f"{out.parent}: no such directory (--out {out}); create it first")
    if out.exists() and GENERATOR not in out.read_text(errors="replace")[:2000]:
        raise UsageError(f"{out} exists and is not a dart_reach report; choose another out",
                         cli=f"{out} exists and is not a dart_reach report; choose another "
                             f"--out")
    if findings_out is not None:
        findings_out = Path(findings_out)
        _check_findings_out(findings_out)
    evaluated = [d for d in run_dirs if unfinished.judged(d)]  # unfinished: its snapshots
    everything = budgets.pooled(evaluated)
    table = everything.table
    groups = budgets.budget_groups(run_dirs)
    named = budgets.labels(list(groups))  # the model named only where several
    blocks = [(budget, dirs, everything if len(groups) == 1 else budgets.pooled(dirs))
              for budget, dirs in groups.items()]
    blocks = [(budget, dirs, pooled_, pooled_.findings()) for budget, dirs, pooled_ in blocks]
    by_budget = pl.concat([budgets.label_findings(found, budget, dirs)
                           for budget, dirs, _, found in blocks])

    missing = [d for d in run_dirs if d not in evaluated]
    notice = ("" if not missing else "<p class='missing'>not post-evaluated yet: "
              + ", ".join(html.escape(str(d)) for d in missing) + ". The findings and figures "
              "need the post-evaluation: run <code>dart-reach evaluate RUN --sensors all "
              "--baseline 20</code> first.</p>")
    sections = [unfinished.standing_html(run_dirs)  # where an unfinished run stands, first
                + _section("The answers", answers.answers_html(by_budget, run_dirs), "answers"),
                _section("Summary", notice + summary_html(by_budget), "summary"),
                _section("Findings of section IV", _findings_body(blocks, by_budget)
                         + "<p>Verdicts are computed from the data when this report is built "
                           "(<code>dart_reach.findings</code>, <code>dart_reach.verdicts</code>; "
                           "the rules and their reasons are in docs/model/claims.md, "
                           "\"Verdicts\").</p>", "findings")]

    prov, train = [], []
    for d in run_dirs:
        prov.append(f"<h3>{html.escape(d.name)}</h3>" + table_html(provenance(d), "provenance"))
        stats_path = d / "generations.parquet"
        if stats_path.is_file():
            stats = pl.read_parquet(stats_path)
            phases = run_phases(d)
            train.append(f"<h3>{html.escape(d.name)}</h3>"
                         + _try(figures.training_curves, stats, phases)
                         + f"<p>{html.escape(TRAINING_NOTE)}</p>"
                         + table_html(training_summary(stats, phases)))
        else:
            train.append(f"<h3>{html.escape(d.name)}</h3><p class='missing'>no generation "
                         "trained yet</p>")
    sections.append(_section("Provenance", "".join(prov), "provenance"))
    sections.append(_section("Training", "".join(train), "training"))

    if table is None:
        sections.append(_section("Post-evaluation", "<p class='missing'>no run is "
                                 "post-evaluated yet: run <code>dart-reach evaluate RUN "
                                 "--sensors all --baseline 20</code></p>", "evaluation"))
    else:
        sections.append(_section("Measures beside the random baseline",
                                 "".join(_baseline_html(named[b], p, len(blocks) > 1)
                                         for b, _, p, _ in blocks if p.table is not None)
                                 + "<p>Means over robots (a robot: its mean over its trials, "
                                   "normal senses); <i>random</i>: random genomes of the phase "
                                   "under the same senses.</p>", "baseline"))
        caches = recordings_dir(out, run_dirs)
        sections.append(_section("Figures 5-9 (standard condition)",
                                 "".join(_run_figures(d, caches[d]) for d in evaluated),
                                 "figures"))
        sections.append(_section("Figure 10 (conditions)", "".join(  # per budget, never pooled
            (f"<h3>{html.escape(named[b])}</h3>" if len(blocks) > 1 else "") + _fig10(p.table)
            for b, _, p, _ in blocks if p.table is not None), "fig10"))
        sections.append(_section("Statistics", "".join(_run_statistics(d) for d in evaluated),
                                 "statistics"))
    page = Template(resources.files(__package__).joinpath("templates/report.html")
                    .read_text(encoding="utf-8"))
    text = page.substitute(
        generator=GENERATOR,
        title=html.escape("dart_reach report: " + ", ".join(d.name for d in run_dirs)),
        generated=time.strftime("%Y-%m-%d %H:%M:%S %z"), body="\n".join(sections))
    if findings_out is not None:  # first: a failure leaves the previous report as it was
        _check_findings_out(findings_out)  # still new, minutes later
        atomic_write(findings_out, lambda p: by_budget.write_parquet(p))
    atomic_write(out, lambda p: p.write_text(text, encoding="utf-8"))
    return out


#: The name the package exports (``dart_reach.build_report``).
build_report = build


def _check_findings_out(path: Path) -> None:
    """``build``'s ``findings_out``: a new parquet file in an existing directory."""
    if path.suffix.lower() != ".parquet":
        raise UsageError(f"findings_out={str(path)!r}: the findings are a parquet file; give a "
                         f"name ending in .parquet", cli=f"--findings {path}: the findings are "
                                                        f"a parquet file; give a name ending "
                                                        f"in .parquet")
    if path.exists():
        raise UsageError(f"findings_out={str(path)!r} exists; choose another file",
                         cli=f"--findings {path} exists; choose another file")
    if not path.parent.is_dir():
        raise UsageError(f"findings_out={str(path)!r}: no such directory {path.parent}",
                         cli=f"--findings {path}: no such directory {path.parent}")


def _run_figures(run_dir: Path, cache: Path) -> str:
    if not results.exists(run_dir / results.EVALUATION):  # unfinished: its snapshots' course
        return f"<h3>{html.escape(run_dir.name)}</h3>" + "".join(_development_figures(run_dir))
    table, phases = condition_trials(run_dir)
    parts = [f"<h3>{html.escape(run_dir.name)}</h3>",
             "<h4>Fig. 5: performance</h4>", _try(figures.fig5_performance, table, phases),
             "<h4>Fig. 6: distances and movement variability</h4>",
             _try(figures.fig6_distances_variability, table, run_dir, phases, cache=cache),
             "<h4>Fig. 7: success per sector</h4>",
             _try(figures.fig7_sector_maps, table, phases,
                  sectors=sector_config(run_dir)),
             "<h4>Fig. 8: hand trajectories and babbling</h4>",
             _try(figures.fig8_trajectories, table, run_dir, phases, cache=cache),
             _try(figures.fig8_babbling, table, phases),
             "<h4>Fig. 9: sensory deprivation</h4>",
             _try(figures.fig9_sensory_deprivation, table, phases),
             "<h4>Table I: the behaviours of each phase</h4>",
             _try(figures.table1_behaviours, table, phases)]
    return "".join(parts + _development_figures(run_dir))


def _development_figures(run_dir: Path) -> list[str]:
    """The measures' course over generations (``snapshots``): from the snapshots'
    post-evaluation if the run has one, else from its best-of-generation recordings."""
    try:
        table = development.load_development(run_dir)
        source = "post-evaluation of the snapshots (evaluate --development)"
        if table is None:
            table = development.recorded_development(run_dir)
            source = "best-of-generation recordings (one trial each, inner-face touches)"
        if table.height == 0:
            return []
        course = development.course(table)
    except (ValueError, OSError) as exc:
        return [f"<p class='missing'>development not drawn: {html.escape(str(exc))}</p>"]
    return [f"<h4>Development over generations: {html.escape(source)}</h4>",
            *[_try(figures.development_figure, course, m, label)
              for m, label in development.MEASURES]]


def _fig10(table: pl.DataFrame) -> str:
    try:
        reps = summaries.replication_performance(table, by=("group",))
    except ValueError as exc:
        return f"<p class='missing'>not drawn: {html.escape(str(exc))}</p>"
    st = fig10_statistics(reps)
    return (_try(figures.fig10_conditions, reps) + "<h4>Per condition (replications)</h4>"
            + table_html(st["summary"]) + "<h4>Mann-Whitney, two-tailed</h4>"
            + f"<p>{html.escape(HOLM_NOTE)}</p>" + table_html(st["pairs"]))


def _run_statistics(run_dir: Path) -> str:
    if not results.exists(run_dir / results.EVALUATION):  # unfinished: see unfinished.standing
        return ""
    table, phases = condition_trials(run_dir)
    measures = [m for m, _, _ in figures.FIG5_MEASURES + figures.FIG6_MEASURES]
    parts = [f"<h3>{html.escape(run_dir.name)}</h3>",
             "<h4>Figs. 5-6: phases compared (Mann-Whitney, two-tailed, robots)</h4>",
             table_html(phase_statistics(table, measures, phases))]
    f9 = fig9_statistics(table, phases)
    parts += ["<h4>Fig. 9: Kruskal-Wallis across senses within each phase</h4>",
              table_html(f9["kruskal"]),
              "<h4>Fig. 9: Mann-Whitney between phase / senses groups</h4>",
              f"<p>{html.escape(HOLM_NOTE)}</p>", table_html(f9["pairs"])]
    return "".join(parts)
