"""The CleanRL-style PPO of ``cleanrl_ppo.py`` as a learner of the self-play league.

The league (``teamenv.selfplay``) needs four methods of a learner: ``initial_weights()``,
``train(steps, opponents, seed) -> weights``, ``save(directory)``, ``load(directory)``.
``CleanRLLearner`` implements them around the example's ``Agent`` (tanh 64-64 actor and
critic, state-independent log std) and its PPO update (GAE, clipped objective), stepping the
league's numpy training env (``TeamBatchEnv``: every player of every env copy one row of the
batch) instead of the PettingZoo env. Everything else — PFSP opponents, snapshots, ratings,
resume — is the league's.

    python examples/selfplay_cleanrl.py --generations 3 --out runs/selfplay_cleanrl
    python examples/selfplay_cleanrl.py --smoke        # what CI runs: seconds

From the command line, with ``examples/`` on the path (the learner is built as
``CleanRLLearner(training_setup, seed=..., **learner options)``)::

    PYTHONPATH=examples teamenv selfplay run runs/league --learner selfplay_cleanrl:CleanRLLearner
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import torch
from cleanrl_ppo import Agent

from teamenv.selfplay import (
    LeagueConfig,
    OpponentMix,
    PolicyWeights,
    RatingSetup,
    TeamBatchEnv,
    TrainingSetup,
    run_league,
)

CHECKPOINT = "cleanrl.pt"


class CleanRLLearner:
    """PPO in plain PyTorch (CleanRL's ``ppo_continuous_action.py`` update) for the league."""

    def __init__(self, setup: TrainingSetup, seed: int = 0, copies: int = 2,
                 num_steps: int = 128, learning_rate: float = 3e-4, gae_lambda: float = 0.95,
                 num_minibatches: int = 4, update_epochs: int = 4, clip_coef: float = 0.2,
                 ent_coef: float = 0.0, vf_coef: float = 0.5, max_grad_norm: float = 0.5) -> None:
        torch.set_num_threads(1)
        torch.manual_seed(seed)
        self.env = TeamBatchEnv(setup, OpponentMix.single("static", seed), copies, seed)
        self.gamma = setup.gamma
        self.num_steps, self.gae_lambda = num_steps, gae_lambda
        self.num_minibatches, self.update_epochs = num_minibatches, update_epochs
        self.clip_coef, self.ent_coef = clip_coef, ent_coef
        self.vf_coef, self.max_grad_norm = vf_coef, max_grad_norm
        self.agent = Agent(self.env.observation_size, self.env.action_size)
        self.optimizer = torch.optim.Adam(self.agent.parameters(), lr=learning_rate, eps=1e-5)
        self.low = torch.as_tensor(self.env.action_low)
        self.high = torch.as_tensor(self.env.action_high)
        self.last_episodes: list = []

    def initial_weights(self) -> PolicyWeights:
        return self.weights()

    def weights(self) -> PolicyWeights:
        """The actor's mean network: Linear, Tanh, Linear, Tanh, Linear."""
        linears = [m for m in self.agent.actor_mean if isinstance(m, torch.nn.Linear)]
        return PolicyWeights.of([(m.weight.detach().numpy().T, m.bias.detach().numpy())
                                 for m in linears])

    def train(self, steps: int, opponents: OpponentMix, seed: int) -> PolicyWeights:
        torch.manual_seed(seed)
        order = np.random.default_rng(seed)
        env, n = self.env, self.env.n_slots
        env.start(opponents, seed)
        obs_size, act_size = env.observation_size, env.action_size
        obs_buf = torch.zeros((self.num_steps, n, obs_size))
        act_buf = torch.zeros((self.num_steps, n, act_size))
        logp_buf, rew_buf, done_buf, val_buf = (torch.zeros((self.num_steps, n))
                                                for _ in range(4))
        next_obs = torch.as_tensor(env.reset())
        next_done = torch.zeros(n)
        for _ in range(max(1, steps // (self.num_steps * n))):
            for t in range(self.num_steps):
                obs_buf[t], done_buf[t] = next_obs, next_done
                with torch.no_grad():
                    action, logp, _, value = self.agent.act(next_obs)
                act_buf[t], logp_buf[t], val_buf[t] = action, logp, value
                clipped = torch.max(torch.min(action, self.high), self.low).numpy()
                obs, rewards, dones, _ = env.step(clipped)
                rew_buf[t] = torch.as_tensor(rewards)
                # an episode cut at episode_s is not an end: its value would be bootstrapped;
                # like cleanrl_ppo.py, this simple loop treats every end as terminal
                next_obs, next_done = torch.as_tensor(obs), torch.as_tensor(dones,
                                                                            dtype=torch.float32)
            self._update(obs_buf, act_buf, logp_buf, rew_buf, done_buf, val_buf, next_obs,
                         next_done, order)
        self.last_episodes = list(env.episodes)
        return self.weights()

    def _update(self, obs_buf, act_buf, logp_buf, rew_buf, done_buf, val_buf, next_obs,
                next_done, order: np.random.Generator) -> None:
        steps, n = rew_buf.shape
        with torch.no_grad():  # generalised advantage estimation, per slot
            next_value = self.agent.value(next_obs)
            advantages = torch.zeros_like(rew_buf)
            last = torch.zeros(n)
            for t in reversed(range(steps)):
                not_done = 1.0 - (next_done if t == steps - 1 else done_buf[t + 1])
                following = next_value if t == steps - 1 else val_buf[t + 1]
                delta = rew_buf[t] + self.gamma * following * not_done - val_buf[t]
                last = delta + self.gamma * self.gae_lambda * not_done * last
                advantages[t] = last
            returns = advantages + val_buf
        b_obs, b_act = obs_buf.reshape(steps * n, -1), act_buf.reshape(steps * n, -1)
        b_logp, b_adv, b_ret = logp_buf.reshape(-1), advantages.reshape(-1), returns.reshape(-1)
        batch = steps * n
        minibatch = max(1, batch // self.num_minibatches)
        for _ in range(self.update_epochs):
            perm = torch.as_tensor(order.permutation(batch))
            for start in range(0, batch, minibatch):
                idx = perm[start:start + minibatch]
                _, new_logp, entropy, new_value = self.agent.act(b_obs[idx], b_act[idx])
                ratio = (new_logp - b_logp[idx]).exp()
                adv = b_adv[idx]
                adv = (adv - adv.mean()) / (adv.std() + 1e-8)
                policy_loss = torch.max(-adv * ratio, -adv * ratio.clamp(
                    1 - self.clip_coef, 1 + self.clip_coef)).mean()
                value_loss = 0.5 * ((new_value - b_ret[idx]) ** 2).mean()
                loss = policy_loss + self.vf_coef * value_loss - self.ent_coef * entropy.mean()
                self.optimizer.zero_grad()
                loss.backward()
                torch.nn.utils.clip_grad_norm_(self.agent.parameters(), self.max_grad_norm)
                self.optimizer.step()

    def save(self, directory: Path) -> None:
        torch.save({"agent": self.agent.state_dict(), "optimizer": self.optimizer.state_dict()},
                   Path(directory) / CHECKPOINT)

    def load(self, directory: Path) -> None:
        state = torch.load(Path(directory) / CHECKPOINT, weights_only=True)
        self.agent.load_state_dict(state["agent"])
        self.optimizer.load_state_dict(state["optimizer"])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--generations", type=int, default=3)
    parser.add_argument("--steps", type=int, default=20_000,
                        help="agent-decisions per generation")
    parser.add_argument("--team-size", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("runs/selfplay_cleanrl"))
    parser.add_argument("--resume", action="store_true")
    parser.add_argument("--smoke", action="store_true",
                        help="a tiny run for CI: 2 generations of 192 decisions, 5 s matches")
    args = parser.parse_args(argv)
    training = TrainingSetup(team_size=args.team_size, episode_s=2.0 if args.smoke else 30.0)
    rating = RatingSetup(half_time_s=5.0, halves=1, recent=1, n_bootstrap=20) if args.smoke \
        else RatingSetup()
    options = {"copies": 1, "num_steps": 64} if args.smoke else {}
    steps, generations = (192, 2) if args.smoke else (args.steps, args.generations)
    config = LeagueConfig(seed=args.seed, steps_per_generation=steps,
                          builtins=("chaser", "static") if args.smoke else
                          ("chaser", "static", "full"),
                          training=training, rating=rating,
                          learner="selfplay_cleanrl:CleanRLLearner", learner_options=options)
    learner = CleanRLLearner(training, seed=args.seed, **options)
    summary = run_league(args.out, generations, None if args.resume else config,
                         resume=args.resume, learner=learner,
                         backend="serial" if args.smoke else "process")
    print(summary.describe())


if __name__ == "__main__":
    main()
