"""Where a run came from, as the report's provenance table shows it (``dart-reach report``,
section "Provenance"): the command, conditions, phases, budgets, genetic algorithm, seeds,
physics step, model version and variant, git revision, package versions, machine and
training wall time, read from the run's manifest and tables (only read).

The model is read as every reader of a run reads it: from the run's settings
(``Settings.from_json``; a manifest from before model versions is version 1's), whose
``Settings.model_record`` is the record a manifest holds under ``model`` (section III: the
model the robots evolved in).
"""

from __future__ import annotations

import json
from pathlib import Path

import polars as pl

from ..evolution.rundir import RunDirectory
from ..evolution.settings import Settings
from ..postevaluation.systematic import run_phases


def provenance(run_dir: Path) -> pl.DataFrame:
    """The provenance of the run at ``run_dir``: columns item, value (text)."""
    manifest = json.loads((run_dir / "manifest.json").read_text())
    run = RunDirectory.open(run_dir)
    s = manifest.get("settings", {})
    phases = run_phases(run_dir)
    wall = 0.0
    stats_path = run_dir / "generations.parquet"
    if stats_path.is_file():
        # wall_s is the whole generation's (all replications), repeated on each row
        wall = float(pl.read_parquet(stats_path).unique(["phase_key", "generation"],
                                                        maintain_order=True)["wall_s"].sum())
    machine = manifest.get("machine") or {}
    rows = [
        ("command", manifest.get("command") or "not recorded (made before commands were)"),
        ("conditions", ", ".join(f"{c.name} ({c.notation})" for c in run.conditions)),
        ("phases (generations)", ", ".join(
            f"{r['notation']} ({r['generations']})"
            for r in phases.unique("phase_key", maintain_order=True).iter_rows(named=True))),
        ("replications / trials / steps", f"{s.get('replications')} / {s.get('trials')} / "
                                          f"{s.get('steps')}"),
        ("genetic algorithm", json.dumps(s.get("ga"))),
        ("seeds", json.dumps(manifest.get("seeds"))),
        ("physics step (s)", str(run.settings.world.physics_dt)),
        ("model version", model_version_text(run.settings, manifest)),
        ("model variant", variant_text(run.settings)),
        ("git revision", str(manifest.get("git_revision"))),
        ("uncommitted changes", dirty(manifest)),
        ("versions", ", ".join(f"{k} {v}" for k, v in (manifest.get("versions") or {}).items())),
        ("machine", ", ".join(f"{k} {v}" for k, v in machine.items()) or "not recorded"),
        ("created", str(manifest.get("created"))),
        ("training wall time", f"{wall / 3600:.2f} h (sum of the generations' wall times)"),
    ]
    return pl.DataFrame(rows, schema=["item", "value"], orient="row")


def model_version_text(settings: Settings, manifest: dict) -> str:
    """The run's model version and what it is (numerics, scene, self-collision), and, for a
    manifest without the ``model`` record, that it was read from the settings (as version 1
    where they name no version)."""
    record = settings.model_record()
    text = (f"{record['version']} ({record['numerics']} numerics, scene {record['scene']}, "
            f"self-collision {'on' if record['self_collision'] else 'off'})")
    if "model" in manifest:
        return text
    if "model_version" not in manifest.get("settings", {}):
        return text + "; not recorded (made before model versions were): version 1"
    return text + "; the manifest holds no model record: read from its settings"


def variant_text(settings: Settings) -> str:
    """The run's variant of its version: none, or its name, what it changes and the run's
    levers (``model.levers``)."""
    variant = settings.model_record()["variant"]
    if variant is None:
        return "none (the version's own levers, scene and self-collision)"
    changes = ", ".join(f"{k} {v}" for k, v in variant["changes"].items())
    levers = ", ".join(f"{k} {v}" for k, v in settings.levers.to_json().items())
    return f"{variant['name']}: changes {changes}; levers {levers}"


def dirty(manifest: dict) -> str:
    """Whether the run's code had uncommitted changes (manifest ``git_dirty``)."""
    if "git_dirty" not in manifest:
        return "not recorded (made before the manifest recorded it)"
    if manifest["git_dirty"] is None:
        return "unknown (not run from a git working tree)"
    if not manifest["git_dirty"]:
        return "none (clean working tree)"
    return f"yes: diff SHA-256 {manifest.get('git_diff_sha256')}"
