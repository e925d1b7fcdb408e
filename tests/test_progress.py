"""Progress of training and post-evaluation: plain lines where the output is not a terminal
(logs), a tqdm bar redrawn in place on a real pseudo-terminal, a widget in a real Jupyter
kernel, from the CLI and from Python."""

from __future__ import annotations

import fcntl
import io
import os
import pty
import select
import struct
import subprocess
import sys
import termios
import textwrap
import time

import nbclient
import nbformat

from dart_reach.evolution.trainer import Progress
from dart_reach.progress import evaluation_bar, training_bar

TINY = ["standard", "--generations", "1", "--replications", "1", "--trials", "1", "--steps", "4",
        "--workers", "1"]


def _update(done: int) -> Progress:
    return Progress("standard", "pre", done, 3, 2, 0.5, 0.25, done, 3, 1.0 * done)


def test_plain_lines_where_the_output_is_not_a_terminal():
    out = io.StringIO()
    with training_bar(out) as bar:
        for done in (1, 2, 3):
            bar(_update(done))
    lines = out.getvalue().splitlines()
    assert len(lines) == 3 and "\r" not in out.getvalue()
    assert lines[1].startswith("standard | pre 2/3 | best 0.5000") and "2/3 generations" in lines[1]


def test_a_bar_on_a_real_terminal(tmp_path):
    """The CLI in a pseudo-terminal draws a tqdm bar (redrawn with carriage returns)."""
    main, child = pty.openpty()
    fcntl.ioctl(child, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 120, 0, 0))  # 120 columns
    proc = subprocess.Popen([sys.executable, "-m", "dart_reach.cli", "train", *TINY,
                             "--out", str(tmp_path / "r")], stdin=child, stdout=child,
                            stderr=child)
    os.close(child)
    chunks, deadline = [], time.monotonic() + 300
    while time.monotonic() < deadline:
        if not select.select([main], [], [], 1.0)[0]:
            continue
        try:
            data = os.read(main, 65536)
        except OSError:  # EIO: the child closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    os.close(main)
    text = b"".join(chunks).decode(errors="replace")
    assert proc.wait(60) == 0, text
    assert "\r" in text and "3/3 [" in text and "generation/s" in text, text


def test_a_widget_in_jupyter(tmp_path):
    """Training called from Python in a real Jupyter kernel shows a progress widget."""
    code = textwrap.dedent(f"""
        from dart_reach.evolution.conditions import load_condition, scaled
        from dart_reach.evolution.settings import Settings
        from dart_reach.evolution.trainer import train
        train([scaled(load_condition("standard"), 1)], Settings(replications=1, trials=1,
              steps=4), {str(tmp_path / "nb")!r}, workers=1)
        """)
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(code)])
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3").execute()
    outputs = nb.cells[0].outputs
    assert any("application/vnd.jupyter.widget-view+json" in o.get("data", {})
               for o in outputs), outputs


def test_evaluation_lines():
    from dart_reach.postevaluation.systematic import EvaluationProgress

    out = io.StringIO()
    with evaluation_bar(out, bar=False) as bar:
        bar(EvaluationProgress(4, 10, 8.0, "gross", "no-sight"))
    assert out.getvalue() == "evaluate | gross | no-sight | 4/10 robots | ETA 0m12s\n"


def test_a_resumed_run_counts_only_what_it_trains(tmp_path):
    """After a resume part-way through a phase, the generations trained by the earlier process
    are neither done nor left to do: the rate and the ETA are this process's."""
    from dart_reach.evolution.conditions import load_condition, scaled
    from dart_reach.evolution.settings import Settings
    from dart_reach.evolution.trainer import train

    class Stop(Exception):
        pass

    def stop_after_one(p: Progress) -> None:
        raise Stop

    args = ([scaled(load_condition("standard"), 3)], Settings(replications=1, trials=1, steps=4),
            tmp_path / "r")
    try:
        train(*args, workers=1, progress=stop_after_one)
    except Stop:
        pass
    seen: list[Progress] = []
    train(*args, workers=1, progress=seen.append, resume=True)
    first = seen[0]
    assert (first.phase, first.generation) == ("pre", 2)
    assert (first.done_generations, first.total_generations) == (1, 9 - 1), first
    assert seen[-1].done_generations == seen[-1].total_generations
