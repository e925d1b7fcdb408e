"""An episode of ``ReachGraspEnv`` as a Rerun recording like a trial's (the trial's own
``recording.trial_rrd``, so the trial layout and ``dart-reach`` readers work on it). Imported
apart from the environment: rerun and polars take about a second to load, which every process
of a vector environment would pay. Its frames (``render_mode="rgb_array"``) are
``viewing.episode``'s.
"""

from __future__ import annotations

from pathlib import Path

from ..recording.rrd import RobotModel, trial_rrd, write_rrd
from .reach_grasp import ReachGraspEnv


def _unwrapped(env) -> ReachGraspEnv:
    env = getattr(env, "unwrapped", env)
    if not isinstance(env, ReachGraspEnv):
        raise TypeError(f"expected a ReachGraspEnv (or a wrapper of one), got "
                        f"{type(env).__name__}")
    if env.trial_data is None:
        raise ValueError("no episode to record: call reset() first")
    return env


def episode_rrd(env, blueprint: bool = True) -> bytes:
    """The .rrd bytes of the current episode of ``env`` (its steps so far), written as
    ``Trial.run``'s trials are (``recording.trial_rrd``): the scene, every sensor, motor and
    fitness term over time. The internal neurons read 0 (a policy's state is not known)."""
    env = _unwrapped(env)
    return trial_rrd(env.trial_data, env.recording_info(), RobotModel(env.world),
                     env.world.config.control_dt, blueprint=blueprint)


def record_episode(env, path) -> Path:
    """Write the current episode of ``env`` to the .rrd file ``path`` (``rerun PATH`` shows
    it); returns the path."""
    return write_rrd(Path(path), episode_rrd(env))
