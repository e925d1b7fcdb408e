"""Real multi-node Ray clusters on this machine (``LocalRayCluster``: every node a ``ray start``
on the loopback address). One cluster serves every check of this file, grown node by node:
trials in blocks of 1, of a lifetime (18) and of the size the back-end chooses give the serial
back-end's fitness to the last bit on clusters of 1, 2 and 4 nodes; training through it is the
serial run, and stays so when a worker node dies in the middle of a generation (its tasks run
again elsewhere). The node is lost last: it leaves the cluster smaller."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

from dart_reach.evolution.backends import LocalRayCluster, RayBackend, SerialBackend, ray_block
from test_backends_blocks import TRIALS, _jobs
from test_trainer import _result, _same

ray = pytest.importorskip("ray")
ENV = dict(os.environ, RAY_AUTH_MODE="disabled", RAY_USAGE_STATS_ENABLED="0")
TRAIN = ["gross-hat", "--replications", "1", "--trials", "2", "--steps", "10", "--seed", "5",
         "--generations", "1"]  # 2 generations of one phase: 40 lifetimes of 2 trials each


@pytest.fixture(scope="module")
def cluster():
    """One local cluster for the file, its head alone at first; this process joins it as a
    driver at the first ``RayBackend`` and leaves it before it stops."""
    with LocalRayCluster(nodes=1) as c:
        try:
            yield c
        finally:
            ray.shutdown()


def _grow(cluster: LocalRayCluster, nodes: int) -> None:
    while len(cluster.nodes) < nodes:
        cluster.add_node()


def test_ray_clusters_of_several_nodes_and_any_block_give_the_serial_bits(cluster):
    """Blocks of one trial; then the default's: a lifetime (18) in the first generation, and in
    the next the size chosen from the first's measured cost."""
    expected = SerialBackend().map(_jobs())
    for nodes in (1, 2, 4):  # 4: more nodes than this machine's 2 cores, as on a busy host
        _grow(cluster, nodes)
        one = RayBackend(cluster.address, block=1)
        assert one.workers == nodes
        assert np.array_equal(one.map(_jobs()), expected), (nodes, 1)
        assert one.last_cost.tasks == 4 * TRIALS
        chosen = RayBackend(cluster.address)
        assert np.array_equal(chosen.map(_jobs()), expected), (nodes, TRIALS)
        first = chosen.last_cost
        assert first.tasks == 4
        block = chosen.block_for(TRIALS)
        assert block == ray_block(first, nodes, TRIALS)
        assert np.array_equal(chosen.map(_jobs()), expected), (nodes, block)
        assert chosen.last_cost.tasks == 4 * math.ceil(TRIALS / block)


def _train(out: Path, *args) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "dart_reach.cli", "train", *TRAIN,
                             "--out", str(out), *args], env=ENV, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)


def test_training_on_a_cluster_survives_losing_a_node_mid_generation(cluster, tmp_path,
                                                                      in_process):
    _grow(cluster, 2)  # or more, after the test above
    assert cluster.cpus() == len(cluster.nodes)
    serial = in_process("train", *TRAIN, "--out", tmp_path / "serial", "--workers", "1")
    assert serial.returncode == 0, serial.stdout + serial.stderr

    # Kill a worker node (SIGKILL to all its processes) as the second (last) generation starts:
    # its tasks are lost mid-generation and run again on the nodes left.
    lossy = _train(tmp_path / "lossy", "--ray", cluster.address)
    lines = []
    for line in lossy.stdout:
        lines.append(line)
        if re.search(r"\| 1/\d+ generations", line):  # the first one is committed
            cluster.kill_node(len(cluster.nodes) - 1)
            break
    out = "".join(lines) + lossy.communicate(timeout=600)[0]
    assert lossy.returncode == 0, out
    assert cluster.nodes[-1].poll() is not None  # the node's `ray start` was killed
    assert _same(_result(tmp_path / "serial"), _result(tmp_path / "lossy"))

    # the stopped cluster is forgotten: a later ray.init() or '--ray auto' does not look for it
    ray.shutdown()
    cluster.close()
    current = Path(tempfile.gettempdir()) / "ray" / "ray_current_cluster"
    port = cluster.address.rpartition(":")[2]
    assert not (current.is_file() and current.read_text().strip().endswith(":" + port))
