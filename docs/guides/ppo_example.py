"""PPO (stable-baselines3) on dart_reach/ReachGrasp-v2, pre-reaching, against the GA at the same
number of trials (docs/guides/gymnasium.md). tests/envs/test_ppo_example.py runs it for a few
thousand steps (skipped without stable-baselines3); the learning itself is a documented result.

    pip install torch==2.13.0 --index-url https://download.pytorch.org/whl/cpu  # the CPU build
    pip install -e ".[rl]"
    python docs/guides/ppo_example.py --timesteps 288000 --ga-run recordings/replication-50x10
"""

from __future__ import annotations

import argparse
import json
import time

import dart_reach  # registers the environment (and pins numpy's kernels before it loads)
import gymnasium as gym
import numpy as np
import polars as pl
import torch
from stable_baselines3 import PPO

from dart_reach.model.task import trial_positions


def lifetime_fitness(policy, env, seed: int) -> float:
    """A GA lifetime's fitness (section III-C): 18 trials, 2 per sector at random points,
    the mean of p_multimodal over all their steps, which is the mean reward."""
    rewards = []
    for sector, position in trial_positions(env.unwrapped.world, np.random.default_rng(seed), 18):
        observation, _ = env.reset(options={"sector": sector, "ball_position": position})
        done = False
        while not done:
            observation, reward, terminated, truncated, _ = env.step(policy(observation))
            rewards.append(reward)
            done = terminated or truncated
    return float(np.mean(rewards))


def ga_at(run: str, phase: str, trials: int) -> dict:
    """The GA's best and mean lifetime fitness (median over replications) at the first
    generation that has used ``trials`` trials per replication (steady state: each generation
    evaluates the parents again and one offspring each, 2 x population lifetimes)."""
    manifest = json.load(open(f"{run}/manifest.json"))
    s = manifest["settings"]
    per_generation = 2 * s["ga"]["population"] * s["trials"]
    generation = max(1, -(-trials // per_generation))
    table = pl.read_parquet(f"{run}/generations.parquet").filter(
        (pl.col("phase") == phase) & (pl.col("generation") == generation))
    return {"generation": generation, "trials_per_generation": per_generation,
            "best_median": float(table["best"].median()),
            "mean_median": float(table["mean"].median()), "replications": table.height}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--timesteps", type=int, default=288_000, help="0.1 s control steps")
    parser.add_argument("--phase", default="pre")
    parser.add_argument("--ga-run", default="recordings/replication-50x10")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    torch.set_num_threads(1)
    env = gym.make(dart_reach.GYM_ID, phase=args.phase)
    model = PPO("MlpPolicy", env, seed=args.seed, verbose=0)
    act = lambda obs: model.predict(obs, deterministic=True)[0]  # noqa: E731
    home = env.unwrapped.home_action
    before = {"home_posture": lifetime_fitness(lambda obs: home, env, 1),
              "ppo_untrained": lifetime_fitness(act, env, 1)}
    start = time.perf_counter()
    model.learn(total_timesteps=args.timesteps)
    seconds = time.perf_counter() - start
    trials = args.timesteps // env.unwrapped.config.steps
    print(json.dumps({
        "phase": args.phase, "timesteps": args.timesteps, "trials": trials,
        "train_seconds": round(seconds, 1), "steps_per_s": round(args.timesteps / seconds, 1),
        **before, "ppo_trained": lifetime_fitness(act, env, 1),
        "ga": ga_at(args.ga_run, args.phase, trials)}, indent=1))


if __name__ == "__main__":
    main()
