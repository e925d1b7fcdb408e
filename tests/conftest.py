"""The suite computes as a user's session does: ``import dart_reach`` pins OpenBLAS's kernels and
numpy's dispatch level only if it comes before numpy is loaded, so it comes first here.

``in_process``: the command line run inside the test's process, for the tests of what a
command does rather than of the process around it."""

import dart_reach  # noqa: F401

import io
import os
import signal
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout

import pytest


def _main_in_process(*args, cwd=None) -> subprocess.CompletedProcess:
    """``dart-reach ARGS`` as ``dart_reach.cli.main`` runs it here, its exit code and output
    returned as ``subprocess.run(..., capture_output=True, text=True)`` returns a process's, stdin
    not a terminal (as a script runs it). It saves a new process's imports (seconds: polars,
    rerun, DART, matplotlib) but sees neither a signal's exit, nor a terminal, nor what a
    library writes to the file descriptors itself: a test of a command's errors keeps one real
    process for those. What ``main`` sets for the process (its stop-signal handlers, the
    unraisable hook) and the working directory are put back afterwards."""
    from dart_reach.cli import main

    out, err = io.StringIO(), io.StringIO()
    handlers = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGINT)}
    hook, stdin, here = sys.unraisablehook, sys.stdin, os.getcwd()
    try:
        if cwd is not None:
            os.chdir(cwd)
        sys.stdin = io.StringIO("")
        with redirect_stdout(out), redirect_stderr(err):
            try:
                code = main([str(a) for a in args])
            except SystemExit as exc:  # argparse's errors and --help, --version
                code = exc.code
                if isinstance(code, str):
                    print(code, file=err)
                    code = 1
                code = code or 0
    finally:
        os.chdir(here)
        sys.stdin, sys.unraisablehook = stdin, hook
        for s, handler in handlers.items():
            signal.signal(s, handler)
    return subprocess.CompletedProcess(["dart-reach", *map(str, args)], code, out.getvalue(),
                                       err.getvalue())


@pytest.fixture(scope="session")
def in_process():
    """``in_process(*args, cwd=None)``: ``dart-reach ARGS`` run in this process
    (``_main_in_process``)."""
    return _main_in_process
