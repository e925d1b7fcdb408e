"""``dart-reach watch`` and the shipped robots (``dart_reach.robots``): a real trial of the best
shipped robot (or of a trained run's), recorded with its layout, in seconds; robots files
exported from a run load back; unavailable phases are one clear line."""

from __future__ import annotations

import dataclasses
import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from dart_reach import robots as data
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.rundir import RunError
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train
from dart_reach.recording.rrd import read_properties, read_rrd
from dart_reach.model.scenes import DEFAULT_SCENE, load_scene
from dart_reach.viewing.watch import _output, display_available, watch
from dart_reach.model.world import SectorConfig


def _cli(*args):
    import os

    environ = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=300, env=environ,
                          stdin=subprocess.DEVNULL)


def test_shipped_robots_keep_their_provenance():
    genomes, fitness, info = data.evolved_pre()
    shipped = data.robots("pre", run="arm-length-shoulder")
    assert len(shipped) == len(genomes) == 20
    assert np.array_equal(shipped[0].genome, genomes[0])
    assert [r.lifetime_fitness for r in shipped] == sorted(fitness.tolist(), reverse=True)
    assert info["replication"] == [r.replication for r in shipped]  # reordered with them
    assert [(r.replication, r.rank) for r in shipped if r.rank == 0] == [(1, 0), (0, 0)]
    assert sorted(r.rank for r in shipped) == sorted(list(range(10)) * 2)
    assert info["budget"]["generations"] == 60 and "learning-check" in info["command"]
    # the scene they evolved in, which watch puts the ball in: the default (docs/model/scene.md)
    assert info["budget"]["scene"] == DEFAULT_SCENE == "arm-length-shoulder"
    assert SectorConfig(**info["budget"]["sectors"]) == SectorConfig()
    assert data.robots("pre", "gross-hat") == []  # gross-hat has no phase pre
    # every shipped file: its phase, its run's budget and scene, genomes that decode
    rows = data.index()
    assert ("evolved_pre.json", "arm-length-shoulder") in [(r["file"], r["run"]) for r in rows]
    for row in rows:
        assert row["run"] and row["robots"] >= 1 and row["git_revision"]
        if row["file"] != "evolved_pre.json":  # export_run's names: RUN-CONDITION-PHASE.json
            assert row["file"] == f"{row['run']}-{row['condition']}-{row['phase']}.json"
        phases = {p.name: p for p in load_condition(row["condition"]).phases}
        assert row["phase"] in phases
        assert row["budget"]["scene"] == DEFAULT_SCENE and row["budget"]["trials"] == 18
        robots = data.robots(row["phase"], row["condition"], run=row["run"])
        assert len(robots) == row["robots"] and all(
            r.genome.dtype == np.uint8 and r.genome.size == robots[0].genome.size
            for r in robots)


def test_watch_records_the_best_shipped_robot(tmp_path):
    # by default: the most developed standard phase that ships, from its longest-trained file
    w = watch(out=tmp_path / "default.rrd", viewer=False)
    standard = [r for r in data.index() if r["condition"] == "standard"]
    order = [p.name for p in load_condition("standard").phases]
    top = max(order.index(r["phase"]) for r in standard)
    longest = max((r for r in standard if order.index(r["phase"]) == top),
                  key=lambda r: (r["budget"]["generations"], r["budget"]["replications"],
                                 r["file"]))
    assert f"standard/{order[top]} replication" in w.robot and longest["file"] in w.robot
    assert read_properties(w.recording)["phase"] == order[top]
    w = watch("pre", shipped="arm-length-shoulder", out=tmp_path / "w.rrd", viewer=False)
    assert w.viewer_pid is None and w.layout.is_file() and w.layout.suffix == ".rbl"
    assert "standard/pre replication 1 rank 0" in w.robot and "evolved_pre.json" in w.robot
    trial = read_properties(w.recording)
    assert trial["phase"] == "pre" and trial["sector"] == 4 and trial["trial"] == 20
    assert read_rrd(w.recording).height == 200  # 20 s of 0.1 s steps
    # the robot is the shipped one: it reaches the centre of sector 4, as in the learning check
    assert w.measures["reached"]
    other = watch("pre", shipped="arm-length-shoulder", out=tmp_path / "nothing.rrd",
                  senses="nothing", sector=0, rank=5, viewer=False)
    assert read_properties(other.recording)["senses"] == "nothing"
    assert "rank 5" in other.robot
    # nothing is overwritten: neither the recording nor a file beside it
    saved = w.recording.read_bytes()
    (tmp_path / "only.rbl").write_text("a layout")
    for taken, existing in (("w.rrd", w.recording), ("only.rrd", tmp_path / "only.rbl")):
        with pytest.raises(FileExistsError, match=f"{existing.name} exists"):
            watch("pre", shipped="arm-length-shoulder", out=tmp_path / taken, viewer=False)
    assert w.recording.read_bytes() == saved
    assert (tmp_path / "only.rbl").read_text() == "a layout"
    assert not (tmp_path / "only.rrd").exists()


