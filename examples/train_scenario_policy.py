# Over 500 lines because an example is read top to bottom in one file: the tasks, training,
# export and the evaluation against its baselines.
"""Train a small MLP player for a scenario against the ball-chasing team, export it as a torch-free .npz policy, and evaluate it on held-out seeds.

Training: Stable-Baselines3 PPO (tanh MLP 64-64, observations normalised by VecNormalize) on
the single-agent view ``gymnasium.make("teamenv/Player-v0", scenario=..., opponents="chaser")``:
the learner is ``left_1``, the right side is the built-in chaser. What the learner controls,
its reward and what counts as a win are the scenario's ``ScenarioTask`` (``TASKS``):

- ``keep_away`` (the default): the learner chooses each kick's power and direction; walking at
  the ball and kicking only when it is in reach are reflexes of the policy file
  (``walk_to_ball``, ``kick_gate_m``), decisions every 5 cycles (``action_repeat``). Reward 1
  per second the episode lasts; a win is lasting the 20 s.
- ``one_v_goalie``: walk and the kick direction within +-18 degrees of the heading, a
  full-power kick asked for every cycle (ungated: only the first kick counts). Reward: the goal.

Training episodes use tuning seeds (``teamenv.seeds.tuning_seeds``), one fixed sequence per env
copy.

Export: the policy's mean action network, the normalisation statistics and the task's reflexes
go into the ``teamenv-mlp-v1`` format (``teamenv.policy_team.save_mlp_policy``), so the
trained player plays as a team plugin (``left="policy", left_config={"path": ...}``) without
torch.

Evaluation: the exported file, loaded by the ``policy`` team, plays ``--eval-episodes``
episodes on evaluation seeds (``teamenv.seeds.evaluation_seeds``, never used in training).
The same seeds are played by the chaser in the learner's seat (chaser v chaser), by the same
network with PPO's initial weights (``untrained``: what the action setup alone gives), by
uniform random actions and, in ``keep_away``, by a hand-written reference
(``KickAwayReference``). Win rates carry a 95 % Wilson interval. Writes the policy, a JSON
report and the learning-curve PNG.

    python examples/train_scenario_policy.py                  # the committed demo (minutes)
    python examples/train_scenario_policy.py --scenario one_v_goalie
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
from dataclasses import dataclass
from pathlib import Path

import gymnasium
import numpy as np

import teamenv
from teamenv.policy_team import apply_reflexes, load_policy, save_mlp_policy
from teamenv.seeds import evaluation_seeds, tuning_seeds


@dataclass(frozen=True)
class ScenarioTask:
    """What the learner does in one scenario: which end reason is a win, which entries of the
    env's Box action (vx, vy, vturn, kick_power, kick_dir, beam...) it learns and how each is
    scaled and offset (``PlayActions``), whether its kick is gated (asked for only when the
    ball is within ``KICK_GATE_SHARE`` of the kick reach: ``teamenv.policy_team.gate_kicks``),
    and its reward (the env's ``reward=`` weights plus ``survival_per_s`` per second of game
    time the episode lasts)."""

    win: str
    learned: tuple[int, ...]
    scale: tuple[float, ...]
    fixed: tuple[float, ...]
    reward: dict[str, float]
    survival_per_s: float = 0.0
    kick_gate: bool = False
    margin_shaping: float = 0.0
    action_repeat: int = 1
    walk_to_ball: bool = False
    ppo: tuple[tuple[str, float], ...] = ()


#: The ball's and opponent 1's positions relative to the player (body frame) in the state-mode
#: Box observation of a 1 v 1 scenario (``teamenv.slots.observation_slot_names``).
_BALL_REL, _OPPONENT_REL = slice(7, 9), slice(16, 18)

#: A gated kick is asked for within this share of the kick reach (the chaser's 0.9: the kick
#: fires 0.5 s after it is asked for, and the ball must still be in reach then).
KICK_GATE_SHARE = 0.9

TASKS = {
    # Walk and kick direction (x0.1: +-18 degrees around the heading); a full-power kick is
    # requested every cycle, ungated: the player is in a kick motion all episode and cannot
    # walk, so only its first kick (at the start, the ball at its feet) counts. Reward: the
    # goal.
    "one_v_goalie": ScenarioTask(
        win="goal", learned=(0, 1, 2, 4), scale=(1.0, 1.0, 1.0, 0.1),
        fixed=(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        reward={"goal": 1.0, "ball_progress": 0.0}),
    # Walk, kick power (0.65 + 0.35 x entry: 0.3..1 over the entry's first unit, so PPO starts
    # at 0.65 and explores soft kicks and full ones) and kick direction (+-180 degrees, to kick
    # away from the chaser); the kick is gated: asked for whenever the ball is in reach (the
    # chaser's rule), so the player walks between kicks. A win is lasting the 20 s; reward: 1
    # per second the episode lasts (no goal term: a goal ends keep-away too).
    "keep_away": ScenarioTask(
        win="time_limit", learned=(3, 4), scale=(0.25, 1.0),
        fixed=(0.0, 0.0, 0.0, 0.45, 0.0, 0.0, 0.0, 0.0, 0.0),
        reward={"goal": 0.0}, survival_per_s=1.0, kick_gate=True,
        action_repeat=5, walk_to_ball=True,
        ppo=(("n_envs", 4), ("n_steps", 256), ("batch_size", 256), ("gamma", 0.98),
             ("total_timesteps", 400_000), ("log_std_init", -2.0))),
}


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


class SurvivalReward(gymnasium.RewardWrapper):
    """Adds ``per_s`` x the cycle length to every step's reward: 1 per second survived."""

    def __init__(self, env: gymnasium.Env, per_s: float, cycle_s: float = 0.02) -> None:
        super().__init__(env)
        self.per_step = per_s * cycle_s

    def reward(self, reward: float) -> float:
        return reward + self.per_step


