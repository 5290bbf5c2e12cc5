"""CleanRL-style PPO in plain PyTorch on the PettingZoo parallel API, one policy shared by every learning agent.

No wrappers: the loop calls ``env.reset``/``env.step`` with a dict of actions and stacks the
agents' observations into one batch, so each agent is one more sample for the shared
Gaussian policy and value function (PPO with clipped objective and GAE, as in CleanRL's
``ppo_continuous_action.py``). The learners are the left team; the right team is the
built-in ball chaser (``--self-play`` makes both teams learners of the same policy).

    python examples/cleanrl_ppo.py                   # 100k agent-steps, a few minutes
    python examples/cleanrl_ppo.py --smoke           # what CI runs: seconds
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np
import torch
from soccer_task import make_env
from torch import nn


def layer(n_in: int, n_out: int, std: float = np.sqrt(2)) -> nn.Linear:
    """A linear layer with CleanRL's orthogonal initialisation."""
    linear = nn.Linear(n_in, n_out)
    nn.init.orthogonal_(linear.weight, std)
    nn.init.constant_(linear.bias, 0.0)
    return linear


class Agent(nn.Module):
    """Separate tanh MLP actor (Gaussian mean, state-independent log std) and critic."""

    def __init__(self, obs_size: int, action_size: int, hidden: int = 64) -> None:
        super().__init__()
        self.critic = nn.Sequential(layer(obs_size, hidden), nn.Tanh(), layer(hidden, hidden),
                                    nn.Tanh(), layer(hidden, 1, std=1.0))
        self.actor_mean = nn.Sequential(layer(obs_size, hidden), nn.Tanh(),
                                        layer(hidden, hidden), nn.Tanh(),
                                        layer(hidden, action_size, std=0.01))
        self.actor_logstd = nn.Parameter(torch.full((1, action_size), -0.5))

    def value(self, obs: torch.Tensor) -> torch.Tensor:
        return self.critic(obs).squeeze(-1)

    def act(self, obs: torch.Tensor, action: torch.Tensor | None = None):
        mean = self.actor_mean(obs)
        dist = torch.distributions.Normal(mean, self.actor_logstd.exp().expand_as(mean))
        if action is None:
            action = dist.sample()
        return action, dist.log_prob(action).sum(-1), dist.entropy().sum(-1), self.value(obs)


