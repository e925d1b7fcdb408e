"""Model version 2's compiled numerics (``model.compiled`` over the kernels of
``model.kernels``): the same equations as version 1, its own rounding, the same bits on every
processor."""

from __future__ import annotations

import hashlib
import importlib
import json
import math
import os
import platform
import subprocess
import sys
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pytest

from dart_reach.evolution.genome import ParamGroup, decode
from dart_reach.evolution.settings import Settings, standard_trial, trial_config
from dart_reach.evolution.conditions import load_condition
from dart_reach.model import compiled, kernels
from dart_reach.model.kernels import floats, kinematics
from dart_reach.model.kernels.network import CompiledNetwork, logistic
from dart_reach.model.compiled_trial import CompiledSteps
from dart_reach.model.ctrnn import N_SENSORS, random_params
from dart_reach.model.reference.network import ReferenceNetwork
from dart_reach.model.reference.steps import ReferenceSteps
from dart_reach.model.versions import Numerics, numerics_of
from dart_reach.model.task import Trial, network_for
from dart_reach.model.world import World, WorldConfig
from dart_reach.robots import robots


@pytest.fixture(scope="module")
def world():
    return World()


def _ulps(a: float, b: float) -> int:
    ia, ib = (np.array([v]).view(np.int64)[0] for v in (a, b))
    return abs(int(ia) - int(ib))


def test_the_exponential_is_within_two_ulp_of_the_c_librarys():
    rng = np.random.default_rng(0)
    xs = np.concatenate([-rng.exponential(3.0, 20000), rng.uniform(-745.0, 0.0, 5000),
                         [0.0, -0.0, -1e-300, -0.5 * math.log(2), -math.log(2), -700.0]])
    worst = max(_ulps(floats.exp_nonpositive(x), math.exp(x)) for x in xs)
    assert worst <= 2
    assert floats.exp_nonpositive(-746.0) == 0.0 and floats.exp_nonpositive(0.0) == 1.0
    assert math.isnan(floats.exp_nonpositive(float("nan")))


def test_the_logistic_is_the_update_equations_sigma_without_overflow():
    for z in (-800.0, -40.0, -3.0, -1e-9, 0.0, 1e-9, 2.5, 40.0, 800.0):
        expected = 1.0 / (1.0 + math.exp(-z)) if z > -700 else 0.0
        assert logistic(z) == pytest.approx(expected, rel=1e-15, abs=1e-300)
    assert logistic(0.0) == 0.5
    assert logistic(3.0) + logistic(-3.0) == pytest.approx(1.0, abs=3e-16)


@pytest.mark.parametrize("reflexes, frozen", [(True, True), (False, False), (True, False)])
def test_the_compiled_network_follows_version_1s_equation(reflexes, frozen):
    rng = np.random.default_rng(3)
    for _ in range(5):
        params = random_params(rng)
        a = ReferenceNetwork(params, reflexes=reflexes, hidden_frozen=frozen)
        b = CompiledNetwork(params, reflexes=reflexes, hidden_frozen=frozen)
        for _ in range(30):
            x = rng.uniform(-1, 1, N_SENSORS)
            assert np.allclose(b.step(x), a.step(x), rtol=0, atol=1e-13)
            assert np.allclose(b.hidden, a.hidden, rtol=0, atol=1e-13)
    with pytest.raises(ValueError, match="25 sensor values"):
        b.step(np.zeros(3))


def test_the_compiled_forward_kinematics_gives_darts_pose_of_every_body(world):
    robot, rng = world.robot, np.random.default_rng(5)
    n = robot.getNumBodyNodes()
    poses = np.zeros((n, 4, 4))
    try:
        for _ in range(20):
            q = rng.uniform(world.lower, world.upper)
            robot.setPositions(q)
            kinematics.body_poses(q, np.arange(n), *world.layout.tree.arrays,
                                  np.zeros((3, 4, 4)), poses)
            for i in range(robot.getNumBodyNodes()):
                assert np.allclose(poses[i], robot.getBodyNode(i).getTransform().matrix(),
                                   rtol=0, atol=1e-12)
    finally:
        world.reset(world.sector_point(4, 0.5, 0.5))


def test_model_version_2_computes_with_the_compiled_numerics(world):
    pre = load_condition("standard").phases[0]
    config = trial_config(pre, Settings(model_version=2))
    assert config.numerics is Numerics.COMPILED is numerics_of(2)
    reference = trial_config(pre, Settings(model_version=1))
    assert reference.numerics is Numerics.REFERENCE
    assert isinstance(Trial(world, config).steps, CompiledSteps)
    assert isinstance(Trial(world, reference).steps, ReferenceSteps)
    assert type(network_for(random_params(np.random.default_rng(0)), config)
                ) is CompiledNetwork


