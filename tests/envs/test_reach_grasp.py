"""The Gymnasium environment is the paper's trial: an evolved robot stepped through it earns the
fitness ``Trial.run`` gives it, bit for bit; its reflexes are the network's; Gymnasium's own
checker passes; same seed, same episode; it runs vectorised; an episode records like a trial."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import dart_reach  # noqa: E402
from dart_reach.envs import REFLEX_MOTORS, ReachGraspEnv  # noqa: E402
from dart_reach.envs.seeing import record_episode  # noqa: E402
from dart_reach.evolution.genome import decode  # noqa: E402
from dart_reach.model.task import Trial, network_for, trial_positions  # noqa: E402
from dart_reach.model.world import World  # noqa: E402
from dart_reach.recording.rrd import read_rrd  # noqa: E402
from dart_reach.robots import robots  # noqa: E402
from dart_reach.viewing.headless import renderer_missing  # noqa: E402


def shipped_network(env: ReachGraspEnv, phase: str, reflexes: bool = True):
    """The best shipped robot of ``phase`` of the 50 x 10 replication, as the GA builds it."""
    robot = robots(phase, run="replication-50x10")[0]
    config = replace(env.config, reflexes=reflexes)
    return robot, config, network_for(decode(robot.genome, env.phase.free_groups), config)


def episode(env, policy, **reset):
    """Step ``policy`` (a network: its ``step(observation)``) through one episode."""
    observation, info = env.reset(**reset)
    policy.reset(motor=info["home_action"])
    rewards, done = [], False
    while not done:
        observation, reward, terminated, truncated, info = env.step(policy.step(observation))
        rewards.append(reward)
        done = terminated or truncated
    return np.array(rewards), info


def test_a_shipped_robot_earns_the_fitness_its_trial_gives_it_bit_for_bit():
    # fine-reaching: full acuity, offset sensors, internal neurons, reflexes (inside the
    # network, so the environment's are off and the network is the whole controller)
    env = ReachGraspEnv(phase="fine", reflexes=False)
    _, config, network = shipped_network(env, "fine")
    rewards, info = episode(env, network, seed=2013)
    sector, position = env.trial_data.sector, env.trial_data.ball_start
    # the position is a GA trial's, drawn from the seed
    k, p = trial_positions(World(), np.random.default_rng(2013), trials=1)[0]
    assert (sector, position.tolist()) == (k, p.tolist())
    data = Trial(World(env.world.config), config).run(network, sector, position)
    assert data.fitness > 0.05  # a robot that reaches: the comparison means something
    assert rewards.shape == (200,) and np.array_equal(rewards, data.p_multimodal)
    assert np.mean(rewards) == data.fitness == info["fitness"]
    mine = env.trial_data
    for name in ("sensors", "joints", "dofs", "motor", "targets", "contacts", "ball"):
        assert np.array_equal(getattr(mine, name), getattr(data, name)), name
    assert mine.steps_run == data.steps_run == 200 and not info["diverged"]


def test_the_reflexes_are_the_networks_and_override_the_action():
    """A pre-reaching robot whose reflex motor neurons have no memory (tau 0) moves its
    reflex motors exactly as the reflex arcs alone do: with the environment's reflexes on it
    earns its trial's fitness, and what the action says there does not matter."""
    env = ReachGraspEnv(phase="pre", steps=40)
    assert env.config.reflexes and env.config.acuity == 3.0
    robot, config, _ = shipped_network(env, "pre")
    params = decode(robot.genome, env.phase.free_groups)
    params.tau_motor[REFLEX_MOTORS] = 0.0
    network = network_for(params, config)
    options = {"sector": 3, "ball_position": World().sector_point(3, 0.5, 0.5)}
    rewards, _ = episode(env, network, options=options)
    data = Trial(World(), config).run(network, 3, options["ball_position"])
    assert np.array_equal(rewards, data.p_multimodal)
    assert np.array_equal(env.trial_data.motor, data.motor)

    class Contrary:  # the same network, its reflex outputs replaced by nonsense
        def reset(self, motor):
            network.reset(motor)

        def step(self, x):
            a = network.step(x).copy()
            a[REFLEX_MOTORS] = 1.0 - a[REFLEX_MOTORS]
            return a
    again, _ = episode(env, Contrary(), options=options)
    assert np.array_equal(again, rewards)
    # with the reflexes off the same nonsense drives the neck and hand: another trial
    off = ReachGraspEnv(phase="pre", steps=40, reflexes=False)
    episode(off, Contrary(), options=options)
    assert not np.array_equal(off.trial_data.joints, env.trial_data.joints)


def test_gymnasiums_checker_passes_and_the_id_is_registered():
    from gymnasium.utils.env_checker import check_env

    env = gymnasium.make(dart_reach.GYM_ID, phase="gross", steps=10)
    assert isinstance(env.unwrapped, ReachGraspEnv) and env.unwrapped.config.acuity == 1.0
    check_env(env.unwrapped, skip_render_check=True)


