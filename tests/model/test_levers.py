"""The model's levers (docs/model/levers.md): each one does what it says, in the real world,
and version 1's defaults are what the committed runs were trained with."""

from dataclasses import replace

import numpy as np
import pytest

from dart_reach.evolution.genome import ParamGroup, decode
from dart_reach.evolution.settings import standard_trial
from dart_reach.measures.fitness import fitness_under_touch_pays
from dart_reach.model import sensors
from dart_reach.model.ctrnn import (MOTOR_INDEX, SENSOR_INDEX, Network, random_params,
                                    reflex_weights)
from dart_reach.model.levers import (REFLEX_EVOLVED_SCALE, Levers, NetworkStart, ReflexInputs,
                                     TouchPay)
from dart_reach.model.versions import check_model_version
from dart_reach.model.task import Trial, network_for
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
    assert [sensors.p_touch_binary(n, 16) for n in (0, 1, 16)] == [0.0, 1.0, 1.0]
    assert [sensors.p_touch_capped(n, 16, 4) for n in (0, 1, 3, 4, 9)] == [0, .25, .75, 1, 1]
    with pytest.raises(ValueError):
        sensors.p_touch_binary(17, 16)


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
    hand_set = Network(params, reflexes=True).effective_w_sensor_motor
    evolved = Network(params, reflexes=True,
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
        Network(params, reflex_inputs=ReflexInputs.EVOLVED).effective_w_sensor_motor,
        params.w_sensor_motor)


def test_the_grasp_reflex_still_acts_with_evolved_inputs_in_random_networks():
    rng = np.random.default_rng(5)
    hand, palm = MOTOR_INDEX["r_hand_fingers"], SENSOR_INDEX["touch/palm"]
    closes = opens = 0
    for _ in range(300):
        net = Network(random_params(rng), reflexes=True, reflex_inputs=ReflexInputs.EVOLVED)
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


def test_self_collision_stops_the_arm_at_the_chest_and_touch_counts_the_ball_only():
    worlds = {on: World(WorldConfig(self_collision=on)) for on in (False, True)}
    # at home nothing collides, the hand's overlapping shapes included
    for w in worlds.values():
        w.reset(w.sector_point(4, 0.5, 0.5))
        for _ in range(3):
            w.step(w.home_targets)
        assert w.world.getLastCollisionResult().getNumContacts() == 0
    # the shoulder driven to the corners of its range: some corners bring the arm to the chest
    names = ("r_shoulder_roll", "r_shoulder_yaw", "r_shoulder_pitch")
    hits = {False: 0, True: 0}
    for corner in np.ndindex(2, 2, 2):
        t = worlds[True].home_targets.copy()
        for name, side in zip(names, corner):
            t[MOTOR_INDEX[name]] = 2.0 * side - 1.0
        for on, w in worlds.items():
            w.reset(w.sector_point(4, 0.5, 0.5))
            for _ in range(20):
                w.step(t)
                hits[on] += _arm_chest_contacts(w)
                if w.hand_contacts_any().any():  # a touch is a touch of the ball
                    hand_ball = np.linalg.norm(w.hand_position() - w.ball_position())
                    assert hand_ball < 0.15
    assert hits[False] == 0  # off: the arm passes through the body
    assert hits[True] > 0  # on: it meets the chest
