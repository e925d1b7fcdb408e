"""Scenes: where the ball hangs, as data (paper sections II-B, III, Fig. 2).

The paper places the ball "in a randomly selected point located within one of 9 sectors of the
spherical surface centered on the iCub's neck" and gives no numbers: the sphere's radius and the
sectors' bounds are open levers, grounded in the infant experiments it copies (docs/model/scene.md,
"The scene"). A scene fixes them. The scenes of the scene study ship as TOML files inside this
package (``dart_reach/model/scenes/*.toml``); a user writes another one and passes its path
wherever a scene name is accepted (``dart-reach train --scene FILE``, :func:`load_scene`).

File format (every key is checked; unknown, missing or mistyped keys raise
:class:`SceneError` naming the file and the problem)::

    name = "arm-length-shoulder"       # letters, digits, '.', '_', '-'
    description = "..."

    [sectors]                          # world.SectorConfig: the 9 sectors of Fig. 2
    radius = 0.344                     # m, of the sphere centred on the neck
    azimuth_edges = [0.0, 15.0, 30.0, 45.0]       # deg, 0 = straight ahead, + to the right
    elevation_edges = [-35.9, -20.9, -5.9, 9.1]   # deg, 0 = neck height, + up

A run records the sectors it was trained with in its manifest (``settings.world.sectors``), so a
run opens and evaluates with its own scene whatever the default is, and ``--resume`` refuses a
different one.
"""

from __future__ import annotations

import os
import re
import tomllib
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

from ..world import SectorConfig, WorldConfig

#: The scene of ``WorldConfig()`` (its ``SectorConfig`` defaults), chosen by the scene study's
#: rule (docs/model/scene.md).
DEFAULT_SCENE = "arm-length-shoulder"

_NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$")
_TOP_KEYS = ("name", "description", "sectors")
_SECTOR_KEYS = ("radius", "azimuth_edges", "elevation_edges")


class SceneError(ValueError):
    """A scene file is malformed, or a scene name is unknown."""


@dataclass(frozen=True)
class Scene:
    """A named placement of the 9 sectors."""

    name: str
    description: str
    sectors: SectorConfig
    source: str = "<memory>"

    def world(self, base: WorldConfig | None = None) -> WorldConfig:
        """``base`` (default ``WorldConfig()``) with this scene's sectors."""
        return replace(base or WorldConfig(), sectors=self.sectors)


def scene_from_dict(data: dict, source: str = "<memory>") -> Scene:
    """Build and check a :class:`Scene` from the parsed contents of a scene file; errors start
    with ``source``."""
    def fail(msg: str):
        raise SceneError(f"{source}: {msg}") from None

    if not isinstance(data, dict):
        fail(f"expected a table of keys, got {type(data).__name__}")
    for table, known, where in ((data, _TOP_KEYS, ""), (data.get("sectors"), _SECTOR_KEYS,
                                                         "[sectors] ")):
        if not isinstance(table, dict):
            fail("[sectors] must be a table")
        unknown = [k for k in table if k not in known]
        missing = [k for k in known if k not in table]
        if unknown or missing:
            fail(f"{where}{'unknown' if unknown else 'missing'} key(s) "
                 f"{', '.join(map(repr, unknown or missing))} (keys: {', '.join(known)})")
    if not isinstance(data["name"], str) or not _NAME_RE.match(data["name"]):
        fail(f"name must be 1-64 letters, digits, '.', '_' or '-', got {data['name']!r}")
    if not isinstance(data["description"], str):
        fail("description must be a string")
    s = data["sectors"]
    try:
        sectors = SectorConfig(radius=s["radius"], azimuth_edges=_edges(s["azimuth_edges"]),
                               elevation_edges=_edges(s["elevation_edges"]))
    except (TypeError, ValueError) as exc:
        fail(f"[sectors] {exc}")
    return Scene(data["name"], data["description"], sectors, source)


def _edges(value) -> tuple:
    if not isinstance(value, list):
        raise ValueError(f"edges must be an array of 4 numbers, got {value!r}")
    return tuple(value)


def _shipped():
    return resources.files(__name__)


def scene_names() -> tuple[str, ...]:
    """The names of the scenes shipped with the package, sorted."""
    return tuple(sorted(p.name[: -len(".toml")] for p in _shipped().iterdir()
                        if p.name.endswith(".toml") and p.is_file()))


def load_scene(name_or_path: str | os.PathLike) -> Scene:
    """A shipped scene by name (:func:`scene_names`) or the scene in a TOML file (a path-like
    object, or a string ending in ``.toml`` or containing a path separator)."""
    if isinstance(name_or_path, str) and name_or_path in scene_names():
        source = f"dart_reach/model/scenes/{name_or_path}.toml"
        text = (_shipped() / f"{name_or_path}.toml").read_bytes()
    elif isinstance(name_or_path, os.PathLike) or (
            isinstance(name_or_path, str)
            and (name_or_path.endswith(".toml") or "/" in name_or_path or os.sep in name_or_path)):
        path = Path(name_or_path)
        if not path.is_file():
            raise SceneError(f"{path}: no such scene file")
        source, text = str(path), path.read_bytes()
    else:
        raise SceneError(f"unknown scene {name_or_path!r}; shipped scenes: "
                         f"{', '.join(scene_names())} (or give the path of a .toml file)")
    try:
        data = tomllib.loads(text.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise SceneError(f"{source}: not a valid TOML file: {exc}") from None
    scene = scene_from_dict(data, source)
    if source.startswith("dart_reach/") and scene.name != name_or_path:
        raise SceneError(f"{source}: its name {scene.name!r} does not match its file name")
    return scene


def scene_of(sectors: SectorConfig) -> str | None:
    """The name of the shipped scene with these sectors, or None (a user's own)."""
    for name in scene_names():
        if load_scene(name).sectors == sectors:
            return name
    return None
