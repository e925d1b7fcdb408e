"""Model version 1's code is frozen: every function its trial's steps run (``steps.
ReferenceSteps`` and what it calls: the network, the sensors, the world's commands and touch
decisions) and the constants they read are pinned by a digest of their source. Version 1 must
reproduce the committed runs bit for bit (tests/model/test_task.py pins its trials); a change
to the model is a new model version (docs/model/trial.md, "How to change the model"), never an
edit of this code. Should a pinned function really have to change (a bug that changes no
result, a move), the digest below is updated in the same commit, with the reason."""

from __future__ import annotations

import hashlib
import inspect

from dart_reach.model import ctrnn, sensors, steps, world

#: The code version 1's steps run, by name.
REFERENCE_CODE = {
    "steps.ReferenceSteps": steps.ReferenceSteps,
    "steps.home_motor": steps.home_motor,
    "ctrnn.Network": ctrnn.Network,
    "ctrnn.sigmoid": ctrnn.sigmoid,
    "ctrnn.motor_targets": ctrnn.motor_targets,
    "ctrnn.reflex_weights": ctrnn.reflex_weights,
    "ctrnn.reflex_biases": ctrnn.reflex_biases,
    "sensors.clip": sensors.clip,
    "sensors.proprioception": sensors.proprioception,
    "sensors.touch": sensors.touch,
    "sensors.project": sensors.project,
    "sensors.visual_angles": sensors.visual_angles,
    "sensors.sight": sensors.sight,
    "sensors.offset": sensors.offset,
    "sensors.p_sight": sensors.p_sight,
    "sensors.p_touch": sensors.p_touch,
    "sensors.p_touch_binary": sensors.p_touch_binary,
    "sensors.p_touch_capped": sensors.p_touch_capped,
    "sensors.p_touch_of": sensors.p_touch_of,
    "sensors.p_multimodal": sensors.p_multimodal,
    "world.World._resolve_robot": world.World._resolve_robot,
    "world.World._resolve_contacts": world.World._resolve_contacts,
    "world.World._set_home": world.World._set_home,
    "world.World._motor_angles": world.World._motor_angles,
    "world.World.targets_for": world.World.targets_for,
    "world.World.reset": world.World.reset,
    "world.World.set_targets": world.World.set_targets,
    "world.World.advance": world.World.advance,
    "world.World.mark_colliding_segments": world.World.mark_colliding_segments,
    "world.World._gather_ball_touch": world.World._gather_ball_touch,
    "world.World._gather_touch": world.World._gather_touch,
    "world.World.motor_positions": world.World.motor_positions,
    "world.World.hand_contacts": world.World.hand_contacts,
    "world.World.hand_contacts_any": world.World.hand_contacts_any,
    "world.inner_face_touch": world.inner_face_touch,
    "world.palm_point": world.palm_point,
    "world.palm_normal": world.palm_normal,
}

#: The constants that code reads, by name.
REFERENCE_CONSTANTS = {
    "ctrnn": ("N_SENSORS", "N_HIDDEN", "N_MOTORS", "PROPRIO", "TOUCH", "SIGHT", "OFFSET",
              "ORIENT_YAW_SIGN", "ORIENT_PITCH_SIGN", "ORIENT_HOME_TARGETS", "ORIENT_GAIN",
              "GRASP_WEIGHT", "GRASP_BIAS", "RESET_MOTOR_STATE"),
    "sensors": ("HALF_FOV_X_DEG", "HALF_FOV_Y_DEG", "NO_TOUCH", "TOUCHING", "NO_SIGHT",
                "SIGHT_RANGE_M", "OFFSET_D_MAX_DEG", "OFFSET_SCALE"),
    "world": ("LIMIT_MARGIN", "BALL_PARKED", "TOUCH_DECISION_MARGIN", "PALM_NORMAL"),
}

#: sha256 (first 16 hex digits) of each pinned source, and of the constants' values.
FROZEN = {
    'steps.ReferenceSteps': '101d112eb015d15d',
    'steps.home_motor': '746229f5e2093a8b',
    'ctrnn.Network': '8282625822ecb645',
    'ctrnn.sigmoid': 'b810be9b4e1561ea',
    'ctrnn.motor_targets': 'dd35bc35ea19eac7',
    'ctrnn.reflex_weights': '5dcd028507b00610',
    'ctrnn.reflex_biases': '76f2702502ecfd8a',
    'sensors.clip': '5d484cd37821dd1a',
    'sensors.proprioception': '8f47ef7f4c119ec6',
    'sensors.touch': 'a9a553faae78c668',
    'sensors.project': 'e4ce35f36d5bfe61',
    'sensors.visual_angles': 'b3eab1144012ff28',
    'sensors.sight': '9b2bd3578182193a',
    'sensors.offset': 'f80e14e4bca43c20',
    'sensors.p_sight': 'd190075b87c448c3',
    'sensors.p_touch': '2718c629efa9d5f4',
    'sensors.p_touch_binary': '737364a7e03f93f3',
    'sensors.p_touch_capped': 'e00080f5b41f65dd',
    'sensors.p_touch_of': 'ddf7a2778dee11f3',
    'sensors.p_multimodal': '7516c8b8bcd6f805',
    'world.World._resolve_robot': '0cc98e4e4cc6cf16',
    'world.World._resolve_contacts': '2b8e80aca17d7436',
    'world.World._set_home': '49565c1ebd0f75af',
    'world.World._motor_angles': '6f37030562ad8302',
    'world.World.targets_for': '20578f88cae757cc',
    'world.World.reset': '6619d2cf0763a9ce',
    'world.World.set_targets': '141a40d9c95db6f1',
    'world.World.advance': '231a4ba7102e4abb',
    'world.World.mark_colliding_segments': '360ef10f7bd2639b',
    'world.World._gather_ball_touch': '8cae4675e19989b1',
    'world.World._gather_touch': '7329303b37bc4441',
    'world.World.motor_positions': '2f485392efa02009',
    'world.World.hand_contacts': '92e292dacf3093a7',
    'world.World.hand_contacts_any': 'c18b4001a7a8ee51',
    'world.inner_face_touch': '46236f614faaecfd',
    'world.palm_point': '5859255b0972470b',
    'world.palm_normal': '2ef35122b2bce76c',
    'constants': '822d6a2a4b4afb48',
}


def reference_digests() -> dict[str, str]:
    modules = {"ctrnn": ctrnn, "sensors": sensors, "world": world}
    found = {name: hashlib.sha256(inspect.getsource(code).encode()).hexdigest()[:16]
             for name, code in REFERENCE_CODE.items()}
    values = repr({f"{m}.{c}": repr(getattr(modules[m], c))
                   for m, names in REFERENCE_CONSTANTS.items() for c in names})
    found["constants"] = hashlib.sha256(values.encode()).hexdigest()[:16]
    return found


def test_version_1s_code_is_unchanged():
    found = reference_digests()
    changed = sorted(name for name in found if FROZEN.get(name) != found[name])
    assert not changed, f"version 1's reference code changed: {changed}"
