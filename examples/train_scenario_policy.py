"""Train a small MLP attacker for a scenario against the ball-chasing team, export it as a torch-free .npz policy, and evaluate it on held-out seeds.

Training: Stable-Baselines3 PPO (tanh MLP 64-64, observations normalised by VecNormalize) on
the single-agent view ``gymnasium.make("teamenv/Player-v0", scenario=..., opponents="chaser")``:
the learner is ``left_1``, the right side is the built-in chaser. The reward is the goal
(+1/-1) by default. The learner acts through ``PlayActions``: walk and a kick direction within
+-18 degrees of its heading; it kicks at full power whenever the ball is in reach. Training
episodes use tuning seeds (``teamenv.seeds.tuning_seeds``), one fixed sequence per env copy.

Export: the policy's mean action network and the normalisation statistics go into the
``teamenv-mlp-v1`` format (``teamenv.policy_team.save_mlp_policy``), so the trained attacker
plays as a team plugin (``left="policy", left_config={"path": ...}``) without torch.

Evaluation: the exported file, loaded by the ``policy`` team, plays ``--eval-episodes``
episodes on evaluation seeds (``teamenv.seeds.evaluation_seeds``, never used in training);
a win is a goal (the scenario's ``end`` reason). The same seeds are played by the chaser as
attacker (chaser v chaser), by the same network with PPO's initial weights (``untrained``:
what ``PlayActions`` alone gives) and by uniform random actions, for comparison. Win rates carry a
95 % Wilson interval. Writes the policy, a JSON report and the learning-curve PNG.

    python examples/train_scenario_policy.py                  # the committed demo (minutes)
    python examples/train_scenario_policy.py --smoke          # what CI runs: seconds
"""

from __future__ import annotations

import argparse
import copy
import json
import sys
import tempfile
import time
from collections import deque
from pathlib import Path

import gymnasium
import numpy as np

import teamenv
from teamenv.policy_team import load_policy, save_mlp_policy
from teamenv.seeds import evaluation_seeds, tuning_seeds

WIN = "goal"
#: The learner's action (``PlayActions``): these entries of the env's Box action (vx, vy,
#: vturn, kick_dir), each multiplied by ``LEARNED_SCALE``; the rest are ``FIXED``.
LEARNED = np.array([0, 1, 2, 4])
LEARNED_SCALE = np.array([1.0, 1.0, 1.0, 0.1])
#: kick_power 1 (a full-power kick whenever the ball is in reach, as the chaser kicks), no beam.
FIXED = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0])


class TuningSeedSchedule(gymnasium.Wrapper):
    """Resets copy ``index`` of ``copies`` with tuning seeds index, index + copies, ... in turn
    (any seed passed to ``reset`` is ignored), so training never plays an evaluation seed."""

    def __init__(self, env: gymnasium.Env, index: int, copies: int) -> None:
        super().__init__(env)
        self.index, self.copies, self.episodes = index, copies, 0

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        del seed
        (next_seed,) = tuning_seeds(1, offset=self.index + self.episodes * self.copies)
        self.episodes += 1
        return self.env.reset(seed=next_seed, options=options)


class PlayActions(gymnasium.ActionWrapper):
    """The learner's action: walk (vx, vy, vturn) and kick direction, entry k in
    [-1/scale_k, 1/scale_k] (``LEARNED_SCALE``); the env gets ``FIXED`` with entry
    ``LEARNED[k]`` = scale_k * entry k, in [-1, 1]. Kick direction (x0.1) spans +-18 degrees
    around the heading instead of +-180, so exploration with PPO's Gaussian aims roughly
    ahead. Kick power is not learned: a full-power kick is requested every cycle, so
    the player kicks whenever the ball is in reach (the chaser's rule). Learning it was tried
    and failed: the exported policy plays PPO's *mean* action, and a mean kick entry near the
    "kick" threshold (PPO has no reason to move it: kicking now or a few cycles later is
    equally good) gave, played deterministically, no kick or weak taps that stop short of the
    goal (2/30 and 0/30 goals on tuning seeds against the chaser's 7/30).
    ``export_policy`` folds scale and fixed entries into the output layer; as PPO clips its
    actions to this space, the file's clip(scale * mean, -1, 1) is exactly the learner's mean
    action."""

    def __init__(self, env: gymnasium.Env) -> None:
        super().__init__(env)
        high = (1.0 / LEARNED_SCALE).astype(np.float32)
        self.action_space = gymnasium.spaces.Box(-high, high, dtype=np.float32)

    def action(self, action: np.ndarray) -> np.ndarray:
        full = FIXED.astype(np.float32)
        full[LEARNED] = np.clip(action, self.action_space.low, self.action_space.high) \
            * LEARNED_SCALE
        return full


