"""Steps per second of the single-agent views and scenario envs, random Box actions.

    python benchmarks/rl_views_speed.py [--steps 3000] [--repeats 3]

Each case runs ``--steps`` env steps (resetting whenever an episode ends, resets counted in
the time) after 50 warm-up steps, ``--repeats`` times; the best and median rates are printed,
per second of this process's CPU time (``time.process_time``: a shared, loaded machine
slows the wall clock, not the work) and per wall-clock second.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from teamenv.policy_team import save_mlp_policy
from teamenv.single_agent import PlayerEnv, TeamEnv


def _policy_file(path: str, team_size: int) -> str:
    env = PlayerEnv(team_size=team_size, teammates="static", opponents="static")
    size = env.observation_space.shape[0]
    rng = np.random.default_rng(0)
    save_mlp_policy(path, [(rng.normal(0, 0.1, (size, 64)), np.zeros(64)),
                           (rng.normal(0, 0.1, (64, 64)), np.zeros(64)),
                           (rng.normal(0, 0.1, (64, 9)), np.zeros(9))], team_size=team_size)
    return path


def cases() -> dict[str, object]:
    policy = _policy_file("/tmp/rl_views_speed_policy.npz", 3)
    return {
        "PlayerEnv one_v_one, chaser defender": lambda: PlayerEnv(scenario="one_v_one"),
        "PlayerEnv empty_goal": lambda: PlayerEnv(scenario="empty_goal"),
        "PlayerEnv counter_3v2, full mates, chaser opp.": lambda: PlayerEnv(
            scenario="counter_3v2"),
        "PlayerEnv counter_3v2, policy (64x64 MLP) opp.": lambda: PlayerEnv(
            scenario="counter_3v2", teammates="static", opponents="policy",
            opponents_config={"path": policy}),
        "TeamEnv counter_3v2 (3 agents), chaser opp.": lambda: TeamEnv(scenario="counter_3v2"),
        "PlayerEnv 11 v 11 kickoff, full mates, full opp.": lambda: PlayerEnv(
            opponents="full", team_size=11),
    }


def rate(make, steps: int) -> tuple[float, float]:
    env = make()
    env.action_space.seed(0)
    env.reset(seed=0)
    actions = [env.action_space.sample() for _ in range(steps + 50)]
    for a in actions[:50]:
        if any(env.step(a)[2:4]):
            env.reset()
    start, cpu = time.perf_counter(), time.process_time()
    for a in actions[50:]:
        if any(env.step(a)[2:4]):
            env.reset()
    return steps / (time.process_time() - cpu), steps / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=3000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print(f"{'case':50s} {'CPU best':>9s} {'median':>7s} {'wall best':>10s}  steps/s")
    for name, make in cases().items():
        cpu, wall = zip(*(rate(make, args.steps) for _ in range(args.repeats)), strict=True)
        print(f"{name:50s} {max(cpu):9.0f} {statistics.median(cpu):7.0f} {max(wall):10.0f}")


if __name__ == "__main__":
    main()
