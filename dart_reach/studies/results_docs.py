"""The results docs, generated from the committed results (``make results``).

Every number and table of a generated doc comes from the runs' committed tables under
``recordings/`` (``postevaluation.results``): its prose is a template,
``docs/results/templates/<doc>.md``, in which ``{{ name }}`` stands for a value computed here,
and the doc itself (``docs/results/<doc>.md``) is the template rendered. A test renders every
template again and fails when a committed doc differs: a doc cannot drift from its data, and a
number typed into a doc by hand has nowhere to go.

``python -m dart_reach.studies.results_docs [ROOT]`` writes the docs of the repository at ROOT
(default: the current directory); ``--check`` writes nothing and exits 1 naming the docs that
differ from their rendering.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path
from typing import Callable, Mapping

import numpy as np

from . import scene_study
from ..evolution.rundir import RunDirectory
from ..model.scenes import scene_of
from ..postevaluation import results

TEMPLATES = Path("docs/results/templates")
OUT = Path("docs/results")
_PLACEHOLDER = re.compile(r"\{\{\s*([A-Za-z0-9_.\-]+)\s*\}\}")
#: Rates are shown in per cent; other measures with 3 significant digits.
_RATES = ("reached", "grasped", "babbling", "babbling_no_ball", "reach_low", "reach_high")


def render(template: str, values: Mapping[str, str], name: str = "template") -> str:
    """``template`` with every ``{{ key }}`` replaced by ``values[key]``; ``KeyError`` naming
    every placeholder that has no value."""
    unknown = sorted({m.group(1) for m in _PLACEHOLDER.finditer(template)} - set(values))
    if unknown:
        raise KeyError(f"{name}: no value for {', '.join(unknown)}")
    return _PLACEHOLDER.sub(lambda m: values[m.group(1)], template)


def number(value: float, measure: str = "") -> str:
    """A value as the docs show it: a rate in whole per cent, else 3 significant digits; a
    missing value as an en dash."""
    if value is None or not np.isfinite(value):
        return "–"
    if measure in _RATES:
        return f"{value:.0%}".replace("%", " %")
    return f"{value:.3g}"


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
    study's tables), ``<scene>.<group>.<measure>`` (``scene_study.summary``'s cells),
    ``<scene>.wall_h`` (training wall time) and the runs' ``trained`` / ``evaluated``
    provenance."""
    runs = scene_study.study_runs(recordings / "scene-study")
    summary = scene_study.summary(runs)
    lever_table = scene_study.levers(scene_study.robots(runs))
    values = {"summary": scene_study.markdown(summary).rstrip("\n"),
              "levers": scene_study.levers_grid(lever_table).rstrip("\n"),
              "levers_full": scene_study.levers_markdown(lever_table).rstrip("\n"),
              **provenance(runs)}
    for row in summary.iter_rows(named=True):
        for measure, value in row.items():
            if isinstance(value, float):
                values[f"{row['scene']}.{row['group']}.{measure}"] = number(value, measure)
    for d in runs:
        run = RunDirectory.open(d)
        scene = scene_of(run.settings.world.sectors) or d.name
        wall = run.status().unique(["condition", "phase"])["wall_h"].sum()
        values[f"{scene}.wall_h"] = f"{wall:.1f}"
    return values


#: Each doc rendered from a template: its name and the function of the recordings directory
#: giving its values.
DOCS: dict[str, Callable[[Path], dict[str, str]]] = {"scene-study.md": scene_study_values}
#: Each doc that is a table alone: its path under docs/results and the function of the
#: recordings directory giving its text.
TABLES: dict[str, Callable[[Path], str]] = {
    "scene-study/scene-study.md":
        lambda recordings: scene_study.tables_text(scene_study.study_runs(
            recordings / "scene-study"))}


def generate(root: Path) -> dict[Path, str]:
    """Every generated doc of the repository at ``root``: path -> its text."""
    recordings = root / "recordings"
    out = {root / OUT / name: text(recordings) for name, text in TABLES.items()}
    for name, values in DOCS.items():
        template = (root / TEMPLATES / name).read_text(encoding="utf-8")
        out[root / OUT / name] = render(template, values(recordings), name)
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m dart_reach.studies.results_docs",
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
    stale = [p for p, text in docs.items()
             if not p.is_file() or p.read_text(encoding="utf-8") != text]
    if args.check:
        for p in stale:
            print(f"{p}: differs from its rendering (make results)", file=sys.stderr)
        return 1 if stale else 0
    for p in stale:
        p.write_text(docs[p], encoding="utf-8")
        print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