def _both_versions(world, phase: str, k: int, u: float, v: float, **changes):
    """The best shipped robot of ``phase`` in one trial (sector ``k`` at fractions u, v)
    under version 1's numerics and under version 2's."""
    robot = robots(phase, run="replication-50x10")[0]
    groups = {ParamGroup.DIRECT} if phase == "pre" else set(ParamGroup)
    runs = []
    for numerics in Numerics:
        cfg = standard_trial(phase, numerics=numerics, **changes)
        runs.append(Trial(world, cfg).run(network_for(decode(robot.genome, groups), cfg), k,
                                          world.sector_point(k, u, v)))
    return runs


@pytest.mark.parametrize("phase, self_collision", [("pre", False), ("fine", False),
                                                    ("pre", True)])
def test_a_version_2_trial_is_version_1s_trial_but_for_rounding(world, phase, self_collision):
    """The same robot, ball and steps under both numerics: the same trial to within rounding
    over the first steps (later the two roundings part as any chaotic system's do); with
    self-collision on, only the ball's contacts touch."""
    if self_collision:
        world = World(WorldConfig(self_collision=True))
    # 30 steps: the hand meets the ball
    v1, v2 = _both_versions(world, phase, 2 if phase == "pre" else 6, 0.4, 0.6, steps=30)
    for name in ("sensors", "motor", "targets", "joints", "dofs", "hand", "shoulder", "ball",
                 "palm_normal", "p_multimodal"):
        assert np.allclose(getattr(v1, name), getattr(v2, name), rtol=0, atol=1e-9), name
    assert np.array_equal(v1.contacts, v2.contacts)
    assert np.array_equal(v1.contacts_any, v2.contacts_any) and v1.contacts.any()
    assert not np.array_equal(v1.motor, v2.motor)  # two roundings indeed


@pytest.mark.parametrize("pay", ["binary", "capped"])
def test_version_2_pays_touch_as_version_1_under_every_pay(world, pay):
    v1, v2 = _both_versions(world, "pre", 2, 0.4, 0.6, steps=30, touch_pay=pay)
    assert v1.contacts.any() and np.array_equal(v1.contacts, v2.contacts)
    assert np.array_equal(v1.p_touch, v2.p_touch) and len(set(v1.p_touch.tolist())) > 1


@pytest.mark.parametrize("senses", ["no-ball", "nothing"])
def test_version_2_deprives_the_senses_as_version_1(world, senses):
    v1, v2 = _both_versions(world, "fine", 5, 0.5, 0.5, steps=20, senses=senses)
    assert np.array_equal(v1.sensors[:, 14:], v2.sensors[:, 14:])  # touch, sight, offsets
    assert np.array_equal(v1.ball, v2.ball) and not v2.contacts.any()
    assert np.allclose(v1.joints, v2.joints, rtol=0, atol=1e-9)


def _fitness_and_run(trial, network, k, ball):
    """A trial's fitness, then its run: (fitness, p per step, the joint positions and motor
    states at the end) of each."""
    ends = []
    for way in ("fitness", "run"):
        if way == "fitness":
            f = trial.fitness(network, ball)
            p = trial.p_series.copy()
        else:
            data = trial.run(network, k, ball)
            f, p = data.fitness, data.p_multimodal
        ends.append((f, p, trial.world.robot.getPositions(), network.motor.copy()))
    return ends


@pytest.mark.parametrize("phase, k", [("pre", 2), ("fine", 6)])
def test_run_and_fitness_agree_to_the_last_bit_under_version_2(world, phase, k):
    """``fitness`` takes a control step in one compiled call (``control_step``), ``run`` in
    the trial's own steps: the same trials to the last bit (every step's p_multimodal, the
    end's joints and motor states), the offset sensors and internal neurons of
    fine-reaching included."""
    cfg = standard_trial(phase, steps=60, numerics=Numerics.COMPILED)
    trial = Trial(world, cfg)
    groups = {ParamGroup.DIRECT} if phase == "pre" else set(ParamGroup)
    for robot in robots(phase, run="replication-50x10")[:2]:
        network = network_for(decode(robot.genome, groups), cfg)
        for kk, (u, v) in ((k, (0.4, 0.6)), (4, (0.5, 0.5))):
            (f1, p1, q1, m1), (f2, p2, q2, m2) = _fitness_and_run(
                trial, network, kk, world.sector_point(kk, u, v))
            assert f1 == f2 and np.array_equal(p1, p2)
            assert np.array_equal(q1, q2) and np.array_equal(m1, m2)
    assert f1 > 0  # the hand met the ball


