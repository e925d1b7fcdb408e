"""The Gymnasium environment is the paper's trial: an evolved robot stepped through it earns the
fitness ``Trial.run`` gives it, bit for bit; its reflexes are the network's; Gymnasium's own
checker passes (and stable-baselines3's, where it is installed); same seed, same episode; it runs
vectorised and pickles; a divergence ends an episode without a reward spike; bad input is
refused; an episode records like a trial."""

from __future__ import annotations

import pickle
import subprocess
import sys
import warnings
from dataclasses import replace

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import dart_reach  # noqa: E402
from dart_reach.envs import REFLEX_MOTORS, NetworkPolicy, ReachGraspEnv  # noqa: E402
from dart_reach.measures import metrics  # noqa: E402
from dart_reach.envs.seeing import record_episode  # noqa: E402
from dart_reach.evolution.genome import decode  # noqa: E402
from dart_reach.model.task import Trial, network_for, trial_positions  # noqa: E402
from dart_reach.model.world import World  # noqa: E402
from dart_reach.recording.rrd import read_rrd  # noqa: E402
from dart_reach.robots import robots  # noqa: E402
from dart_reach.viewing.camera import SceneCamera  # noqa: E402


def shipped_network(env: ReachGraspEnv, phase: str, reflexes: bool = True):
    """The best shipped robot of ``phase`` of the 50 x 10 replication, as the GA builds it."""
    robot = robots(phase, run="replication-50x10")[0]
    config = replace(env.config, reflexes=reflexes)
    return robot, config, network_for(decode(robot.genome, env.phase.free_groups), config)


def episode(env, policy, **reset):
    """Step ``policy`` (a ``NetworkPolicy``: ``reset(info)``, ``policy(observation)``) through
    one episode."""
    observation, info = env.reset(**reset)
    policy.reset(info)
    rewards, done = [], False
    while not done:
        observation, reward, terminated, truncated, info = env.step(policy(observation))
        rewards.append(reward)
        done = terminated or truncated
    return np.array(rewards), info


@pytest.mark.parametrize("model_version", [1, 2])
def test_a_shipped_robot_earns_the_fitness_its_trial_gives_it_bit_for_bit(model_version):
    # fine-reaching: full acuity, offset sensors, internal neurons, reflexes (inside the
    # network, so the environment's are off and the network is the whole controller)
    env = ReachGraspEnv(phase="fine", reflexes=False, model_version=model_version)
    robot, config, network = shipped_network(env, "fine")
    # the robot as a policy (version 1: its network built by of_robot, the trial's by the
    # GA's code; version 2: the trial's network, computed by version 2's numerics)
    policy = (NetworkPolicy.of_robot(robot) if model_version == 1
              else NetworkPolicy(shipped_network(env, "fine")[2]))
    rewards, info = episode(env, policy, seed=2013)
    sector, position = env.trial_data.sector, env.trial_data.ball_start
    # the position is a GA trial's, drawn from the seed
    k, p = trial_positions(World(), np.random.default_rng(2013), trials=1)[0]
    assert (sector, position.tolist()) == (k, p.tolist())
    data = Trial(World(env.world.config), config).run(network, sector, position)
    assert data.fitness > 0.05  # a robot that reaches: the comparison means something
    assert rewards.shape == (200,) and np.array_equal(rewards, data.p_multimodal)
    assert np.mean(rewards) == data.fitness == info["fitness"]
    mine = env.trial_data
    for name in ("sensors", "joints", "dofs", "targets", "contacts", "contacts_any", "ball"):
        assert np.array_equal(getattr(mine, name), getattr(data, name)), name
    # the motor outputs the actions stand for, (a + 1) / 2: 2 s - 1 rounds below s = 1/4
    assert np.allclose(mine.motor, data.motor, rtol=0, atol=1e-15)
    assert mine.steps_run == data.steps_run == 200 and not info["diverged"]
    # the episode's end says what the post-evaluation's measures say of the trial
    m = metrics.trial_metrics(data)
    assert (info["reached"], info["grasped"]) == (m["reached"], m["grasped"])
    assert info["is_success"] == info["grasped"]


def test_actions_are_used_as_given_float64_never_rounded_to_float32():
    env = ReachGraspEnv(phase="gross", reflexes=False, steps=5)
    env.reset(seed=1)
    action = np.linspace(-0.9, 0.9, 14) + 1e-12  # not float32 numbers
    assert not np.array_equal(action, action.astype(np.float32).astype(np.float64))
    env.step(action)
    assert np.array_equal(env.trial_data.targets[0], action)
    single = env.action_space.sample()
    assert single.dtype == np.float32
    env.step(single)
    assert np.array_equal(env.trial_data.targets[1], single.astype(np.float64))
    # beyond [-1, 1]: clipped; the motor record holds the outputs the targets stand for
    env.step(np.full(14, 3.0))
    assert (env.trial_data.targets[2] == 1.0).all() and (env.trial_data.motor[2] == 1.0).all()


