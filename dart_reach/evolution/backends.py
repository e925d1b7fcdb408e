"""The parallel back-ends: the lifetimes of many genomes (and any other work unit, such as the
post-evaluation's robots), behind one interface with three implementations.

``SerialBackend`` (one process), ``PoolBackend`` (a local process pool, the default: all
cores) and ``RayBackend`` (a Ray cluster, the ``cluster`` extra). A job carries everything
that defines its result — the genome, the phase's free groups, the trial configuration, the world
configuration and its own seed — so the fitness of a job does not depend on which worker runs it,
in which order, or how many workers there are: results are identical to the last bit.

DART worlds cannot be pickled: each worker process builds its world once per ``WorldConfig``
and keeps it.

Work is scheduled in *blocks* of consecutive trials of one lifetime (``run_block``): one trial
per block in the local pool (no worker idles at a generation's end), more on a Ray cluster,
where every task costs the driver CPU time to submit and collect (``RayBackend``, ``block``).
A trial's result depends on its job and its index only, so the block size, the number of
workers and the back-end never change a bit (tests/evolution/test_backends_blocks.py). After
each ``map`` a back-end keeps what it cost (``MapCost``: tasks, the driver's CPU, the workers'
CPU, the wall time), which the training prints and the bench's scaling model reads.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import resource
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Iterator, Sequence, TypeVar

import numpy as np

from ..errors import UsageError
from .genome import decode
from .settings import seed_at
from ..model.task import Trial, TrialConfig, network_for, trial_positions
from ..model.world import World, WorldConfig


@dataclass(frozen=True)
class Job:
    """One lifetime: a genome's fitness over ``trial.trials`` trials."""

    genome: np.ndarray  # uint8 genes
    free_groups: frozenset
    trial: TrialConfig
    world: WorldConfig
    seed: tuple[int, ...]  # where its seed sits in the run's tree (settings.seed_address)


_WORLDS: dict[WorldConfig, World] = {}
_TRIALS: dict[tuple[WorldConfig, TrialConfig], Trial] = {}


def worker_trial(world: WorldConfig, trial: TrialConfig) -> Trial:
    """The ``Trial`` of this process for a world and trial configuration, built on first use."""
    runner = _TRIALS.get((world, trial))
    if runner is None:
        if world not in _WORLDS:
            _WORLDS[world] = World(world)
        runner = _TRIALS[(world, trial)] = Trial(_WORLDS[world], trial)
    return runner


def _rng(job: Job) -> np.random.Generator:
    return np.random.default_rng(seed_at(job.seed))


_NETWORK: list = [None, None]  # (genome bytes, groups, trial config), Network: the last built
_POSITIONS: list = [None, None]  # (seed, world, trials), the ball's positions: the last drawn


def run_trial(unit: tuple[Job, int]) -> float:
    """The fitness of trial k of a job: the same trial, at the same position, as trial k of
    ``task.lifetime`` with the job's generator."""
    job, k = unit
    trial = worker_trial(job.world, job.trial)
    key = (job.seed, job.world, job.trial.trials)
    if _POSITIONS[0] != key:
        _POSITIONS[:] = key, trial_positions(trial.world, _rng(job), job.trial.trials)
    position = _POSITIONS[1][k][1]
    key = (job.genome.tobytes(), job.free_groups, job.trial)
    if _NETWORK[0] != key:
        _NETWORK[:] = key, network_for(decode(job.genome, job.free_groups), job.trial)
    return trial.fitness(_NETWORK[1], position)


def run_block(unit: tuple[Job, int, int]) -> tuple[list[float], float]:
    """Trials ``start`` to ``stop`` - 1 of a job (``run_trial`` each) and the CPU seconds this
    worker spent on them."""
    job, start, stop = unit
    t0 = time.process_time()
    fitness = [run_trial((job, k)) for k in range(start, stop)]
    return fitness, time.process_time() - t0


@dataclass(frozen=True)
class MapCost:
    """What one ``Backend.map`` cost: ``tasks`` (blocks), ``trials``, ``driver_cpu_s`` (the
    calling process's CPU seconds: submitting, collecting, bookkeeping; with
    ``SerialBackend`` the trials too), ``worker_cpu_s`` (the CPU seconds spent on the trials,
    summed over the workers) and ``wall_s``."""

    tasks: int
    trials: int
    driver_cpu_s: float
    worker_cpu_s: float
    wall_s: float


