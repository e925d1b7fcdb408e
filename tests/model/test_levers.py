"""The model's levers (docs/model/levers.md): each one does what it says, in the real world,
and version 1's defaults are what the committed runs were trained with; in the living model
(the compiled numerics) each has one implementation, whose effect the last tests check through
the step functions that the genetic algorithm's trial, the recorded trial and the environment
all call (``compiled_trial.CompiledSteps``, ``model.compiled``, ``model.kernels``)."""

from dataclasses import replace

import numpy as np
import pytest

from dart_reach.evolution.genome import ParamGroup, decode
from dart_reach.evolution.settings import standard_trial
from dart_reach.measures.fitness import fitness_under_touch_pays
from dart_reach.model import compiled
from dart_reach.model.kernels import sensing
from dart_reach.model.kernels.network import CompiledNetwork
from dart_reach.model.sensors import TOUCHING
from dart_reach.model.ctrnn import (MOTOR_INDEX, N_SENSORS, SENSOR_INDEX, TOUCH,
                                    random_params, reflex_weights)
from dart_reach.model.levers import (REFLEX_EVOLVED_SCALE, Levers, NetworkStart, ReflexInputs,
                                     TouchPay)
from dart_reach.model.versions import Numerics, check_model_version
from dart_reach.model.task import Senses, Trial, TrialConfig, network_for
from dart_reach.model.world import World, WorldConfig
from dart_reach.robots import evolved_pre


@pytest.fixture(scope="module")
def world():
    return World()


def _touching_trial(world, **levers):
    """A shipped pre-reacher's trial that touches the ball (sector 4), under ``levers``."""
    cfg = standard_trial("pre", steps=120, **levers)
    genomes, _, _ = evolved_pre()
    trial = Trial(world, cfg)
    for genome in genomes[:6]:
        network = network_for(decode(genome, {ParamGroup.DIRECT}), cfg)
        for k in (4, 1, 7):
            data = trial.run(network, k, world.sector_point(k, 0.5, 0.5))
            if data.contacts.any(axis=1).sum() >= 3 and (data.contacts.sum(axis=1) > 1).any():
                return genome, k, data
    pytest.fail("no shipped pre-reacher touches the ball with several segments")


def test_levers_refuse_unknown_values_and_name_the_choices():
    with pytest.raises(ValueError, match="touch_pay must be one of 'faces', 'binary', 'capped'"):
        Levers(touch_pay="area")
    with pytest.raises(ValueError, match="unknown lever"):
        Levers.from_json({"touch": "binary"})
    with pytest.raises(ValueError, match="knows 1"):
        check_model_version(7)
    assert Levers.from_json(None) == Levers()  # a manifest before levers: version 1's
    assert Levers(touch_pay="binary").changed() == {"touch_pay": "binary"}


def test_touch_pays_follow_their_definitions():
    pay = sensing.touch_pay
    assert [pay(n, 16, sensing.PAY_CODES[TouchPay.FACES]) for n in (0, 4, 16)] == [0, .25, 1]
    assert [pay(n, 16, sensing.PAY_CODES[TouchPay.BINARY]) for n in (0, 1, 16)] == [0, 1, 1]
    assert [pay(n, 16, sensing.PAY_CODES[TouchPay.CAPPED])
            for n in (0, 1, 3, 4, 9)] == [0, .25, .75, 1, 1]


def test_a_trial_under_another_touch_pay_moves_the_same_and_scores_as_rescored(world):
    """The pay is not a sensor: the same trajectory, and its fitness is what
    ``fitness_under_touch_pays`` computes from the faces trial's touches."""
    genome, k, faces = _touching_trial(world)
    rescored = fitness_under_touch_pays(faces)
    assert rescored["fitness_faces"] == faces.fitness  # to the last bit
    assert rescored["fitness_binary"] > faces.fitness  # several segments touch at once
    for pay in (TouchPay.BINARY, TouchPay.CAPPED):
        cfg = standard_trial("pre", steps=120, touch_pay=pay)
        data = Trial(world, cfg).run(network_for(decode(genome, {ParamGroup.DIRECT}), cfg), k,
                                     world.sector_point(k, 0.5, 0.5))
        np.testing.assert_array_equal(data.hand, faces.hand)
        assert data.fitness == rescored[f"fitness_{pay.value}"]
        assert Trial(world, cfg).fitness(network_for(decode(genome, {ParamGroup.DIRECT}), cfg),
                                         world.sector_point(k, 0.5, 0.5)) == data.fitness


