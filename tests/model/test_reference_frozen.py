"""Model version 1 is frozen: its code lives in dart_reach/model/reference/ and is never edited,
so that every run trained under it resumes, evaluates and reproduces bit for bit
(tests/model/test_task.py and tests/evolution/test_training_digest.py pin its trials).

Two pins. Every file of the reference folder, by a digest of its bytes: editing any of them
fails. The shared code version 1 runs besides (the DART world's construction, layout, reset
and readings, the network's parameters and reflexes, ``ctrnn.motor_targets``, the sensors'
constants), by a digest of each function's source and of the constants' values: that code is
the living model's as well, so a change there changes every version's results.

Either way a change to the model is a new model version (docs/model/trial.md, "How to change
the model"), never an edit of this code. Should a pinned shared function have to change
without changing any result (a move), its digest below is updated in the same commit, with the
reason."""

from __future__ import annotations

import hashlib
import re
import inspect
from pathlib import Path

from dart_reach.model import ctrnn, levers, reference, sensors, steps, world

#: The reference folder and the sha256 (first 16 hex digits) of each of its files.
#: ``steps.py``: ``palm_normal`` (the records' palm normal, which only version 1's steps
#: compute with it) moved in from ``world``, where it was pinned as shared code: its code
#: unchanged, its docstring naming the section; no result changes (the trial digests of
#: tests/model/test_task.py stay).
#: ``servo.py``: version 1's servo (``set_targets``, ``advance``, ``mark_colliding_segments``,
#: ``_gather_ball_touch``, ``_gather_touch``, ``inner_face_touch``, ``TOUCH_DECISION_MARGIN``)
#: moved in from ``world``, where it was pinned as shared code, its source unchanged (each
#: function's digest below as it was there), as ``ReferenceServo`` over the world's layout;
#: ``steps.py`` builds it and runs its reset after ``World.reset`` (which ran it itself), and
#: ``__init__.py`` names it. No result changes (the trial digests of tests/model/test_task.py
#: and tests/evolution/test_training_digest.py stay).
REFERENCE_FOLDER = Path(reference.__file__).parent
FROZEN_FILES = {
    "__init__.py": "5f5c320e0bc66249",
    "network.py": "5908184f4c20f0de",
    "sensors.py": "035c76577a7052f0",
    "servo.py": "8ba6cfdf7e642004",
    "steps.py": "91cb3696e41627db",
}

#: The shared code version 1's steps run, outside the reference folder, by name.
SHARED_CODE = {
    "steps.home_motor": steps.home_motor,
    "ctrnn.Network": ctrnn.Network,
    "ctrnn.motor_targets": ctrnn.motor_targets,
    "ctrnn.reflex_weights": ctrnn.reflex_weights,
    "ctrnn.reflex_biases": ctrnn.reflex_biases,
    "sensors.clip": sensors.clip,
    "world.World._resolve_robot": world.World._resolve_robot,
    "world.World._resolve_contacts": world.World._resolve_contacts,
    "world.World._set_home": world.World._set_home,
    "world.World._motor_angles": world.World._motor_angles,
    "world.World._describe": world.World._describe,
    "world.World.targets_for": world.World.targets_for,
    "world.World.reset": world.World.reset,
    "world.World.motor_positions": world.World.motor_positions,
    "world.World.hand_contacts": world.World.hand_contacts,
    "world.World.hand_contacts_any": world.World.hand_contacts_any,
    "world.palm_point": world.palm_point,
}

#: The shared constants that code reads, by module.
SHARED_CONSTANTS = {
    "ctrnn": ("N_SENSORS", "N_HIDDEN", "N_MOTORS", "PROPRIO", "TOUCH", "SIGHT", "OFFSET",
              "ORIENT_YAW_SIGN", "ORIENT_PITCH_SIGN", "ORIENT_HOME_TARGETS", "ORIENT_GAIN",
              "GRASP_WEIGHT", "GRASP_BIAS", "RESET_MOTOR_STATE"),
    "sensors": ("HALF_FOV_X_DEG", "HALF_FOV_Y_DEG", "NO_TOUCH", "TOUCHING", "NO_SIGHT",
                "SIGHT_RANGE_M", "OFFSET_D_MAX_DEG", "OFFSET_SCALE"),
    "world": ("LIMIT_MARGIN", "BALL_PARKED", "PALM_NORMAL"),
    "levers": ("TOUCH_CAP", "REFLEX_EVOLVED_SCALE"),
}

