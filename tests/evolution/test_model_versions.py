"""Model versions and levers in runs: written in every manifest, read back, kept on resume,
refused when bad (docs/model/levers.md); the screen of a run's robots under other levers."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import polars as pl
import pytest

from dart_reach.evolution.rundir import RunDirectory
from dart_reach.evolution.settings import Settings
from dart_reach.model.levers import Levers, NetworkStart, ReflexInputs, TouchPay
from dart_reach.model.versions import (CURRENT_MODEL_VERSION, MODEL_VERSIONS, model_version,
                                       versions_table)
from dart_reach.model.world import WorldConfig
from dart_reach.studies.lever_screen import Arm, screen

ROOT = Path(__file__).resolve().parents[2]
CONDITION = """\
name = "pre-only"
notation = "pre"
description = "pre-reaching alone, for the model version tests"
generations_per_phase = 2

[[phases]]
name = "pre"
acuity = 3.0
offset_sensors = false
free_groups = ["direct"]
reflexes = true
"""


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=600)


def _train(condition, out, *extra, via=_cli):
    return via("train", condition, "--replications", "3", "--trials", "1", "--steps", "20",
               "--seed", "4", "--workers", "1", "--record-every", "0", "--snapshot-every",
               "1", "--out", out, *extra)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A tiny pre-only run under two levers (3 replications: not a divisor of 20, which a
    condition of one phase allows)."""
    folder = tmp_path_factory.mktemp("versions")
    condition = folder / "pre.toml"
    condition.write_text(CONDITION)
    out = folder / "run"
    result = _train(condition, out, "--touch-pay", "binary", "--self-collision", "on")
    assert result.returncode == 0, result.stderr
    return condition, out


def test_a_run_writes_its_version_and_levers_and_reads_them_back(run):
    _, out = run
    manifest = json.loads((out / "manifest.json").read_text())
    settings = manifest["settings"]
    assert settings["model_version"] == CURRENT_MODEL_VERSION  # the version new runs use
    # the manifest names the version's whole record, and this run as a named variant of it
    record = manifest["model"]
    assert record["version"] == CURRENT_MODEL_VERSION
    assert record["scene"] == model_version(CURRENT_MODEL_VERSION).scene
    assert record["variant"]["changes"] == {"touch_pay": "binary", "self_collision": "on"}
    assert record["variant"]["name"] == (f"v{CURRENT_MODEL_VERSION}+self_collision=on"
                                         f"+touch_pay=binary")
    assert settings["levers"] == {"reflex_inputs": "hand-set", "touch_pay": "binary",
                                  "network_start": "hold-home"}
    assert settings["world"]["self_collision"] is True
    opened = RunDirectory.open(out).settings
    assert opened.levers == Levers(touch_pay=TouchPay.BINARY)
    assert opened.world.self_collision and opened.model_version == CURRENT_MODEL_VERSION


def test_a_manifest_from_before_versions_is_version_1_with_its_levers():
    manifest = json.loads((ROOT / "recordings/standard-500x10/manifest.json").read_text())
    assert "model_version" not in manifest["settings"]  # written before versions existed
    settings = Settings.from_json(manifest["settings"])
    assert settings.model_version == 1 and settings.levers == Levers()
    assert settings.world.self_collision is False


def test_resume_keeps_the_levers_and_refuses_others_without_touching_the_run(run, in_process):
    condition, out = run
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file() and p.name != ".lock"}
    result = _train(condition, out, "--touch-pay", "capped", "--self-collision", "on",
                    "--resume")
    assert result.returncode == 2 and "touch_pay given here differs" in result.stderr, \
        result.stderr
    assert result.stderr.count("\n") == 1
    # the others in this process: the same code, without a new process's imports
    other = _train(condition, out, "--scene", "near", "--seed", "5", "--resume", via=in_process)
    assert other.returncode == 2 and "scene, seed given here differ" in other.stderr, \
        other.stderr
    after = {p: p.read_bytes() for p in out.rglob("*") if p.is_file() and p.name != ".lock"}
    assert after == before
    again = _train(condition, out, "--touch-pay", "binary", "--self-collision", "on",
                   "--resume", via=in_process)
    assert again.returncode == 0, again.stderr  # the same levers: it resumes (here: done)
    # nothing typed twice: without the levers, the resume takes them from the manifest
    plain = in_process("train", condition, "--out", out, "--workers", "1", "--resume")
    assert plain.returncode == 0, plain.stderr


