"""A real multi-node Ray cluster on this machine (two ``ray start`` nodes, all traffic on the
loopback address): training through it is bit-identical to the serial back-end, and stays so
when a worker node dies in the middle of a generation (its tasks run again elsewhere)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from dart_reach.evolution.backends import LocalRayCluster
from test_trainer import _result, _same

pytest.importorskip("ray")
ENV = dict(os.environ, RAY_AUTH_MODE="disabled", RAY_USAGE_STATS_ENABLED="0")
TRAIN = ["standard", "--replications", "2", "--trials", "2", "--steps", "30", "--seed", "5",
         "--generations", "3"]


def _train(out: Path, *args) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "dart_reach.cli", "train", *TRAIN,
                             "--out", str(out), *args], env=ENV, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)


def test_training_on_a_two_node_cluster_survives_losing_a_node(tmp_path):
    serial = _train(tmp_path / "serial", "--workers", "1")
    with LocalRayCluster(nodes=2) as cluster:
        assert cluster.cpus() == 2
        two = _train(tmp_path / "two", "--ray", cluster.address)
        out = two.communicate(timeout=600)[0]
        assert two.returncode == 0, out
        assert serial.wait(600) == 0, serial.stdout.read()
        assert _same(_result(tmp_path / "serial"), _result(tmp_path / "two"))

        # Kill the worker node (SIGKILL to all its processes) as the second generation starts.
        lossy = _train(tmp_path / "lossy", "--ray", cluster.address)
        lines = []
        for line in lossy.stdout:
            lines.append(line)
            if re.search(r"\| 1/\d+ generations", line):  # the first one is committed
                cluster.kill_node(1)
                break
        out = "".join(lines) + lossy.communicate(timeout=600)[0]
        assert lossy.returncode == 0, out
        assert cluster.nodes[1].poll() is not None  # the node's `ray start` was killed
    assert _same(_result(tmp_path / "serial"), _result(tmp_path / "lossy"))
    # the killed cluster is forgotten: a later ray.init() or '--ray auto' does not look for it
    current = Path(tempfile.gettempdir()) / "ray" / "ray_current_cluster"
    port = cluster.address.rpartition(":")[2]
    assert not (current.is_file() and current.read_text().strip().endswith(":" + port))
