"""Data shipped with the package: genomes of evolved robots (benchmarks and tests need
robots that move and touch the ball like evolving ones, not only random networks)."""

from __future__ import annotations

import json
from importlib import resources

import numpy as np


def evolved_pre() -> tuple[np.ndarray, np.ndarray, dict]:
    """The final population of the learning check of docs/analysis.md (pre-reaching, 30
    generations): genomes (20, N_GENES) uint8 best first, their lifetime fitness, and the
    provenance (command, git revision, phase)."""
    info = json.loads(resources.files(__package__).joinpath("evolved_pre.json").read_text())
    genomes = np.array([np.frombuffer(bytes.fromhex(h), np.uint8)
                        for h in info.pop("genomes_hex")])
    return genomes, np.array(info.pop("lifetime_fitness")), info