def test_a_version_is_a_whole_model_and_settings_take_it_whole():
    for number, version in MODEL_VERSIONS.items():
        settings = Settings(model_version=number)
        assert settings.world == version.world() and settings.levers == version.levers
        assert settings.variant == {} and settings.model_record()["variant"] is None
        assert settings.world.sectors == version.sectors()
    v1 = Settings(model_version=1)
    near = Settings(model_version=1, world=WorldConfig(self_collision=True),
                    levers=Levers(reflex_inputs=ReflexInputs.EVOLVED))
    assert v1.world.sectors == WorldConfig().sectors  # version 1: arm-length-shoulder
    assert near.variant == {"reflex_inputs": "evolved", "self_collision": "on"}
    assert near.model_record()["variant"]["name"] == "v1+reflex_inputs=evolved+self_collision=on"
    assert Settings().model_version == CURRENT_MODEL_VERSION


def test_the_docs_table_of_versions_is_the_packages():
    page = (ROOT / "docs" / "model" / "levers.md").read_text()
    assert versions_table() in page
    assert f"New runs use version {CURRENT_MODEL_VERSION}" in page


@pytest.mark.parametrize("bad, named", [
    (["--touch-pay", "area"], "--touch-pay"), (["--network-start", "1"], "--network-start"),
    (["--self-collision", "yes"], "--self-collision"), (["--model-version", "9"],
                                                          "--model-version")])
def test_bad_lever_values_are_one_line_and_exit_2(tmp_path, bad, named):
    result = _cli("train", "standard", "--out", tmp_path / "r", *bad)
    assert result.returncode == 2 and named in result.stderr, result.stderr
    assert result.stderr.count("\n") == 1 and not (tmp_path / "r").exists()


def test_an_unknown_model_version_in_a_manifest_is_refused(run, tmp_path, in_process):
    import shutil

    from dart_reach import integrity

    _, out = run
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    manifest = json.loads((copy / "manifest.json").read_text())
    manifest["settings"]["model_version"] = 7
    # written through the run's ledger, as a newer dart_reach would write it
    integrity.recorded_write(copy, copy / "manifest.json",
                             lambda p: p.write_text(json.dumps(manifest)))
    result = in_process("status", copy)
    assert result.returncode == 2 and "model version 7" in result.stderr, result.stderr


def test_the_screen_runs_a_runs_robots_under_other_levers(run):
    _, out = run
    base = RunDirectory.open(out).settings.world
    arms = [Arm("as-trained", base, Levers(touch_pay=TouchPay.BINARY)),
            Arm("zero", base, Levers(touch_pay=TouchPay.BINARY,
                                     network_start=NetworkStart.ZERO))]
    table = screen(out, 2, arms, robots=1, senses=("normal",), workers=1)
    assert table.height == 2 * 3 * 45  # arms x replications x positions
    mine = table.filter(pl.col("arm") == "as-trained")
    # a trial's fitness under the pay it ran with is its rescoring to the last bit
    np.testing.assert_array_equal(mine["fitness"], mine["fitness_binary"])
    zero = table.filter(pl.col("arm") == "zero")
    assert not np.array_equal(mine["hand_path"], zero["hand_path"])  # the start matters
    assert json.loads(zero["levers"][0]) == {"network_start": "zero", "touch_pay": "binary"}
    only = screen(out, 2, arms[:1], robots=2, senses=("normal",), workers=1, only={(1, 0)})
    assert only.select("replication", "rank").unique().rows() == [(1, 0)]
    np.testing.assert_array_equal(only["fitness"], mine.filter(pl.col("replication") == 1)
                                  ["fitness"])
    again = screen(out, 2, arms[:1], robots=1, senses=("normal",), workers=2)
    assert again.equals(mine)  # same result whatever the workers
    with pytest.raises(ValueError, match="no snapshot of pre at generation 9"):
        screen(out, 9, arms)


def test_the_screen_command_refuses_bad_input_before_screening(run, tmp_path, in_process):
    _, out = run
    result = in_process("screen", out, "--generation", "2", "--arm", "a b", "--out",
                        tmp_path / "s.parquet")
    assert result.returncode == 2 and "--arm" in result.stderr, result.stderr
    assert not (tmp_path / "s.parquet").exists()
    other = tmp_path / "other.parquet"
    pl.DataFrame({"x": [1]}).write_parquet(other)
    saved = other.read_bytes()
    for table, says in ((tmp_path / "s.txt", "a screen table is a .parquet file"),
                        (tmp_path, "a screen table is a .parquet file"),
                        (tmp_path / "no" / "s.parquet", "no such directory"),
                        (out / "s.parquet", "inside the run"),
                        (other, "not a screen table")):
        result = in_process("screen", out, "--generation", "2", "--arm", "a", "--out", table)
        assert result.returncode == 2 and result.stderr.count("\n") == 1, result.stderr
        assert says in result.stderr, result.stderr
    assert other.read_bytes() == saved and not (out / "s.parquet").exists()
