"""A tiny real run (the standard condition, 1 generation per phase, 2 replications) shared by
the post-evaluation tests (made once for the session); they copy it before writing into it."""

from __future__ import annotations

import pytest

from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train


@pytest.fixture(scope="session")
def trained(built_once):
    def build(root):
        train([scaled(load_condition("standard"), 1)],
              Settings(replications=2, trials=1, steps=5, seed=1), root / "tiny", workers=1)

    return built_once("postevaluation-trained", build) / "tiny"