def peak_rss_mb(_=None) -> float:
    """This process's peak resident memory (MB); sent to a pool's workers, each worker's. It
    lives here, beside the work it measures, so that a worker loads nothing more to run it
    (from the bench's module it would import Rerun, and hold several times the training's
    memory: docs/results/benchmarks.md, "Memory")."""
    time.sleep(0.2)  # so that every worker takes one of these tasks
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def fitness_of_trials(trials: Sequence[float]) -> float:
    """A lifetime's fitness from its trials' fitness, exactly as ``task.lifetime`` computes
    it; a non-finite result scores 0 (the worst)."""
    fitness = float(np.mean(trials))
    return fitness if np.isfinite(fitness) else 0.0


T = TypeVar("T")
R = TypeVar("R")


class Backend:
    """Runs a module-level function over items on the workers; results in item order."""

    workers: int = 1
    #: the cost of the last ``map`` (None before the first)
    last_cost: MapCost | None = None

    def imap(self, fn: Callable[[T], R], items: Iterable[T]) -> Iterator[R]:
        raise NotImplementedError

    def block_for(self, trials: int) -> int:
        """Trials per task for lifetimes of ``trials`` trials: one, so that no worker idles
        at the end of a generation while another finishes a whole lifetime."""
        return 1

    def map(self, jobs: Sequence[Job]) -> np.ndarray:
        """The fitness of every job, scheduled in blocks of ``block_for`` trials; the result
        is the same to the last bit as running job by job (``task.lifetime``), whatever the
        blocks. Its cost is kept in ``last_cost``."""
        t0, cpu0 = time.monotonic(), time.process_time()
        units = []
        for job in jobs:
            n = job.trial.trials
            b = max(1, min(self.block_for(n), n))
            units += [(job, k, min(k + b, n)) for k in range(0, n, b)]
        trials, worker_cpu = [], 0.0
        for fitness, cpu in self.imap(run_block, units):
            trials += fitness
            worker_cpu += cpu
        at = np.cumsum([0] + [job.trial.trials for job in jobs])
        result = np.array([fitness_of_trials(trials[at[i]:at[i + 1]])
                           for i in range(len(jobs))], dtype=float)
        self.last_cost = MapCost(len(units), len(trials), time.process_time() - cpu0,
                                 worker_cpu, time.monotonic() - t0)
        return result

    def close(self) -> None:
        pass


class SerialBackend(Backend):
    def imap(self, fn, items):
        return map(fn, items)


class PoolBackend(Backend):
    """A pool of ``workers`` local processes (default: every core)."""

    def __init__(self, workers: int | None = None):
        self.workers = workers or os.cpu_count() or 1
        if self.workers < 1:
            raise ValueError(f"workers must be at least 1, got {self.workers}")
        self._pool = ProcessPoolExecutor(
            self.workers, mp_context=multiprocessing.get_context("forkserver"),
            initializer=_exit_with_parent, initargs=(os.getpid(),))

    def imap(self, fn, items):
        # One item at a time per worker keeps the load balanced; results come in item order.
        return self._pool.map(fn, items)

    def close(self) -> None:
        self._pool.shutdown(cancel_futures=True)


def _exit_with_parent(parent: int, period_s: float = 0.5) -> None:
    """Pool worker initializer: end this worker as soon as the process that made the pool is
    gone, however it ended (a SIGKILL runs no clean-up of its own)."""
    def watch() -> None:
        while True:
            time.sleep(period_s)
            try:
                os.kill(parent, 0)
            except ProcessLookupError:
                os._exit(1)
            except PermissionError:  # the PID now belongs to another user's process
                os._exit(1)
    threading.Thread(target=watch, daemon=True, name="exit-with-parent").start()


#: Times Ray runs a task again when the node or worker process running it dies (a task is a
#: pure function of its job: run again, it returns the same result to the last bit).
RAY_TASK_RETRIES = 5
#: s to wait for a Ray cluster's address to answer before giving up.
RAY_CONNECT_TIMEOUT_S = 10.0


def _check_reachable(address: str) -> None:
    """ValueError unless something listens at a ``host:port`` (or ``ray://host:port``)
    address: ``ray.init`` would wait for minutes."""
    hostport = address.split("://", 1)[-1]
    host, sep, port = hostport.rpartition(":")
    if not sep or not port.isdigit():
        raise UsageError(f"ray_address={address!r}: expected 'auto', 'local' or HOST:PORT",
                         cli=f"--ray {address}: expected 'auto', 'local' or HOST:PORT")
    try:
        socket.create_connection((host, int(port)), timeout=RAY_CONNECT_TIMEOUT_S).close()
    except OSError as exc:
        why = f"no Ray cluster answers there ({exc.strerror or exc})"
        raise UsageError(f"ray_address={address!r}: {why}", cli=f"--ray {address}: {why}"
                         ) from None


