"""Ctrl-C and SIGTERM: a long command (train, evaluate, bench --physics) saves its work, says
how to go on, and exits with 130 (Ctrl-C) or 143 (SIGTERM)."""

from __future__ import annotations

import signal


class Terminated(KeyboardInterrupt):
    """SIGTERM, handled like Ctrl-C (work saved, a message) but exit code 143."""


#: The stop signals received. Python only prints an exception raised in a destructor (a
#: signal can land in rerun's flush on garbage collection), so a stop could be lost: every
#: progress report (between generations, between robots) raises it again.
stops: list[KeyboardInterrupt] = []


def on_stop_signal(signum, frame):
    exc = Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()
    stops.append(exc)
    raise exc


def unraisable(hook):
    """``sys.unraisablehook`` that stays quiet about a stop signal swallowed by a destructor
    (it is raised again at the next progress report)."""
    def quiet(info) -> None:
        if not isinstance(info.exc_value, KeyboardInterrupt):
            hook(info)
    return quiet


def checked(callback):
    """A progress callback that first raises a stop signal a destructor swallowed."""
    def report(update) -> None:
        if stops:
            raise stops[0]
        callback(update)
    return report


def interrupted(exc: KeyboardInterrupt) -> int:
    """The exit code of a command stopped by ``exc``: 143 for SIGTERM, 130 for Ctrl-C."""
    return 143 if isinstance(exc, Terminated) else 130


#: The exit codes of a command stopped by a signal (``interrupted``).
STOPPED = (130, 143)


def ignore_stop_signals() -> None:
    """Ignore Ctrl-C and SIGTERM from now on: for a command that has stopped, saved its work
    and said how to go on. What is left is the interpreter's shutdown, which takes Python's
    handler away before it ends; a stop signal landing then would end the process by the
    signal (its parent sees it killed by SIGINT) instead of with the exit code chosen."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
