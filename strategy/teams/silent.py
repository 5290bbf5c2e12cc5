"""The silent team: the full team with its say channel switched off.

Each agent follows its own role vector (no voting), so comparing ``full`` with ``silent``
measures what talking is worth.
"""

from __future__ import annotations

from typing import Any

from strategy.teams.full import FullTeam
from strategy.teams.full_config import FullTeamConfig
from teamenv.team_config import team_config
from teamenv.teams import TeamContext


class SilentTeam(FullTeam):
    """``FullTeam`` with ``communicate=False`` by default; config keys: the fields of
    ``FullTeamConfig``, checked (and named in errors) as the silent team's."""

    name = "silent"
    defaults = {"communicate": False}

    def __init__(self, context: TeamContext, **config: Any) -> None:
        team_config(self.name, FullTeamConfig, {**self.defaults, **config})
        super().__init__(context, **config)
