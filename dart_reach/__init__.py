"""dart_reach: the reaching-and-grasping development model of Savastano & Nolfi (IEEE TAMD 2013)
on a DART-simulated iCub upper body.

The subpackages follow the data flow, each importing only those before it:

- ``model``: the robot, the DART world and its scenes, the sensors (Eqs. 1-4), the CTRNN and
  its reflexes, one trial and its fitness (Eq. 5), the scripted reach;
- ``measures``: what one trial shows (reach, grasp, path, variability, contacts, babbling);
- ``recording``: trials and training as Rerun ``.rrd`` files (the only user of rerun);
- ``evolution``: genomes, the GA, conditions and phases, the parallel back-ends, the run
  directory and the trainer;
- ``postevaluation``: the 45 systematic trials of every robot under each sense, snapshots
  over generations;
- ``analysis``: runs as polars tables, summaries, statistics, verdicts, the paper's claims,
  budgets, figures and the report;
- ``robots``: the evolved robots the package ships; ``viewing``: watch, video, the headless
  viewer; ``envs``: the trial as a Gymnasium environment, ``GYM_ID`` (the ``gym`` extra);
  ``studies``: validation, benchmarks, the physics-step and scene studies; ``cli``.

The names below are what the README and the notebooks use; they are imported on first use, so
that ``import dart_reach`` (and ``dart-reach --help``) does not load DART, Rerun and matplotlib.
"""

from __future__ import annotations

import importlib

# First, before anything loads numpy: pin numpy's and OpenBLAS's kernels, and record whether
# numpy was loaded already (then the pin cannot take: model version 1 refuses to run).
from . import pinning  # noqa: F401

__version__ = "0.1.0"

#: The Gymnasium id of the paper's trial as an environment (``envs``; the ``gym`` extra). v2:
#: the model version new runs use (``model.versions.CURRENT_MODEL_VERSION``); v1, still
#: registered, the same environment on model version 1, the model it had; ``gymnasium.make``
#: refuses v0 (``ReachGraspEnv``'s version history).
GYM_ID = "dart_reach/ReachGrasp-v2"


def _register_gym_environment() -> None:
    """Register ``GYM_ID`` with Gymnasium where it is installed (the ``gym`` extra); without it,
    nothing. The environment's module is loaded by ``gymnasium.make``, not here, but Gymnasium
    and numpy, which it loads, are: ``import dart_reach`` and ``dart-reach --help`` take that
    much longer where the extra is installed (docs/guides/gymnasium.md)."""
    try:
        import gymnasium
    except ImportError:
        return
    for gym_id, kwargs in ((GYM_ID, {}), ("dart_reach/ReachGrasp-v1", {"model_version": 1})):
        if gym_id not in gymnasium.registry:
            gymnasium.register(gym_id, entry_point="dart_reach.envs.reach_grasp:ReachGraspEnv",
                               max_episode_steps=200,  # the trial's 200 steps of 0.1 s
                               kwargs=kwargs)


_register_gym_environment()

#: public name -> module that defines it
_PUBLIC = {
    "World": "model.world", "WorldConfig": "model.world",
    "load_scene": "model.scenes",
    "load_condition": "evolution.conditions", "scaled": "evolution.conditions",
    "variant": "evolution.conditions", "condition_names": "evolution.conditions",
    "Settings": "evolution.settings", "train": "evolution.trainer",
    "RunDirectory": "evolution.rundir",
    "evaluate_run": "postevaluation.systematic", "load_evaluation": "postevaluation.systematic",
    "run_phases": "postevaluation.systematic", "SENSES": "postevaluation.systematic",
    "load_runs": "analysis.tables", "read_rrd": "recording.rrd",
    "read_properties": "recording.rrd", "export_run": "analysis.export",
    "save_series": "recording.export",
    "watch": "viewing.watch", "build_report": "analysis.report",
}
#: public module names -> subpackage.module
_MODULES = {"figures": "analysis.figures", "summaries": "analysis.summaries",
            "stats": "analysis.stats", "findings": "analysis.findings",
            "tables": "analysis.tables", "report": "analysis.report",
            "metrics": "measures.metrics", "robots": "robots"}

__all__ = sorted([*_PUBLIC, *_MODULES, "__version__", "GYM_ID"])


def __getattr__(name: str):
    if name in _MODULES:
        return importlib.import_module(f"{__name__}.{_MODULES[name]}")
    if name in _PUBLIC:
        return getattr(importlib.import_module(f"{__name__}.{_PUBLIC[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return __all__