def test_network_start_zero_starts_every_state_at_zero(world):
    genome, k, home = _touching_trial(world)
    cfg = standard_trial("pre", steps=120, network_start=NetworkStart.ZERO)
    data = Trial(world, cfg).run(network_for(decode(genome, {ParamGroup.DIRECT}), cfg), k,
                                 world.sector_point(k, 0.5, 0.5))
    fresh = network_for(decode(genome, {ParamGroup.DIRECT}), cfg)
    fresh.reset(motor=np.zeros(14))
    np.testing.assert_array_equal(fresh.step(data.sensors[0]), data.motor[0])
    assert not np.array_equal(data.motor[0], home.motor[0])


def test_evolved_reflex_inputs_scale_the_other_inputs_and_keep_the_arcs():
    params = random_params(np.random.default_rng(3))
    mask, w = reflex_weights()
    hand_set = CompiledNetwork(params, reflexes=True).effective_w_sensor_motor
    evolved = CompiledNetwork(params, reflexes=True,
                              reflex_inputs=ReflexInputs.EVOLVED).effective_w_sensor_motor
    arcs = w != 0
    np.testing.assert_array_equal(hand_set[mask], w[mask])
    np.testing.assert_array_equal(evolved[arcs], w[arcs])
    others = mask & ~arcs
    np.testing.assert_array_equal(evolved[others],
                                  params.w_sensor_motor[others] * REFLEX_EVOLVED_SCALE)
    np.testing.assert_array_equal(evolved[~mask], params.w_sensor_motor[~mask])
    # without the reflexes the lever changes nothing
    np.testing.assert_array_equal(
        CompiledNetwork(params, reflex_inputs=ReflexInputs.EVOLVED).effective_w_sensor_motor,
        params.w_sensor_motor)


def test_the_grasp_reflex_still_acts_with_evolved_inputs_in_random_networks():
    rng = np.random.default_rng(5)
    hand, palm = MOTOR_INDEX["r_hand_fingers"], SENSOR_INDEX["touch/palm"]
    closes = opens = 0
    for _ in range(300):
        net = CompiledNetwork(random_params(rng), reflexes=True,
                              reflex_inputs=ReflexInputs.EVOLVED)
        W, b = net.effective_w_sensor_motor[hand], net.effective_bias_motor[hand]
        x = np.concatenate([rng.uniform(-1, 1, 14), rng.choice([-1.0, 1.0], 6),
                            rng.uniform(-1, 1, 2), rng.uniform(0, 1, 1), np.zeros(2)])
        x[palm] = 1.0
        closes += W @ x - b > 0
        x[palm] = -1.0
        opens += W @ x - b < 0
    assert closes >= 0.95 * 300 and opens >= 0.95 * 300


def _arm_chest_contacts(world) -> int:
    result = world.world.getLastCollisionResult()
    names = {(c.collisionObject1.getShapeFrame().getBodyNodePtr().getName(),
              c.collisionObject2.getShapeFrame().getBodyNodePtr().getName())
             for c in result.getContacts()}
    return sum("chest" in pair or "torso_2" in pair for pair in names)


# ------------------------------------------------------------- one implementation per lever
#: p_touch of n inner-face touches (of 16 segments) under each pay (``levers.TouchPay``).
EXPECTED_PAY = {TouchPay.FACES: lambda n: n / 16, TouchPay.BINARY: lambda n: float(n > 0),
                TouchPay.CAPPED: lambda n: min(n, 4) / 4}


@pytest.mark.parametrize("pay", list(TouchPay))
def test_the_touch_pay_is_the_one_sensing_steps(world, pay):
    """n segments touching on their inner face (the world's touch record, which the physics
    substeps fill): the recorded trial's and the environment's ``sense`` and the genetic
    algorithm's ``control_step`` pay p_touch as the lever says (binary 1 where faces pays
    n / 16), and p_multimodal = min(p_sight, p_touch) (Eq. 5), through the one sensing step."""
    cfg = TrialConfig(numerics=Numerics.COMPILED, touch_pay=pay, steps=1)
    trial = Trial(world, cfg)
    steps = trial.steps
    network = network_for(random_params(np.random.default_rng(1)), cfg)
    robot, ball = world.robot, world.ball_body
    for n in (0, 1, 3, 4, 9, 16):
        steps.reset(world.sector_point(4, 0.5, 0.5))
        world.touched[:] = np.arange(16) < n
        assert steps.sense() and steps.p_sight > 0  # the ball in view at home
        assert steps.p_touch == EXPECTED_PAY[pay](n)
        assert steps.p_multimodal == min(steps.p_sight, steps.p_touch)
        touching = world.touched[world.layout.touch_segments]
        assert np.array_equal(steps.x[TOUCH] == TOUCHING, touching)
        world.touched[:] = np.arange(16) < n
        p = np.zeros(1)
        assert compiled.control_step(0, robot.getPositions(), ball.getCOM(),
                                     robot.getGravityForces(), steps.state, network.state, p)
        assert p[0] == steps.p_multimodal


