"""Trials scheduled in blocks (``backends.run_block``): the fitness of every job is the same to
the last bit whatever the block size, the number of workers and the back-end (serial and the
local pool here; real Ray clusters of several one-CPU nodes in tests/evolution/
test_ray_cluster.py, on these jobs), and the block a Ray back-end chooses follows the driver's
measured cost as ``ray_block``'s model says."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dart_reach.evolution.backends import (RAY_DRIVER_HEADROOM, Job, MapCost, PoolBackend,
                                           RayBackend, SerialBackend, ray_block)
from dart_reach.evolution.conditions import load_condition
from dart_reach.evolution.genome import as_groups
from dart_reach.evolution.settings import Settings, trial_config
from dart_reach.robots import robots

TRIALS = 18


def _jobs() -> list[Job]:
    """The best 2 shipped pre- and fine-reachers, 18 trials of 12 steps each."""
    phases = {p.name: p for p in load_condition("standard").phases}
    settings = Settings(trials=TRIALS, steps=12)
    jobs = []
    for name in ("pre", "fine"):
        trial = trial_config(phases[name], settings)
        for i, robot in enumerate(robots(name, run="replication-50x10")[:2]):
            jobs.append(Job(robot.genome, as_groups(phases[name].free_groups), trial,
                            settings.world, (3, len(jobs), i)))
    return jobs


@pytest.fixture(scope="module")
def serial():
    backend = SerialBackend()
    return backend.map(_jobs()), backend.last_cost


def test_blocks_and_pool_give_the_serial_bits_and_their_cost(serial):
    expected, cost = serial
    assert (cost.tasks, cost.trials) == (4 * TRIALS, 4 * TRIALS)  # a trial per task
    assert cost.worker_cpu_s > 0 and cost.driver_cpu_s >= cost.worker_cpu_s  # in-process
    pool = PoolBackend(2)
    try:
        assert np.array_equal(pool.map(_jobs()), expected)
        assert pool.last_cost.tasks == 4 * TRIALS
    finally:
        pool.close()
    for block, tasks in ((1, 72), (5, 16), (TRIALS, 4), (100, 4)):
        backend = SerialBackend()
        backend.block_for = lambda trials, b=block: b
        assert np.array_equal(backend.map(_jobs()), expected), block
        assert backend.last_cost.tasks == tasks


def test_ray_block_is_the_smallest_that_keeps_the_driver_within_its_share():
    # a task costs the driver 1 ms, a trial a worker 50 ms
    cost = MapCost(tasks=100, trials=1800, driver_cpu_s=0.1, worker_cpu_s=90.0, wall_s=1.0)
    for cpus in (2, 16, 64, 256):
        b = ray_block(cost, cpus, TRIALS)
        assert b == min(TRIALS, max(1, math.ceil(RAY_DRIVER_HEADROOM * 0.001 * cpus / 0.05)))
        share = 1800 * 0.05 / cpus / RAY_DRIVER_HEADROOM  # the driver's allowance, s
        if b < TRIALS:  # within it, and the next smaller block would not be
            assert 0.001 * 1800 / b <= share + 1e-12
            assert b == 1 or 0.001 * 1800 / (b - 1) > share
    assert [ray_block(cost, n, TRIALS) for n in (2, 16, 64, 256)] == [1, 2, 6, 18]
    assert ray_block(MapCost(0, 0, 0.0, 0.0, 0.0), 8, TRIALS) == TRIALS  # nothing measured
    with pytest.raises(ValueError, match="block"):
        RayBackend("local", block=0)
