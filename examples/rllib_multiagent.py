"""Ray RLlib PPO on the env through RLlib's PettingZoo wrapper, with one shared policy or one policy per team.

Both teams are learners. ``--policies shared`` maps every agent to one policy (self-play: each
side sees itself attacking +x, so one policy can play either side); ``--policies per-team``
maps ``left_*`` to ``left_team`` and ``right_*`` to ``right_team`` through
``policy_mapping_fn``. Sampling runs in the driver process (``num_env_runners=0``), which
keeps start-up short on a small machine; raise ``--env-runners`` to sample in parallel.

    python examples/rllib_multiagent.py --policies per-team        # 20 iterations, minutes
    python examples/rllib_multiagent.py --smoke                    # what CI runs
"""

from __future__ import annotations

import argparse
import csv
import os
from pathlib import Path

from soccer_task import make_env

ENV_NAME = "teamenv_soccer"


def policy_mapping(mode: str):
    """The ``policy_mapping_fn`` for a ``--policies`` mode: agent id -> policy (module) id."""
    if mode == "shared":
        return lambda agent_id, episode=None, **kwargs: "shared"
    return lambda agent_id, episode=None, **kwargs: agent_id.split("_")[0] + "_team"


def build_algorithm(args: argparse.Namespace):
    """A PPO algorithm on the wrapped env with the chosen policies."""
    from ray.rllib.algorithms.ppo import PPOConfig
    from ray.rllib.core.rl_module.default_model_config import DefaultModelConfig
    from ray.rllib.env.wrappers.pettingzoo_env import ParallelPettingZooEnv
    from ray.tune.registry import register_env

    register_env(ENV_NAME, lambda config: ParallelPettingZooEnv(make_env(**config)))
    policies = {"shared"} if args.policies == "shared" else {"left_team", "right_team"}
    config = (
        PPOConfig()
        .environment(ENV_NAME, env_config={"team_size": args.team_size, "right": None,
                                           "max_cycles": args.max_cycles})
        .multi_agent(policies=policies, policy_mapping_fn=policy_mapping(args.policies))
        .env_runners(num_env_runners=args.env_runners, rollout_fragment_length="auto")
        .learners(num_learners=0)
        .training(train_batch_size_per_learner=args.batch_size,
                  minibatch_size=min(128, args.batch_size), num_epochs=4, lr=3e-4)
        .rl_module(model_config=DefaultModelConfig(fcnet_hiddens=[64, 64]))
        .debugging(seed=args.seed)
    )
    return config.build_algo()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--policies", choices=("shared", "per-team"), default="shared")
    parser.add_argument("--iterations", type=int, default=20, help="training iterations")
    parser.add_argument("--batch-size", type=int, default=4000,
                        help="env steps per iteration (train_batch_size_per_learner; x agents = agent-steps)")
    parser.add_argument("--team-size", type=int, default=2)
    parser.add_argument("--max-cycles", type=int, default=400, help="episode length (20 ms cycles)")
    parser.add_argument("--env-runners", type=int, default=0,
                        help="sampling worker processes (0 = sample in the driver)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--ray-address", default=None,
                        help="join this Ray cluster (auto, HOST:PORT, ray://HOST:PORT); default: "
                             "a private local instance")
    parser.add_argument("--out", type=Path, default=Path("runs/rllib_multiagent"))
    parser.add_argument("--smoke", action="store_true",
                        help="a tiny run for CI: 2 iterations of 256 env steps, 1 v 1")
    args = parser.parse_args(argv)
    if args.smoke:
        args.iterations, args.batch_size, args.team_size, args.max_cycles = 2, 256, 1, 32

    import ray

    from teamenv.tournament.ray_cluster import init_ray

    # Ray's dashboard and metrics agents are not needed and cost seconds at start-up.
    os.environ.setdefault("RAY_DISABLE_USAGE_STATS", "1")
    # a private local instance unless --ray-address names a cluster to join (a plain
    # ray.init(num_cpus=...) fails wherever another Ray cluster runs or once ran)
    local = args.ray_address in (None, "local")
    init_ray(args.ray_address, max(1, args.env_runners + 1) if local else None,
             include_dashboard=False, log_to_driver=False, configure_logging=False)
    try:
        algo = build_algorithm(args)
        rows = []
        for iteration in range(1, args.iterations + 1):
            result = algo.train()
            runners = result["env_runners"]
            per_module = runners.get("module_episode_returns_mean", {})
            steps = runners.get("num_agent_steps_sampled_lifetime", 0)
            steps = int(sum(steps.values()) if isinstance(steps, dict) else steps)
            rows.append((iteration, steps, runners.get("episode_return_mean", float("nan")),
                         *(per_module.get(p, float("nan")) for p in sorted(per_module))))
            modules = "  ".join(f"{p} {per_module[p]:+.3f}" for p in sorted(per_module))
            print(f"iteration {iteration:3d}  agent-steps {steps:7d}  mean episode return "
                  f"(all agents) {rows[-1][2]:+.3f}  per policy: {modules}", flush=True)
        args.out.mkdir(parents=True, exist_ok=True)
        checkpoint = algo.save(str((args.out / "checkpoint").resolve()))
        algo.stop()
    finally:
        ray.shutdown()
    with open(args.out / "returns.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["iteration", "agent_steps", "mean_episode_return",
                         *(f"return_{p}" for p in sorted(per_module))])
        writer.writerows(rows)
    print(f"saved {checkpoint.checkpoint.path} and {args.out / 'returns.csv'}")


if __name__ == "__main__":
    main()
