"""The silent team: the full team with its say channel switched off.

Each agent follows its own role vector (no voting), so comparing ``full`` with ``silent``
measures what talking is worth.
"""

from __future__ import annotations

from strategy.teams.full import FullTeam


class SilentTeam(FullTeam):
    """``FullTeam`` with ``communicate=False`` by default."""

    name = "silent"
    defaults = {"communicate": False}