@pytest.mark.parametrize("model_version", [1, 2])
def test_the_reflexes_are_the_networks_and_override_the_action(model_version):
    """A pre-reaching robot whose reflex motor neurons have no memory (tau 0) moves its
    reflex motors exactly as the reflex arcs alone do: with the environment's reflexes on it
    earns its trial's fitness, and what the action says there does not matter."""
    env = ReachGraspEnv(phase="pre", steps=40, model_version=model_version)
    assert env.config.reflexes and env.config.acuity == 3.0
    robot, config, _ = shipped_network(env, "pre")
    params = decode(robot.genome, env.phase.free_groups)
    params.tau_motor[REFLEX_MOTORS] = 0.0
    network = network_for(params, config)
    options = {"sector": 3, "ball_position": World().sector_point(3, 0.5, 0.5)}
    rewards, _ = episode(env, NetworkPolicy(network), options=options)
    data = Trial(World(), config).run(network, 3, options["ball_position"])
    assert np.array_equal(rewards, data.p_multimodal)
    assert np.array_equal(env.trial_data.targets, data.targets)
    # the reflex motors' outputs are the arcs' own; the others' stand for their targets
    assert np.array_equal(env.trial_data.motor[:, REFLEX_MOTORS], data.motor[:, REFLEX_MOTORS])
    assert np.allclose(env.trial_data.motor, data.motor, rtol=0, atol=1e-15)

    class Contrary(NetworkPolicy):  # the same network, its reflex targets replaced by nonsense
        def __call__(self, observation):
            a = super().__call__(observation)
            a[REFLEX_MOTORS] = -a[REFLEX_MOTORS]
            return a
    again, _ = episode(env, Contrary(network), options=options)
    assert np.array_equal(again, rewards)
    # with the reflexes off the same nonsense drives the neck and hand: another trial
    off = ReachGraspEnv(phase="pre", steps=40, reflexes=False, model_version=model_version)
    episode(off, Contrary(network), options=options)
    assert not np.array_equal(off.trial_data.joints, env.trial_data.joints)


def test_gymnasiums_checker_passes_and_the_id_is_registered():
    from gymnasium.utils.env_checker import check_env

    env = gymnasium.make(dart_reach.GYM_ID, phase="gross", steps=10)
    assert dart_reach.GYM_ID == "dart_reach/ReachGrasp-v2"
    assert env.spec.max_episode_steps == 200
    assert isinstance(env.unwrapped, ReachGraspEnv) and env.unwrapped.config.acuity == 1.0
    assert env.action_space == gymnasium.spaces.Box(-1, 1, (14,), np.float32)
    assert env.observation_space == gymnasium.spaces.Box(-1, 1, (25,), np.float64)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)  # its render check too: no Vulkan driver needed


def test_v1_runs_model_version_1_and_v0_is_refused_naming_the_newest():
    env = gymnasium.make("dart_reach/ReachGrasp-v1", phase="pre", steps=10).unwrapped
    new = gymnasium.make(dart_reach.GYM_ID, phase="pre", steps=10).unwrapped
    assert env.config.numerics.value == "reference" and new.config.numerics.value == "compiled"
    assert env.world.config.sectors.radius < new.world.config.sectors.radius  # 0.344, 0.46 m
    with pytest.warns(DeprecationWarning, match="v2"), pytest.raises(
            gymnasium.error.DeprecatedEnv, match="Please use `dart_reach/ReachGrasp-v2`"):
        gymnasium.make("dart_reach/ReachGrasp-v0")


def test_stable_baselines3s_checker_passes_without_a_warning():
    sb3_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sb3_checker.check_env(ReachGraspEnv(phase="fine", steps=10), warn=True)


def test_the_registered_time_limit_truncates_and_nothing_else_does():
    env = gymnasium.make(dart_reach.GYM_ID, phase="pre")
    env.reset(seed=4)
    home = env.unwrapped.home_action.astype(np.float32)
    for t in range(200):
        _, reward, terminated, truncated, info = env.step(home)
        assert not terminated and truncated == (t == 199) and 0.0 <= reward <= 1.0
    assert not info["diverged"] and "reason" not in info
    assert {"fitness", "reached", "grasped", "is_success"} <= set(info)


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
    actions = np.random.default_rng(1).uniform(-1, 1, (steps, 2, 14)).astype(np.float32)
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


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_make_vec_runs_the_registered_environment(mode):
    envs = gymnasium.make_vec(dart_reach.GYM_ID, num_envs=2, vectorization_mode=mode,
                              phase="gross", steps=3, render_mode="rgb_array", width=64,
                              height=48)
    try:
        assert envs.single_action_space == gymnasium.spaces.Box(-1, 1, (14,), np.float32)
        observations, infos = envs.reset(seed=7)
        assert observations.shape == (2, 25) and infos["sector"].shape == (2,)
        for _ in range(3):
            observations, rewards, terminated, truncated, infos = envs.step(
                envs.action_space.sample())
        assert truncated.all() and not terminated.any() and np.isfinite(observations).all()
        assert infos["_is_success"].all() and infos["is_success"].dtype == bool
        frames = envs.render()  # one camera image per environment
        assert [f.shape for f in frames] == [(48, 64, 3)] * 2
    finally:
        envs.close()