def make_player_env(scenario: str, reward: dict[str, float], index: int, copies: int):
    """A factory for copy ``index`` of the training env (SB3's VecEnvs take factories)."""
    def make():
        from stable_baselines3.common.monitor import Monitor

        env = gymnasium.make("teamenv/Player-v0", scenario=scenario, opponents="chaser",
                             teammates="static", reward=reward)
        return Monitor(PlayActions(TuningSeedSchedule(env, index, copies)),
                       info_keywords=("end",))
    return make


def wilson_interval(wins: int, episodes: int) -> tuple[float, float]:
    """95 % Wilson score interval of a win rate."""
    from scipy.stats import binomtest

    interval = binomtest(wins, episodes).proportion_ci(confidence_level=0.95, method="wilson")
    return float(interval.low), float(interval.high)


def play_episodes(scenario: str, left: str, left_config: dict | None, seeds) -> dict:
    """Plays ``left`` (a team) against the chaser on each seed; end reasons and the win rate."""
    env = teamenv.parallel_env(scenario=scenario, left=left, left_config=left_config,
                               right="chaser")
    ends: dict[str, int] = {}
    per_seed = []
    for seed in seeds:
        env.reset(seed=seed)
        while env.end_reason is None:
            env.step({})
        ends[env.end_reason] = ends.get(env.end_reason, 0) + 1
        per_seed.append(env.end_reason)
    wins, episodes = ends.get(WIN, 0), len(seeds)
    low, high = wilson_interval(wins, episodes)
    return {"episodes": episodes, "wins": wins, "win_rate": wins / episodes,
            "win_rate_95ci_wilson": [low, high], "ends": dict(sorted(ends.items())),
            "end_per_seed": per_seed}


class RandomActions:
    """Uniform random Box actions in [-1, 1]^9 from its own seeded generator."""

    def __init__(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)

    def __call__(self, obs_batch: np.ndarray) -> np.ndarray:
        return self.rng.uniform(-1.0, 1.0, (len(obs_batch), 9)).astype(np.float32)


def export_policy(model, vec_normalize, path: Path, team_size: int) -> Path:
    """SB3 PPO MlpPolicy (tanh hidden layers, identity mean head) + VecNormalize -> .npz."""
    import torch

    linears = [m for m in model.policy.mlp_extractor.policy_net if isinstance(m, torch.nn.Linear)]
    linears.append(model.policy.action_net)
    layers = [(lin.weight.detach().numpy().T.copy(), lin.bias.detach().numpy().copy())
              for lin in linears]
    w_out, b_out = layers[-1]  # (hidden, 4): to the env's 9 outputs (PlayActions)
    w_full = np.zeros((w_out.shape[0], len(FIXED)), np.float32)
    w_full[:, LEARNED] = w_out * LEARNED_SCALE
    b_full = FIXED.astype(np.float32)
    b_full[LEARNED] = b_out * LEARNED_SCALE
    layers[-1] = (w_full, b_full)
    rms = vec_normalize.obs_rms
    path.parent.mkdir(parents=True, exist_ok=True)
    save_mlp_policy(path, layers, activation="tanh", output_activation="identity",
                    obs_mean=rms.mean.astype(np.float32),
                    obs_std=np.sqrt(rms.var + vec_normalize.epsilon).astype(np.float32),
                    obs_clip=float(vec_normalize.clip_obs), team_size=team_size)
    # The file must act as the trained model does: compare on the last rollout's observations.
    raw = model.rollout_buffer.observations.reshape(-1, rms.mean.shape[0])
    raw = raw * np.sqrt(rms.var + vec_normalize.epsilon) + rms.mean  # buffer holds normalised
    mean, _ = model.predict(vec_normalize.normalize_obs(raw), deterministic=True)
    got = load_policy(path)(raw.astype(np.float32))
    expected = np.tile(FIXED, (len(raw), 1))
    expected[:, LEARNED] = np.clip(mean * LEARNED_SCALE, -1.0, 1.0)  # mean: clipped by SB3
    if not np.allclose(got, expected, atol=1e-4):
        raise RuntimeError(f"exported policy differs from the model by "
                           f"{np.abs(got - expected).max():.2e}")
    return path