def test_version_2s_fitness_scores_an_explosion_zero_and_steps_a_version_1_network(world):
    cfg = standard_trial("pre", steps=30, numerics=Numerics.COMPILED)
    trial = Trial(world, cfg)
    params = decode(robots("pre", run="replication-50x10")[0].genome, {ParamGroup.DIRECT})
    ball = world.sector_point(2, 0.4, 0.6)
    v1_network = network_for(params, standard_trial("pre", numerics=Numerics.REFERENCE))
    (f1, p1, q1, _), (f2, p2, q2, _) = _fitness_and_run(trial, v1_network, 2, ball)
    assert f1 == f2 > 0 and np.array_equal(p1, p2) and np.array_equal(q1, q2)
    network, steps = network_for(params, cfg), trial.steps
    assert trial.fitness(network, ball) > 0
    original, calls = steps.servo.substeps, []

    def exploding():  # the real substeps, then the state blown up after 5 control steps
        original()
        calls.append(1)
        if len(calls) == 5:
            world.robot.setVelocities(np.full(world.robot.getNumDofs(), np.nan))
    steps.servo.substeps = exploding
    assert trial.fitness(network, ball) == 0.0 and len(calls) == 6


def test_version_2_grows_its_contact_buffers_and_decides_the_same_touches(world):
    """A substep with more contacts than the buffers hold: they grow (with the touch
    decisions' state), and the trial is the same to the last bit."""
    cfg = standard_trial("pre", steps=30, numerics=Numerics.COMPILED)
    params = decode(robots("pre", run="replication-50x10")[0].genome, {ParamGroup.DIRECT})
    ball, runs = world.sector_point(2, 0.4, 0.6), []
    for size in (None, 1):
        trial = Trial(world, cfg)
        if size:
            trial.steps.servo.hold_contacts(size)
        runs.append(trial.run(network_for(params, cfg), 2, ball))
    assert len(trial.steps.servo.contact_segments) > 1 and runs[0].contacts.any()
    for name in ("contacts", "contacts_any", "dofs", "sensors"):
        assert np.array_equal(getattr(runs[0], name), getattr(runs[1], name)), name


# ------------------------------------------------------------------ the digest of version 2
#: Digests of every record of 8 trials per phase (2 shipped robots x 4 sectors, 150 steps;
#: pre-reaching and fine-reaching, whose offset sensors and internal neurons count), computed
#: at the revision that introduced version 2, on x86_64 with dartpy 6.20.0 and numpy 2.4.6 at
#: the dispatch level ``import dart_reach`` pins (X86_V3): the compiled code does not depend on
#: the processor (tested below), but the scene's geometry (the sectors' points, numpy's sin and
#: cos) and the records' products are numpy's, as in version 1.
GOLDEN_V2 = {"pre": "4f24f162d68ab8df", "fine": "dc7c46b934986c3d"}
GOLDEN_V2_PLATFORM = ("x86_64", "6.20.0", "2.4.6", "X86_V3")
RECORDS = ("dofs", "joints", "hand", "shoulder", "ball", "contacts", "contacts_any", "sensors",
           "hidden", "motor", "targets", "p_sight", "p_touch", "p_multimodal")


def version_2_trials() -> dict:
    """Computed in this process: the digests of ``GOLDEN_V2`` (``run``'s records), and per
    phase the same trials' fitness as ``run`` and as ``fitness`` (the genetic algorithm's
    trial, one compiled call a control step) gives it, as hex floats."""
    world, found = World(), {"digests": {}, "run": {}, "fitness": {}}
    for phase in GOLDEN_V2:
        cfg = standard_trial(phase, steps=150, numerics=Numerics.COMPILED)
        trial = Trial(world, cfg)
        groups = {ParamGroup.DIRECT} if phase == "pre" else set(ParamGroup)
        h, run, fitness = hashlib.sha256(), [], []
        for robot in robots(phase, run="replication-50x10")[:2]:
            network = network_for(decode(robot.genome, groups), cfg)
            for k in (0, 3, 4, 8):
                ball = world.sector_point(k, 0.3, 0.6)
                data = trial.run(network, k, ball)
                for name in RECORDS:
                    h.update(np.ascontiguousarray(getattr(data, name)).tobytes())
                run.append(data.fitness.hex())
                fitness.append(trial.fitness(network, ball).hex())
        found["digests"][phase] = h.hexdigest()[:16]
        found["run"][phase], found["fitness"][phase] = run, fitness
    return found