def test_the_environment_pickles_and_the_copy_steps_as_the_original():
    import cloudpickle

    env = gymnasium.make(dart_reach.GYM_ID, phase="fine", steps=5)
    env.reset(seed=0)
    actions = np.random.default_rng(2).uniform(-1, 1, (5, 14)).astype(np.float32)
    for dumps, loads in ((pickle.dumps, pickle.loads), (cloudpickle.dumps, cloudpickle.loads)):
        copy = loads(dumps(env))
        assert copy.spec.max_episode_steps == 200 and copy.unwrapped is not env.unwrapped
        assert copy.unwrapped.config == env.unwrapped.config
        mine, theirs = (run_actions(e.unwrapped, 3, actions) for e in (env, copy))
        assert all(np.array_equal(x, y) for x, y in zip(mine, theirs))


def test_a_diverged_physics_ends_the_episode_without_a_reward_spike():
    """The real world's state blown up (NaN velocities, as the trial's own test does) after
    4 steps: the 5th step terminates with reward 0, the reason, the last finite observation,
    and the trial's fitness 0, as ``Trial.run`` gives it; its frame is still a frame."""
    env = ReachGraspEnv(phase="gross", steps=20, render_mode="rgb_array")
    observation, _ = env.reset(seed=5, options={"sector": 4})
    rewards = []
    for _ in range(4):
        observation, reward, terminated, truncated, info = env.step(env.home_action)
        assert not (terminated or truncated)
        rewards.append(reward)
    env.world.robot.setVelocities(np.full(env.world.robot.getNumDofs(), np.nan))
    last, reward, terminated, truncated, info = env.step(env.home_action)
    assert terminated and not truncated and reward == 0.0
    assert info["diverged"] and "not finite" in info["reason"] and info["fitness"] == 0.0
    assert np.isfinite(last).all() and env.observation_space.contains(last)
    assert np.array_equal(last, env.trial_data.sensors[4])  # the state the action saw
    assert env.trial_data.diverged and env.trial_data.steps_run == 5
    assert not info["is_success"] and {"reached", "grasped"} <= set(info)
    frame = env.render()  # the robot's poses are not finite: not drawn
    assert frame.shape == (240, 320, 3) and frame.dtype == np.uint8
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(env.home_action)
    env.reset(seed=5)  # and a new episode runs
    assert not env.step(env.home_action)[2]


def test_bad_options_are_refused_with_their_reason():
    with pytest.raises(ValueError, match="unknown phase 'crawl'.*gross"):
        ReachGraspEnv(phase="crawl")
    with pytest.raises(ValueError, match="steps must be a positive"):
        ReachGraspEnv(steps=0)
    with pytest.raises(ValueError, match="render_mode"):
        ReachGraspEnv(render_mode="depth_array")
    with pytest.raises(ValueError, match="width must be an integer of at least 8"):
        ReachGraspEnv(render_mode="rgb_array", width=4)
    env = ReachGraspEnv(steps=3)
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(env.home_action)
    with pytest.raises(ValueError, match="unknown reset option.*'colour'"):
        env.reset(options={"colour": "red"})
    with pytest.raises(ValueError, match="needs its 'sector'"):
        env.reset(options={"ball_position": [0.0, 0.0, 0.0]})
    for sector in (9, -1, 2.0, "3", True, np.bool_(False)):
        with pytest.raises(ValueError, match="must be an integer in 0..8"):
            env.reset(options={"sector": sector})
    assert env.reset(options={"sector": np.int64(8)})[1]["sector"] == 8
    # a ball position is checked against its sector of the scene's sectors
    world = env.world
    corner = world.sector_point(0, 0.0, 0.0)
    assert env.reset(options={"sector": 0, "ball_position": corner})[1]["sector"] == 0
    assert env.reset(options={"sector": 0, "ball_position": corner.round(3)})  # rounding
    for sector, position, why in (
            (1, corner, "not in sector 1"),  # another sector's point
            (4, world.sector_point(4, 0.5, 0.5) + [5.0, 0, 0], "not in sector 4"),  # 5 m away
            (4, world.neck_centre, "not in sector 4"),
            (4, world.sector_point(4, 0.5, 0.5) * 1.01, "not in sector 4"),  # off the sphere
            (4, [0.1, 0.2], "3 finite numbers"), (4, [np.nan, 0, 0], "3 finite numbers")):
        with pytest.raises(ValueError, match=why):
            env.reset(options={"sector": sector, "ball_position": position})
    near = ReachGraspEnv(scene="near", steps=3).world
    with pytest.raises(ValueError, match="not in sector 4"):  # the default scene's point
        ReachGraspEnv(scene="near", steps=3).reset(
            options={"sector": 4, "ball_position": world.sector_point(4, 0.5, 0.5)})
    ReachGraspEnv(scene="near", steps=3).reset(
        options={"sector": 4, "ball_position": near.sector_point(4, 0.5, 0.5)})
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


