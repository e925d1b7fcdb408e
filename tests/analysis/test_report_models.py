"""Runs of different models in one report (``dart-reach report``, ``budgets``,
``run_provenance``): two tiny real runs of the standard condition at the same scene and
budget, one under model version 1 and one under version 2, are two budgets, never pooled,
their columns and headings named by their model; a run's provenance names its model version
and variant (with its levers when a variant), and a committed run from before the manifest
recorded its model is read as version 1."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest

from dart_reach.analysis import budgets, report, run_provenance
from dart_reach.analysis.claims import CLAIMS
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train
from dart_reach.model.levers import TouchPay

ROOT = Path(__file__).resolve().parents[2]
#: Versions 1 and 2 share their scene (arm-length-shoulder) and differ in their numerics.
SCENE = "arm-length-shoulder"


@pytest.fixture(scope="module")
def two_models(tmp_path_factory) -> dict[int, Path]:
    """Model version -> a tiny run of the standard condition (1 generation per phase, 2
    replications) trained under it, same seed, nothing post-evaluated."""
    base = tmp_path_factory.mktemp("models")
    runs = {}
    for version in (1, 2):
        out = base / f"v{version}"
        train([scaled(load_condition("standard"), 1)],
              Settings(replications=2, trials=1, steps=6, seed=2, model_version=version),
              out, workers=1)
        runs[version] = out
    return runs


def test_runs_of_two_models_are_two_budgets(two_models):
    v1, v2 = two_models[1], two_models[2]
    groups = budgets.budget_groups([v2, v1])
    assert groups == {budgets.Budget(SCENE, 1, 2, "v1"): [v1],
                      budgets.Budget(SCENE, 1, 2, "v2"): [v2]}
    by_budget = budgets.findings_by_budget([v1, v2])
    assert by_budget.select("model", "runs").unique(maintain_order=True).rows() == [
        ("v1", "v1"), ("v2", "v2")]
    assert by_budget.group_by("model").len().sort("model")["len"].to_list() == [len(CLAIMS)] * 2
    table = budgets.side_by_side(by_budget)
    assert {"1 gen/phase, model v1: verdict", "1 gen/phase, model v2: verdict"} <= set(
        table.columns)


def test_the_report_keeps_the_models_apart_and_names_their_versions(two_models, tmp_path):
    text = report.build([two_models[1], two_models[2]], tmp_path / "r.html").read_text()
    found = text[text.index('<section id="findings">'):text.index('<section id="provenance">')]
    assert found.count('<table class="findings">') == 2  # one per model, never pooled
    for version in (1, 2):
        assert (f"<h3>{SCENE}, 1 generation per phase, 2 replications, model v{version}: "
                f"v{version}</h3>") in found
    assert "trained under 2 models (v1, v2;" in found
    prov = text[text.index('<section id="provenance">'):text.index('<section id="training">')]
    versions = re.findall(r"<td>model version</td><td>([^<]*)</td>", prov)
    assert versions == [f"1 (reference numerics, scene {SCENE}, self-collision off)",
                        f"2 (compiled numerics, scene {SCENE}, self-collision off)"]
    assert re.findall(r"<td>model variant</td><td>([^<]*)</td>", prov) == [
        "none (the version&#x27;s own levers, scene and self-collision)"] * 2


def test_a_variant_names_its_changes_and_its_levers():
    settings = Settings(model_version=3)
    variant = replace(settings, levers=replace(settings.levers, touch_pay=TouchPay.BINARY))
    assert run_provenance.variant_text(variant) == (
        "v3+touch_pay=binary: changes touch_pay binary; levers reflex_inputs hand-set, "
        "touch_pay binary, network_start hold-home")
    assert run_provenance.variant_text(settings).startswith("none")


def test_a_run_from_before_the_model_record_is_version_1():
    """A committed run whose manifest holds no model record nor version: read as version 1
    (``Settings.from_json``), and the table says it was not recorded."""
    rows = dict(run_provenance.provenance(ROOT / "recordings" / "replication-10").rows())
    assert rows["model version"] == (f"1 (reference numerics, scene {SCENE}, self-collision "
                                     "off); not recorded (made before model versions were): "
                                     "version 1")
    assert rows["model variant"].startswith("none")
    assert budgets.budget_of(ROOT / "recordings" / "replication-10").model == "v1"
