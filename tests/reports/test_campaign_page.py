"""The campaign's page (reports.campaign) is its rendering from the committed tables, and its
rules are the pre-registered ones (docs/results/campaign.md): the calibration's grid and the
rule that picks version 3's scene."""

from __future__ import annotations

import shutil
import subprocess

import polars as pl
import pytest

from dart_reach import integrity
from dart_reach.analysis import budgets, findings
from dart_reach.analysis.claims import CLAIMS
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train
from dart_reach.files import write_parquet
from dart_reach.model.scenes import load_scene
from dart_reach.postevaluation import results
from dart_reach.postevaluation.snapshots import load_development
from reports import babbling_before_touch, campaign
from reports import results as results_docs


def test_the_committed_page_is_its_rendering():
    assert campaign.PAGE.read_text() == campaign.page(), "run 'python -m reports.campaign'"


def test_the_pre_registration_is_kept_above_the_results():
    text = campaign.PAGE.read_text()
    plan = text[: text.index(campaign.MARK)]
    for fixed in ("0.35 <= mean <= 0.65", ">= 0.31 m", "< 0.05", "at least half of the best",
                  "{0.42, 0.44, 0.46, 0.48, 0.50}", "{1, 1.25, 1.5, 2}", "within 0.02",
                  "(r - 0.42) / 0.08 + (w - 1)", "seed 2031", "generation 100"):
        assert fixed in plan, fixed


def test_the_grid_is_the_pre_registered_one_and_stays_on_the_sphere():
    scenes = campaign.grid()
    assert len(scenes) == 20
    base = load_scene(campaign.BASE_SCENE).sectors
    r, w, first = scenes[0]
    assert (r, w) == (0.42, 1.0) and first == base  # beyond-arm-length itself
    widest = [s for r, w, s in scenes if (r, w) == (0.5, 2.0)][0]
    assert widest.azimuth_edges == (-22.5, 7.5, 37.5, 67.5)
    assert widest.elevation_edges == pytest.approx((-58.4, -28.4, 1.6, 31.6))
    for _, w, s in scenes:  # 3 x 3 equal sectors, widened about the patch's centre
        az, el = s.azimuth_edges, s.elevation_edges
        assert az[1] - az[0] == pytest.approx(15 * w) == pytest.approx(az[3] - az[2])
        assert (az[0] + az[3]) / 2 == pytest.approx(22.5)
        assert (el[0] + el[3]) / 2 == pytest.approx(-13.4)


def _scenes(reach: dict) -> pl.DataFrame:
    rows = [{"arm": campaign.arm_name(r, w), "population": "p", "replication": 0, "rank": 0,
             "trial": t, "reached": t < round(reach[(r, w)] * 100)}
            for r in campaign.RADII for w in campaign.WIDENINGS for t in range(100)]
    return campaign.scene_reach(pl.DataFrame(rows))


def test_the_rule_picks_the_closest_to_one_half_and_breaks_ties_by_the_smallest_change():
    reach = {(r, w): 0.9 for r in campaign.RADII for w in campaign.WIDENINGS}
    reach[(0.48, 1.0)] = 0.57  # closest alone
    reach[(0.50, 2.0)] = 0.60
    pick = campaign.choose_scene(_scenes(reach))
    assert (pick["radius"], pick["widening"]) == (0.48, 1.0)
    # 0.05 from one half, so 0.57 (0.07) is tied with it; both change 0.75 from the base
    # (0.5 + 0.25 and 0.75 + 0): the smaller widening wins
    reach[(0.46, 1.25)] = 0.45
    pick = campaign.choose_scene(_scenes(reach))
    assert (pick["radius"], pick["widening"]) == (0.48, 1.0)
    reach[(0.44, 1.0)] = 0.44  # 0.06 from one half, tied, change 0.25: the smallest
    pick = campaign.choose_scene(_scenes(reach))
    assert (pick["radius"], pick["widening"]) == (0.44, 1.0)
    reach[(0.50, 1.5)] = 0.50  # exactly one half: no other within 0.02 of it
    pick = campaign.choose_scene(_scenes(reach))
    assert (pick["radius"], pick["widening"]) == (0.50, 1.5)


def test_version_3_runs_on_the_scene_the_committed_screen_chose():
    from dart_reach.model.versions import model_version

    pick = campaign.choose_scene(campaign.scene_reach(pl.read_parquet(campaign.SCREEN)))
    chosen = [s for r, w, s in campaign.grid() if (r, w) == (pick["radius"], pick["widening"])]
    assert model_version(3).scene == "calibrated-reach"
    assert load_scene("calibrated-reach").sectors == chosen[0] == model_version(3).sectors()


def test_a_snapshot_between_judgements_is_described_from_its_trials_not_judged():
    table = load_development(campaign.CAMPAIGN, senses=None)
    g50 = table.filter((pl.col("phase") == "pre") & (pl.col("generation") == 50))
    lines = campaign.described_snapshots(g50.with_columns(pl.lit(60).alias("generation")),
                                         [60])
    assert "described, not judged" in lines[0]
    row = [c.strip() for c in lines[-2].strip("|").split("|")]
    normal = g50.filter((pl.col("senses") == "normal") & ~pl.col("baseline"))
    assert row[0] == "60" and row[1] == str(normal["replication"].n_unique())
    assert float(row[2]) == pytest.approx(normal["reached"].cast(pl.Float64).mean(), abs=0.005)
    assert campaign.described_snapshots(table, []) == []


