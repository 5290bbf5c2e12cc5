"""The small soccer task the RL examples train on: an N v N env with flat Box spaces and a dense shaped reward.

Goals alone are too rare for a short run to learn from, so each agent also earns the ball's
progress towards the goal its team attacks (metres) and, less, its own approach to the ball.
Both terms are differences of consecutive world states, so over an episode they add up to how
far the ball went forward and how much closer the agent got to it.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

import teamenv
from teamenv.rewards import RewardInput

# Ball state leads env.state(): x, y, vx, vy; then 7 numbers per player: x, y, heading, ...
BALL_X, BALL_Y, BALL_STATE_SIZE, PLAYER_STATE_SIZE = 0, 1, 4, 7


class BallProgressReward:
    """Goal reward (+1 / -1) plus ``progress_weight`` per metre the ball moves towards the
    opponents' goal and ``approach_weight`` per metre the agent closes on the ball.

    A plain class (not a closure) so the env pickles into vector-env subprocesses.
    """

    def __init__(self, team_size: int, progress_weight: float = 0.5,
                 approach_weight: float = 0.1) -> None:
        self.team_size = team_size
        self.progress_weight = progress_weight
        self.approach_weight = approach_weight

    def _ball_distances(self, state: np.ndarray) -> np.ndarray:
        players = state[BALL_STATE_SIZE:BALL_STATE_SIZE + 2 * self.team_size * PLAYER_STATE_SIZE]
        xy = players.reshape(2 * self.team_size, PLAYER_STATE_SIZE)[:, :2]
        return np.hypot(xy[:, 0] - state[BALL_X], xy[:, 1] - state[BALL_Y])

    def __call__(self, cycle: RewardInput) -> Mapping[str, float]:
        ball_dx = float(cycle.state[BALL_X] - cycle.previous_state[BALL_X])
        approach = self._ball_distances(cycle.previous_state) - self._ball_distances(cycle.state)
        rewards = {}
        for agent in cycle.agents:
            side, number = agent.rsplit("_", 1)
            team = 0 if side == "left" else 1
            player = team * self.team_size + int(number) - 1
            rewards[agent] = (cycle.default[agent]
                              + self.progress_weight * cycle.attack_sign[team] * ball_dx
                              + self.approach_weight * float(approach[player]))
        return rewards


def make_env(team_size: int = 2, right: str | None = "chaser", max_cycles: int = 400,
             field: str = "simspark"):
    """The examples' PettingZoo ParallelEnv: box observations/actions, shaped reward.

    ``right="chaser"`` puts the built-in ball-chasing team on the right (the learners are the
    left team); ``right=None`` makes both sides learners (self-play through a shared policy, or
    one policy per team).
    """
    return teamenv.parallel_env(
        field=field, team_size=team_size, right=right, observation_format="box",
        action_format="box", reward_fn=BallProgressReward(team_size), max_cycles=max_cycles)