def test_the_default_recording_takes_the_first_free_name(tmp_path):
    default = tmp_path / "standard-pre-sector4.rrd"
    assert _output(None, default) == default
    default.with_suffix(".gif").write_text("a picture")
    assert _output(None, default) == tmp_path / "standard-pre-sector4-2.rrd"
    (tmp_path / "standard-pre-sector4-2.rrd").write_text("a recording")
    assert _output(None, default) == tmp_path / "standard-pre-sector4-3.rrd"
    with pytest.raises(ValueError, match="must end in .rrd"):
        _output(tmp_path / "x.mp4", default)


def test_watch_a_trained_run_and_export_its_robots(tmp_path):
    run = train([scaled(load_condition("standard"), 1)],
                Settings(replications=2, trials=1, steps=4, seed=5,
                         world=load_scene("arm-length-shoulder").world()), tmp_path / "run",
                workers=1, progress=False)
    w = watch(run=run.out, out=tmp_path / "t.rrd", viewer=False)
    assert "standard/fine" in w.robot and str(run.out) in w.robot  # the last phase trained
    w = watch("gross", run=run.out, replication=1, out=tmp_path / "g.rrd", viewer=False)
    assert "standard/gross replication 1 rank 0" in w.robot
    (tmp_path / "robots").mkdir()
    path = data.export_robots(run.out, "gross", tmp_path / "robots" / "gross.json")
    info = json.loads(path.read_text())
    assert info["budget"]["replications"] == 2 and info["replication"] == [0, 0, 1, 1]
    assert info["budget"]["scene"] == "arm-length-shoulder"
    shipped = data.robots("gross", directory=tmp_path / "robots")
    genomes, fitness = run.load_final(run.conditions[0].phases[1])
    assert np.array_equal(shipped[0].genome, genomes[int(np.argmax(fitness[:, 0])), 0])
    with pytest.raises(FileExistsError):
        data.export_robots(run.out, "gross", path)
    with pytest.raises(ValueError, match="replication=7"):
        watch(run=run.out, replication=7, viewer=False, out=tmp_path / "x.rrd")


