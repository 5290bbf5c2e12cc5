"""Deliberately broken team plugins, named as module:Class in tests."""

import time

from strategy.teams.static import StaticTeam


class RaisingTeam(StaticTeam):
    def act(self, observations):
        if observations and next(iter(observations.values()))["game"][0] > 1.0:
            raise RuntimeError("boom")
        return super().act(observations)


class InvalidTeam(StaticTeam):
    def act(self, observations):
        return {agent: {"walk": [float("nan"), 0, 0]} for agent in observations}


class SlowTeam(StaticTeam):
    def act(self, observations):
        time.sleep(0.05)
        return super().act(observations)


class StallingTeam(StaticTeam):
    def act(self, observations):
        while True:
            time.sleep(0.01)