def train(args: argparse.Namespace) -> tuple[Agent, list[tuple[int, float, int]]]:
    """Runs PPO; returns the agent and the curve rows (agent-steps, mean return, episodes)."""
    torch.manual_seed(args.seed)
    env = make_env(team_size=args.team_size, right=None if args.self_play else "chaser",
                   max_cycles=args.max_cycles)
    learners = list(env.possible_agents)
    n_agents = len(learners)
    obs_size = env.observation_space(learners[0]).shape[0]
    action_size = env.action_space(learners[0]).shape[0]
    agent = Agent(obs_size, action_size)
    optimizer = torch.optim.Adam(agent.parameters(), lr=args.learning_rate, eps=1e-5)

    steps = args.num_steps
    obs_buf = torch.zeros((steps, n_agents, obs_size))
    act_buf = torch.zeros((steps, n_agents, action_size))
    logp_buf = torch.zeros((steps, n_agents))
    rew_buf = torch.zeros((steps, n_agents))
    done_buf = torch.zeros((steps, n_agents))
    val_buf = torch.zeros((steps, n_agents))

    episode = 0
    obs, _ = env.reset(seed=args.seed)
    next_obs = torch.as_tensor(np.stack([obs[a] for a in learners]))
    next_done = torch.zeros(n_agents)
    returns_now = np.zeros(n_agents)
    finished: list[float] = []
    curve: list[tuple[int, float, int]] = []
    iterations = max(1, args.total_timesteps // (steps * n_agents))
    for iteration in range(1, iterations + 1):
        for t in range(steps):
            obs_buf[t], done_buf[t] = next_obs, next_done
            with torch.no_grad():
                action, logp, _, value = agent.act(next_obs)
            act_buf[t], logp_buf[t], val_buf[t] = action, logp, value
            clipped = action.clamp(-1.0, 1.0).numpy()
            obs, rewards, terms, truncs, _ = env.step(
                {a: clipped[i] for i, a in enumerate(learners)})
            rew_buf[t] = torch.as_tensor([rewards[a] for a in learners], dtype=torch.float32)
            returns_now += rew_buf[t].numpy()
            if not env.agents:  # every agent ends together (GameOver or max_cycles)
                finished.extend(returns_now.tolist())
                returns_now[:] = 0.0
                episode += 1
                obs, _ = env.reset(seed=args.seed + episode)
                next_done = torch.ones(n_agents)
            else:
                next_done = torch.as_tensor([float(terms[a] or truncs[a]) for a in learners])
            next_obs = torch.as_tensor(np.stack([obs[a] for a in learners]))

        with torch.no_grad():  # generalised advantage estimation, per agent
            next_value = agent.value(next_obs)
            advantages = torch.zeros_like(rew_buf)
            last = torch.zeros(n_agents)
            for t in reversed(range(steps)):
                not_done = 1.0 - (next_done if t == steps - 1 else done_buf[t + 1])
                following = next_value if t == steps - 1 else val_buf[t + 1]
                delta = rew_buf[t] + args.gamma * following * not_done - val_buf[t]
                last = delta + args.gamma * args.gae_lambda * not_done * last
                advantages[t] = last
            returns = advantages + val_buf

        b_obs, b_act = obs_buf.reshape(-1, obs_size), act_buf.reshape(-1, action_size)
        b_logp, b_adv = logp_buf.reshape(-1), advantages.reshape(-1)
        b_ret, batch = returns.reshape(-1), steps * n_agents
        minibatch = batch // args.num_minibatches
        order = np.random.default_rng(args.seed + iteration)
        for _ in range(args.update_epochs):
            perm = torch.as_tensor(order.permutation(batch))
            for start in range(0, batch, minibatch):
                idx = perm[start:start + minibatch]
                _, new_logp, entropy, new_value = agent.act(b_obs[idx], b_act[idx])
                ratio = (new_logp - b_logp[idx]).exp()
                adv = b_adv[idx]
                adv = (adv - adv.mean()) / (adv.std() + 1e-8)
                policy_loss = torch.max(-adv * ratio, -adv * ratio.clamp(
                    1 - args.clip_coef, 1 + args.clip_coef)).mean()
                value_loss = 0.5 * ((new_value - b_ret[idx]) ** 2).mean()
                loss = policy_loss + args.vf_coef * value_loss - args.ent_coef * entropy.mean()
                optimizer.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(agent.parameters(), args.max_grad_norm)
                optimizer.step()

        if finished:
            recent = finished[-10 * n_agents:]
            curve.append((iteration * batch, float(np.mean(recent)), len(recent)))
            print(f"agent-steps {iteration * batch:7d}  mean episode return "
                  f"{curve[-1][1]:+.3f} (last {len(recent)} agent-episodes)", flush=True)
    env.close()
    return agent, curve


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--total-timesteps", type=int, default=100_000,
                        help="agent-steps to train for (every agent's step counts)")
    parser.add_argument("--team-size", type=int, default=2)
    parser.add_argument("--self-play", action="store_true",
                        help="both teams learn (one shared policy) instead of facing the chaser")
    parser.add_argument("--max-cycles", type=int, default=400, help="episode length (20 ms cycles)")
    parser.add_argument("--num-steps", type=int, default=512, help="env steps per rollout")
    parser.add_argument("--learning-rate", type=float, default=3e-4)
    parser.add_argument("--gamma", type=float, default=0.99)
    parser.add_argument("--gae-lambda", type=float, default=0.95)
    parser.add_argument("--num-minibatches", type=int, default=4)
    parser.add_argument("--update-epochs", type=int, default=4)
    parser.add_argument("--clip-coef", type=float, default=0.2)
    parser.add_argument("--ent-coef", type=float, default=0.0)
    parser.add_argument("--vf-coef", type=float, default=0.5)
    parser.add_argument("--max-grad-norm", type=float, default=0.5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("runs/cleanrl_ppo"))
    parser.add_argument("--smoke", action="store_true",
                        help="a tiny run for CI: 2 rollouts of 64 steps, 32-cycle episodes")
    args = parser.parse_args(argv)
    if args.smoke:
        args.num_steps, args.max_cycles = 64, 32
        args.total_timesteps = 2 * args.num_steps * args.team_size * (2 if args.self_play else 1)

    agent, curve = train(args)
    args.out.mkdir(parents=True, exist_ok=True)
    torch.save(agent.state_dict(), args.out / "agent.pt")
    with open(args.out / "returns.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["agent_steps", "mean_episode_return", "episodes"])
        writer.writerows(curve)
    print(f"saved {args.out / 'agent.pt'} and {args.out / 'returns.csv'}")


if __name__ == "__main__":
    main()