def test_every_phase_of_a_run_exports_and_loads_back_by_run(tmp_path):
    """export_run: one robots file per condition and phase, loadable with one call, filtered
    by run; an existing file or an unfinished phase stops it before anything is written."""
    run = train([scaled(load_condition(c), 1) for c in ("standard", "gross-hat")],
                Settings(replications=2, trials=1, steps=4, seed=5), tmp_path / "run-a",
                workers=1, progress=False)
    out = tmp_path / "robots"
    out.mkdir()
    paths = data.export_run(run.out, out, per_replication=1)
    assert [p.name for p in paths] == ["run-a-standard-pre.json", "run-a-standard-gross.json",
                                       "run-a-standard-fine.json",
                                       "run-a-gross-hat-gross-hat.json"]
    assert {(r["condition"], r["phase"], r["run"], r["robots"]) for r in data.index(out)} == {
        ("standard", "pre", "run-a", 2), ("standard", "gross", "run-a", 2),
        ("standard", "fine", "run-a", 2), ("gross-hat", "gross-hat", "run-a", 2)}
    hat = data.robots("gross-hat", "gross-hat", directory=out, run="run-a")
    genomes, fitness = run.load_final(run.conditions[1].phases[0])
    assert [(r.replication, r.rank) for r in hat] == sorted(
        [(0, 0), (1, 0)], key=lambda rr: -fitness[rr[0], 0])
    assert np.array_equal(hat[0].genome, genomes[int(np.argmax(fitness[:, 0])), 0])
    assert hat[0].provenance["run"] == "run-a" and hat[0].provenance["budget"]["generations"] == 2
    assert data.robots("gross-hat", "gross-hat", directory=out, run="another") == []
    # nothing is written when one file exists, or when a phase has not finished
    again = tmp_path / "again"
    again.mkdir()
    (again / "run-a-standard-fine.json").write_text("{}")
    with pytest.raises(FileExistsError, match="run-a-standard-fine.json"):
        data.export_run(run.out, again)
    assert [p.name for p in again.iterdir()] == ["run-a-standard-fine.json"]
    with pytest.raises(FileNotFoundError, match="no such directory"):
        data.export_run(run.out, tmp_path / "nowhere")
    empty = tmp_path / "empty"
    empty.mkdir()
    run.final_path(run.conditions[0].phases[2]).unlink()
    with pytest.raises(RunError, match="phase fine has not finished"):
        data.export_run(run.out, empty)
    assert list(empty.iterdir()) == []


def test_watch_takes_one_shipped_runs_robots_the_longest_trained_by_default(tmp_path):
    """Two runs ship the same phase: watch never mixes their replications and ranks; it
    takes the run with more generations per phase (then more replications)."""
    from dart_reach.viewing.watch import _longest_trained

    out = tmp_path / "robots"
    out.mkdir()
    for name, generations, replications in (("short", 1, 4), ("long", 2, 2)):
        run = train([scaled(load_condition("standard"), generations)],
                    Settings(replications=replications, trials=1, steps=4, seed=5),
                    tmp_path / name, workers=1, progress=False)
        data.export_robots(run.out, "pre", out / f"{name}.json", per_replication=1)
    both = data.robots("pre", directory=out)
    assert {r.provenance["run"] for r in both} == {"short", "long"} and len(both) == 6
    chosen = _longest_trained(both)
    assert {r.provenance["run"] for r in chosen} == {"long"} and len(chosen) == 2
    same = [r for r in both if r.provenance["run"] == "short"]
    assert _longest_trained(same) == same
    # equal generations: the run with more replications
    widened = [dataclasses.replace(r, provenance={**r.provenance, "budget": {
        **r.provenance["budget"], "generations": 2}}) for r in same]
    assert _longest_trained(widened + chosen) == widened