def test_the_cost_is_split_by_processor_and_the_rest_projected_at_the_latest_ones_pace():
    cpu = {"model": "EPYC", "vector": "AVX2"}, {"model": "EPYC", "vector": "AVX-512"}
    sessions = [{"cpu": cpu[0]}, {"cpu": cpu[0]}, {"cpu": cpu[1]}, {}]
    per = pl.DataFrame({"generation": [1, 2, 3, 4, 5, 6], "session": [0, 1, 1, 2, 2, 3],
                        "core_s": [100.0, 120.0, 140.0, 40.0, 50.0, float("nan")]})
    line = campaign.processors_line(per, sessions, 3600)
    assert "EPYC (AVX2): 3 generations, median 120.0" in line
    assert "EPYC (AVX-512): 2 generations, median 45.0" in line
    assert "not recorded" not in line  # its only generation's cost is unknown
    assert line.endswith("3,600 replication-generations left at the latest one's median: "
                         "45 core-hours, 22 h on 2 cores.")
    later = per.with_columns(pl.Series("core_s", [100.0, 120.0, 140.0, 40.0, 50.0, 60.0]))
    assert "a processor not recorded (?): 1 generation, median 60.0" in \
        campaign.processors_line(later, sessions, 3600)
    assert "60 core-hours" in campaign.processors_line(later, sessions, 3600)


@pytest.fixture(scope="module")
def pre_finished(tmp_path_factory, in_process):
    """A tiny standard run on version 3 (3 generations a phase, a snapshot after each) stopped
    once gross-reaching's first generation is done: pre-reaching finished and post-evaluated
    as ``make campaign-phases`` does (finished phases, every sense, random genomes), and
    every snapshot saved, gross's first among them, as ``make campaign-snapshots`` does."""
    out = tmp_path_factory.mktemp("campaign-phases") / "run"

    def stop_in_gross(progress):
        if progress.phase == "gross":
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        train([scaled(load_condition("standard"), 3)],
              Settings(replications=2, trials=1, steps=4, seed=5, model_version=3), out,
              workers=1, progress=stop_in_gross, snapshot_every=1)
    assert campaign.phase_claims(out) is None  # no phase post-evaluated yet
    for args in (("--sensors", "all", "--robots", "1", "--baseline", "1", "--record", "none"),
                 ("--development", "1", "--development-sensors", "normal,no-ball")):
        done = in_process("evaluate", out, "--finished-only", "--workers", "1", *args)
        assert done.returncode == 0, done.stderr
    before = babbling_before_touch.compute(out)  # claim A1, as make campaign-phases measures it
    integrity.write(out / babbling_before_touch.TABLE, lambda p: write_parquet(before, p))
    return out


def test_the_phase_claims_are_judged_on_the_finished_phases_alone(pre_finished):
    """At the end of pre-reaching the page judges the claims of pre-reaching and the random
    genomes alone, as the report judges them; gross-reaching's first snapshot, which the
    report of an unfinished run would read as its whole course, is left out."""
    found = campaign.phase_claims(pre_finished)
    claims = {c.id: c for c in CLAIMS}
    judged = found.filter(pl.col("verdict") != "not run")["claim"].to_list()
    for claim in ("F1 reach about half", "V3 babbling appears in pre",
                  "A1 ball absent, pre: babbling same"):
        assert claim in judged
    for claim in judged:
        groups = {g.split("@")[0].removeprefix("random ") for g in
                  (claims[claim].a, claims[claim].b)}
        assert groups <= {"pre", ""}, claim
    as_the_report = budgets.findings_by_budget([pre_finished])
    assert as_the_report.filter(pl.col("claim") == "V4 babbling fades in gross")[
        "verdict"][0] != "not run"  # the report reads gross's one snapshot as its course
    assert "V4 babbling fades in gross" not in judged
    same = ~pl.col("claim").str.starts_with("V")
    columns = ["claim", "verdict", "effect", "verdict_robots"]
    assert found.filter(same).select(columns).equals(as_the_report.filter(same).select(columns))
    section = campaign.phase_claims_section(found)
    paper = found.filter(~pl.col("own") & ~pl.col("infants"))
    shown = [line for line in section.splitlines() if line.startswith("| ")][1:]
    assert [line.split(" | ")[0].removeprefix("| ") for line in shown] == \
        paper.filter(pl.col("verdict") != "not run")["claim"].to_list()
    assert f"The paper's {paper.height} claims" in section
    assert "No phase has finished" in campaign.phase_claims_section(None)


