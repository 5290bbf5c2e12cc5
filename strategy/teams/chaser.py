"""The ball-chasing team: the player closest to the ball runs to it and kicks at goal.

A template for a first team: decisions use only each agent's own observation.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from strategy.behaviours.direct import kick_toward, walk_to
from strategy.perception.worldmodel import WorldModel
from strategy.teams.common import Beliefs
from teamenv import PlayMode
from teamenv.team_config import in_range, team_config
from teamenv.teams import TeamContext

OWN_KICKABLE = {"PlayOn", "KickOff_Left", "KickIn_Left", "CornerKick_Left", "GoalKick_Left"}


@dataclass(frozen=True)
class ChaserConfig:
    """The chaser's options.

    kick_reach: kick when the ball is this close (m); None: 0.9 x the body's kick reach.
    all_chase: every agent chases the ball (False: only the one that believes it is closest).
    """

    kick_reach: float | None = field(default=None, metadata=in_range(0.0, low_open=True))
    all_chase: bool = False


class ChaserTeam:
    """Every agent that believes it is the closest teammate to the ball chases it and kicks
    towards the opponents' goal; the others hold a spot between the ball and their goal.
    Config keys: the fields of ``ChaserConfig``."""

    def __init__(self, context: TeamContext, **config: Any):
        self.config = team_config("chaser", ChaserConfig, config)
        self.context = context
        self.bounds = (context.walk_low, context.walk_high)
        kick_reach = self.config.kick_reach
        self.kick_reach = context.kick_reach * 0.9 if kick_reach is None else float(kick_reach)
        self.all_chase = self.config.all_chase
        self.goal = np.array([context.field.half_length, 0.0])
        self.beliefs = Beliefs(context)

    def reset(self, seed: int) -> None:
        self.beliefs.reset(seed)

    def act(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
        return {agent: self._decide(view)
                for agent, view in self.beliefs.update(observations).items()}

    def _decide(self, view: WorldModel) -> dict[str, Any]:
        if view.play_mode.name not in OWN_KICKABLE or view.fallen:
            return {"walk": np.zeros(3)} if view.play_mode != PlayMode.PlayOn else \
                {"walk": walk_to(view, view.ball, *self.bounds, face=view.ball)}
        dist = np.hypot(*(view.teammates - view.ball).T)
        dist[~view.teammates_present] = np.inf
        mine = float(np.hypot(*(view.position - view.ball)))
        if not self.all_chase and mine > dist.min() + 1e-6:
            home = view.ball * 0.5 + np.array([-self.context.field.half_length, 0.0]) * 0.5
            return {"walk": walk_to(view, home, *self.bounds, face=view.ball)}
        if mine <= self.kick_reach:
            return {"walk": np.zeros(3), "kick": kick_toward(view, self.goal)}
        # Approach from behind the ball, on the line to the goal.
        to_goal = self.goal - view.ball
        behind = view.ball - 0.25 * to_goal / max(1e-6, float(np.hypot(*to_goal)))
        target = behind if mine > 0.6 else view.ball
        return {"walk": walk_to(view, target, *self.bounds, face=view.ball)}
