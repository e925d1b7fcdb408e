"""What the generated results pages share (``reports.results`` and the pages it renders): the
placeholders of their templates and how their tables are written (their numbers: the
package's ``dart_reach.analysis.formatting``, the one number formatter)."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Mapping

import polars as pl

from dart_reach.analysis import formatting
from dart_reach.evolution.rundir import RunDirectory

_PLACEHOLDER = re.compile(r"\{\{\s*([A-Za-z0-9_.\-]+)\s*\}\}")


def render(template: str, values: Mapping[str, str], name: str = "template") -> str:
    """``template`` with every ``{{ key }}`` replaced by ``values[key]``; ``KeyError`` naming
    every placeholder that has no value."""
    unknown = sorted({m.group(1) for m in _PLACEHOLDER.finditer(template)} - set(values))
    if unknown:
        raise KeyError(f"{name}: no value for {', '.join(unknown)}")
    return _PLACEHOLDER.sub(lambda m: values[m.group(1)], template)


def markdown_table(table: pl.DataFrame) -> str:
    """``table`` as a markdown table: floats to 3 significant digits (``formatting.number``),
    booleans as yes/no, nulls as an en dash."""
    def cell(value) -> str:
        if value is None:
            return "–"
        if isinstance(value, bool):
            return "yes" if value else "no"
        if isinstance(value, float):
            return formatting.number(value)
        return str(value).replace("|", "\\|")

    lines = ["| " + " | ".join(table.columns) + " |", "|" + "---|" * table.width]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in table.iter_rows()]
    return "\n".join(lines)


def training_text(run: RunDirectory) -> str:
    """Where a run's training stands: replication-generations done of all, wall time,
    sessions and the revisions that trained it (its manifest)."""
    table = run.status()
    done, total = int(table["generations"].sum()), int(table["of"].sum())
    wall = table.unique(["condition", "phase"])["wall_h"].sum()
    sessions = json.loads((run.out / "manifest.json").read_text()).get("sessions", [])
    revisions = sorted({str(s.get("git_revision"))[:7] for s in sessions})
    return (f"{done:,} of {total:,} replication-generations, {wall:.1f} h of wall time in "
            f"{len(sessions)} session(s) at {', '.join(revisions)}")


def write_page(path: Path, text: str, check: bool) -> int:
    """A generated page: with ``check``, say whether ``path`` differs from ``text`` and return
    1 when it does (stale), else write it; 0 otherwise."""
    if check:
        stale = path.read_text() != text
        print(f"{path}: {'stale' if stale else 'up to date'}")
        return int(stale)
    path.write_text(text)
    print(f"wrote {path}")
    return 0
