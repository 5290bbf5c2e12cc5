"""Potential-based reward shaping (Ng, Harada and Russell 1999) as an env ``reward_fn``.

Why it exists. A goal is the reward that matters, and it is rare: a short training run sees
too few to learn from. A dense hint helps, but an arbitrary one changes what the best policy
is (a bonus for touching the ball breeds players that dribble in circles). Shaping of the form

    F(s, s') = gamma * Phi(s') - Phi(s)

for any potential ``Phi`` of the state is the one dense hint that provably leaves the optimal
policies unchanged: along an episode the discounted shaping terms telescope to
``gamma^T Phi(s_T) - Phi(s_0)``, which no choice of actions after ``s_0`` can change, provided
``gamma`` is the learner's discount and ``Phi`` is 0 in terminal states.

The env's ``ball_progress`` term (``teamenv.rewards``) is this shaping with ``Phi`` = the ball's
x and ``gamma = 1``; a learner that discounts (every PPO does) sees it change the optimum a
little (it favours progress *now* over the same progress later). ``PotentialShaping`` takes
the learner's ``gamma`` per env cycle. A learner that decides every ``k`` cycles with discount
``gamma_d`` per decision uses ``gamma = gamma_d ** (1 / k)`` and must sum a decision's cycle
rewards discounted by that ``gamma`` (``teamenv.selfplay.batch_env`` does), which makes the
shaping exact per decision too.

The terms are per team (team 0 left, team 1 right, from each team's own view) and are added to
``RewardInput.default`` (the goal reward, or the ``reward=`` terms). ``Phi(s') = 0`` when the
game is over (``GameOver``), the only terminal state the reward function can see; a scenario's
own end and a time-limit truncation are not terminal for it (a truncated episode's value is
bootstrapped by the learner, as it should be).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from teamenv.errors import ConfigError
from teamenv.field import FieldSpec, field_preset

#: Layout of ``Simulation.global_state``: ball x, y, vx, vy; 7 values per player (x, y first;
#: left team first); 5 game values.
_BALL_X, _BALL_Y, _PLAYERS, _PER_PLAYER = 0, 1, 4, 7
_STATE_FIXED = 4 + 5


class BallToGoalPotential:
    """``Phi_team(s)`` = minus the ball's distance to the centre of the goal that team attacks,
    divided by the field length: about -1 at the own goal, 0 in the opponents' goal.

    A team gains shaping by moving the ball towards the goal and loses it when the ball moves
    back, wherever it is on the pitch; the distance (rather than the x coordinate alone) also
    rewards moving the ball in from the touchline towards the goal mouth.
    """

    def __init__(self, field: str | FieldSpec = "simspark") -> None:
        self.field = field_preset(field)

    def __call__(self, state: np.ndarray, attack_sign: tuple[float, float]) -> np.ndarray:
        """(Phi_left, Phi_right) for the world-frame global ``state``."""
        x, y = float(state[_BALL_X]), float(state[_BALL_Y])
        half = self.field.half_length
        out = np.empty(2)
        for team in (0, 1):
            gx = float(attack_sign[team]) * half
            out[team] = -math.sqrt((x - gx) ** 2 + y ** 2) / self.field.length
        return out


class TeamToBallPotential:
    """``Phi_team(s)`` = minus the distance from the team's player nearest the ball to the
    ball, divided by the field length.

    It pays a team for getting *someone* to the ball — only the nearest player counts, so it
    does not pay three players for all running at it (the swarm every ball-chasing learner
    falls into); the others are free to take positions. Reading the team size from the
    state's length, it fits every team size.
    """

    def __init__(self, field: str | FieldSpec = "simspark") -> None:
        self.field = field_preset(field)

    def __call__(self, state: np.ndarray, attack_sign: tuple[float, float]) -> np.ndarray:
        n = (len(state) - _STATE_FIXED) // (2 * _PER_PLAYER)
        players = np.asarray(state[_PLAYERS:_PLAYERS + 2 * n * _PER_PLAYER], dtype=np.float64)
        xy = players.reshape(2 * n, _PER_PLAYER)[:, :2]
        dx, dy = xy[:, 0] - float(state[_BALL_X]), xy[:, 1] - float(state[_BALL_Y])
        dist = np.sqrt(dx * dx + dy * dy)
        return -np.array([dist[:n].min(), dist[n:].min()]) / self.field.length


class WeightedPotentials:
    """The sum of potentials, each times its weight: ``{name: weight}`` over ``POTENTIALS``."""

    def __init__(self, weights: Mapping[str, float], field: str | FieldSpec = "simspark") -> None:
        unknown = sorted(set(weights) - set(POTENTIALS))
        if unknown:
            raise ConfigError(f"shaping: unknown potential(s) {unknown}; potentials are "
                              f"{sorted(POTENTIALS)}")
        self.terms = [(float(w), POTENTIALS[name](field)) for name, w in weights.items()]

    def __call__(self, state: np.ndarray, attack_sign: tuple[float, float]) -> np.ndarray:
        total = np.zeros(2)
        for weight, potential in self.terms:
            total += weight * potential(state, attack_sign)
        return total


POTENTIALS = {"ball_to_goal": BallToGoalPotential, "team_to_ball": TeamToBallPotential}


class PotentialShaping:
    """``reward_fn`` adding ``weight * (gamma * Phi(s') - Phi(s))`` to every agent's reward,
    ``Phi`` from its team's view.

    ``potential(state, attack_sign) -> (Phi_left, Phi_right)``: e.g. ``BallToGoalPotential``.
    A plain class (no closures), so an env using it pickles into vector-env workers.
    """

    def __init__(self, potential, gamma: float, weight: float = 1.0) -> None:
        if not callable(potential):
            raise ConfigError(f"shaping: potential must be callable, got {potential!r}")
        for name, value, low in (("gamma", gamma, 0.0), ("weight", weight, -math.inf)):
            if isinstance(value, bool) or not isinstance(value, (int, float)) or \
                    not math.isfinite(value) or value < low:
                raise ConfigError(f"shaping: {name} must be a finite number"
                                  f"{' >= 0' if low == 0.0 else ''}, got {value!r}")
        if gamma > 1.0:
            raise ConfigError(f"shaping: gamma must be in [0, 1], got {gamma!r}")
        self.potential, self.gamma, self.weight = potential, float(gamma), float(weight)
        self._last_state: np.ndarray | None = None
        self._last_phi: np.ndarray | None = None

    def __call__(self, reward_input) -> Mapping[str, float]:
        state, prev = reward_input.state, reward_input.previous_state
        sign = reward_input.attack_sign
        # Phi(s) was Phi(s') of the last call when the env hands the same state back; that
        # keeps the telescoping exact across the half-time side change (attack_sign flips).
        if prev is not None and prev is self._last_state:
            phi_before = self._last_phi
        else:
            phi_before = np.zeros(2) if prev is None else self.potential(prev, sign)
        phi_after = np.zeros(2) if reward_input.play_mode == "GameOver" else \
            self.potential(state, sign)
        self._last_state, self._last_phi = state, phi_after
        shaping = self.weight * (self.gamma * phi_after - phi_before)
        return {agent: float(reward_input.default[agent])
                + float(shaping[0 if agent.startswith("left_") else 1])
                for agent in reward_input.agents}

    def __getstate__(self) -> dict:
        state = dict(self.__dict__)
        state["_last_state"] = state["_last_phi"] = None  # a cache, not part of the object
        return state