@pytest.fixture
def here(in_process, monkeypatch):
    """``_cli``'s command in this process (the same code, without a process's imports), with no
    display either."""
    for name in ("DISPLAY", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(name, raising=False)
    return in_process


def test_cli_lists_the_shipped_robots_and_watches_one_shipped_run(tmp_path, here):
    result = _cli("robots")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert len(lines) == 1 + len(data.index())
    for row, line in zip(data.index(), lines[1:]):
        assert line.startswith(str(row["run"])) and line.endswith(row["file"])
        assert f"{row['condition']}/{row['phase']}" in line
    result = here("watch", "pre", "--shipped", "arm-length-shoulder", "--out",
                  tmp_path / "w.rrd")
    assert result.returncode == 0, result.stderr
    assert "evolved_pre.json" in result.stdout
    result = here("watch", "--shipped", "no-such-run", "--out", tmp_path / "n.rrd")
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert "--shipped no-such-run: no such shipped run" in result.stderr
    result = here("watch", "--shipped", "arm-length-shoulder", "--run", tmp_path,
                  "--out", tmp_path / "b.rrd")
    assert result.returncode == 2 and "not both" in result.stderr
    assert not (tmp_path / "n.rrd").exists() and not (tmp_path / "b.rrd").exists()


def test_the_learning_checks_robots_ship_as_the_standard_conditions(tmp_path):
    """The learning check's pre-only/pre trains the maturational state of standard/pre: its
    robots ship under standard (loadable by watch); a condition whose phase differs refuses."""
    check = Path(__file__).parents[2] / "docs" / "learning-check.toml"
    run = train([scaled(load_condition(check), 1)],
                Settings(replications=1, trials=1, steps=4, seed=5), tmp_path / "run",
                workers=1, progress=False)
    path = data.export_robots(run.out, "pre", tmp_path / "pre.json", ship_as="standard")
    assert json.loads(path.read_text())["phase"]["condition"] == "standard"
    assert [r.condition for r in data.robots("pre", directory=tmp_path)] == ["standard"] * 2
    with pytest.raises(ValueError, match="pre-star has no phase 'pre'"):
        data.export_robots(run.out, "pre", tmp_path / "x.json", ship_as="pre-star")
    other = tmp_path / "no-reflexes.toml"
    other.write_text(check.read_text()
                     .replace('name = "pre-only"', 'name = "no-reflexes"')
                     .replace("reflexes = true", "reflexes = false"))
    with pytest.raises(ValueError, match="reflexes differ"):
        data.export_robots(run.out, "pre", tmp_path / "x.json", ship_as=str(other))
    assert not (tmp_path / "x.json").exists()


def test_cli_watch_without_a_display_writes_and_says_how_to_open(tmp_path, here):
    result = _cli("watch", "pre", "--out", tmp_path / "w.rrd")
    assert result.returncode == 0, result.stderr
    assert "shipped robot standard/pre" in result.stdout
    line = result.stdout.splitlines()[-1]
    command = shlex.split(line)
    assert command[-2:] == [str(tmp_path / "w.rrd"), str(tmp_path / "w.rbl")]
    # and the trial drawn beside them by the numpy camera, where the output says
    for picture in (tmp_path / "w.png", tmp_path / "w.gif"):
        assert picture.stat().st_size > 1000 and str(picture) in result.stdout
    # the command runs without the virtual environment on the PATH (here: asked its version)
    bare = {"PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}
    version = subprocess.run([*command[:-2], "--version"], capture_output=True, text=True,
                             env=bare, cwd=tmp_path, timeout=60)
    assert version.returncode == 0 and "rerun" in version.stdout, version.stderr
    result = here("watch", "gross", "--condition", "pre-star", "--out", tmp_path / "f.rrd")
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert "gross: pre-star has no phase 'gross' (its phases: pre-star)" in result.stderr
    result = here("watch", "medium", "--out", tmp_path / "f.rrd")
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert "standard has no phase 'medium' (its phases: pre, gross, fine)" in result.stderr
    assert not (tmp_path / "f.rrd").exists()


def test_a_robot_that_does_not_ship_advises_a_small_training(tmp_path, here):
    result = _cli("watch", "--condition", "fine-hat", "--shipped", "replication-50",
                  "--out", tmp_path / "f.rrd")
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert "no shipped robot of fine-hat in shipped run 'replication-50'" in result.stderr
    advice = re.search(r"(dart-reach train [^,]+), then watch it: (dart-reach watch .+)$",
                       result.stderr.strip())
    assert advice and "--run recordings/fine-hat-small" in advice[2], result.stderr
    train = shlex.split(advice[1])
    assert train[-2:] == ["--out", "recordings/fine-hat-small"]
    # the advised run is small: train announces no cost (under a core-hour) and asks nothing;
    # here it stops at once on a directory that holds something else
    busy = tmp_path / "busy"
    busy.mkdir()
    (busy / "x").write_text("x")
    small = here(*train[1:-2], "--workers", "1", "--out", busy)
    assert small.returncode == 2 and "not empty" in small.stderr, small.stderr
    assert "core-hours" not in small.stderr
    assert not (tmp_path / "f.rrd").exists()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="X11 and Wayland variables")
def test_display_detection():
    assert not display_available({})
    assert display_available({"DISPLAY": ":0"})
    assert display_available({"WAYLAND_DISPLAY": "wayland-0"})
