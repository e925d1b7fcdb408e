"""The learner's guide runs: docs/guides/ppo_example.py trains stable-baselines3's PPO on the
environment for one rollout (2,048 steps) and scores it as the GA scores an individual, beside
the GA of a committed run. Skipped without stable-baselines3 (the ``rl`` extra); the learning
itself is a documented result (docs/guides/gymnasium.md), not a timed test."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("gymnasium")
pytest.importorskip("stable_baselines3")

ROOT = Path(__file__).resolve().parents[2]


def test_the_ppo_example_trains_and_scores_a_policy():
    out = subprocess.run(
        [sys.executable, str(ROOT / "docs/guides/ppo_example.py"), "--timesteps", "2048",
         "--ga-run", str(ROOT / "recordings/replication-50x10")],
        capture_output=True, text=True, timeout=900, cwd=ROOT)
    assert out.returncode == 0, out.stderr[-3000:]
    result = json.loads(out.stdout)
    assert result["timesteps"] == 2048 and result["trials"] == 10
    for key in ("home_posture", "ppo_untrained", "ppo_trained"):
        assert 0.0 <= result[key] <= 1.0 and math.isfinite(result[key]), key
    assert result["ga"]["generation"] == 1 and result["ga"]["replications"] == 10