def test_importing_dart_reach_needs_no_gymnasium():
    code = ("import sys; sys.modules['gymnasium'] = None\n"
            "import dart_reach; print(dart_reach.GYM_ID)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == dart_reach.GYM_ID, out.stderr


def run_actions(env, seed, actions):
    observations = [env.reset(seed=seed)[0].copy()]
    rewards = []
    for a in actions:
        observation, reward, *_ = env.step(a)
        observations.append(observation.copy())
        rewards.append(reward)
    return np.array(observations), np.array(rewards)


def test_same_seed_same_episode_another_seed_another():
    env = ReachGraspEnv(phase="gross", steps=15)
    actions = np.random.default_rng(0).random((15, 14))
    first, r1 = run_actions(env, 5, actions)
    second, r2 = run_actions(env, 5, actions)
    other, _ = run_actions(env, 6, actions)
    assert np.array_equal(first, second) and np.array_equal(r1, r2)
    assert not np.array_equal(first, other)
    # the offset sensors read "nothing seen" (0) where the phase has none, not in fine-reaching
    assert (first[:, 23:] == 0.0).all()


@pytest.mark.parametrize("vector", ["SyncVectorEnv", "AsyncVectorEnv"])
def test_vector_environments_step_as_single_ones(vector):
    steps = 4
    make = lambda: ReachGraspEnv(phase="fine", steps=steps)  # noqa: E731
    actions = np.random.default_rng(1).random((steps, 2, 14))
    envs = getattr(gymnasium.vector, vector)([make, make])
    try:
        observations, _ = envs.reset(seed=[11, 12])
        rewards = []
        for a in actions:
            observations, reward, terminated, truncated, info = envs.step(a)
            rewards.append(reward)
        assert truncated.all() and not terminated.any()
    finally:
        envs.close()
    single = make()
    for i, seed in enumerate((11, 12)):
        expected_obs, expected_rewards = run_actions(single, seed, actions[:, i])
        assert np.array_equal(observations[i], expected_obs[-1])
        assert np.array_equal(np.array(rewards)[:, i], expected_rewards)


def test_bad_options_are_refused_with_their_reason():
    with pytest.raises(ValueError, match="unknown phase 'crawl'.*gross"):
        ReachGraspEnv(phase="crawl")
    with pytest.raises(ValueError, match="steps must be a positive"):
        ReachGraspEnv(steps=0)
    with pytest.raises(ValueError, match="render_mode"):
        ReachGraspEnv(render_mode="human")
    env = ReachGraspEnv(steps=3)
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(env.home_action)
    with pytest.raises(ValueError, match="unknown reset option.*'colour'"):
        env.reset(options={"colour": "red"})
    with pytest.raises(ValueError, match="needs its 'sector'"):
        env.reset(options={"ball_position": [0.0, 0.0, 0.0]})
    with pytest.raises(ValueError, match="sector must be an integer in 0..8"):
        env.reset(options={"sector": 9})
    observation, _ = env.reset(seed=0)
    with pytest.raises(ValueError, match="read-only"):  # the trial's record is safe
        observation *= 2.0
    with pytest.raises(ValueError, match=r"shape \(14,\)"):
        env.step(np.zeros(13))
    with pytest.raises(ValueError, match="finite"):
        env.step(np.full(14, np.nan))
    for _ in range(3):
        env.step(env.home_action)
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(env.home_action)


def test_an_episode_records_like_a_trial(tmp_path):
    env = ReachGraspEnv(phase="pre", steps=200)
    env.reset(seed=3, options={"sector": 4})
    for _ in range(12):
        env.step(env.action_space.sample())
    table = read_rrd(record_episode(env, tmp_path / "episode.rrd"))
    assert table["step"].to_list() == list(range(12))
    for term in ("p_sight", "p_multimodal"):
        assert np.array_equal(table[f"fitness/{term}"].to_numpy(),
                              getattr(env.trial_data, term)[:12])


@pytest.mark.skipif(renderer_missing() is None, reason="a Vulkan driver is installed here")
def test_rendering_without_a_vulkan_driver_says_so():
    with pytest.raises(RuntimeError, match="Vulkan"):
        ReachGraspEnv(render_mode="rgb_array")


@pytest.mark.skipif(renderer_missing() is not None,
                    reason=f"no headless renderer here: {renderer_missing()}")
def test_render_draws_the_episode():
    env = ReachGraspEnv(render_mode="rgb_array", steps=5)
    try:
        env.reset(seed=0)
        env.step(env.home_action)
        frame = env.render()
    finally:
        env.close()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    assert frame.std() > 5  # a picture, not a blank