def _free_port() -> int:
    """A TCP port free on the loopback address now (the system's choice)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _driver_ip(address: str) -> dict:
    """``ray.init`` options for a cluster at ``address``: a cluster on this machine's loopback
    address (nodes started with ``--node-ip-address 127.0.0.1``) needs the driver on it too,
    or Ray looks for a node on the machine's outward address and waits for ever."""
    host = address.split("://", 1)[-1].rpartition(":")[0]
    return {"_node_ip_address": host} if host in ("127.0.0.1", "localhost") else {}


#: Blocks on a Ray cluster are sized so that submitting and collecting the tasks would take the
#: driver at most 1 / RAY_DRIVER_HEADROOM of a generation's wall time (``ray_block``).
RAY_DRIVER_HEADROOM = 4


def ray_block(cost: MapCost, cpus: int, trials: int) -> int:
    """Trials per Ray task for the next generation, from the last one's ``cost`` on ``cpus``
    CPUs, for lifetimes of ``trials`` trials. The model (docs/guides/cluster.md, "Blocks"): a
    task costs the driver d = driver CPU / tasks, a trial costs a worker c = worker CPU /
    trials; a generation of T trials in blocks of b keeps the workers busy T c / N and the
    driver d T / b, and ends with a tail of about one block, b c. The smallest b with
    d T / b <= (T c / N) / H, b = ceil(H d N / c), keeps the driver out of the way and the
    tail shortest; clamped to 1 .. ``trials``."""
    if cost.tasks == 0 or cost.trials == 0 or cost.worker_cpu_s <= 0:
        return trials
    d = cost.driver_cpu_s / cost.tasks
    c = cost.worker_cpu_s / cost.trials
    return int(min(trials, max(1, math.ceil(RAY_DRIVER_HEADROOM * d * cpus / c))))


class RayBackend(Backend):
    """The same jobs as Ray tasks (``--ray auto`` or a cluster address), in blocks of
    ``block`` trials, or, by default, of a lifetime for the first ``map`` and of
    ``ray_block``'s size from the last ``map``'s measured cost after it."""

    def __init__(self, address: str = "auto", workers: int | None = None,
                 block: int | None = None):
        if block is not None and (isinstance(block, bool) or not isinstance(block, int)
                                  or block < 1):
            raise ValueError(f"block must be a positive number of trials, got {block!r}")
        self.block = block
        try:
            import ray
        except ImportError:
            extra = "the 'cluster' extra: pip install 'dart_reach[cluster]'"
            raise UsageError(f"ray_address needs {extra}", cli=f"--ray needs {extra}"
                             ) from None
        self._ray = ray
        if not ray.is_initialized():
            options = {"include_dashboard": False, "log_to_driver": False}
            if address == "local":  # a new private instance, never a cluster found on disk
                ray.init(address="local", num_cpus=workers, **options)
            elif address == "auto":
                ray.init(address="auto", **options)
            else:
                _check_reachable(address)
                ray.init(address=address, **options, **_driver_ip(address))
        self.workers = int(ray.cluster_resources().get("CPU", 1))
        self._remote = {}

    def block_for(self, trials: int) -> int:
        if self.block is not None:
            return self.block
        if self.last_cost is None:
            return trials
        return ray_block(self.last_cost, self.workers, trials)

    def imap(self, fn, items):
        remote = self._remote.get(fn)
        if remote is None:
            remote = self._remote[fn] = self._ray.remote(
                num_cpus=1, max_retries=RAY_TASK_RETRIES)(fn)
        refs = [remote.remote(item) for item in items]
        return (self._ray.get(ref) for ref in refs)


def make_backend(workers: int | None = None, ray_address: str | None = None,
                 block: int | None = None) -> Backend:
    """Ray if an address is given (in blocks of ``block`` trials; None: sized from the
    measured cost), else serial for one worker, else a local process pool."""
    if ray_address:
        return RayBackend(ray_address, workers, block)
    if workers == 1:
        return SerialBackend()
    return PoolBackend(workers)


