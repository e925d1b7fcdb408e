"""The paper's trial as a Gymnasium environment (the ``gym`` extra; docs/guides/gymnasium.md).

``import dart_reach`` registers it as ``dart_reach/ReachGrasp-v0`` where Gymnasium is installed:
``gymnasium.make("dart_reach/ReachGrasp-v0", phase="gross")``. ``reach_grasp``: the
environment, a thin wrapper over ``model.task.Trial``; ``seeing``: an episode as a Rerun
recording like a trial's, and the frames of ``render_mode="rgb_array"`` (imported apart: rerun
and polars take about a second to load, which every process of a vector environment would pay).
"""

from .reach_grasp import REFLEX_MOTORS, ReachGraspEnv, shipped_phases

__all__ = ["REFLEX_MOTORS", "ReachGraspEnv", "shipped_phases"]
