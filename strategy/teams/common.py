"""What the simple built-in teams share: their beliefs in either mode (they walk and kick with
``strategy.behaviours.direct``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from strategy.perception.team_worldmodels import team_world_models
from strategy.perception.vision_perceiver import VisionPerceiver
from strategy.perception.worldmodel import WorldModel
from teamenv.teams import TeamContext


class Beliefs:
    """Each agent's ``WorldModel`` from its own observation: read directly in ``state``
    mode (unrounded), through localization and filtering in ``vision`` mode (no talking)."""

    def __init__(self, context: TeamContext) -> None:
        self.field = context.field
        self.index = {agent: k for k, agent in enumerate(context.agents)}
        self.perceiver = VisionPerceiver(context, communicate=False) \
            if context.observation_mode == "vision" else None

    def reset(self, seed: int) -> None:
        if self.perceiver is not None:
            self.perceiver.reset(seed)

    def update(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, WorldModel]:
        if self.perceiver is not None:
            return self.perceiver.update(observations)
        return team_world_models(observations, self.index, self.field, resolution=None)