def test_the_summary_counts_the_claims_of_the_phases_finished_and_post_evaluated(
        pre_finished, tmp_path):
    """The summary's sentence on the campaign (``reports.results.campaign_values``) counts the
    claims the page judges; a phase that has finished but is not post-evaluated yet (a final of
    gross-reaching here, before ``make campaign-phases``) changes neither, and without a
    post-evaluation no claim is judged."""
    recordings = tmp_path / "recordings"
    run_dir = recordings / campaign.CAMPAIGN.relative_to(campaign.ROOT / "recordings")
    shutil.copytree(pre_finished, run_dir)
    values = results_docs.campaign_values(recordings)
    c = findings.summary(campaign.phase_claims(run_dir))
    assert (f"phases (pre-reaching) can judge: reproduced {c['reproduced']}, contradicted "
            f"{c['contradicted']}, inconclusive {c['inconclusive']}") in values["claims"]
    assert values["pre_reacher"] == ("none of its judged pre-reaching generations (50, 100, "
                                     "250, 500) is post-evaluated yet")
    run = RunDirectory.open(run_dir)
    pre, gross = (p for _, p in run.unique_phases()[:2])
    shutil.copy(run.final_path(pre), run.final_path(gross))
    assert [p.name for p in campaign.judged_phases(run_dir)] == ["pre"]
    columns = ["claim", "verdict", "effect", "verdict_robots"]
    assert campaign.phase_claims(run_dir).select(columns).equals(
        campaign.phase_claims(pre_finished).select(columns))
    assert results_docs.campaign_values(recordings) == values
    for stored in results.stored_files(run_dir / results.EVALUATION):
        stored.unlink()
    assert campaign.judged_phases(run_dir) == []
    assert results_docs.campaign_values(recordings)["claims"].startswith("No phase has")


def test_a_later_phases_snapshots_are_described_too(pre_finished):
    """Gross-reaching's snapshots (its generation 1 here) are described in the same measures,
    under their phase's name, from their own trials."""
    table = load_development(pre_finished, senses=None)
    lines = campaign.described_snapshots(table, [1], "gross")
    assert lines[0].startswith("Snapshots of gross-reaching") and "judged" not in lines[0]
    assert lines[2].startswith("| gross-reaching generation |")
    row = [c.strip() for c in lines[-2].strip("|").split("|")]
    gross = table.filter((pl.col("phase") == "gross") & (pl.col("senses") == "normal"))
    assert row[0] == "1" and row[1] == str(gross["replication"].n_unique())
    assert float(row[2]) == pytest.approx(gross["reached"].cast(pl.Float64).mean(), abs=0.005)


def run_recipe(recipe: str, here, copy) -> None:
    """A recipe of the Makefile's campaign targets run for real, on the run ``here`` and its
    copy ``copy``."""
    done = subprocess.run(["make", "-s", "-C", str(campaign.ROOT), "--eval",
                           f"back: ; {recipe}", "back", f"CAMPAIGN={here}",
                           f"CAMPAIGN_COPY={copy}"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def test_a_table_comes_back_from_the_copy_in_the_form_the_copy_holds_it(tmp_path):
    """The Makefile's copy-back (``campaign_back``) run for real: a table that went into parts
    in the copy (over 4 MB) replaces the single file here, which ``read_table`` would
    otherwise read first; the copy's ledger comes with it."""
    here, copy = tmp_path / "here", tmp_path / "copy"
    (here / "development.parquet").parent.mkdir(parents=True)
    (here / "development.parquet").write_text("old")
    (here / "ledger.json").write_text("old")
    (copy / "development").mkdir(parents=True)
    for name in ("development/part-000.parquet", "development/part-001.parquet", "ledger.json"):
        (copy / name).write_text(name)
    run_recipe("$(call campaign_back,development)", here, copy)
    assert sorted(str(p.relative_to(here)) for p in here.rglob("*") if p.is_file()) == [
        "development/part-000.parquet", "development/part-001.parquet", "ledger.json"]
    assert (here / "ledger.json").read_text() == "ledger.json"


def test_a_phase_post_evaluated_beside_the_snapshots_is_kept(pre_finished, tmp_path,
                                                            in_process):
    """``make campaign-snapshots`` once a phase has finished: ``evaluate`` also post-evaluates
    that phase in the copy (here, a robot more under one sense). The tables come back with
    the copy's ledger (``CAMPAIGN_TABLES``), so that work is kept and the run here is whole;
    brought back without the evaluation table, the ledger would name a table not here."""
    here, copy = tmp_path / "here", tmp_path / "copy"
    shutil.copytree(pre_finished, here)
    shutil.copytree(here, copy)
    done = in_process("evaluate", copy, "--finished-only", "--workers", "1", "--sensors",
                      "no-touch", "--robots", "2", "--development", "1",
                      "--development-sensors", "normal", "--record", "none")
    assert done.returncode == 0, done.stderr
    evaluated = (copy / "evaluation.parquet").read_bytes()
    assert evaluated != (here / "evaluation.parquet").read_bytes()
    run_recipe("$(call campaign_back,development)", here, copy)
    with pytest.raises(integrity.DamagedFile, match="evaluation.parquet"):
        integrity.verify_run(here)
    run_recipe("$(call campaign_back,$(CAMPAIGN_TABLES))", here, copy)
    assert integrity.verify_run(here) == len(integrity.ledger(here))
    assert (here / "evaluation.parquet").read_bytes() == evaluated
