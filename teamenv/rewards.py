"""The env's rewards: the goal rewards, the weighted terms of ``reward=`` (goal, ball
progress, possession) and the ``reward_fn=`` that shapes them last (``CycleRewards``).

Every term is team-shared and zero-sum: each agent of a team gets the same value, and the
other team's agents get its negative. Signs are from the agent's own team's view (it attacks
+x in its team frame): positive is good for that team.

- ``goal``: +1 when the agent's team scores, -1 when it concedes (the env's built-in reward).
- ``ball_progress``: metres the ball moved towards the goal the team attacks this cycle
  (negative when it moves back). Counted only on cycles that end in PlayOn, so the referee's
  placements (kick-off after a goal, the ball put on a set-play spot) add nothing; a kick-off
  or set play that is taken counts from its spot.
- ``possession``: +cycle_s (0.02) per cycle in PlayOn while the team has the ball, so +1 per
  second of possession: a team has it when its player nearest the ball is within kick reach
  (the locomotion profile's ``kick_reach``) and strictly nearer than every opponent.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from teamenv.errors import ConfigError
from teamenv.teams import SIDES

if TYPE_CHECKING:
    from teamenv.sim.playmode import PlayMode
    from teamenv.sim.simulation import CycleReport

REWARD_TERMS = ("goal", "ball_progress", "possession")

@dataclass(frozen=True)
class RewardInput:
    """What a reward function sees each cycle (all world-frame; team 0 is left).

    ``default`` holds the built-in goal rewards: +1 to every agent of a scoring team, -1 to
    every agent of the other, 0 otherwise.
    """

    agents: tuple[str, ...]
    report: CycleReport
    state: np.ndarray
    previous_state: np.ndarray
    play_mode: str
    attack_sign: tuple[float, float]
    default: Mapping[str, float]


RewardFn = Callable[[RewardInput], Mapping[str, float]]

#: Layout of ``Simulation.global_state``: ball x, y, vx, vy, then 7 values per player.
_BALL, _PLAYERS, _PER_PLAYER = 0, 4, 7


def reward_weights(spec: str | Mapping[str, float] | None) -> dict[str, float] | None:
    """Validate the ``reward=`` option: None, a term name (weight 1), or ``{term: weight}``
    (an empty dict: every reward 0). Returns the weights, or None for None."""
    if spec is None:
        return None
    if isinstance(spec, str):
        spec = {spec: 1.0}
    if not isinstance(spec, Mapping):
        raise ConfigError(f"reward: expected None, one of {list(REWARD_TERMS)} or a dict of "
                          f"weights, got {spec!r}")
    weights: dict[str, float] = {}
    for term, weight in spec.items():
        if term not in REWARD_TERMS:
            raise ConfigError(f"reward: unknown term {term!r}; terms are {list(REWARD_TERMS)}")
        if isinstance(weight, bool) or not isinstance(weight, (int, float)) or \
                not math.isfinite(weight):
            raise ConfigError(f"reward[{term!r}]: weight must be a finite number, got "
                              f"{weight!r}")
        weights[term] = float(weight)
    return weights


class RewardTerms:
    """Computes the weighted terms of ``reward=`` for the agents of one cycle.

    ``team_size`` players per side; ``kick_reach`` (m) decides possession; ``cycle_s`` (s)
    scales possession to +1 per second.
    """

    def __init__(self, weights: Mapping[str, float], team_size: int, kick_reach: float,
                 cycle_s: float) -> None:
        self.weights = dict(weights)
        self.team_size = team_size
        self.kick_reach = kick_reach
        self.cycle_s = cycle_s

    def __call__(self, reward_input: Any) -> dict[str, float]:
        """Rewards per agent from a ``RewardInput`` (its ``default`` holds the goal
        rewards; ``state``/``previous_state`` the world-frame global state)."""
        team_value = np.zeros(2)  # per team: left, right
        agents = reward_input.agents
        goal = self.weights.get("goal", 0.0)
        playing = reward_input.play_mode == "PlayOn"
        state, prev = reward_input.state, reward_input.previous_state
        sign = np.asarray(reward_input.attack_sign, dtype=float)
        progress = self.weights.get("ball_progress", 0.0)
        if progress and playing and prev is not None:
            dx = float(state[_BALL]) - float(prev[_BALL])
            team_value += progress * dx * sign
        possession = self.weights.get("possession", 0.0)
        if possession and playing:
            owner = self.possessing_team(state)
            if owner is not None:
                team_value[owner] += possession * self.cycle_s
                team_value[1 - owner] -= possession * self.cycle_s
        out = {}
        for agent in agents:
            team = 0 if agent.startswith("left_") else 1
            out[agent] = goal * reward_input.default[agent] + float(team_value[team])
        return out

    def possessing_team(self, state: np.ndarray) -> int | None:
        """0 (left) or 1 (right) when that team's player nearest the ball is within kick reach
        and strictly nearer than every opponent; None otherwise."""
        n = self.team_size
        players = np.asarray(state[_PLAYERS:_PLAYERS + 2 * n * _PER_PLAYER], dtype=float)
        xy = players.reshape(2 * n, _PER_PLAYER)[:, :2]
        dist = np.hypot(xy[:, 0] - state[_BALL], xy[:, 1] - state[_BALL + 1])
        nearest = (float(dist[:n].min()), float(dist[n:].min()))
        team = 0 if nearest[0] < nearest[1] else 1 if nearest[1] < nearest[0] else None
        if team is None or nearest[team] > self.kick_reach:
            return None
        return team


class CycleRewards:
    """Every agent's reward for one cycle, as the env's options ask: the goal rewards, the
    weighted ``reward=`` terms instead when ``weights`` are given, then ``reward_fn`` on top
    (its ``RewardInput.default`` holds what came before; its result is the reward).

    ``needs_state``: whether the world state of each cycle must be passed (the terms and
    ``reward_fn`` read it).
    """

    def __init__(self, weights: Mapping[str, float] | None, reward_fn: RewardFn | None,
                 team_size: int, kick_reach: float, cycle_s: float) -> None:
        self.terms = None if weights is None else RewardTerms(weights, team_size, kick_reach,
                                                              cycle_s)
        self.reward_fn = reward_fn
        self.needs_state = reward_fn is not None or self.terms is not None

    def __call__(self, agents: Sequence[str], report: CycleReport, state: np.ndarray | None,
                 previous_state: np.ndarray | None, play_mode: PlayMode,
                 attack_sign: Sequence[float]) -> dict[str, float]:
        default = dict.fromkeys(agents, 0.0)
        for event in report.referee:
            if event.kind == "goal":
                scorer = SIDES[event.team]
                for a in agents:
                    default[a] += 1.0 if a.startswith(scorer + "_") else -1.0
        if self.terms is None and self.reward_fn is None:
            return default
        reward_input = RewardInput(
            agents=tuple(agents), report=report, state=state, previous_state=previous_state,
            play_mode=play_mode.name, attack_sign=tuple(attack_sign), default=default)
        if self.terms is not None:  # reward= first; reward_fn sees it as its default
            default = self.terms(reward_input)
            if self.reward_fn is None:
                return default
            reward_input = replace(reward_input, default=default)
        shaped = self.reward_fn(reward_input)
        missing = [a for a in agents if a not in shaped]
        if missing:
            raise ConfigError(f"reward_fn: returned no reward for agents {missing}")
        return {a: float(shaped[a]) for a in agents}
