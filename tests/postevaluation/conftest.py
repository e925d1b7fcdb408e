"""A tiny real run (the standard condition, 1 generation per phase, 2 replications) shared by
the post-evaluation tests; they copy it before writing into it."""

from __future__ import annotations

import pytest

from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train


@pytest.fixture(scope="session")
def trained(tmp_path_factory):
    out = tmp_path_factory.mktemp("runs") / "tiny"
    train([scaled(load_condition("standard"), 1)],
          Settings(replications=2, trials=1, steps=5, seed=1), out, workers=1)
    return out