class MarginShaping(gymnasium.Wrapper):
    """Potential-based shaping (Ng, Harada and Russell 1999: it leaves the optimal policy
    unchanged): adds ``weight`` x (gamma * phi(next) - phi(now)), phi = the player's lead in
    the race for the ball, (opponent's distance to the ball - own distance) / ``scale_m``,
    clipped to [-1, 1]; phi = 0 after the last step. Read from the state-mode Box observation
    (ball and opponent 1 relative to the player, body frame)."""

    def __init__(self, env: gymnasium.Env, weight: float, gamma: float,
                 scale_m: float = 5.0) -> None:
        super().__init__(env)
        self.weight, self.gamma, self.scale_m = weight, gamma, scale_m
        self.phi = 0.0

    def potential(self, obs: np.ndarray) -> float:
        ball = obs[_BALL_REL]
        opponent = obs[_OPPONENT_REL]
        lead = float(np.hypot(*(ball - opponent)) - np.hypot(*ball))
        return float(np.clip(lead / self.scale_m, -1.0, 1.0))

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        self.phi = self.potential(obs)
        return obs, info

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        phi = 0.0 if terminated or truncated else self.potential(obs)
        reward = float(reward) + self.weight * (self.gamma * phi - self.phi)
        self.phi = phi
        return obs, reward, terminated, truncated, info


class PlayActions(gymnasium.Wrapper):
    """The learner's action: the env gets ``task.fixed`` with entry ``task.learned[k]`` =
    ``fixed + scale_k * entry_k``. Entry k ranges over the preimage of [-1, 1] under that map,
    so PPO's clipping to this space is exactly the env's clipping, and the exported file
    (``export_policy`` folds scale and offset into its output layer, then clips to [-1, 1])
    acts as the model's clipped mean action does.

    Kick power is not learned as an on/off switch: a kick is requested every cycle (gated by
    the ball's distance when ``task.kick_gate``: ``gate_m``). Learning the switch was tried in
    ``one_v_goalie`` and failed: the exported policy plays PPO's *mean* action, and a mean
    kick entry near the "kick" threshold (PPO has no reason to move it: kicking now or a few
    cycles later is equally good) gave, played deterministically, no kick or weak taps that
    stop short of the goal (2/30 and 0/30 goals on tuning seeds against the chaser's 7/30).
    In ``one_v_goalie`` the kick direction is scaled by 0.1 (+-18 degrees around the heading)
    so that exploration with PPO's Gaussian aims roughly ahead."""

    def __init__(self, env: gymnasium.Env, task: ScenarioTask, gate_m: float | None) -> None:
        super().__init__(env)
        self.gate_m = gate_m
        self.repeat = task.action_repeat
        self.walk_to_ball = task.walk_to_ball
        self.last_obs: np.ndarray | None = None
        self.learned = np.array(task.learned)
        self.scale = np.array(task.scale)
        self.fixed = np.array(task.fixed, dtype=np.float32)
        offset = self.fixed[self.learned]
        self.action_space = gymnasium.spaces.Box(
            ((-1.0 - offset) / self.scale).astype(np.float32),
            ((1.0 - offset) / self.scale).astype(np.float32), dtype=np.float32)

    def reset(self, **kwargs):
        self.last_obs, info = self.env.reset(**kwargs)
        return self.last_obs, info

    def step(self, action: np.ndarray):
        full = self.fixed.copy()
        full[self.learned] += np.clip(action, self.action_space.low, self.action_space.high) \
            * self.scale
        full = np.clip(full, -1.0, 1.0)
        total = 0.0
        for _ in range(self.repeat):
            act = apply_reflexes(self.last_obs[None], full[None], self.gate_m,
                                 self.walk_to_ball)[0]
            self.last_obs, reward, terminated, truncated, info = self.env.step(act)
            total += float(reward)
            if terminated or truncated:
                break
        return self.last_obs, total, terminated, truncated, info


