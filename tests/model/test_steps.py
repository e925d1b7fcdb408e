"""The trial's step functions behind one interface (``model.steps``), and the world's public,
frozen layout they read (``model.layout``)."""

from __future__ import annotations

import dataclasses
import importlib
import re
from pathlib import Path

import numpy as np
import pytest

from dart_reach.model import compiled, compiled_trial, icub, servo, steps, task
from dart_reach.model.compiled_trial import CompiledSteps
from dart_reach.model.ctrnn import MOTOR_NAMES, N_SENSORS
from dart_reach.model.layout import TOUCH_SEGMENTS
from dart_reach.model.reference.steps import ReferenceSteps
from dart_reach.model.steps import TrialSteps
from dart_reach.model.task import Trial, TrialConfig
from dart_reach.model.versions import Numerics
from dart_reach.model.world import World

MODEL = Path(task.__file__).parent
#: The living model's kernels (``model.kernels``), one module per concept.
KERNELS = [importlib.import_module(f"dart_reach.model.kernels.{name}")
           for name in ("floats", "kinematics", "motors", "network", "sensing", "touch")]


@pytest.fixture(scope="module")
def world():
    return World()


def test_the_layout_is_frozen_and_read_only(world):
    layout = world.layout
    with pytest.raises(dataclasses.FrozenInstanceError):
        layout.max_move = 1.0
    for f in dataclasses.fields(layout):
        value = getattr(layout, f.name)
        if isinstance(value, np.ndarray):
            assert not value.flags.writeable, f.name
            with pytest.raises(ValueError):
                value[...] = 0
    for a in layout.tree.arrays:
        assert not a.flags.writeable
    with pytest.raises(TypeError):
        layout.touch_faces[object()] = None


def test_the_layout_names_the_skeletons_indices(world):
    layout, robot = world.layout, world.robot
    assert layout.motor_dofs.tolist() == \
        [robot.getJoint(n).getIndexInSkeleton(0) for n in MOTOR_NAMES[:13]]
    assert [robot.getBodyNode(int(b)).getName() for b in layout.segment_body] == \
        list(icub.HAND_SEGMENTS)
    assert robot.getBodyNode(layout.camera_body).getName() == icub.CAMERA
    assert robot.getBodyNode(layout.hand_body).getName() == icub.HAND
    assert robot.getBodyNode(layout.shoulder_body).getName() == icub.SHOULDER
    assert [icub.HAND_SEGMENTS[i] for i in TOUCH_SEGMENTS] == list(icub.TOUCH_BODIES)
    assert (layout.dof_motor[layout.finger_dofs] == 13).all()
    assert np.array_equal(layout.motor_limit_span,
                          world.motor_limit_upper - world.motor_limit_lower)
    assert layout.max_move == world.config.max_joint_speed * world.config.control_dt
    assert not layout.tree.unsupported
    assert sorted({f.segment for f in layout.touch_faces.values()}) == \
        list(range(len(icub.HAND_SEGMENTS)))
    assert {body.getName(): i for body, i in layout.segment_index.items()} == \
        {name: i for i, name in enumerate(icub.HAND_SEGMENTS)}


@pytest.mark.parametrize("numerics, kind", [(Numerics.REFERENCE, ReferenceSteps),
                                            (Numerics.COMPILED, CompiledSteps)])
def test_a_trial_takes_its_numerics_steps_by_composition(world, numerics, kind):
    """The steps are chosen at construction; no method of the trial is replaced on the
    instance; both kinds offer the whole interface."""
    trial = Trial(world, TrialConfig(steps=5, numerics=numerics))
    assert type(trial.steps) is kind
    for name in ("sense", "observe", "command", "control", "begin", "run", "fitness", "reset"):
        assert name not in vars(trial), name
    members = [m for m in vars(TrialSteps) if not m.startswith("_")]
    members += list(TrialSteps.__annotations__)
    for name in members:
        assert hasattr(trial.steps, name), name
    assert trial.steps.x.shape == (N_SENSORS,)


@pytest.mark.parametrize("module", [task, steps, compiled_trial, servo, compiled, *KERNELS])
def test_the_step_code_reads_no_private_attribute_of_another_object(module):
    """``self._name`` only: never ``world._name``, ``trial._name``, ``network._name``."""
    source = Path(module.__file__).read_text()
    found = re.findall(r"(?<![\w.])(?!self\b)([A-Za-z_]\w*)\._[A-Za-z]\w*", source)
    assert not found, found


def test_the_sensor_and_motor_layout_is_named_once():
    """``ctrnn``'s slices and indices name the vectors' entries; the compiled step functions
    and kernels write through them, never through a literal index."""
    from dart_reach.model import ctrnn, kernels

    names = ctrnn.SENSOR_NAMES
    assert [names[i] for i in (ctrnn.SIGHT_X, ctrnn.SIGHT_Y, ctrnn.SIGHT_DISTANCE,
                               ctrnn.OFFSET_X, ctrnn.OFFSET_Y)] == \
        ["sight/x", "sight/y", "sight/distance", "offset/x", "offset/y"]
    for layer, prefix in ((ctrnn.PROPRIO, "proprio/"), (ctrnn.TOUCH, "touch/"),
                          (ctrnn.SIGHT, "sight/"), (ctrnn.OFFSET, "offset/")):
        assert all(n.startswith(prefix) for n in names[layer])
    assert sum(len(names[s]) for s in (ctrnn.PROPRIO, ctrnn.TOUCH, ctrnn.SIGHT, ctrnn.OFFSET)
               ) == ctrnn.N_SENSORS
    motors = ctrnn.MOTOR_NAMES
    assert all(n.startswith("neck") for n in motors[ctrnn.NECK])
    assert all(n.startswith("torso") for n in motors[ctrnn.TORSO])
    assert all(n.startswith("r_") for n in motors[ctrnn.ARM])
    assert motors[ctrnn.HAND_MOTOR] == "r_hand_fingers"
    assert motors[ctrnn.JOINT_MOTORS] == motors[:ctrnn.HAND_MOTOR]
    code = [Path(compiled.__file__), *Path(kernels.__file__).parent.glob("*.py")]
    assert len(code) > 5
    for path in code:
        assert not re.findall(r"\bx\[\d", path.read_text()), path.name
