"""The suite computes as a user's session does: ``import dart_reach`` pins OpenBLAS's kernels and
numpy's dispatch level only if it comes before numpy is loaded, so it comes first here.

``in_process``: the command line run inside the test's process, for the tests of what a
command does rather than of the process around it. ``built_once``: an expensive directory
(a trained and post-evaluated run) built once for the whole session and read by every
pytest-xdist worker that needs it."""

import dart_reach  # noqa: F401

import fcntl
import io
import os
import shutil
import signal
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path
from typing import Callable

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


@pytest.fixture(scope="session")
def built_once(tmp_path_factory):
    """``built_once(name, build)``: a directory of its own, filled by ``build(directory)`` once
    in the whole session: the first pytest-xdist worker to ask builds it, holding a lock on
    it, and every other worker that asks (one that took some of the same file's tests, say)
    waits for it and reads the same directory instead of building its own. For what tests only
    read; a test that writes copies it first. A build that fails is made afresh by the next
    who asks."""
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent  # the session's, shared by its workers
    root = root / "built-once"
    root.mkdir(exist_ok=True)

    def get(name: str, build: Callable[[Path], object]) -> Path:
        path, done = root / name, root / f"{name}.done"
        with open(root / f"{name}.lock", "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            if not done.exists():
                shutil.rmtree(path, ignore_errors=True)
                path.mkdir()
                build(path)
                done.touch()
        return path

    return get
