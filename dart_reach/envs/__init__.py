"""The paper's trial as a Gymnasium environment (the ``gym`` extra; docs/guides/gymnasium.md).

``import dart_reach`` registers it as ``dart_reach/ReachGrasp-v2`` where Gymnasium is installed:
``gymnasium.make("dart_reach/ReachGrasp-v2", phase="gross")`` (``-v1``: the same on model
version 1). ``reach_grasp``: the
environment, a thin wrapper over ``model.task.Trial``; ``policy``: a controller network (a
shipped robot's) as a policy; ``seeing``: an episode as a Rerun recording like a trial's
(imported apart: rerun and polars take about a second to load, which every process of a
vector environment would pay). Its ``rgb_array`` frames are ``viewing.episode``'s, a camera
image drawn in numpy; its ``human`` mode streams to a Rerun viewer (``viewing.live``).
"""

from .policy import NetworkPolicy
from .reach_grasp import REFLEX_MOTORS, ReachGraspEnv, check_ball_position, shipped_phases

__all__ = ["REFLEX_MOTORS", "NetworkPolicy", "ReachGraspEnv", "check_ball_position",
           "shipped_phases"]