#: sha256 (first 16 hex digits) of each shared function's source, and of each module's
#: constants' values. ``ctrnn.Network``: the network's parameters, reflexes and states (its
#: numpy update moved, unchanged, to ``reference.network.ReferenceNetwork``). ``world``:
#: the servo's code and buffers moved out to ``reference/servo.py`` (``_resolve_robot`` no
#: longer builds the servo's lists, ``_resolve_contacts`` and ``_describe`` hand the segments'
#: bodies to the layout, ``reset`` no longer commands the motors, ``TOUCH_DECISION_MARGIN``
#: left the constants); ``_describe`` pinned since version 1's servo reads the layout it
#: builds.
FROZEN_SHARED = {
    "steps.home_motor": "746229f5e2093a8b",
    "ctrnn.Network": "71f14fc26ac60ec0",
    "ctrnn.motor_targets": "dd35bc35ea19eac7",
    "ctrnn.reflex_weights": "5dcd028507b00610",
    "ctrnn.reflex_biases": "76f2702502ecfd8a",
    "sensors.clip": "5d484cd37821dd1a",
    "world.World._resolve_robot": "429383ebfcb469fb",
    "world.World._resolve_contacts": "fc51bc3ee3b79101",
    "world.World._set_home": "49565c1ebd0f75af",
    "world.World._motor_angles": "6f37030562ad8302",
    "world.World._describe": "307870a0fe6734f0",
    "world.World.targets_for": "20578f88cae757cc",
    "world.World.reset": "28342d2f365910da",
    "world.World.motor_positions": "2f485392efa02009",
    "world.World.hand_contacts": "92e292dacf3093a7",
    "world.World.hand_contacts_any": "c18b4001a7a8ee51",
    "world.palm_point": "5859255b0972470b",
    "constants.ctrnn": "37be81c181f74a6a",
    "constants.sensors": "e97643c044925f52",
    "constants.world": "8af76c496d420322",
    "constants.levers": "abe2fef0a99be91d",
}

WHAT_TO_DO = ("version 1 must reproduce its committed runs bit for bit, so its code is never "
              "edited: undo the edit and make the change a new model version (docs/model/"
              "trial.md, 'How to change the model')")


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()[:16]


def reference_file_digests() -> dict[str, str]:
    """The digest of every file of the reference folder, by its path in the folder."""
    return {path.relative_to(REFERENCE_FOLDER).as_posix(): _digest(path.read_bytes())
            for path in sorted(REFERENCE_FOLDER.rglob("*.py"))}


def shared_digests() -> dict[str, str]:
    """The digest of each shared function's source, and of the shared constants' values
    (per module)."""
    modules = {"ctrnn": ctrnn, "sensors": sensors, "world": world, "levers": levers}
    found = {name: _digest(inspect.getsource(code).encode())
             for name, code in SHARED_CODE.items()}
    for m, names in SHARED_CONSTANTS.items():
        values = repr({f"{m}.{c}": repr(getattr(modules[m], c)) for c in names})
        found[f"constants.{m}"] = _digest(values.encode())
    return found


def test_every_file_of_version_1s_reference_folder_is_unchanged():
    found = reference_file_digests()
    changed = sorted(name for name in found.keys() | FROZEN_FILES.keys()
                     if found.get(name) != FROZEN_FILES.get(name))
    assert not changed, (f"dart_reach/model/reference/ changed ({', '.join(changed)}): "
                         f"{WHAT_TO_DO}")


def test_the_shared_code_version_1_runs_is_unchanged():
    found = shared_digests()
    changed = sorted(name for name in found if FROZEN_SHARED.get(name) != found[name])
    assert not changed, (f"shared code that version 1 runs changed ({', '.join(changed)}): "
                         f"it changes every model version's results; {WHAT_TO_DO}")


def test_only_the_trial_builds_version_1s_code():
    """Nothing but ``task`` imports the reference folder: ``task.steps_for`` and ``task.
    network_for`` build version 1's steps and network for a trial of its numerics; the living
    model and its users (the environment, the measures, the studies) never reach it."""
    package = REFERENCE_FOLDER.parent.parent
    pattern = re.compile(r"^\s*(from\s+\S*reference\S*\s+import|import\s+\S*reference"
                         r"|from\s+\S+\s+import\s+.*\breference\b)", re.MULTILINE)
    found = sorted(path.relative_to(package).as_posix() for path in package.rglob("*.py")
                   if REFERENCE_FOLDER not in path.parents
                   and pattern.search(path.read_text()))
    assert found == ["model/task.py"], found
