"""What the simple built-in teams share: their beliefs in either mode (they walk and kick with
``strategy.behaviours.direct``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from strategy.perception.perceiver import perceiver_for
from strategy.perception.worldmodel import WorldModel
from teamenv.teams import TeamContext


class Beliefs:
    """Each agent's ``WorldModel`` from its own observation: read directly in ``state``
    mode (unrounded), through localization and filtering in ``vision`` mode (no talking)."""

    def __init__(self, context: TeamContext) -> None:
        self.perceiver = perceiver_for(context, communicate=False, resolution=None)

    def reset(self, seed: int) -> None:
        self.perceiver.reset(seed)

    def update(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, WorldModel]:
        return self.perceiver.update(observations)
