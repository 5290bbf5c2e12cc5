"""The static team: every player walks to a fixed spot in its own half and stays there."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from strategy.behaviours.direct import walk_to
from strategy.teams.common import Beliefs
from teamenv.team_config import in_range, team_config
from teamenv.teams import TeamContext


@dataclass(frozen=True)
class StaticConfig:
    """The static team's option. depth: how far towards the halfway line the deepest field
    players stand, as a fraction of the half's length."""

    depth: float = field(default=0.5, metadata=in_range(0.0, 1.0, low_open=True))


class StaticTeam:
    """Holds a fixed grid of positions in the own half (a goalie on the goal line); never
    kicks. The weakest opponent, useful as a baseline and for tests. Config keys: the fields
    of ``StaticConfig``."""

    def __init__(self, context: TeamContext, **config: Any):
        self.config = team_config("static", StaticConfig, config)
        depth = self.config.depth
        self.context = context
        self.bounds = (context.walk_low, context.walk_high)
        f, n = context.field, context.team_size
        spots = [np.array([-f.half_length + 0.3, 0.0])]
        rest = n - 1
        for k in range(rest):
            y = f.half_width * 0.8 * (((k + 1) / (rest + 1)) * 2 - 1)
            x = -f.half_length * depth * (0.9 if k % 2 else 0.5)
            spots.append(np.array([x, y]))
        self.spots = {agent: spots[k] for k, agent in enumerate(context.agents)}
        self.beliefs = Beliefs(context)

    def reset(self, seed: int) -> None:
        self.beliefs.reset(seed)  # vision mode's particle filters; the decisions are fixed

    def act(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
        out = {}
        for agent, view in self.beliefs.update(observations).items():
            out[agent] = {"walk": walk_to(view, self.spots[agent], *self.bounds, face=view.ball, speed=0.6)}
        return out
