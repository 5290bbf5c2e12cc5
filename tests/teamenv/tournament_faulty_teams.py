"""Team plugins that fail on purpose, named as ``module:Class`` by the tournament tests."""

from __future__ import annotations

import os
import time
from collections.abc import Mapping
from typing import Any

from strategy.teams.static import StaticTeam


class RaisingTeam(StaticTeam):
    """Raises after one second of game time."""

    def act(self, observations: Mapping[str, Any]) -> dict:
        if observations and next(iter(observations.values()))["game"][0] > 1.0:
            raise RuntimeError("boom")
        return super().act(observations)


class InvalidTeam(StaticTeam):
    """Returns a NaN walk command."""

    def act(self, observations: Mapping[str, Any]) -> dict:
        return {agent: {"walk": [float("nan"), 0.0, 0.0]} for agent in observations}


class SlowTeam(StaticTeam):
    """Takes 300 ms per cycle (over a 100 ms budget)."""

    def act(self, observations: Mapping[str, Any]) -> dict:
        time.sleep(0.3)
        return super().act(observations)


class StallingTeam(StaticTeam):
    """Never returns from act() (caught by the stall watchdog)."""

    def act(self, observations: Mapping[str, Any]) -> dict:
        while True:
            time.sleep(0.01)


class CrashingTeam(StaticTeam):
    """Kills the process it runs in (as a segfault would) after one second of game time."""

    def act(self, observations: Mapping[str, Any]) -> dict:
        if observations and next(iter(observations.values()))["game"][0] > 1.0:
            os._exit(13)
        return super().act(observations)


class PickyTeam(StaticTeam):
    """Accepts a ``mode`` override of "a" or "b" only."""

    def __init__(self, context: Any, mode: str = "a", depth: float = 0.5) -> None:
        if mode not in ("a", "b"):
            raise ValueError(f"picky team: mode must be 'a' or 'b', got {mode!r}")
        super().__init__(context, depth=depth)
        self.mode = mode


class CrashOnceTeam(StaticTeam):
    """Kills the process it runs in on its first act() of the run, once: the first one to find
    no marker file (path in ``TEAMENV_TEST_CRASH_MARKER``) creates it and dies; later ones
    play as the static team. For tests of a worker killed mid-tournament."""

    def act(self, observations: Mapping[str, Any]) -> dict:
        marker = os.environ.get("TEAMENV_TEST_CRASH_MARKER")
        if marker:
            try:
                fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            except FileExistsError:
                pass
            else:
                os.close(fd)
                os._exit(13)
        return super().act(observations)
