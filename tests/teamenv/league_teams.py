"""Team plugins for the league-match tests, named as module:Class."""

from __future__ import annotations


class ScriptedTeam:
    """Keeps its context and reset seeds; every agent does ``ACTION`` (a class attribute)."""

    ACTION: dict = {}
    contexts: list = []

    def __init__(self, context, **config):
        self.context, self.config, self.seeds = context, config, []
        ScriptedTeam.contexts.append(context)

    def reset(self, seed):
        self.seeds.append(seed)

    def act(self, observations):
        return {agent: dict(self.ACTION) for agent in observations}


class RaisingTeam(ScriptedTeam):
    def act(self, observations):
        raise ValueError("no idea")