def make_player_env(scenario: str, task: ScenarioTask, reward: dict[str, float],
                    index: int, copies: int, gamma: float):
    """A factory for copy ``index`` of the training env (SB3's VecEnvs take factories)."""
    def make():
        from stable_baselines3.common.monitor import Monitor

        env = gymnasium.make("teamenv/Player-v0", scenario=scenario, opponents="chaser",
                             teammates="static", reward=reward)
        env = TuningSeedSchedule(env, index, copies)
        if task.survival_per_s:
            env = SurvivalReward(env, task.survival_per_s)
        if task.margin_shaping:
            env = MarginShaping(env, task.margin_shaping, gamma)
        return Monitor(PlayActions(env, task, kick_gate_m(scenario) if task.kick_gate else None),
                       info_keywords=("end",))
    return make


def kick_gate_m(scenario: str) -> float:
    """``KICK_GATE_SHARE`` of the kick reach of the scenario's locomotion profile (m)."""
    return KICK_GATE_SHARE * float(teamenv.parallel_env(scenario=scenario).sim.profile.kick_reach)


def wilson_interval(wins: int, episodes: int) -> tuple[float, float]:
    """95 % Wilson score interval of a win rate."""
    from scipy.stats import binomtest

    interval = binomtest(wins, episodes).proportion_ci(confidence_level=0.95, method="wilson")
    return float(interval.low), float(interval.high)


def play_episodes(scenario: str, win: str, left: str, left_config: dict | None,
                  seeds) -> dict:
    """Plays ``left`` (a team) against the chaser on each seed; end reasons and the rate of
    the ``win`` end reason."""
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
    wins, episodes = ends.get(win, 0), len(seeds)
    low, high = wilson_interval(wins, episodes)
    return {"episodes": episodes, "wins": wins, "win_rate": wins / episodes,
            "win_rate_95ci_wilson": [low, high], "ends": dict(sorted(ends.items())),
            "end_per_seed": per_seed}


class KickAwayReference:
    """A hand-written keep-away player on the state-mode Box observation, through the same
    reflexes as a ``walk_to_ball`` file (walk at the ball, kick when it is in reach): every
    kick at power ``power``, straight away from opponent 1 (the line from it through the
    ball). A yardstick for what the learner could reach, not a learner."""

    def __init__(self, gate_m: float, power: float = 0.3) -> None:
        self.gate_m, self.power = gate_m, power

    def __call__(self, obs_batch: np.ndarray) -> np.ndarray:
        obs = np.asarray(obs_batch, dtype=np.float64)
        away = obs[:, _BALL_REL] - obs[:, _OPPONENT_REL]
        actions = np.zeros((len(obs), 9))
        actions[:, 3] = self.power
        actions[:, 4] = np.arctan2(away[:, 1], away[:, 0]) / np.pi
        return apply_reflexes(obs, actions, self.gate_m, walk_to_ball=True)


