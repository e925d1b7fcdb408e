"""Every Python block of the README runs as written, saved as a script, in README order in
one working directory (so the tables block reads the run the ablation block made); so does
the Python of the model reference (``DOC_SNIPPETS``); and every relative link of the README,
docs/ and notebooks/README.md resolves, anchors included.

Budgets are made tiny by exact substitutions (``TINY``): each must be found in the README as
written, so a changed snippet fails here until this table follows it. The substituted run is
the ablation block's (the tables block's default run is ``make demo``'s, which this test
does not make). No display: ``watch`` writes its files instead of starting a viewer."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
#: documentation pages whose Python blocks run as scripts here (those of docs/guides/ablations.md
#: run in tests/test_ablations.py)
DOC_SNIPPETS = (ROOT / "docs" / "model" / "world.md", ROOT / "docs" / "guides" / "gymnasium.md")

#: (text in the README, what the test runs instead)
TINY = (
    ('scaled(load_condition("standard"), 3)', 'scaled(load_condition("standard"), 1)'),
    ("Settings(replications=4, seed=0)", "Settings(replications=2, trials=1, steps=4, seed=0)"),
    ('RUN = "recordings/demo-standard"', 'RUN = "recordings/ablation"'),
)


def python_blocks(text: str) -> list[str]:
    """The README's ```python blocks, dedented (some sit in a list item)."""
    blocks = []
    for m in re.finditer(r"^( *)```python\n(.*?)^\1```", text, re.M | re.S):
        indent = len(m.group(1))
        blocks.append("".join(line[indent:] if line.strip() else "\n"
                              for line in m.group(2).splitlines(keepends=True)))
    return blocks


def test_every_readme_snippet_runs_as_a_script(tmp_path):
    text = README.read_text()
    for original, tiny in TINY:
        assert text.count(original) == 1, f"the README changed: update TINY for {original!r}"
        text = text.replace(original, tiny)
    blocks = python_blocks(text)
    assert len(blocks) >= 3
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    for i, block in enumerate(blocks):
        script = tmp_path / f"snippet{i}.py"
        script.write_text(block)
        result = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env,
                                capture_output=True, text=True, timeout=900)
        assert result.returncode == 0, f"README block {i}:\n{block}\n{result.stderr[-3000:]}"
    assert (tmp_path / "ablation-report.html").is_file()  # beside, never in, the run
    assert not (tmp_path / "recordings" / "ablation" / "report.html").exists()
    assert (tmp_path / "recordings" / "watch" / "standard-pre-sector4.rrd").is_file()


def test_the_model_reference_snippets_run_as_scripts(tmp_path):
    for doc in DOC_SNIPPETS:
        blocks = python_blocks(doc.read_text())
        assert blocks, f"{doc}: no Python block"
        for i, block in enumerate(blocks):
            script = tmp_path / f"{doc.stem}{i}.py"
            script.write_text(block)
            result = subprocess.run([sys.executable, str(script)], cwd=tmp_path,
                                    capture_output=True, text=True, timeout=300)
            assert result.returncode == 0, f"{doc} block {i}:\n{block}\n{result.stderr[-3000:]}"


def _pages() -> list[Path]:
    """The pages a reader follows links in (the results docs' templates are checked through
    their renderings, whose links are relative to docs/results/)."""
    templates = ROOT / "docs" / "results" / "templates"
    return [README, ROOT / "notebooks" / "README.md",
            *sorted(p for p in (ROOT / "docs").rglob("*.md") if templates not in p.parents)]


def _anchors(page: Path) -> set[str]:
    """GitHub's heading anchors: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"^```.*?^```", "", page.read_text(), flags=re.M | re.S)
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-")
            for h in re.findall(r"^#+ (.*)$", text, re.M)}


def test_every_relative_link_resolves():
    broken = []
    for page in _pages():
        text = re.sub(r"^```.*?^```", "", page.read_text(), flags=re.M | re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"[a-z]+:", target):  # https:, mailto:
                continue
            path, _, anchor = target.partition("#")
            resolved = (page.parent / path).resolve() if path else page
            if not resolved.exists():
                broken.append(f"{page.relative_to(ROOT)}: {target}")
            elif anchor and resolved.suffix == ".md" and anchor not in _anchors(resolved):
                broken.append(f"{page.relative_to(ROOT)}: {target} (no such heading)")
    assert not broken, "broken links:\n" + "\n".join(broken)
