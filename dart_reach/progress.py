"""Progress of long work (training, post-evaluation) for people: a tqdm bar on a terminal and
in Jupyter (``tqdm.auto`` draws a widget there), one plain line per update anywhere else (a
log file, a pipe), so that logs stay readable.

``training_bar()`` and ``evaluation_bar()`` make callbacks for ``trainer.train`` and
``systematic.evaluate_run`` (which use them by default) and ``snapshots.measure_snapshots``;
a callback is also a context manager that closes its bar.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable


def _duration(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "?"
    m, s = divmod(int(seconds), 60)
    h, m = divmod(m, 60)
    return f"{h}h{m:02d}m" if h else f"{m}m{s:02d}s"


def in_jupyter() -> bool:
    """True when running in a Jupyter (IPython) kernel."""
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None else None
    return shell is not None and hasattr(shell, "kernel")


def interactive(stream) -> bool:
    """True on a terminal or in a Jupyter kernel: where a bar redraws in place."""
    return in_jupyter() or bool(getattr(stream, "isatty", lambda: False)())


class ProgressBar:
    """A progress callback: ``read(update)`` gives (done, total, unit label, text)."""

    def __init__(self, read: Callable, stream=None, bar: bool | None = None):
        self._read = read
        self._stream = stream if stream is not None else sys.stderr
        self._bar_wanted = interactive(self._stream) if bar is None else bar
        self._bar = None

    def __call__(self, update) -> None:
        done, total, unit, text = self._read(update)
        if not self._bar_wanted:
            eta = getattr(update, "eta_s", math.nan)
            self._stream.write(f"{text} | {done}/{total} {unit}s | ETA {_duration(eta)}\n")
            self._stream.flush()
            return
        if self._bar is None:
            from tqdm.auto import tqdm

            # A resumed run starts part-way: its rate counts only what this process does.
            self._bar = tqdm(total=total, initial=done - 1, unit=unit, file=self._stream,
                             dynamic_ncols=True, smoothing=0.1)
        self._bar.set_description_str(text, refresh=False)
        self._bar.update(done - self._bar.n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> "ProgressBar":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def training_bar(stream=None, bar: bool | None = None) -> ProgressBar:
    """Progress of ``trainer.train``: generations done of all phases and replications'."""
    return ProgressBar(lambda p: (
        p.done_generations, p.total_generations, "generation",
        f"{p.condition} | {p.phase} {p.generation}/{p.generations} | best {p.best:.4f} "
        f"mean {p.mean:.4f} | driver {p.driver_cpu_s:.2f} s CPU for {p.tasks} tasks"),
        stream, bar)


def evaluation_bar(stream=None, bar: bool | None = None) -> ProgressBar:
    """Progress of ``systematic.evaluate_run`` and ``snapshots.measure_snapshots``: robots
    post-evaluated."""
    return ProgressBar(lambda p: (p.robots_done, p.robots_total, "robot",
                                  f"evaluate | {p.phase} | {p.senses}"), stream, bar)