def _golden_platform() -> bool:
    from dart_reach.evolution.provenance import simd

    return (platform.machine(), version("dartpy"), np.__version__, simd()) == GOLDEN_V2_PLATFORM


@pytest.mark.skipif(not _golden_platform(),
                    reason=f"version 2's digests were recorded on {GOLDEN_V2_PLATFORM} "
                           f"(machine, dartpy, numpy, numpy's dispatch level)")
def test_version_2_trials_are_pinned_and_the_same_compiled_for_an_avx2_processor(tmp_path):
    """The digests in this process (compiled for this processor) and in a process whose
    compiled code targets Haswell (AVX2 and FMA, no AVX-512; Numba's ``NUMBA_CPU_NAME``):
    the same, and the recorded ones; the genetic algorithm's trials of the same robots give
    the same fitness as ``run`` in both. (Measured once more by hand at the revision that
    introduced version 2: compiled for a generic x86-64, the same digests.)"""
    here = version_2_trials()
    script = ("import importlib.util, json, dart_reach; "
              f"spec = importlib.util.spec_from_file_location('t', {__file__!r}); "
              "t = importlib.util.module_from_spec(spec); spec.loader.exec_module(t); "
              "print(json.dumps(t.version_2_trials()))")
    env = dict(os.environ, NUMBA_CPU_NAME="haswell", NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                         text=True, check=True)
    assert json.loads(out.stdout.strip().splitlines()[-1]) == here
    assert here["digests"] == GOLDEN_V2
    assert here["fitness"] == here["run"] and len(set(here["run"]["pre"])) > 1


# ------------------------------------------------------------------ uncompiled, for debugging
#: The modules of ``model.kernels`` that hold compiled functions: all but ``structures``.
KERNELS = tuple(sorted(p.stem for p in Path(kernels.__file__).parent.glob("*.py")
                       if p.stem not in ("__init__", "structures")))


def test_every_kernel_module_is_compiled_here():
    """In this process (compiled), every module of ``KERNELS`` holds Numba dispatchers, so
    that the uncompiled process's check below can fail."""
    assert set(KERNELS) >= {"floats", "kinematics", "motors", "network", "sensing", "touch"}
    for name in KERNELS:
        module = importlib.import_module(f"dart_reach.model.kernels.{name}")
        assert any(hasattr(f, "py_func") for f in vars(module).values()), name


def touching_trial() -> dict:
    """Computed in this process: one version 2 trial of the best shipped pre-reacher whose
    hand meets the ball (30 steps), as ``run`` records it (the digest of every record, whether
    a segment touched) and its fitness by ``run`` and by ``fitness`` (``control_step``), as
    hex floats."""
    world = World()
    cfg = standard_trial("pre", steps=30, numerics=Numerics.COMPILED)
    trial = Trial(world, cfg)
    params = decode(robots("pre", run="replication-50x10")[0].genome, {ParamGroup.DIRECT})
    network, ball = network_for(params, cfg), world.sector_point(2, 0.4, 0.6)
    data = trial.run(network, 2, ball)
    h = hashlib.sha256()
    for name in RECORDS:
        h.update(np.ascontiguousarray(getattr(data, name)).tobytes())
    return {"digest": h.hexdigest(), "touched": bool(data.contacts.any()),
            "run": data.fitness.hex(), "fitness": trial.fitness(network, ball).hex()}


def test_the_compiled_steps_run_uncompiled_to_the_same_bits():
    """``NUMBA_DISABLE_JIT=1`` (docs/model/trial.md, running the compiled model uncompiled):
    every function of ``model.compiled`` and of the kernels' modules runs as Python, their
    structures as plain objects, and a trial whose hand touches the ball is the same to the
    last bit, recorded and as the genetic algorithm scores it."""
    script = ("import importlib, importlib.util, json, dart_reach; "
              f"spec = importlib.util.spec_from_file_location('t', {__file__!r}); "
              "t = importlib.util.module_from_spec(spec); spec.loader.exec_module(t); "
              "from dart_reach.model import compiled; "
              "kernels = [importlib.import_module('dart_reach.model.kernels.' + m) "
              f"for m in {KERNELS!r}]; "
              "assert not hasattr(compiled.control_step, 'py_func'); "
              "assert not [f for m in kernels for f in vars(m).values() "
              "if hasattr(f, 'py_func')]; "
              "print(json.dumps(t.touching_trial()))")
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                         text=True, check=True)
    compiled_trial = touching_trial()
    assert json.loads(out.stdout.strip().splitlines()[-1]) == compiled_trial
    assert compiled_trial["touched"] and compiled_trial["run"] == compiled_trial["fitness"]