class TrainingCurve:
    """SB3 callback: per finished training episode, the agent-step, return and win."""

    def __new__(cls, *args, **kwargs):
        from stable_baselines3.common.callbacks import BaseCallback

        class _Curve(BaseCallback):
            def __init__(self, report_every: int, budget_s: float) -> None:
                super().__init__()
                self.deadline = time.perf_counter() + budget_s
                self.episodes: list[tuple[int, float, bool]] = []
                self.report_every = report_every
                self.recent: deque = deque(maxlen=100)

            def _on_step(self) -> bool:
                for done, info in zip(self.locals["dones"], self.locals["infos"], strict=True):
                    if done and "episode" in info:
                        won = info.get("end") == WIN
                        self.episodes.append((self.num_timesteps, float(info["episode"]["r"]),
                                              won))
                        self.recent.append(won)
                        if len(self.episodes) % self.report_every == 0:
                            print(f"agent-steps {self.num_timesteps:8d}  episodes "
                                  f"{len(self.episodes):5d}  win rate (last "
                                  f"{len(self.recent)}) {np.mean(self.recent):.2f}", flush=True)
                return time.perf_counter() < self.deadline  # False stops training

        return _Curve(*args, **kwargs)


def plot_curve(episodes: list[tuple[int, float, bool]], baselines: dict, learned: dict,
               scenario: str, wall_s: float, path: Path, window: int = 100) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    steps = np.array([e[0] for e in episodes])
    returns = np.array([e[1] for e in episodes])
    wins = np.array([e[2] for e in episodes], dtype=float)
    kernel = np.ones(min(window, len(wins))) / min(window, len(wins))
    fig, (ax_win, ax_ret) = plt.subplots(1, 2, figsize=(11, 4))
    if len(wins):
        ax_win.plot(steps[len(kernel) - 1:], np.convolve(wins, kernel, "valid"),
                    label=f"learner, training episodes (mean of {len(kernel)})")
        ax_ret.plot(steps[len(kernel) - 1:], np.convolve(returns, kernel, "valid"))
    colors = {"chaser": "tab:red", "untrained": "tab:orange", "random": "tab:gray",
              "learned": "tab:green"}
    for name, result in {**baselines, "learned": learned}.items():
        low, high = result["win_rate_95ci_wilson"]
        ax_win.axhspan(low, high, color=colors[name], alpha=0.15)
        ax_win.axhline(result["win_rate"], color=colors[name], ls="--",
                       label=f"{name} on {result['episodes']} evaluation seeds: "
                             f"{result['win_rate']:.2f} [{low:.2f}, {high:.2f}]")
    ax_win.set(xlabel="agent-steps", ylabel="win rate (goal scored)", ylim=(0, 1),
               title=f"{scenario}: attacker vs the chaser")
    ax_win.legend(fontsize=7, loc="upper left")
    ax_ret.set(xlabel="agent-steps", ylabel="episode return (shaped)",
               title=f"training return (PPO, CPU, {wall_s / 60:.1f} min wall)")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="one_v_goalie",
                        help="a teamenv.scenarios name with one left player")
    parser.add_argument("--total-timesteps", type=int, default=1_000_000)
    parser.add_argument("--max-train-minutes", type=float, default=18.0,
                        help="stop training after this much wall time (whichever comes first)")
    parser.add_argument("--goal-weight", type=float, default=1.0)
    parser.add_argument("--progress-weight", type=float, default=0.0,
                        help="reward per metre of ball progress towards the goal (default 0: "
                             "with 0.05-0.1 PPO learnt to walk the ball forward, a dribble the "
                             "keeper wins)")
    parser.add_argument("--n-envs", type=int, default=8,
                        help="env copies, each in its own worker process (SB3 SubprocVecEnv)")
    parser.add_argument("--subprocess", action=argparse.BooleanOptionalAction, default=True,
                        help="env copies in worker processes (SubprocVecEnv), or in-process "
                             "(DummyVecEnv) with --no-subprocess")
    parser.add_argument("--n-steps", type=int, default=512, help="PPO rollout per env copy")
    parser.add_argument("--batch-size", type=int, default=512)
    parser.add_argument("--n-epochs", type=int, default=10)
    parser.add_argument("--learning-rate", type=float, default=3e-4)
    parser.add_argument("--gamma", type=float, default=0.995)
    parser.add_argument("--gae-lambda", type=float, default=0.98)
    parser.add_argument("--ent-coef", type=float, default=0.0)
    parser.add_argument("--log-std-init", type=float, default=-1.0,
                        help="initial log std of PPO's Gaussian actions (0: std 1)")
    parser.add_argument("--seed", type=int, default=0, help="PPO's seed (network, sampling)")
    parser.add_argument("--eval-episodes", type=int, default=100)
    parser.add_argument("--policy", type=Path, default=Path("examples/policies/one_v_goalie.npz"))
    parser.add_argument("--report", type=Path,
                        default=Path("examples/policies/one_v_goalie.json"))
    parser.add_argument("--plot", type=Path, default=Path("docs/rl_learning_curve.png"))
    parser.add_argument("--smoke", action="store_true",
                        help="a tiny run for CI: 256 agent-steps, 2 evaluation episodes; give "
                             "--policy/--report/--plot elsewhere")
    args = parser.parse_args(argv)
    if args.smoke:
        args.total_timesteps, args.eval_episodes, args.n_envs = 256, 2, 2
        args.batch_size = 64

    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecNormalize

    reward = {"goal": args.goal_weight, "ball_progress": args.progress_weight}
    start = time.perf_counter()
    factories = [make_player_env(args.scenario, reward, k, args.n_envs)
                 for k in range(args.n_envs)]
    torch.set_num_threads(1)  # small networks: more threads only compete with the env copies
    copies = SubprocVecEnv(factories) if args.subprocess and not args.smoke \
        else DummyVecEnv(factories)
    vec_env = VecNormalize(copies, norm_obs=True, norm_reward=True, clip_obs=10.0,
                           gamma=args.gamma)
    model = PPO("MlpPolicy", vec_env, n_steps=64 if args.smoke else args.n_steps,
                batch_size=args.batch_size, n_epochs=args.n_epochs,
                learning_rate=args.learning_rate, gamma=args.gamma, gae_lambda=args.gae_lambda,
                ent_coef=args.ent_coef, policy_kwargs={"log_std_init": args.log_std_init},
                seed=args.seed, device="cpu", verbose=0)
    curve = TrainingCurve(report_every=1 if args.smoke else 50,
                          budget_s=60.0 * args.max_train_minutes)
    initial_weights = copy.deepcopy(model.policy.state_dict())
    model.learn(total_timesteps=args.total_timesteps, callback=curve)
    train_wall_s = time.perf_counter() - start
    team_size = teamenv.scenarios.SCENARIOS[args.scenario].team_sizes[0]
    export_policy(model, vec_env, args.policy, team_size)
    # The same network with PPO's initial weights (and the final observation statistics):
    # what the action parameterisation (PlayActions) gives before any training.
    model.policy.load_state_dict(initial_weights)
    with tempfile.TemporaryDirectory() as tmp:
        untrained_path = export_policy(model, vec_env, Path(tmp) / "untrained.npz", team_size)
        untrained = load_policy(untrained_path)
    vec_env.close()

    seeds = evaluation_seeds(args.eval_episodes)
    learned = play_episodes(args.scenario, "policy", {"path": str(args.policy)}, seeds)
    baselines = {"chaser": play_episodes(args.scenario, "chaser", None, seeds),
                 "untrained": play_episodes(args.scenario, "policy", {"policy": untrained},
                                            seeds),
                 "random": play_episodes(args.scenario, "policy",
                                         {"policy": RandomActions(args.seed)}, seeds)}
    total_wall_s = time.perf_counter() - start
    report = {
        "command": "python examples/train_scenario_policy.py " + " ".join(sys.argv[1:] if argv is None else argv),
        "scenario": args.scenario, "reward": reward, "total_timesteps": args.total_timesteps,
        "max_train_minutes": args.max_train_minutes, "trained_timesteps": model.num_timesteps,
        "training_episodes": len(curve.episodes),
        "training_seeds": f"{len(curve.episodes) + args.n_envs} tuning seeds: copy k of "
                          f"{args.n_envs} plays tuning seeds k, k + {args.n_envs}, ...",
        "ppo": {key: getattr(args, key) for key in (
            "n_envs", "n_steps", "batch_size", "n_epochs", "learning_rate", "gamma",
            "gae_lambda", "ent_coef", "log_std_init", "seed")},
        "learner_actions": f"Box entries {LEARNED.tolist()} (vx, vy, vturn, kick_dir) = "
                           f"{LEARNED_SCALE.tolist()} * learned entry; the others fixed at "
                           f"{FIXED.tolist()}",
        "evaluation_seeds": [seeds[0], seeds[-1]],
        "train_wall_s": train_wall_s, "total_wall_s": total_wall_s,
        "learned": learned, "baselines": baselines,
        "curve": [[s, r, int(w)] for s, r, w in curve.episodes],
    }
    args.report.parent.mkdir(parents=True, exist_ok=True)
    args.report.write_text(json.dumps(report, indent=1) + "\n")
    plot_curve(curve.episodes, baselines, learned, args.scenario, train_wall_s, args.plot)
    for name, result in {"learned": learned, **baselines}.items():
        low, high = result["win_rate_95ci_wilson"]
        print(f"{name:8s} wins {result['wins']:3d}/{result['episodes']}  "
              f"win rate {result['win_rate']:.3f} [{low:.3f}, {high:.3f}]  ends {result['ends']}")
    print(f"training {train_wall_s / 60:.1f} min wall, total {total_wall_s / 60:.1f} min; "
          f"wrote {args.policy}, {args.report}, {args.plot}")


if __name__ == "__main__":
    main()