def red(frame: np.ndarray) -> np.ndarray:
    r, g, b = (frame[..., i].astype(int) for i in range(3))
    return (r > 40) & (r > 3 * g) & (r > 3 * b)


def test_rgb_array_is_a_camera_image_that_follows_the_episode():
    """rgb_array: the scene through a fixed camera, drawn without a GPU; the same episode
    gives the same frames bit for bit; the ball is red where the camera sees it."""
    frames = []
    for _ in range(2):
        env = gymnasium.make(dart_reach.GYM_ID, phase="gross", render_mode="rgb_array",
                             width=200, height=150)
        env.reset(seed=5, options={"sector": 2})
        shots = [env.render()]
        for _ in range(8):  # the arm goes to its targets' middle, away from home
            env.step(np.zeros(14, np.float32))
            shots.append(env.render())
        frames.append(shots)
        camera = SceneCamera(env.unwrapped.world, 200, 150)
        env.close()
    first, second = frames
    assert all(f.shape == (150, 200, 3) and f.dtype == np.uint8 for f in first)
    assert all(np.array_equal(a, b) for a, b in zip(first, second))
    assert (first[0] != first[-1]).any(axis=2).sum() > 100  # the arm moved
    # to the episode's end: the last frame is the world's final state
    short = ReachGraspEnv(phase="gross", render_mode="rgb_array", steps=2)
    short.reset(seed=5, options={"sector": 2})
    short.step(np.zeros(14, np.float32))
    assert short.step(np.zeros(14, np.float32))[3]
    assert np.array_equal(short.render(), SceneCamera(short.world).image(short.world))
    rows, cols = np.nonzero(red(first[0]))
    ball = camera.project(env.unwrapped.trial_data.ball[0])[0]
    assert abs(cols.mean() + 0.5 - ball[0]) < 1.5 and abs(rows.mean() + 0.5 - ball[1]) < 1.5


def test_human_mode_streams_each_step_as_the_trial_records_it(tmp_path):
    """human: each step goes to the stream once its action is taken, in the trial layout;
    the stream read back is the episode's recording, and episodes follow one another."""
    live = tmp_path / "live.rrd"
    env = ReachGraspEnv(phase="pre", render_mode="human", viewer=str(live))
    env.reset(seed=3, options={"sector": 4})
    assert env.render() is None and not live.exists()  # a reset alone opens nothing
    for _ in range(12):
        env.step(env.action_space.sample())
        assert env.render() is None
    recorded = read_rrd(record_episode(env, tmp_path / "episode.rrd"))
    env.reset(seed=4, options={"sector": 0})
    for _ in range(3):
        env.step(env.home_action)
    second = env.trial_data
    env.close()
    table = read_rrd(live)
    assert table["step"].to_list() == list(range(15))
    columns = [c for c in recorded.columns if c not in ("step", "sim_time")]
    assert len(columns) > 60
    for column in columns:  # the first episode: its recording's rows, every series
        assert np.array_equal(table[column].to_numpy()[:12], recorded[column].to_numpy()), \
            column
    assert np.array_equal(table["fitness/p_sight"].to_numpy()[12:], second.p_sight[:3])
    assert np.allclose(table["sim_time"].to_numpy(), np.arange(15) * 0.1)


def test_human_mode_without_a_display_serves_the_stream(monkeypatch, capsys):
    import socket

    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    env = ReachGraspEnv(phase="pre", render_mode="human", steps=3)
    try:
        env.reset(seed=0)
        env.step(env.home_action)
        message = capsys.readouterr().err
        assert "no display here: serving the episodes at rerun+http://127.0.0.1:" in message
        port = int(message.split("rerun+http://127.0.0.1:")[1].split("/")[0])
        with socket.create_connection(("127.0.0.1", port), timeout=5):
            pass  # a viewer can connect: `rerun --connect URL`
    finally:
        env.close()
