"""The run directory survives anything: a fault injected at each kind of file rename of a tiny run
(SIGKILL, SIGTERM, a full disk), a file-size limit, a second process, a deleted or damaged
file, a killed parent's workers, a Ray address where nothing listens."""

from __future__ import annotations

import json
import os
import re
import select
import shutil
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import polars as pl
import pytest

from dart_reach import integrity
from dart_reach.recording.rrd import read_rrd

STRACE = shutil.which("strace")
RENAMES = "rename,renameat,renameat2"
CONDITION = """\
name = "two"
notation = "two"
description = "pre- then gross-reaching, for the run-directory tests"
generations_per_phase = 1

[[phases]]
name = "pre"
acuity = 3.0
offset_sensors = false
free_groups = ["direct"]
reflexes = true

[[phases]]
name = "gross"
acuity = 1.0
offset_sensors = false
free_groups = ["direct", "hidden"]
reflexes = true
"""


@pytest.fixture(scope="module")
def condition(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("condition") / "two.toml"
    path.write_text(CONDITION)
    return path


def _train_args(condition: Path, out: Path, *extra) -> list[str]:
    return ["train", str(condition), "--replications", "1", "--trials", "1", "--steps", "3",
            "--seed", "2", "--workers", "1", "--record-every", "1", "--snapshot-every", "1",
            "--out", str(out), *extra]


def _cli(*args, timeout=300, prefix=()):
    return subprocess.run([*prefix, sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout)


def _strace(inject: str) -> list[str]:
    return [STRACE, "-f", "-qq", "-o", "/dev/null", "-e", f"trace={RENAMES}", "-e",
            f"inject={RENAMES}:{inject}"]


#: A process that has imported the command line and the trainer and run one lifetime of the
#: model (its compiled functions loaded), then forks a training for each request: a real
#: process of its own, faulted by strace attached to it before it begins (``Zygote``). The
#: threads those imports start (OpenBLAS's, jemalloc's, polars' and rerun's) are idle at the
#: fork and not carried into the child, whose writes do not wait on them: the reference run,
#: made so, is the run a new process makes (the tests that resume a copy of it in one). A
#: request is a JSON line (the arguments, the file for stderr, whether to wait for a tracer);
#: the answer, the child's PID, then its exit code as ``subprocess`` gives it (-9 for
#: SIGKILL). The child ends as ``python -m dart_reach.cli`` does (``sys.exit(main())``), with
#: ``sys.argv`` as there.
ZYGOTE = r"""
import ctypes, json, os, sys, time, warnings

import dart_reach.cli  # first, as the command's own process: it pins numpy's kernels
import dart_reach.evolution.trainer
import numpy as np
from dart_reach.evolution.backends import Job, SerialBackend
from dart_reach.evolution.conditions import load_condition
from dart_reach.evolution.genome import N_GENES, as_groups
from dart_reach.evolution.settings import Settings, trial_config

warnings.filterwarnings("ignore", ".*multi-threaded.*fork", DeprecationWarning)
pre, settings = load_condition("standard").phases[0], Settings(trials=1, steps=3)
SerialBackend().map([Job(np.zeros(N_GENES, np.uint8), as_groups(pre.free_groups),
                         trial_config(pre, settings), settings.world, (0,))])


def traced():
    with open("/proc/self/status") as status:
        return any(line.split()[1:] != ["0"] for line in status if line.startswith("TracerPid:"))


def serve():
    for line in sys.stdin:
        request = json.loads(line)
        pid = os.fork()
        if pid == 0:
            return request
        print(pid, flush=True)
        print(os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]), flush=True)
    sys.exit(0)


request = serve()
try:
    null = os.open(os.devnull, os.O_RDWR)
    err = os.open(request["stderr"], os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    for fd, target in ((0, null), (1, null), (2, err)):
        os.dup2(target, fd)
    sys.argv = ["dart-reach", *request["args"]]
    if request["traced"]:
        # PR_SET_PTRACER, PR_SET_PTRACER_ANY: where Yama lets a process trace only its
        # descendants (ptrace_scope 1), strace, not this child's ancestor, may attach
        ctypes.CDLL(None).prctl(0x59616D61, ctypes.c_ulong(-1), 0, 0, 0)
    deadline = time.monotonic() + 60
    while request["traced"] and not traced():
        if time.monotonic() > deadline:
            os._exit(3)
        time.sleep(0.002)
except BaseException:
    os._exit(3)
sys.exit(dart_reach.cli.main(request["args"]))
"""


class Zygote:
    """``ZYGOTE`` running: ``run`` forks a training from it, strace attached if given. A fault
    costs the child's own work (1.4 CPU-s for the whole run under strace) where a new
    interpreter's imports and loading of the compiled model came on top (6 CPU-s)."""

    def __init__(self):
        self._proc, self._buffer = None, b""

    def _line(self, deadline: float) -> int:
        fd = self._proc.stdout.fileno()
        while b"\n" not in self._buffer:
            if not select.select([fd], [], [], max(0.0, deadline - time.monotonic()))[0]:
                raise TimeoutError("no answer from the zygote")
            chunk = os.read(fd, 4096)
            assert chunk, "the zygote ended"
            self._buffer += chunk
        line, _, self._buffer = self._buffer.partition(b"\n")
        return int(line)

    def run(self, args, stderr: Path, strace: list[str] | None = None,
            timeout: float = 300) -> tuple[int, str]:
        """``dart-reach ARGS`` in a child, strace (its command, without ``-p``) attached before
        the child begins: the exit code and what it wrote to stderr."""
        deadline = time.monotonic() + timeout
        if self._proc is None:  # started at its first run
            self._proc = subprocess.Popen([sys.executable, "-c", ZYGOTE],
                                          stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        request = {"args": [str(a) for a in args], "stderr": str(stderr),
                   "traced": strace is not None}
        self._proc.stdin.write(json.dumps(request).encode() + b"\n")
        self._proc.stdin.flush()
        pid = self._line(deadline)
        tracer = subprocess.Popen([*strace, "-p", str(pid)], stderr=subprocess.PIPE,
                                  text=True) if strace else None
        try:
            code = self._line(deadline)
        except TimeoutError:
            os.kill(pid, signal.SIGKILL)
            raise
        finally:
            if tracer is not None:
                tracer.wait(timeout=60)
        # 3: the child was never traced (strace could not attach: its error says why)
        assert tracer is None or code != 3, tracer.stderr.read()
        return code, stderr.read_text()

    def close(self) -> None:
        if self._proc is not None:
            self._proc.stdin.close()
            self._proc.wait(timeout=60)


@pytest.fixture(scope="module")
def zygotes():
    """Two ``Zygote``s (each started when first used): faults are injected two at a time."""
    pair = [Zygote(), Zygote()]
    yield pair
    for z in pair:
        z.close()


def _npz(path: Path) -> dict:
    with np.load(path) as d:
        return {k: d[k].copy() for k in d.files if k != "stats/wall_s"}


def snapshot(out: Path) -> dict:
    """Everything a run directory holds, comparable across runs: tables without wall times,
    arrays, recordings' contents; the manifest without its creation time, command line (which
    names the run's own directory) and the state of the source tree it was made from (a run
    started again after an edit records the edit)."""
    files = sorted(p.relative_to(out) for p in out.rglob("*") if p.is_file() and p.name != ".lock")
    assert not [f for f in files if f.name.endswith(".tmp")], files
    snap: dict = {"files": [str(f) for f in files]}
    for f in files:
        p = out / f
        if f.suffix == ".npz":
            snap[str(f)] = _npz(p)
        elif f.suffix == ".parquet":
            table = pl.read_parquet(p)
            snap[str(f)] = table.drop("wall_s") if "wall_s" in table.columns else table
        elif f.suffix == ".rrd":
            snap[str(f)] = read_rrd(p)
        elif f.name == "manifest.json":
            manifest = json.loads(p.read_text())
            snap[str(f)] = {k: v for k, v in manifest.items()
                            if k not in ("created", "command", "git_revision", "git_dirty",
                                         "git_diff_sha256", "sessions")}
        elif f.name == integrity.LEDGER_FILE:
            # the ledger accepts each file on disk (with the old digest too where a kill came
            # before a write's last step) and names every file (the digests differ between
            # runs: a .npz holds the time it was written)
            ledger = integrity.ledger(out)
            assert all(integrity.sha256(out / n) in d for n, d in ledger.items()), ledger
            assert sorted(ledger) == sorted(str(g) for g in files if g.name != f.name), ledger
            snap[str(f)] = sorted(ledger)
    return snap


def same(a: dict, b: dict) -> bool:
    if a["files"] != b["files"]:
        return False
    for k, v in a.items():
        w = b[k]
        if isinstance(v, dict) and k != "files" and not k.endswith("manifest.json"):
            if v.keys() != w.keys() or not all(np.array_equal(v[x], w[x]) for x in v):
                return False
        elif isinstance(v, pl.DataFrame):
            if not v.equals(w):
                return False
        elif v != w:
            return False
    return True


@pytest.fixture(scope="module")
def reference(condition, built_once, zygotes):
    """An uninterrupted run, and how many renames it makes: a process forked as the faulted
    ones are (the tests that compare a new process's run with it check that both are one),
    made once for the session (read only: copy it to write)."""
    def build(root):
        out = root / "run"
        trace = [STRACE, "-f", "-qq", "-o", str(root / "renames.txt"), "-e",
                 f"trace={RENAMES}"] if STRACE else None
        code, err = zygotes[0].run(_train_args(condition, out), root / "stderr.txt", trace)
        assert code == 0, err

    root = built_once("run-directory-reference", build)
    out = root / "run"
    targets = [_kind(line, out) for line in (root / "renames.txt").read_text().splitlines()
               if "rename" in line and _in_run(line, out)] if STRACE else []
    return out, snapshot(out), len(targets), targets


def _in_run(line: str, out: Path) -> bool:
    """Whether a rename in strace's output lands in the run directory (not, say, Numba's
    cache of a function compiled afresh, which the same process writes beside its source)."""
    return Path(re.findall(r'"([^"]*)"', line)[-1]).is_relative_to(out)


def _kind(line: str, out: Path) -> str:
    """What a rename in strace's output commits: its target in the run directory, with the
    phase's directory and the generation left out (``phases/*/best/*.rrd``)."""
    target = re.findall(r'"([^"]*)"', line)[-1]
    name = Path(target).relative_to(out).as_posix()
    name = re.sub(r"^phases/[^/]+/", "phases/*/", name)
    return re.sub(r"gen\d+[^/]*$", "*" + Path(name).suffix, name)


def _faults_then_resume(condition, root: Path, cases, zygotes,
                        in_process) -> list[tuple[int, str, dict]]:
    """Each case (``inject``, n): a training process (forked from a ``Zygote``) with the
    fault injected at its n-th rename (two such processes at a time), then the run resumed in
    this process (the same command and code, without a new process's imports): the exit code
    and stderr of the faulted process and a ``snapshot`` of the resumed run, per case."""
    def cut(case, zygote):
        inject, n = case
        out = root / f"{inject.split('=')[1].split(':')[0]}-{n}"
        return out, zygote.run(_train_args(condition, out), root / f"{out.name}.stderr",
                               _strace(f"{inject}:when={n}"))

    def cut_all(i):
        return [cut(case, zygotes[i]) for case in cases[i::2]]

    with ThreadPoolExecutor(2) as pool:
        halves = list(pool.map(cut_all, range(2)))
    faulted = [halves[i % 2][i // 2] for i in range(len(cases))]
    results = []
    for (_, n), (out, (code, err)) in zip(cases, faulted):
        # stopped before its manifest was written, the run is started again, not resumed
        resume = ("--resume",) if (out / "manifest.json").exists() else ()
        again = in_process(*_train_args(condition, out, *resume))
        assert again.returncode == 0, (n, err, again.stderr)
        results.append((code, err, snapshot(out)))
    return results


def _kill_points(targets: list[str]) -> list[int]:
    """Where to SIGKILL a run (1-based renames): every moment of its commit sequence once.
    A phase commits the same files in the same order (asserted), so a kill at every rename of
    the last phase meets every kind of file and every pair of consecutive commits (a data file
    renamed but the manifest not yet, and the reverse), with a finished phase to keep besides.
    What the last phase cannot show is added: the renames before any phase began (nothing to
    resume from yet) and, in the first phase, its checkpoint and its final (a phase resumed
    from its checkpoint with no phase finished; all of a phase's results in but its final not).
    Here 30 of the run's 49 renames: a kill at each costs a process, and its resume."""
    finals = [i for i, t in enumerate(targets) if t == "phases/*/final.npz"]
    # a file's rename comes between two of the ledger's (integrity.recorded_write): a phase
    # begins with the ledger accepting its first file and ends with the ledger naming its final
    starts = [next(i for i, t in enumerate(targets) if t.startswith("phases/")) - 1]
    starts += [f + 2 for f in finals[:-1]]
    phases = [targets[a:f + 2] for a, f in zip(starts, finals)]
    assert finals[-1] + 2 == len(targets), targets
    assert len(phases) >= 2 and all(p == phases[0] for p in phases), targets
    first, last = starts[0], starts[-1]
    in_first = [first + phases[0].index(k) for k in ("phases/*/checkpoint.npz",
                                                     "phases/*/final.npz")]
    return [n + 1 for n in sorted({*range(first), *in_first, *range(last, len(targets))})]


@pytest.mark.skipif(not STRACE, reason="needs strace to inject faults at exact renames")
def test_sigkill_at_each_kind_of_rename_resumes_to_the_same_directory(condition, reference,
                                                                       tmp_path, zygotes,
                                                                       in_process):
    _, expected, renames, targets = reference
    assert renames >= 10  # manifest, recordings, checkpoints, tables, finals
    points = _kill_points(targets)
    assert {targets[n - 1] for n in points} == set(targets)
    results = _faults_then_resume(condition, tmp_path, [("signal=SIGKILL", n) for n in points],
                                  zygotes, in_process)
    for n, (code, err, snap) in zip(points, results):
        assert code == -signal.SIGKILL, (n, err)
        assert same(snap, expected), f"killed at rename {n}: resumed run differs"


@pytest.mark.skipif(not STRACE, reason="needs strace to inject faults at exact renames")
def test_sigterm_and_full_disk_at_renames(condition, reference, tmp_path, zygotes, in_process):
    _, expected, renames, _ = reference
    cases = [("signal=SIGTERM", n) for n in (2, renames // 2, renames - 1)]
    cases += [("error=ENOSPC", n) for n in (1, 3, renames // 2 + 1, renames)]
    results = _faults_then_resume(condition, tmp_path, cases, zygotes, in_process)
    for (inject, n), (code, err, snap) in zip(cases, results):
        if inject == "signal=SIGTERM":
            assert code == 143 and "--resume" in err and "Traceback" not in err, (n, err)
        else:
            lines = err.strip().splitlines()
            assert code == 2 and "No space left on device" in lines[-1], (n, err)
            assert "Traceback" not in err
        assert same(snap, expected), f"{inject} at rename {n}: resumed run differs"


def test_file_size_limit_is_one_line_and_resumable(condition, reference, tmp_path, in_process):
    _, expected, *_ = reference
    out = tmp_path / "run"
    cut = _cli(*_train_args(condition, out), prefix=["prlimit", "--fsize=12000"])
    assert cut.returncode == 2, cut.stderr
    line = cut.stderr.strip().splitlines()[-1]
    assert "File too large" in line and str(out) in line, cut.stderr
    again = in_process(*_train_args(condition, out, "--resume"))
    assert again.returncode == 0, again.stderr
    assert same(snapshot(out), expected)


def test_lock_refuses_a_second_process_and_a_killed_holder_never_blocks(condition, tmp_path,
                                                                        in_process):
    from dart_reach.files import DirectoryLock

    out = tmp_path / "run"
    slow = _train_args(condition, out)[:-2] + ["--trials", "18", "--steps", "200", "--out", out]
    first = subprocess.Popen([sys.executable, "-m", "dart_reach.cli", *map(str, slow)],
                             stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while not (out / "manifest.json").exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    for i, args in enumerate((slow + ["--resume"], slow, ["evaluate", out])):
        second = (_cli if i == 0 else in_process)(*args)  # the others: the same code, here
        assert second.returncode == 2, second.stderr
        assert f"PID {first.pid}" in second.stderr or "unfinished" in second.stderr, \
            second.stderr
        assert second.stderr.count("\n") == 1
    assert first.poll() is None, "the first run must still be running"
    first.send_signal(signal.SIGKILL)
    first.wait()
    with DirectoryLock(out):  # the dead holder's lock is free at once
        pass


def test_deleted_or_stale_files_are_rebuilt_or_refused(condition, reference, tmp_path,
                                                       in_process):
    src, expected, *_ = reference
    out = tmp_path / "run"
    # a deleted table, training.rrd and best table, and a left-over temporary: rebuilt exactly
    shutil.copytree(src, out)
    pre = next(out.glob("phases/pre-*"))
    for name in ("generations.parquet", "training.rrd"):
        (out / name).unlink()
    (pre / "best.parquet").unlink()
    (pre / ".checkpoint.npz.abc.tmp").write_bytes(b"half")
    result = _cli(*_train_args(condition, out, "--resume"))
    assert result.returncode == 0, result.stderr
    assert same(snapshot(out), expected)
    # a deleted checkpoint of a finished phase, or one older than the table: refused, untouched
    for damage in ("delete", "older"):
        out = tmp_path / damage
        shutil.copytree(src, out)
        gross = next(out.glob("phases/gross-*"))
        if damage == "delete":
            (gross / "checkpoint.npz").unlink()
        else:
            (gross / "final.npz").unlink()
            shutil.copy(pre / "checkpoint.npz", gross / "checkpoint.npz")
        before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file() and p.name != ".lock"}
        result = in_process(*_train_args(condition, out, "--resume"))
        assert result.returncode == 2 and "checkpoint.npz" in result.stderr, result.stderr
        assert result.stderr.count("\n") == 1
        after = {p: p.read_bytes() for p in out.rglob("*") if p.is_file() and p.name != ".lock"}
        assert after == before


@pytest.mark.parametrize("content", ["[]", "null", '"x"'])
def test_malformed_manifest_is_one_line(condition, reference, tmp_path, content, in_process):
    out = tmp_path / "run"
    shutil.copytree(reference[0], out)
    (out / "manifest.json").write_text(content)
    run = _cli if content == "[]" else in_process  # the others in this process: the same code
    for args in (_train_args(condition, out, "--resume"), ["evaluate", out]):
        result = run(*args)
        assert result.returncode == 2 and "manifest.json" in result.stderr, result.stderr
        assert result.stderr.count("\n") == 1


def test_manifest_with_a_null_ball_and_a_binary_manifest(reference, tmp_path, in_process):
    out = tmp_path / "run"
    shutil.copytree(reference[0], out)
    m = json.loads((out / "manifest.json").read_text())
    m["settings"]["world"]["ball"] = None
    (out / "manifest.json").write_text(json.dumps(m))
    result = in_process("evaluate", out)
    assert result.returncode == 2 and "manifest.json" in result.stderr, result.stderr
    (out / "manifest.json").write_bytes(bytes(range(256)))
    result = in_process("evaluate", out)
    assert result.returncode == 2 and "manifest.json" in result.stderr, result.stderr


def test_snapshots_are_kept_and_a_damaged_one_is_named(reference, tmp_path, in_process):
    src, expected, *_ = reference
    shots = [f for f in expected["files"] if "/snapshots/" in f]
    assert len(shots) == 2, expected["files"]  # generation 1 of each phase
    out = tmp_path / "run"
    shutil.copytree(src, out)
    result = in_process("evaluate", out, "--robots", "1", "--record", "none",
                        "--development", "1", "--workers", "1")
    assert result.returncode == 0, result.stderr
    assert pl.read_parquet(out / "development.parquet").height == 2 * 45
    (out / shots[0]).write_bytes(b"not a snapshot")
    (out / "development.parquet").unlink()
    result = _cli("evaluate", out, "--robots", "1", "--record", "none", "--development", "1",
                  "--workers", "1")
    last = result.stderr.strip().splitlines()[-1]  # after the post-evaluation's own lines
    # a snapshot the manifest recorded is refused as damaged (its hash), naming what to do
    assert result.returncode == 2 and shots[0] in last and "damaged" in last \
        and "delete it" in last, result.stderr
    assert "Traceback" not in result.stderr


def test_same_named_conditions_and_unfit_names_are_refused(condition, tmp_path, in_process):
    copy = tmp_path / "copy.toml"
    copy.write_text(CONDITION.replace("generations_per_phase = 1", "generations_per_phase = 2"))
    result = _cli("train", condition, copy, "--out", tmp_path / "r")
    assert result.returncode == 2 and "named two" in result.stderr, result.stderr
    assert not (tmp_path / "r").exists()
    long = tmp_path / "long.toml"
    long.write_text(CONDITION.replace('name = "pre"', f'name = "{"p" * 260}"'))
    result = in_process("train", long, "--out", tmp_path / "r")
    assert result.returncode == 2 and "at most 64 characters" in result.stderr, result.stderr


def test_os_errors_are_one_line(condition, tmp_path):
    too_long = tmp_path / ("x" * 300)
    result = _cli(*_train_args(condition, too_long))
    assert result.returncode == 2 and "File name too long" in result.stderr, result.stderr
    assert result.stderr.count("\n") == 1
    if os.geteuid() != 0:  # root writes through permissions
        locked = tmp_path / "locked"
        locked.mkdir(mode=0o500)
        result = _cli(*_train_args(condition, locked / "run"))
        assert result.returncode == 2 and "Permission denied" in result.stderr, result.stderr


def test_pool_workers_die_with_their_parent(condition, tmp_path):
    out = tmp_path / "run"
    args = _train_args(condition, out)
    args[args.index("--workers") + 1] = "2"
    args[args.index("--steps") + 1] = "200"
    parent = subprocess.Popen([sys.executable, "-m", "dart_reach.cli", *args],
                              stderr=subprocess.DEVNULL)
    children: set[int] = set()
    deadline = time.monotonic() + 120
    while len(children) < 2 and time.monotonic() < deadline:
        children = _descendants(parent.pid) - {parent.pid}
        time.sleep(0.2)
    assert len(children) >= 2, "the pool never started"
    parent.send_signal(signal.SIGKILL)
    parent.wait()
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(_alive(p) for p in children):
        time.sleep(0.2)
    assert not [p for p in children if _alive(p)], "a worker outlived its parent"


def _descendants(pid: int) -> set[int]:
    out = subprocess.run(["ps", "-e", "-o", "pid=,ppid="], capture_output=True, text=True)
    parents = {}
    for line in out.stdout.split("\n"):
        if line.strip():
            p, pp = map(int, line.split())
            parents[p] = pp
    found, frontier = {pid}, {pid}
    while frontier:
        frontier = {p for p, pp in parents.items() if pp in frontier} - found
        found |= frontier
    return found


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().split(")")[-1].split()[0]
    except FileNotFoundError:
        return False
    return state != "Z"


def test_ray_address_with_nothing_there_fails_in_one_line(condition, tmp_path):
    pytest.importorskip("ray")
    # the timeout only guards the suite against a hang; how fast it fails is not tested here
    result = _cli(*_train_args(condition, tmp_path / "r"), "--ray", "127.0.0.1:1", timeout=60)
    assert result.returncode == 2 and "127.0.0.1:1" in result.stderr, result.stderr
    assert result.stderr.count("\n") == 1


def test_small_bad_inputs_name_the_option(tmp_path, in_process):
    for i, (args, fragment) in enumerate(((["reach", "--seconds", "-1"], "--seconds"),
                                          (["reach", "--seconds", "0"], "--seconds"),
                                          (["reach", "--seconds", "inf"], "--seconds"),
                                          (["bench", "--seconds", "-1"], "--seconds"),
                                          (["bench", "--repeats", "0"], "--repeats"),
                                          (["read", tmp_path], "directory"),
                                          (["read", ""], "FILE.rrd: expected a path, got an "
                                                         "empty one"),
                                          (["train", "standard", "--out", " "],
                                           "--out: expected a path"))):
        result = (_cli if i == 0 else in_process)(*args)  # the others: the same code, here
        assert result.returncode == 2 and fragment in result.stderr, (args, result.stderr)
        assert result.stderr.count("\n") == 1, result.stderr


def test_files_honour_the_umask_and_commands_are_quoted(condition, tmp_path):
    out = tmp_path / "with space"
    result = subprocess.run(
        ["sh", "-c", 'umask 022 && exec "$0" -m dart_reach.cli "$@"', sys.executable,
         *_train_args(condition, out)], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert f"dart-reach evaluate '{out}'" in result.stderr
    for p in out.rglob("*"):
        if p.is_file():
            assert p.stat().st_mode & 0o777 == 0o644, p


def test_evaluate_is_locked_and_sigterm_keeps_every_robot_it_reported(reference, tmp_path):
    out = tmp_path / "run"
    shutil.copytree(reference[0], out)
    first = subprocess.Popen([sys.executable, "-m", "dart_reach.cli", "evaluate", str(out),
                              "--sensors", "all", "--record", "none", "--workers", "1"],
                             stderr=subprocess.PIPE, text=True)
    reported, done = 0, re.compile(r"(\d+)/\d+ robots")
    for line in first.stderr:
        if done.search(line):
            reported = int(done.search(line).group(1))
            break
    second = _cli("evaluate", out, "--workers", "1")
    assert second.returncode == 2 and f"PID {first.pid}" in second.stderr, second.stderr
    first.send_signal(signal.SIGTERM)
    rest = first.stderr.read()
    first.wait(timeout=60)
    assert first.returncode == 143, rest
    assert "interrupted" in rest and "Traceback" not in rest
    for line in rest.splitlines():
        if done.search(line):
            reported = int(done.search(line).group(1))
    table = pl.read_parquet(out / "evaluation.parquet")
    saved = int(re.search(r"interrupted: (\d+) trials are saved", rest).group(1))
    # every reported robot kept, whole robots only; at most the one whose progress line the
    # signal pre-empted beyond them
    assert saved == table.height and table.height % 45 == 0, rest
    assert reported >= 1 and reported * 45 <= table.height <= (reported + 1) * 45
