"""The training digest: what the genetic algorithm computes is pinned to the last bit, so that a
faster revision may take over a long run at a resume only when it trains exactly as the
revision that began it (docs/guides/runs.md, "Long runs").

Two parts, each a digest of float64 bytes:

- the lifetime fitness the back-ends give the shipped evolved robots of the ten-replication
  run (``replication-50x10``: 2 of each of pre-, gross- and fine-reaching, 9 trials of 200
  steps at the GA's positions), robots that touch and hold the ball, so that the contacts,
  the grasp reflex and the offset sensors all count;
- a tiny training of the standard condition (2 generations per phase, 2 replications, 2
  trials of 30 steps): its generations table and every phase's final population.

Version 1's digests were computed at revision 101bebd (the revision that began the full-budget run
``standard-500x10``), on x86_64 with dartpy 6.20.0 and numpy 2.4.6 at numpy's AVX2 dispatch
level (``provenance.simd``: the level ``import dart_reach`` pins). Elsewhere the test is
skipped, as the trial digests of tests/model/test_task.py are.
"""

from __future__ import annotations

import hashlib

import numpy as np
import polars as pl
import pytest

from dart_reach.evolution.backends import Job, SerialBackend
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.genome import as_groups
from dart_reach.evolution.settings import Settings, trial_config
from dart_reach.evolution.trainer import train
from dart_reach.robots import robots

#: Per model version, per numpy dispatch level. The campaign's version (3, its own scene and
#: version 2's compiled numerics) is pinned here at the revision that registers it, before its
#: campaign begins.
GOLDEN = {1: {"X86_V3": {"robots": "f81ed924ac7e7e19", "training": "0fe27afab9a601aa"}},
          3: {"X86_V3": {"robots": "a73ee4b07c7a51d6", "training": "a88c5fe651f30d5e"}}}
GOLDEN_PLATFORM = ("x86_64", "6.20.0", "2.4.6")


def _golden_platform() -> bool:
    import platform
    from importlib.metadata import version

    from dart_reach.evolution.provenance import simd

    return ((platform.machine(), version("dartpy"), np.__version__) == GOLDEN_PLATFORM
            and simd() in GOLDEN[1])


def _digest(values) -> str:
    return hashlib.sha256(np.ascontiguousarray(values, dtype=np.float64).tobytes()
                          ).hexdigest()[:16]


def robots_fitness(version: int = 1) -> np.ndarray:
    """The lifetime fitness (9 trials) of the best 2 shipped robots of each phase under a
    model version (its numerics, levers and scene)."""
    phases = {p.name: p for p in load_condition("standard").phases}
    settings = Settings(trials=9, model_version=version)
    jobs = []
    for name, phase in phases.items():
        trial = trial_config(phase, settings)
        for i, robot in enumerate(robots(name, run="replication-50x10")[:2]):
            jobs.append(Job(robot.genome, as_groups(phase.free_groups), trial, settings.world,
                            (49, i)))
    return SerialBackend().map(jobs)


def tiny_training(out, version: int = 1) -> np.ndarray:
    """The fitness columns of a tiny training's generations table and its final populations
    (genes and fitness), as one float64 vector."""
    settings = Settings(replications=2, trials=2, steps=30, seed=49, model_version=version)
    run = train([scaled(load_condition("standard"), 2)], settings, out, workers=1,
                progress=False)
    stats = pl.read_parquet(run.out / "generations.parquet").sort(
        "phase_key", "replication", "generation")
    parts = [stats[c].to_numpy() for c in ("best", "mean", "min")]
    for d in sorted((run.out / "phases").iterdir()):
        with np.load(d / "final.npz") as f:
            parts += [f["population"].ravel().astype(np.float64), f["fitness"].ravel()]
    return np.concatenate(parts)


@pytest.mark.skipif(not _golden_platform(), reason=f"digests recorded on {GOLDEN_PLATFORM} "
                    f"(machine, dartpy, numpy) at numpy dispatch levels {sorted(GOLDEN[1])}")
@pytest.mark.parametrize("version", sorted(GOLDEN))
def test_training_is_bit_identical_to_the_revision_that_began_its_versions_runs(tmp_path,
                                                                                 version):
    """Version 1: the revision that began ``standard-500x10``; version 3: the revision
    that registered it, before its campaign (``recordings/campaign/standard-v3``) began."""
    from dart_reach.evolution.provenance import simd

    fitness = robots_fitness(version)
    assert (fitness > 0).sum() >= 3  # robots that touch: contacts count in the digest
    found = {"robots": _digest(fitness),
             "training": _digest(tiny_training(tmp_path / "run", version))}
    assert found == GOLDEN[version][simd()]
