"""Stable-Baselines3 PPO with one shared policy over every learning agent, fed by SuperSuit's vector envs.

SuperSuit's ``pettingzoo_env_to_vec_env_v1`` turns the ParallelEnv's agents into the slots of
a vector env (one slot per agent, all sharing one policy), ``concat_vec_envs_v1`` stacks
copies of it (in ``--num-cpus`` worker processes) and hands SB3 its VecEnv. The learners are
the left team; the right team is the built-in ball chaser.

    python examples/sb3_supersuit_ppo.py                     # 100k agent-steps, a few minutes
    python examples/sb3_supersuit_ppo.py --smoke             # what CI runs: seconds
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import supersuit
from soccer_task import make_env
from stable_baselines3 import PPO
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.vec_env import VecMonitor
from supersuit.vector.sb3_vector_wrapper import SB3VecEnvWrapper


class SeededSB3VecEnv(SB3VecEnvWrapper):
    """SuperSuit's SB3 wrapper with the ``seed`` SB3 calls (SuperSuit 3.11 forwards it to a
    concatenated env that has none): the next reset seeds copy k with ``seed + k``."""

    def seed(self, seed: int | None = None) -> list[None]:
        self._next_seed = seed
        return [None] * self.num_envs

    def reset(self, seed: int | None = None, options: dict | None = None):
        seed = getattr(self, "_next_seed", None) if seed is None else seed
        self._next_seed = None
        observations, self.reset_infos = self.venv.reset(seed=seed, options=options)
        return observations


class ReturnCurve(BaseCallback):
    """Prints and records the mean episode return (per agent) after every rollout."""

    def __init__(self) -> None:
        super().__init__()
        self.rows: list[tuple[int, float, int]] = []

    def _on_step(self) -> bool:
        return True

    def _on_rollout_end(self) -> None:
        episodes = list(self.model.ep_info_buffer)
        if episodes:
            mean = sum(e["r"] for e in episodes) / len(episodes)
            self.rows.append((self.num_timesteps, mean, len(episodes)))
            print(f"agent-steps {self.num_timesteps:7d}  mean episode return {mean:+.3f} "
                  f"(last {len(episodes)} agent-episodes)", flush=True)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--total-timesteps", type=int, default=100_000,
                        help="agent-steps to train for (every agent's step counts)")
    parser.add_argument("--team-size", type=int, default=2)
    parser.add_argument("--max-cycles", type=int, default=400, help="episode length (20 ms cycles)")
    parser.add_argument("--num-envs", type=int, default=4, help="env copies")
    parser.add_argument("--num-cpus", type=int, default=2, help="worker processes for the copies")
    parser.add_argument("--n-steps", type=int, default=256, help="PPO rollout length per slot")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("runs/sb3_supersuit_ppo"))
    parser.add_argument("--smoke", action="store_true",
                        help="a tiny run for CI: 2 rollouts of 2 envs in-process, 64-cycle episodes")
    args = parser.parse_args(argv)
    if args.smoke:
        args.total_timesteps, args.max_cycles, args.num_envs, args.num_cpus, args.n_steps = (
            512, 64, 2, 0, 64)

    env = make_env(team_size=args.team_size, right="chaser", max_cycles=args.max_cycles)
    vec_env = supersuit.pettingzoo_env_to_vec_env_v1(env)
    vec_env = supersuit.concat_vec_envs_v1(vec_env, args.num_envs, num_cpus=args.num_cpus)
    vec_env = VecMonitor(SeededSB3VecEnv(vec_env))
    slots = vec_env.num_envs
    model = PPO("MlpPolicy", vec_env, n_steps=args.n_steps,
                batch_size=min(256, args.n_steps * slots), n_epochs=4, learning_rate=3e-4,
                ent_coef=0.01, seed=args.seed, device="cpu", verbose=0)
    curve = ReturnCurve()
    model.learn(total_timesteps=args.total_timesteps, callback=curve)
    vec_env.close()

    args.out.mkdir(parents=True, exist_ok=True)
    model.save(args.out / "model.zip")
    with open(args.out / "returns.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["agent_steps", "mean_episode_return", "episodes"])
        writer.writerows(curve.rows)
    print(f"saved {args.out / 'model.zip'} and {args.out / 'returns.csv'}")


if __name__ == "__main__":
    main()
