"""Developmental phases and experimental conditions as data (paper sections III-D, IV-C, Fig. 10).

A :class:`Condition` is an ordered list of :class:`Phase` s. Each phase sets the maturational
state of the robot (visual acuity, sight-offset sensors, reflexes, which parameter groups learn)
and its training budget. The conditions of the paper ship as TOML files inside this package
(``dart_reach/evolution/conditions/*.toml``); a user writes another one (another acuity, another
budget, another order) and passes its path wherever a condition name is accepted, without touching
code.

File format (every key is checked; unknown, missing or mistyped keys raise
:class:`ConditionError` naming the file and the problem)::

    name = "gross-h"                   # command-line friendly: letters, digits, '.', '_', '-'
    notation = "pre-h -> gross-h"       # the paper's notation (Fig. 10)
    description = "..."
    generations_per_phase = 500        # optional, default 500 (III-D: "Each phase lasts 500")

    [[phases]]                         # in training order
    name = "pre-h"
    notation = "pre-h"                 # optional, default: name
    acuity = 1.0                       # exponent a of Eqs. 1-2 (3 = low acuity, 1 = full)
    offset_sensors = false             # the two sight-offset sensors (Eq. 4) are available
    free_groups = ["direct"]           # genome.ParamGroup values that learn in this phase
    reflexes = true                    # the hand-coded orienting and grasp reflexes (III-D)
    budget_phases = 1                  # optional, default 1: budget in units of standard phases

Budgets: a phase trains for ``generations = budget_phases * generations_per_phase``. The
non-incremental controls last as long as the incremental phases they replace (IV-C): gross^ has
``budget_phases = 2`` (pre + gross), fine^ ``budget_phases = 3`` (pre + gross + fine), so
:func:`scaled` changes every budget at once and keeps the ratios.

Keys: every phase has a stable ``key``, a hash of what determines its training (acuity, offset
sensors, free groups, reflexes, generations) and of the key of the phase before it (a prefix
key; names, notations and descriptions do not enter it). Two phases with equal keys train the
same thing from the same starting point, so a runner trains them once: e.g. pre-h in the
``pre-h`` and ``gross-h`` conditions. The key does not cover the GA configuration or the seeds,
which are the same for every phase of a run.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import re
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from ..genome import ParamGroup, as_groups, free_mask

#: III-D: "Each phase lasts 500 generations."
DEFAULT_GENERATIONS_PER_PHASE = 500
#: Version of the content hashed into phase keys (change it if the key's meaning changes).
KEY_VERSION = 1
#: Length of a phase key in hex digits.
KEY_LENGTH = 16

_NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")
_TOP_REQUIRED = ("name", "notation", "description", "phases")
_TOP_OPTIONAL = ("generations_per_phase",)
_PHASE_REQUIRED = ("name", "acuity", "offset_sensors", "free_groups", "reflexes")
_PHASE_OPTIONAL = ("notation", "budget_phases")
_HINTS = {
    "generations": "set the top-level generations_per_phase and the phase's budget_phases "
                   "(generations = budget_phases x generations_per_phase)",
}


class ConditionError(ValueError):
    """A condition or phase is malformed, or a condition name or file is unknown."""


def _is_int(x) -> bool:
    return isinstance(x, int) and not isinstance(x, bool)


def _typename(x) -> str:
    return type(x).__name__


#: Names become directory and file names (``phases/<name>-<key>/``): short enough for any file
#: system.
MAX_NAME = 64


def _check_name(value, what: str) -> str:
    if not isinstance(value, str) or not _NAME_RE.match(value):
        raise ConditionError(
            f"{what} must be a non-empty string of letters, digits, '.', '_' or '-' "
            f"(command-line friendly), got {value!r}")
    if len(value) > MAX_NAME:
        raise ConditionError(f"{what} must be at most {MAX_NAME} characters, got {len(value)}")
    return value


@dataclass(frozen=True)
class Phase:
    """One developmental phase: the robot's maturational state and the training budget (III-D).

    - ``name``: command-line friendly (``"pre-h"``); ``notation``: the paper's (``"pre-h"``,
      ``"gross^*"``).
    - ``acuity``: the exponent a of Eqs. 1-2 (dimensionless, > 0); 3 = low acuity (pre-reaching),
      1 = full acuity (afterwards), as the text of III-B and III-D says (Table I swaps them).
    - ``offset_sensors``: whether the two sight-offset sensors (Eq. 4) are available.
    - ``free_groups``: the :class:`~dart_reach.genome.ParamGroup` s that learn (given as groups or
      their names; stored in the enum's order).
    - ``reflexes``: whether the hand-coded orienting and grasp reflexes are present.
    - ``generations``: training budget in generations (> 0); ``budget_phases``: the same budget
      in units of standard phases (see the module docstring).
    - ``previous_key``: the key of the phase before it in its condition ("" for the first); set
      by :class:`Condition`.
    """

    name: str
    notation: str
    acuity: float
    offset_sensors: bool
    free_groups: tuple[ParamGroup, ...]
    reflexes: bool
    generations: int
    budget_phases: int = 1
    previous_key: str = ""

    def __post_init__(self):
        _check_name(self.name, "name")
        if not isinstance(self.notation, str) or not self.notation.strip():
            raise ConditionError(f"notation must be a non-empty string, got {self.notation!r}")
        if (not isinstance(self.acuity, (int, float)) or isinstance(self.acuity, bool)
                or not math.isfinite(self.acuity) or self.acuity <= 0):
            raise ConditionError(f"acuity must be a number > 0 (the exponent a of Eqs. 1-2), "
                                 f"got {self.acuity!r} ({_typename(self.acuity)})")
        object.__setattr__(self, "acuity", float(self.acuity))
        for key in ("offset_sensors", "reflexes"):
            v = getattr(self, key)
            if not isinstance(v, bool):
                raise ConditionError(f"{key} must be true or false, got {v!r} ({_typename(v)})")
        groups = self.free_groups
        if not isinstance(groups, (list, tuple, set, frozenset)):
            raise ConditionError(f"free_groups must be a list of group names, got {groups!r} "
                                 f"({_typename(groups)})")
        groups = list(groups)
        try:
            parsed = as_groups(groups)
        except (ValueError, TypeError) as e:
            raise ConditionError(f"free_groups: {e}") from None
        if len(parsed) != len(groups):
            raise ConditionError(f"free_groups lists a group twice: {groups!r}")
        if not parsed:
            raise ConditionError("free_groups is empty: a phase must free at least one group")
        object.__setattr__(self, "free_groups", tuple(g for g in ParamGroup if g in parsed))
        for key in ("generations", "budget_phases"):
            v = getattr(self, key)
            if not _is_int(v) or v <= 0:
                raise ConditionError(f"{key} must be an integer > 0, got {v!r} ({_typename(v)})")
        if not isinstance(self.previous_key, str):
            raise ConditionError(f"previous_key must be a string, got {self.previous_key!r}")

    @property
    def free_group_names(self) -> tuple[str, ...]:
        """The free groups by their names in condition files."""
        return tuple(g.value for g in self.free_groups)

    @property
    def key(self) -> str:
        """Stable prefix key: a hash of this phase's training content and ``previous_key``."""
        content = {
            "version": KEY_VERSION,
            "previous": self.previous_key,
            "acuity": self.acuity,
            "offset_sensors": self.offset_sensors,
            "free_groups": list(self.free_group_names),
            "reflexes": self.reflexes,
            "generations": self.generations,
        }
        text = json.dumps(content, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()[:KEY_LENGTH]

    def free_mask(self) -> np.ndarray:
        """Genes that may mutate in this phase (see :func:`dart_reach.genome.free_mask`)."""
        return free_mask(self.free_groups)

    def to_dict(self, derived: bool = True) -> dict:
        """The phase as a ``[[phases]]`` table of a condition file (JSON-friendly); with
        ``derived`` also its ``generations`` and ``key``."""
        d = {"name": self.name, "notation": self.notation, "acuity": self.acuity,
             "offset_sensors": self.offset_sensors, "free_groups": list(self.free_group_names),
             "reflexes": self.reflexes, "budget_phases": self.budget_phases}
        if derived:
            d.update(generations=self.generations, key=self.key)
        return d


@dataclass(frozen=True)
class Condition:
    """An experimental condition (IV-C, Fig. 10): phases trained one after the other, each
    starting from the population that the previous one ends with (III-D).

    The constructor checks that phase names are unique, that every phase's
    ``generations == budget_phases * generations_per_phase``, and that free groups only grow
    from a phase to the next; it links each phase's ``previous_key`` to the key of the phase
    before it. ``source`` (the file it was read from) is informative and not compared.
    """

    name: str
    notation: str
    description: str
    phases: tuple[Phase, ...]
    generations_per_phase: int = DEFAULT_GENERATIONS_PER_PHASE
    source: str = dataclasses.field(default="<memory>", compare=False)

    def __post_init__(self):
        _check_name(self.name, "name")
        for key in ("notation", "description"):
            v = getattr(self, key)
            if not isinstance(v, str) or not v.strip():
                raise ConditionError(f"{key} must be a non-empty string, got {v!r}")
        g = self.generations_per_phase
        if not _is_int(g) or g <= 0:
            raise ConditionError(f"generations_per_phase must be an integer > 0, got {g!r} "
                                 f"({_typename(g)})")
        phases = self.phases
        if not isinstance(phases, (list, tuple)) or not phases:
            raise ConditionError("phases must be a non-empty list of phases")
        if not all(isinstance(p, Phase) for p in phases):
            raise ConditionError("phases must hold Phase objects")
        names = [p.name for p in phases]
        dupes = sorted({n for n in names if names.count(n) > 1})
        if dupes:
            raise ConditionError(f"phase names must be unique within a condition: {dupes}")
        linked, previous = [], None
        for i, p in enumerate(phases):
            if p.generations != p.budget_phases * g:
                raise ConditionError(
                    f"phases[{i}] {p.name!r}: generations {p.generations} != budget_phases "
                    f"{p.budget_phases} x generations_per_phase {g}")
            if previous is not None and not set(previous.free_groups) <= set(p.free_groups):
                lost = [x.value for x in previous.free_groups if x not in p.free_groups]
                raise ConditionError(
                    f"phases[{i}] {p.name!r}: free_groups must include those of the previous "
                    f"phase (groups only mature, they are not frozen again); missing {lost}")
            p = dataclasses.replace(p, previous_key=previous.key if previous else "")
            linked.append(p)
            previous = p
        object.__setattr__(self, "phases", tuple(linked))

    @property
    def total_generations(self) -> int:
        return sum(p.generations for p in self.phases)

    @property
    def keys(self) -> tuple[str, ...]:
        """The prefix key of every phase, in order."""
        return tuple(p.key for p in self.phases)

    def to_dict(self, derived: bool = True) -> dict:
        """The condition as the contents of a condition file (JSON-friendly, e.g. for a run's
        manifest): ``condition_from_dict(c.to_dict(derived=False)) == c``. With ``derived`` each
        phase also carries its ``generations`` and prefix ``key``. ``source`` is left out."""
        return {"name": self.name, "notation": self.notation, "description": self.description,
                "generations_per_phase": self.generations_per_phase,
                "phases": [p.to_dict(derived) for p in self.phases]}

    def phase(self, name: str) -> Phase:
        """The phase called ``name``."""
        for p in self.phases:
            if p.name == name:
                return p
        raise ConditionError(f"condition {self.name!r} has no phase {name!r}; "
                             f"phases: {[p.name for p in self.phases]}")

    def newly_free(self, index: int) -> frozenset[ParamGroup]:
        """The groups that phase ``index`` frees with respect to the phase before it: the genes
        to :func:`dart_reach.genome.release` at the transition (empty for the first phase, whose
        population is random in every gene)."""
        if not 0 <= index < len(self.phases):
            raise IndexError(f"phase index {index} out of range 0..{len(self.phases) - 1}")
        if index == 0:
            return frozenset()
        return frozenset(self.phases[index].free_groups) - set(self.phases[index - 1].free_groups)


# ------------------------------------------------------------------------------------ loading
def _check_keys(table: dict, required: Iterable[str], optional: Iterable[str], where: str) -> None:
    required, optional = tuple(required), tuple(optional)
    known = required + optional
    for k in table:
        if k not in known:
            hint = f"; {_HINTS[k]}" if k in _HINTS else ""
            raise ConditionError(f"{where}unknown key {k!r} (known keys: {', '.join(known)}){hint}")
    missing = [k for k in required if k not in table]
    if missing:
        raise ConditionError(f"{where}missing key(s) {', '.join(map(repr, missing))}")


def condition_from_dict(data: dict, source: str = "<memory>") -> Condition:
    """Build and validate a :class:`Condition` from the parsed contents of a condition file.

    Raises :class:`ConditionError` whose message starts with ``source`` and says what is wrong
    and where (e.g. ``"my.toml: phases[1] 'gross': acuity must be a number > 0, got -1 (int)"``).
    """
    def fail(msg: str):
        raise ConditionError(f"{source}: {msg}") from None

    if not isinstance(data, dict):
        fail(f"expected a table of keys, got {_typename(data)}")
    try:
        _check_keys(data, _TOP_REQUIRED, _TOP_OPTIONAL, "")
    except ConditionError as e:
        fail(str(e))
    gpp = data.get("generations_per_phase", DEFAULT_GENERATIONS_PER_PHASE)
    if not _is_int(gpp) or gpp <= 0:
        fail(f"generations_per_phase must be an integer > 0, got {gpp!r} ({_typename(gpp)})")
    raw_phases = data["phases"]
    if not isinstance(raw_phases, list) or not raw_phases:
        fail("phases must be a non-empty array of tables ([[phases]] sections)")
    phases = []
    for i, t in enumerate(raw_phases):
        label = f"phases[{i}]"
        if not isinstance(t, dict):
            fail(f"{label}: expected a table ([[phases]] section), got {_typename(t)}")
        if isinstance(t.get("name"), str):
            label += f" {t['name']!r}"
        try:
            _check_keys(t, _PHASE_REQUIRED, _PHASE_OPTIONAL, "")
            budget = t.get("budget_phases", 1)
            if not _is_int(budget) or budget <= 0:
                raise ConditionError(
                    f"budget_phases must be an integer > 0, got {budget!r} ({_typename(budget)})")
            phases.append(Phase(
                name=t["name"], notation=t.get("notation", t["name"]), acuity=t["acuity"],
                offset_sensors=t["offset_sensors"], free_groups=t["free_groups"],
                reflexes=t["reflexes"], generations=budget * gpp, budget_phases=budget))
        except ConditionError as e:
            fail(f"{label}: {e}")
    try:
        return Condition(name=data["name"], notation=data["notation"],
                         description=data["description"], phases=tuple(phases),
                         generations_per_phase=gpp, source=source)
    except ConditionError as e:
        fail(str(e))


def _parse_toml(text: bytes, source: str) -> Condition:
    try:
        data = tomllib.loads(text.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise ConditionError(f"{source}: not a valid TOML file: {e}") from None
    return condition_from_dict(data, source)


def _shipped():
    return resources.files(__name__)


def condition_names() -> tuple[str, ...]:
    """The names of the conditions shipped with the package, sorted."""
    return tuple(sorted(p.name[: -len(".toml")] for p in _shipped().iterdir()
                        if p.name.endswith(".toml") and p.is_file()))


def list_conditions() -> tuple[Condition, ...]:
    """The conditions shipped with the package, loaded, sorted by name."""
    return tuple(load_condition(name) for name in condition_names())


def load_condition(name_or_path: str | os.PathLike) -> Condition:
    """A shipped condition by name (see :func:`list_conditions`) or the condition in a TOML file.

    A ``str`` that is a shipped name (:func:`condition_names`) loads the shipped file; a
    path-like object, or a string ending in ``.toml`` or containing a path separator, is read as
    a file. Anything else raises :class:`ConditionError` listing the shipped names.
    """
    if isinstance(name_or_path, str) and name_or_path in condition_names():
        res = _shipped() / f"{name_or_path}.toml"
        shipped = f"dart_reach/evolution/conditions/{name_or_path}.toml"
        cond = _parse_toml(res.read_bytes(), shipped)
        if cond.name != name_or_path:
            raise ConditionError(f"{shipped}: the file's name {cond.name!r} does not match its "
                                 f"file name")
        return cond
    if isinstance(name_or_path, os.PathLike) or (
            isinstance(name_or_path, str)
            and (name_or_path.endswith(".toml") or "/" in name_or_path or os.sep in name_or_path)):
        path = Path(name_or_path)
        if not path.is_file():
            raise ConditionError(f"{path}: no such condition file")
        return _parse_toml(path.read_bytes(), str(path))
    if not isinstance(name_or_path, str):
        raise TypeError(f"expected a condition name or a path, got {_typename(name_or_path)}")
    raise ConditionError(f"unknown condition {name_or_path!r}; shipped conditions: "
                         f"{', '.join(condition_names())} (or give the path of a .toml file)")


def scaled(condition: Condition, generations: int | None = None) -> Condition:
    """A copy of ``condition`` whose budget per standard phase is ``generations``.

    Every phase then trains ``budget_phases * generations`` generations (e.g. ``generations=50``:
    pre, gross and fine 50 each, gross^ 100, fine^ 150). Phase keys change accordingly.
    ``None`` returns ``condition`` unchanged.
    """
    if generations is None:
        return condition
    if not _is_int(generations) or generations <= 0:
        raise ConditionError(f"generations must be an integer > 0, got {generations!r}")
    phases = tuple(dataclasses.replace(p, generations=p.budget_phases * generations)
                   for p in condition.phases)
    return dataclasses.replace(condition, phases=phases, generations_per_phase=generations)


def variant(condition: Condition, name: str, phases: dict[str, dict] | None = None,
            **changes) -> Condition:
    """A new condition made from ``condition`` (an ablation written in Python): renamed
    ``name``, with ``changes`` to its own fields (``notation``, ``description``,
    ``generations_per_phase``) and ``phases`` = {phase name: {field: value}} changes to its
    phases' fields (``acuity``, ``reflexes``, ``offset_sensors``, ``free_groups``,
    ``notation``, ``name``, ``budget_phases``); the phase name ``"*"`` changes every phase.
    Every check of ``Condition`` and ``Phase`` applies; a changed phase gets a new key, so it
    is trained anew, while unchanged leading phases are shared with the original condition
    when both are trained in one run.

    >>> std = load_condition("standard")
    >>> sharp = variant(std, "standard-sharp", phases={"pre": {"acuity": 1.0}})
    >>> sharp.phase("pre").acuity, sharp.phase("gross").acuity
    (1.0, 1.0)
    """
    phases = dict(phases or {})
    unknown = set(phases) - {p.name for p in condition.phases} - {"*"}
    if unknown:
        raise ConditionError(f"condition {condition.name!r} has no phase {sorted(unknown)}; "
                             f"phases: {[p.name for p in condition.phases]}")
    allowed = {f.name for f in dataclasses.fields(Phase)} - {"generations", "previous_key"}
    for phase_name, fields in phases.items():
        bad = set(fields) - allowed
        if bad:
            raise ConditionError(f"phases[{phase_name!r}]: unknown or derived fields "
                                 f"{sorted(bad)}; changeable: {sorted(allowed)}")
    g = changes.get("generations_per_phase", condition.generations_per_phase)
    new_phases = []
    for p in condition.phases:
        fields = {**phases.get("*", {}), **phases.get(p.name, {})}
        p = dataclasses.replace(p, **fields)
        new_phases.append(dataclasses.replace(p, generations=p.budget_phases * g))
    description = changes.pop("description", f"{condition.description} (variant {name})")
    return dataclasses.replace(condition, name=name, description=description,
                               phases=tuple(new_phases), source="<memory>", **changes)


__all__ = [
    "Condition", "ConditionError", "DEFAULT_GENERATIONS_PER_PHASE", "Phase",
    "condition_from_dict", "condition_names", "list_conditions", "load_condition", "scaled",
    "variant",
]
