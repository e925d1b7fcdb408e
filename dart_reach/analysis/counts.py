"""The answer in numbers, for the report's first screen: the paper's claims by verdict at each
budget (``budget_counts``) and by section of the paper (``section_counts``), the
replication as the unit, with how many decided ones survive Holm's adjustment; and the claims
that no budget ran (``never_run``).

Every function takes the frame of ``budgets.findings_by_budget`` (one row per claim and
budget) and counts the paper's claims of its robots only (``findings.reading``, the
headline): the paper's claims of infants and the project's own are counted apart, in each
budget's findings table.
"""

from __future__ import annotations

import polars as pl

from . import findings, verdicts


def section_part(column: str = "section") -> pl.Expr:
    """A claim's section of the paper: the first part of its ``section`` ("IV-A-2, Fig. 5"
    and "IV-A-2: controls" are "IV-A-2")."""
    return (pl.col(column).str.split(",").list.first().str.split(":").list.first()
            .str.strip_chars())


def budget_label(by_budget: pl.DataFrame) -> pl.Expr:
    """A budget in a few characters: "50 gen/phase", with " x 10" (replications) when the
    frame's budgets differ in replications, ", <scene>" when they differ in scene and
    ", model <model>" when in model."""
    parts = [pl.format("{} gen/phase", "generations_per_phase")]
    if by_budget["replications"].n_unique() > 1:
        parts.append(pl.format(" x {}", "replications"))
    return pl.concat_str(parts + _scene_and_model(by_budget))


def _scene_and_model(by_budget: pl.DataFrame) -> list[pl.Expr]:
    """A budget's scene and model, each where the frame's budgets differ in it."""
    return [pl.format(f", {prefix}{{}}", column) for column, prefix in
            (("scene", ""), ("model", "model ")) if by_budget[column].n_unique() > 1]


def _counted(by_budget: pl.DataFrame, by: list[str], label: pl.Expr) -> pl.DataFrame:
    head = findings.reading(by_budget).with_columns(
        section_part().alias("section"), label.alias("budget"))
    holm = (((pl.col("verdict") == verdicts.REPRODUCED) & (pl.col("p_holm") < verdicts.ALPHA))
            | ((pl.col("verdict") == verdicts.CONTRADICTED)
               & (pl.col("p_holm_against") < verdicts.ALPHA)))
    return (head.group_by(*by, maintain_order=True)
            .agg(pl.len().alias("claims"),
                 *[(pl.col("verdict") == v).sum().alias(v) for v in verdicts.VERDICTS],
                 holm.sum().alias("decided after Holm")))


def budget_counts(by_budget: pl.DataFrame) -> pl.DataFrame:
    """One row per budget (scene, then generations per phase, replications, model), named in
    full ("50 gen/phase x 10 replications", the scene and the model added when the budgets
    differ in them):
    its runs, how many of the paper's claims it tested, how many got each verdict (they sum
    to ``claims``), and how many decided ones survive Holm's adjustment within the budget."""
    ordered = by_budget.sort("scene", "generations_per_phase", "replications", "model",
                             maintain_order=True)
    label = pl.concat_str([pl.format("{} gen/phase x {} replications", "generations_per_phase",
                                     "replications"), *_scene_and_model(by_budget)])
    return _counted(ordered, ["budget", "runs"], label)


def section_counts(by_budget: pl.DataFrame) -> pl.DataFrame:
    """The paper's claims by section of the paper (``section_part``) and budget: how many
    got each verdict and how many decided ones survive Holm's adjustment."""
    return _counted(by_budget, ["section", "budget"], budget_label(by_budget))


def never_run(by_budget: pl.DataFrame, who: str = findings.ROBOTS) -> pl.DataFrame:
    """``who``'s claims (``findings.READINGS``; default the paper's of its robots), with
    ``claim``, ``section`` and ``note``, that no budget of the frame ran: not run at every
    budget (no data for them)."""
    claims = findings.reading(by_budget, who)
    return (claims.group_by("claim", maintain_order=True)
            .agg(pl.col("section").first(), pl.col("note").first(),
                 (pl.col("verdict") == verdicts.NOT_RUN).all().alias("none"))
            .filter("none").drop("none"))