class LocalRayCluster:
    """A Ray cluster of ``nodes`` nodes of ``cpus`` CPUs each on this machine, every node a
    real ``ray start`` (a raylet, its object store and workers) on the loopback address: what
    a cluster of machines is, on one machine, for tests and the bench. Each node runs in its
    own process group, so ``kill_node`` ends one as abruptly as a machine that dies.

    Nodes start one after the other, each counted by the head before the next starts
    (``add_node`` adds one later). What lets several nodes share one machine: each node's
    own ports where Ray's defaults are fixed (the dashboard agent's HTTP port, 52365 on every
    node) or drawn from one range by every node (the workers' ports: chosen by the system
    here), a small object store (``object_store_mb``: a task carries a job, kilobytes; by
    default every node would claim 30 % of the memory), one log monitor (the head's), no
    dashboard, and the workers at the nodes' own priority (Ray runs its workers 15 steps
    nicer than the raylet, ``RAY_worker_niceness``: beside other work on the same cores they
    then get almost no CPU).

    Use as a context manager; ``address`` is what ``--ray`` takes.
    """

    def __init__(self, nodes: int = 2, cpus: int = 1, timeout_s: float = 120.0,
                 object_store_mb: int = 100):
        ray = shutil.which("ray", path=os.path.dirname(sys.executable)) or shutil.which("ray")
        if ray is None:
            raise ValueError("a Ray cluster needs the 'cluster' extra: "
                             "pip install 'dart_reach[cluster]'")
        self._ray, self._cpus_per_node, self._timeout_s = ray, cpus, timeout_s
        self._object_store = str(object_store_mb * 2**20)
        self._env = dict(os.environ, RAY_USAGE_STATS_ENABLED="0", RAY_worker_niceness="0")
        self._env.setdefault("RAY_AUTH_MODE", "disabled")
        port = _free_port()
        self.address = f"127.0.0.1:{port}"
        self.nodes: list = []
        self._logs = tempfile.TemporaryDirectory(prefix="dart-reach-ray-")
        try:
            self._start("--head", "--port", str(port), "--include-dashboard=false")
            for _ in range(nodes - 1):
                self.add_node()
        except BaseException:
            self.close()
            raise

    def add_node(self) -> None:
        """Start one more node, and return once the head counts its CPUs."""
        self._start("--address", self.address, "--include-log-monitor=false")

    def _start(self, *args) -> None:
        log = open(Path(self._logs.name) / f"node-{len(self.nodes)}.log", "wb")
        with log:  # the node writes on after this process has closed its copy
            self.nodes.append(subprocess.Popen(
                [self._ray, "start", "--block", "--num-cpus", str(self._cpus_per_node),
                 "--node-ip-address", "127.0.0.1", "--disable-usage-stats",
                 "--object-store-memory", self._object_store,
                 "--dashboard-agent-listen-port", str(_free_port()),
                 "--min-worker-port", "0", "--max-worker-port", "0", *args],
                env=self._env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True))
        self._wait_for(len(self.nodes) * self._cpus_per_node, self._timeout_s)

    def cpus(self) -> float:
        """The CPUs the cluster's head counts among its live nodes (0 if it does not answer)."""
        out = subprocess.run([self._ray, "status", "--address", self.address], env=self._env,
                             text=True, capture_output=True, timeout=60).stdout
        for line in out.splitlines():  # e.g. " 0.0/2.0 CPU"
            if line.strip().endswith(" CPU") and "/" in line:
                return float(line.split("/")[1].split()[0])
        return 0.0

    def _wait_for(self, cpus: float, timeout_s: float) -> None:
        """Wait until the last node says it has started (its log, read for free), then until
        the head counts ``cpus`` CPUs (``ray status``: a process that imports Ray, over a
        second of CPU, so asked rarely)."""
        deadline = time.monotonic() + timeout_s
        node, log = self.nodes[-1], Path(self._logs.name) / f"node-{len(self.nodes) - 1}.log"
        started = False
        while node.poll() is None and time.monotonic() < deadline:
            if not started:
                started = b"Ray runtime started" in log.read_bytes()
                time.sleep(0.5)
            elif self.cpus() >= cpus:
                return
            else:
                time.sleep(2.0)
        tail = log.read_text(errors="replace").strip().splitlines()[-5:]
        raise RuntimeError(f"the local Ray cluster at {self.address} did not reach {cpus:g} "
                           f"CPUs in {timeout_s:.0f} s; its last node said: " + " | ".join(tail))

    def kill_node(self, index: int) -> None:
        """SIGKILL every process of node ``index`` (0 is the head)."""
        try:
            os.killpg(self.nodes[index].pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.nodes[index].wait()

    def close(self) -> None:
        for i in reversed(range(len(self.nodes))):
            self.kill_node(i)
        # Killed nodes cannot tidy up: forget this cluster, or Ray's next ray.init() (and
        # ``--ray auto``) would look for it.
        current = Path(tempfile.gettempdir()) / "ray" / "ray_current_cluster"
        try:
            if current.read_text().strip().endswith(":" + self.address.rpartition(":")[2]):
                current.unlink()
        except OSError:
            pass
        self._logs.cleanup()

    def __enter__(self) -> "LocalRayCluster":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
