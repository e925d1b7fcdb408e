"""Model versions: a version is a whole model, in one frozen record.

Where the paper fixes a number the model follows it; where it leaves a choice open the model
makes one (the levers, ``model.levers``; the scene, ``model.scenes``; self-collision of the
robot's body, ``world.WorldConfig.self_collision``), and the numerics compute the equations.
A :class:`ModelVersion` names all four. Every run writes its version and that record into its
manifest (``settings.model_version`` and ``model``; a manifest without a version was written by
version 1), and resumes, evaluates and reproduces under it, so the default can change without
losing a committed result. A run that sets a lever, the scene or self-collision away from its
version's record is a *variant* of that version, named in its manifest (:meth:`ModelVersion.
variant`). The table of versions is :data:`MODEL_VERSIONS`; docs/model/levers.md's table of
versions is tested against it.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field, replace

from .levers import Levers
from .scenes import load_scene, scene_of
from .world import SectorConfig, WorldConfig


class Numerics(enum.Enum):
    """How a model version computes the trial's Python around DART's step (the sensors, the
    network, the fitness terms, the motor commands): the equations are the same, the rounding
    is not.

    - ``REFERENCE`` (version 1): numpy and Python floats, frozen in ``model.reference``.
    - ``COMPILED`` (versions 2 and 3): compiled with Numba, every operation in a fixed order
      and the logistic's exponential written out (``model.compiled``).
    """

    REFERENCE = "reference"
    COMPILED = "compiled"


@dataclass(frozen=True)
class ModelVersion:
    """A whole model: its ``numerics``, its ``scene`` (a shipped scene's name: where the ball
    hangs), ``self_collision`` of the arm with the body, and the trial's ``levers``."""

    number: int
    numerics: Numerics
    scene: str
    self_collision: bool = False
    levers: Levers = field(default_factory=Levers)
    summary: str = ""

    def sectors(self) -> SectorConfig:
        """This version's sectors (its scene's)."""
        return load_scene(self.scene).sectors

    def world(self, base: WorldConfig | None = None) -> WorldConfig:
        """``base`` (default ``WorldConfig()``: its physics step and bodies) with this
        version's scene and self-collision."""
        return replace(base or WorldConfig(), sectors=self.sectors(),
                       self_collision=self.self_collision)

    def to_json(self) -> dict:
        return {"version": self.number, "numerics": self.numerics.value, "scene": self.scene,
                "self_collision": self.self_collision, "levers": self.levers.to_json()}

    def variant(self, world: WorldConfig, levers: Levers) -> dict[str, str]:
        """What a run's ``world`` and ``levers`` change from this record, name -> value
        (empty: the version itself). The scene is named by its shipped name, or by its radius
        when it is a user's own."""
        changed = levers.changed_from(self.levers)
        if world.sectors != self.sectors():
            changed["scene"] = (scene_of(world.sectors)
                                or f"custom (radius {world.sectors.radius:g} m)")
        if world.self_collision != self.self_collision:
            changed["self_collision"] = "on" if world.self_collision else "off"
        return changed


def variant_name(number: int, changes: dict[str, str]) -> str:
    """A variant's name: ``v<number>`` and its changes, e.g. ``v3+touch_pay=binary``."""
    return "+".join([f"v{number}", *(f"{k}={v}" for k, v in sorted(changes.items()))])


#: The model versions this package can run. A run trained under a version always runs under
#: it (digests pin version 1's trials, tests/model/test_task.py; version 2's,
#: tests/model/test_compiled.py; the training of versions 1 and 3,
#: tests/evolution/test_training_digest.py).
MODEL_VERSIONS = {v.number: v for v in (
    ModelVersion(1, Numerics.REFERENCE, "arm-length-shoulder",
                 summary="the first model: the defaults of Levers(), the scene "
                         "arm-length-shoulder (sphere radius 0.344 m), no self-collision, the "
                         "numerics of dart_reach 0.x"),
    ModelVersion(2, Numerics.COMPILED, "arm-length-shoulder",
                 summary="version 1's model computed by compiled numerics (model.compiled): "
                         "the same equations and physics, rounded alike on every processor, "
                         "faster"),
    ModelVersion(3, Numerics.COMPILED, "calibrated-reach",
                 summary="version 2's numerics and version 1's levers with the scene "
                         "calibrated on Fig. 5's reach (sphere radius 0.46 m, chosen by the "
                         "second pre-registration's screen, docs/results/campaign.md): the "
                         "campaign's model"),
)}
#: The version new runs are trained under (``train`` without ``--model-version``, ``Settings()``,
#: the Gymnasium environment).
CURRENT_MODEL_VERSION = 3


def check_model_version(version) -> int:
    """``version`` as an int if this package can run it; ``ValueError`` naming the versions
    it knows otherwise."""
    if isinstance(version, bool) or not isinstance(version, int) or version not in MODEL_VERSIONS:
        raise ValueError(f"model version {version!r} is not one this dart_reach can run (it "
                         f"knows {', '.join(map(str, MODEL_VERSIONS))}); a run made by a newer "
                         f"dart_reach needs that version of the package")
    return version


def model_version(version: int) -> ModelVersion:
    """The record of a model version (``ValueError`` for one this package cannot run)."""
    return MODEL_VERSIONS[check_model_version(version)]


def numerics_of(version: int) -> Numerics:
    """The numerics a model version computes with."""
    return model_version(version).numerics


def versions_table() -> str:
    """The table of model versions as markdown (``dart-reach versions`` prints it;
    docs/model/levers.md holds it and a test keeps the two equal)."""
    rows = ["| version | numerics | scene | self-collision | levers | what it is |",
            "|---|---|---|---|---|---|"]
    for v in MODEL_VERSIONS.values():
        current = " (new runs)" if v.number == CURRENT_MODEL_VERSION else ""
        levers = ", ".join(f"{k} {x}" for k, x in v.levers.to_json().items())
        rows.append(f"| {v.number}{current} | {v.numerics.value} | `{v.scene}` | "
                    f"{'on' if v.self_collision else 'off'} | {levers} | {v.summary} |")
    return "\n".join(rows) + "\n"