class RandomActions:
    """Uniform random Box actions in [-1, 1]^9 from its own seeded generator."""

    def __init__(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)

    def __call__(self, obs_batch: np.ndarray) -> np.ndarray:
        return self.rng.uniform(-1.0, 1.0, (len(obs_batch), 9)).astype(np.float32)


def export_policy(model, vec_normalize, scenario: str, task: ScenarioTask, path: Path,
                  team_size: int) -> Path:
    """SB3 PPO MlpPolicy (tanh hidden layers, identity mean head) + VecNormalize -> .npz."""
    import torch

    linears = [m for m in model.policy.mlp_extractor.policy_net if isinstance(m, torch.nn.Linear)]
    linears.append(model.policy.action_net)
    layers = [(lin.weight.detach().numpy().T.copy(), lin.bias.detach().numpy().copy())
              for lin in linears]
    w_out, b_out = layers[-1]  # (hidden, 4): to the env's 9 outputs (PlayActions)
    learned, scale = np.array(task.learned), np.array(task.scale, dtype=np.float32)
    fixed = np.array(task.fixed, dtype=np.float32)
    w_full = np.zeros((w_out.shape[0], len(fixed)), np.float32)
    w_full[:, learned] = w_out * scale
    b_full = fixed.copy()
    b_full[learned] += b_out * scale
    layers[-1] = (w_full, b_full)
    rms = vec_normalize.obs_rms
    path.parent.mkdir(parents=True, exist_ok=True)
    save_mlp_policy(path, layers, activation="tanh", output_activation="identity",
                    obs_mean=rms.mean.astype(np.float32),
                    obs_std=np.sqrt(rms.var + vec_normalize.epsilon).astype(np.float32),
                    obs_clip=float(vec_normalize.clip_obs), team_size=team_size,
                    kick_gate_m=kick_gate_m(scenario) if task.kick_gate else None,
                    walk_to_ball=task.walk_to_ball, action_repeat=task.action_repeat)
    # The file must act as the trained model does: compare on the last rollout's observations.
    raw = model.rollout_buffer.observations.reshape(-1, rms.mean.shape[0])
    raw = raw * np.sqrt(rms.var + vec_normalize.epsilon) + rms.mean  # buffer holds normalised
    mean, _ = model.predict(vec_normalize.normalize_obs(raw), deterministic=True)
    got = load_policy(path)(raw.astype(np.float32))
    expected = np.tile(fixed, (len(raw), 1))
    expected[:, learned] += mean * scale  # the mean, clipped by SB3 to PlayActions' space
    expected = apply_reflexes(raw, expected, kick_gate_m(scenario) if task.kick_gate else None,
                              task.walk_to_ball)
    if not np.allclose(got, expected, atol=1e-4):
        raise RuntimeError(f"exported policy differs from the model by "
                           f"{np.abs(got - expected).max():.2e}")
    return path


