"""Prioritized fictitious self-play (PFSP): which opponents the learner trains against.

AlphaStar (Vinyals et al. 2019, "Grandmaster level in StarCraft II using multi-agent
reinforcement learning", Methods: "Prioritized fictitious self-play") picks an opponent B
from a pool with probability

    P(B) = f(p_win(A, B)) / sum over C of f(p_win(A, C))

where ``p_win(A, B)`` is the learner A's estimated probability of beating B and ``f`` a
weighting (``WEIGHTINGS``):

- ``hard``: ``f(p) = (1 - p) ** exponent`` (AlphaStar's f_hard, exponent 2 by default): mostly
  the opponents the learner still loses to; a beaten opponent is rarely played, never quite
  forgotten;
- ``variance``: ``f(p) = p * (1 - p)``: the opponents of about the learner's level, where a game
  says most about who is better (AlphaStar's f_var, used for its main exploiters' curriculum);
- ``linear``: ``f(p) = 1 - p``: a milder ``hard``;
- ``uniform``: ``f(p) = 1``: plain fictitious self-play (every past opponent alike).

When every weight is 0 (``hard`` against a pool the learner beats with certainty) the draw is
uniform. ``latest_share`` reserves that share of the draws for the latest snapshot (plain
self-play, AlphaStar's main agents play 35 % of their games so).

Draws are reproducible without any shared state: ``OpponentMix.draw(copy, episode)`` seeds a
``numpy.random.Generator`` from (mix seed, copy, episode), so the same episode of the same env
copy gets the same opponent whatever process draws it and in whatever order.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

import portable_math as pm
from teamenv.errors import ConfigError
from teamenv.tournament.spec import TeamSpec, parse_team_spec

WEIGHTINGS = ("hard", "variance", "linear", "uniform")


def check_weighting(weighting: str, exponent: float = 2.0) -> None:
    """ConfigError unless ``weighting`` is one of ``WEIGHTINGS`` and ``exponent`` > 0."""
    if weighting not in WEIGHTINGS:
        raise ConfigError(f"pfsp: weighting {weighting!r} is not one of {list(WEIGHTINGS)}")
    if isinstance(exponent, bool) or not isinstance(exponent, (int, float)) or \
            not math.isfinite(exponent) or exponent <= 0:
        raise ConfigError(f"pfsp: exponent must be a finite number > 0, got {exponent!r}")


def pfsp_weights(p_win: Sequence[float], weighting: str = "hard",
                 exponent: float = 2.0) -> np.ndarray:
    """The unnormalised weights ``f(p_win)`` of each opponent."""
    check_weighting(weighting, exponent)
    p = np.asarray(p_win, dtype=float)
    if p.ndim != 1 or not np.all((p >= 0.0) & (p <= 1.0)):
        raise ConfigError(f"pfsp: p_win must be probabilities in [0, 1], got {list(p_win)}")
    if weighting == "hard":
        return np.asarray(pm.power(1.0 - p, float(exponent)), dtype=float)
    if weighting == "variance":
        return p * (1.0 - p)
    if weighting == "linear":
        return 1.0 - p
    return np.ones_like(p)


def pfsp_probabilities(p_win: Sequence[float], weighting: str = "hard", exponent: float = 2.0,
                       latest_share: float = 0.0, latest: int | None = None) -> np.ndarray:
    """Sampling probabilities of each opponent: the normalised PFSP weights (uniform when
    they are all 0), mixed with ``latest_share`` on opponent index ``latest``."""
    weights = pfsp_weights(p_win, weighting, exponent)
    if len(weights) == 0:
        raise ConfigError("pfsp: no opponents to choose from")
    total = float(weights.sum())
    probs = weights / total if total > 0.0 else np.full(len(weights), 1.0 / len(weights))
    if not (isinstance(latest_share, (int, float)) and 0.0 <= latest_share <= 1.0):
        raise ConfigError(f"pfsp: latest_share must be in [0, 1], got {latest_share!r}")
    if latest_share > 0.0:
        if latest is None or not 0 <= latest < len(probs):
            raise ConfigError(f"pfsp: latest_share {latest_share} needs the latest snapshot "
                              f"among the opponents (index {latest!r})")
        probs = (1.0 - latest_share) * probs
        probs[latest] += latest_share
    return probs


@dataclass(frozen=True)
class OpponentMix:
    """The opponents of one training call with their sampling probabilities, and the seed of
    its draws (``draw``)."""

    teams: tuple[TeamSpec, ...]
    probabilities: tuple[float, ...]
    seed: int

    def __post_init__(self) -> None:
        object.__setattr__(self, "teams", tuple(parse_team_spec(t) for t in self.teams))
        probs = np.asarray(self.probabilities, dtype=float)
        if len(self.teams) == 0 or probs.shape != (len(self.teams),) or \
                not np.all(probs >= 0.0) or not math.isclose(float(probs.sum()), 1.0,
                                                              abs_tol=1e-9):
            raise ConfigError(f"opponent mix: {len(self.teams)} teams need as many "
                              f"probabilities >= 0 summing to 1, got {list(self.probabilities)}")
        object.__setattr__(self, "probabilities", tuple(float(p) for p in probs))
        object.__setattr__(self, "_cumulative", np.cumsum(probs))  # a cache, not a field

    def draw(self, copy: int, episode: int) -> TeamSpec:
        """The opponent of episode ``episode`` of env copy ``copy`` (a pure function)."""
        u = np.random.default_rng([self.seed, copy, episode]).random()
        index = int(np.searchsorted(self._cumulative, u * self._cumulative[-1], side="right"))
        return self.teams[min(index, len(self.teams) - 1)]

    @classmethod
    def single(cls, team: str | TeamSpec, seed: int = 0) -> OpponentMix:
        """Always ``team``."""
        return cls((parse_team_spec(team),), (1.0,), seed)