def test_the_reflex_inputs_lever_is_the_one_network_steps(world):
    """The same sensors and parameters under both levers through ``act`` (``act_step``, which
    ``control_step`` calls): only the three reflex motors' targets differ; their evolved
    direct inputs move them under ``EVOLVED`` and not under ``HAND_SET``."""
    rng = np.random.default_rng(7)
    params = random_params(rng)
    mask, w = reflex_weights()
    reflex_motors, evolved_inputs = mask.any(axis=1), mask & (w == 0)
    moved = replace(params, w_sensor_motor=np.where(evolved_inputs, -params.w_sensor_motor,
                                                    params.w_sensor_motor))
    x = rng.uniform(-1.0, 1.0, N_SENSORS)
    targets = {}
    for lever in ReflexInputs:
        cfg = TrialConfig(numerics=Numerics.COMPILED, reflex_inputs=lever, steps=1)
        steps = Trial(world, cfg).steps
        for name, p in (("params", params), ("moved", moved)):
            network = network_for(p, cfg)
            assert type(network) is CompiledNetwork
            network.reset()
            steps.x[:] = x
            assert steps.act(network)
            targets[lever, name] = steps.targets.copy()
    hand_set, evolved = ReflexInputs.HAND_SET, ReflexInputs.EVOLVED
    assert np.array_equal(targets[hand_set, "params"][~reflex_motors],
                          targets[evolved, "params"][~reflex_motors])
    assert (targets[hand_set, "params"] != targets[evolved, "params"])[reflex_motors].all()
    assert np.array_equal(targets[hand_set, "params"], targets[hand_set, "moved"])
    assert (targets[evolved, "params"] != targets[evolved, "moved"])[reflex_motors].all()


@pytest.mark.parametrize("start", list(NetworkStart))
def test_the_network_start_lever_is_the_one_start_of_every_trial(world, start):
    """``HOLD_HOME``: the start's targets are the home posture's; ``ZERO``: every motor state
    0 (targets -1). The recorded trial and the genetic algorithm's trial both start the
    network there (its first update, from the first sensors, is the same as a fresh network's
    from that start)."""
    cfg = TrialConfig(numerics=Numerics.COMPILED, network_start=start, steps=1)
    trial = Trial(world, cfg)
    steps = trial.steps
    assert steps.targets_of(steps.home_motor)
    if start is NetworkStart.HOLD_HOME:
        np.testing.assert_allclose(steps.targets, world.home_targets, rtol=0, atol=1e-12)
    else:
        assert (steps.home_motor == 0).all() and (steps.targets == -1).all()
    params = random_params(np.random.default_rng(2))
    ball = world.sector_point(4, 0.5, 0.5)
    data = trial.run(network_for(params, cfg), 4, ball)
    fresh = network_for(params, cfg)
    fresh.reset(motor=steps.home_motor)
    np.testing.assert_array_equal(fresh.step(data.sensors[0]), data.motor[0])
    network = network_for(params, cfg)
    trial.fitness(network, ball)
    np.testing.assert_array_equal(network.motor, data.motor[0])


def test_self_collision_is_the_one_physics_steps():
    """The living model's servo (the compiled steps' ``reset``, ``command`` and ``advance``),
    the ball parked away: at home nothing collides, the hand's overlapping shapes included;
    with the shoulder driven to the corners of its range, with self-collision on the arm meets
    the chest, off it passes through; either way no touch is counted (a touch is a hand
    segment on the ball, never on the body)."""
    names = ("r_shoulder_roll", "r_shoulder_yaw", "r_shoulder_pitch")
    hits = {}
    for on in (False, True):
        w = World(WorldConfig(self_collision=on))
        steps = Trial(w, TrialConfig(numerics=Numerics.COMPILED,
                                     senses=Senses.NO_BALL)).steps
        steps.reset(w.sector_point(4, 0.5, 0.5))
        for _ in range(3):
            steps.command(w.home_targets)
            steps.advance()
        assert w.world.getLastCollisionResult().getNumContacts() == 0
        hits[on] = 0
        for corner in np.ndindex(2, 2, 2):
            t = w.home_targets.copy()
            for name, side in zip(names, corner):
                t[MOTOR_INDEX[name]] = 2.0 * side - 1.0
            steps.reset(w.sector_point(4, 0.5, 0.5))
            for _ in range(20):
                steps.command(t)
                steps.advance()
                hits[on] += _arm_chest_contacts(w)
                assert not w.touched_any.any()
    assert hits[False] == 0 and hits[True] > 0