class TrainingCurve:
    """SB3 callback: per finished training episode, the agent-step, return and win."""

    def __new__(cls, *args, **kwargs):
        from stable_baselines3.common.callbacks import BaseCallback

        class _Curve(BaseCallback):
            def __init__(self, report_every: int, budget_s: float, win: str) -> None:
                super().__init__()
                self.deadline = time.perf_counter() + budget_s
                self.episodes: list[tuple[int, float, bool]] = []
                self.report_every = report_every
                self.recent: deque = deque(maxlen=100)
                self.win = win

            def _on_step(self) -> bool:
                for done, info in zip(self.locals["dones"], self.locals["infos"], strict=True):
                    if done and "episode" in info:
                        won = info.get("end") == self.win
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
               scenario: str, win: str, wall_s: float, path: Path, window: int = 100) -> None:
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
              "reference": "tab:purple", "learned": "tab:green"}
    for name, result in {**baselines, "learned": learned}.items():
        low, high = result["win_rate_95ci_wilson"]
        ax_win.axhspan(low, high, color=colors[name], alpha=0.15)
        ax_win.axhline(result["win_rate"], color=colors[name], ls="--",
                       label=f"{name} on {result['episodes']} evaluation seeds: "
                             f"{result['win_rate']:.2f} [{low:.2f}, {high:.2f}]")
    ax_win.set(xlabel="agent-steps", ylabel=f"win rate (episode end: {win})", ylim=(0, 1),
               title=f"{scenario}: left_1 vs the chaser")
    ax_win.legend(fontsize=7, loc="upper left")
    ax_ret.set(xlabel="agent-steps", ylabel="episode return",
               title=f"training return (PPO, CPU, {wall_s / 60:.1f} min wall)")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def output_paths(scenario: str, smoke: bool, policy: Path | None = None,
                 report: Path | None = None, plot: Path | None = None) -> tuple[Path, Path, Path]:
    """Where a run writes its policy, report and figure: the committed files of a real run
    (examples/policies/, docs/), or runs/ for a smoke run, which never writes over them."""
    if smoke:
        here = Path("runs") / f"train_scenario_policy_smoke_{scenario}"
        defaults = (here / "policy.npz", here / "report.json", here / "curve.png")
    else:
        defaults = (Path(f"examples/policies/{scenario}.npz"),
                    Path(f"examples/policies/{scenario}.json"),
                    Path(f"docs/rl_learning_curve_{scenario}.png"))
    return policy or defaults[0], report or defaults[1], plot or defaults[2]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="keep_away", choices=sorted(TASKS),
                        help="the scenario (its task: win, actions, reward, in TASKS)")
    parser.add_argument("--total-timesteps", type=int, default=None,
                        help="learner decisions (default 1 000 000 or the task's)")
    parser.add_argument("--max-train-minutes", type=float, default=18.0,
                        help="stop training after this much wall time (whichever comes first)")
    parser.add_argument("--goal-weight", type=float, default=None,
                        help="the env's goal reward weight (default: the task's)")
    parser.add_argument("--progress-weight", type=float, default=None,
                        help="reward per metre of ball progress towards the goal (default 0: "
                             "with 0.05-0.1 PPO learnt to walk the ball forward, a dribble the "
                             "keeper wins)")
    parser.add_argument("--n-envs", type=int, default=None,
                        help="env copies, each in its own worker process (SB3 SubprocVecEnv); "
                             "default 8 or the task's")
    parser.add_argument("--subprocess", action=argparse.BooleanOptionalAction, default=True,
                        help="env copies in worker processes (SubprocVecEnv), or in-process "
                             "(DummyVecEnv) with --no-subprocess")
    parser.add_argument("--n-steps", type=int, default=None,
                        help="PPO rollout per env copy (default 512 or the task's)")
    parser.add_argument("--batch-size", type=int, default=None,
                        help="default 512 or the task's")
    parser.add_argument("--n-epochs", type=int, default=10)
    parser.add_argument("--learning-rate", type=float, default=3e-4)
    parser.add_argument("--gamma", type=float, default=None,
                        help="per decision (default 0.995 or the task's)")
    parser.add_argument("--gae-lambda", type=float, default=0.98)
    parser.add_argument("--ent-coef", type=float, default=0.0)
    parser.add_argument("--log-std-init", type=float, default=None,
                        help="initial log std of PPO's Gaussian actions (0: std 1; default -1 "
                             "or the task's)")
    parser.add_argument("--seed", type=int, default=0, help="PPO's seed (network, sampling)")
    parser.add_argument("--eval-episodes", type=int, default=100)
    parser.add_argument("--policy", type=Path, default=None,
                        help="default examples/policies/<scenario>.npz")
    parser.add_argument("--report", type=Path, default=None,
                        help="default examples/policies/<scenario>.json")
    parser.add_argument("--plot", type=Path, default=None,
                        help="default docs/rl_learning_curve_<scenario>.png")
    parser.add_argument("--smoke", action="store_true",
                        help="a tiny run for CI: 256 agent-steps, 2 evaluation episodes; "
                             "writes under runs/ unless --policy/--report/--plot say where")
    args = parser.parse_args(argv)
    task = TASKS[args.scenario]
    for key, value in {"n_envs": 8, "n_steps": 512, "batch_size": 512, "gamma": 0.995,
                       "total_timesteps": 1_000_000, "log_std_init": -1.0,
                       **dict(task.ppo)}.items():
        if getattr(args, key) is None:
            setattr(args, key, type(value)(value))
    if args.smoke:
        args.total_timesteps, args.eval_episodes, args.n_envs = 256, 2, 2
        args.batch_size = 64

    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecNormalize

    args.policy, args.report, args.plot = output_paths(args.scenario, args.smoke, args.policy,
                                                       args.report, args.plot)
    for path in (args.policy, args.report, args.plot):
        path.parent.mkdir(parents=True, exist_ok=True)
    reward = dict(task.reward)
    if args.goal_weight is not None:
        reward["goal"] = args.goal_weight
    if args.progress_weight is not None:
        reward["ball_progress"] = args.progress_weight
    start = time.perf_counter()
    factories = [make_player_env(args.scenario, task, reward, k, args.n_envs, args.gamma)
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
                          budget_s=60.0 * args.max_train_minutes, win=task.win)
    initial_weights = copy.deepcopy(model.policy.state_dict())
    model.learn(total_timesteps=args.total_timesteps, callback=curve)
    train_wall_s = time.perf_counter() - start
    team_size = teamenv.scenarios.SCENARIOS[args.scenario].team_sizes[0]
    export_policy(model, vec_env, args.scenario, task, args.policy, team_size)
    # The same network with PPO's initial weights (and the final observation statistics):
    # what the action parameterisation (PlayActions) gives before any training.
    model.policy.load_state_dict(initial_weights)
    with tempfile.TemporaryDirectory() as tmp:
        untrained_path = export_policy(model, vec_env, args.scenario, task,
                                       Path(tmp) / "untrained.npz",
                                       team_size)
        untrained = load_policy(untrained_path)
    vec_env.close()

    seeds = evaluation_seeds(args.eval_episodes)
    learned = play_episodes(args.scenario, task.win, "policy", {"path": str(args.policy)},
                            seeds)
    baselines = {"chaser": play_episodes(args.scenario, task.win, "chaser", None, seeds),
                 "untrained": play_episodes(args.scenario, task.win, "policy",
                                            {"policy": untrained}, seeds),
                 "random": play_episodes(args.scenario, task.win, "policy",
                                         {"policy": RandomActions(args.seed)}, seeds)}
    if task.walk_to_ball:
        baselines["reference"] = play_episodes(
            args.scenario, task.win, "policy",
            {"policy": KickAwayReference(kick_gate_m(args.scenario))}, seeds)
    total_wall_s = time.perf_counter() - start
    report = {
        "command": "python examples/train_scenario_policy.py " + " ".join(sys.argv[1:] if argv is None else argv),
        "scenario": args.scenario, "win": task.win, "reward": reward,
        "survival_reward_per_s": task.survival_per_s,
        "margin_shaping": task.margin_shaping, "total_timesteps": args.total_timesteps,
        "max_train_minutes": args.max_train_minutes, "trained_timesteps": model.num_timesteps,
        "training_episodes": len(curve.episodes),
        "training_seeds": f"{len(curve.episodes) + args.n_envs} tuning seeds: copy k of "
                          f"{args.n_envs} plays tuning seeds k, k + {args.n_envs}, ...",
        "ppo": {key: getattr(args, key) for key in (
            "n_envs", "n_steps", "batch_size", "n_epochs", "learning_rate", "gamma",
            "gae_lambda", "ent_coef", "log_std_init", "seed")},
        "learner_actions": f"Box entries {list(task.learned)} = fixed + {list(task.scale)} "
                           f"* learned entry, clipped to [-1, 1]; fixed = {list(task.fixed)}",
        "evaluation_seeds": [seeds[0], seeds[-1]],
        "train_wall_s": train_wall_s, "total_wall_s": total_wall_s,
        "learned": learned, "baselines": baselines,
        "curve": [[s, r, int(w)] for s, r, w in curve.episodes],
    }
    args.report.parent.mkdir(parents=True, exist_ok=True)
    args.report.write_text(json.dumps(report, indent=1) + "\n")
    plot_curve(curve.episodes, baselines, learned, args.scenario, task.win, train_wall_s,
               args.plot)
    for name, result in {"learned": learned, **baselines}.items():
        low, high = result["win_rate_95ci_wilson"]
        print(f"{name:8s} wins {result['wins']:3d}/{result['episodes']}  "
              f"win rate {result['win_rate']:.3f} [{low:.3f}, {high:.3f}]  ends {result['ends']}")
    print(f"training {train_wall_s / 60:.1f} min wall, total {total_wall_s / 60:.1f} min; "
          f"wrote {args.policy}, {args.report}, {args.plot}")


if __name__ == "__main__":
    main()
