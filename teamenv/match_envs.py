"""The envs one process keeps between its matches, so a tournament worker builds each only once.

A match's env is built from its teams, their configs, the match options and the cycle budget;
nothing else. ``reset(seed)`` puts a built env (its physics world, referee, channel, the team
plugins' state and seeds) where a fresh one starts, so a match on a kept env is the match on a
fresh one, bit for bit (tested: a tournament on kept envs stores the rows of one that builds an
env per match). What is saved is the build: ~20-35 ms a match (the teams' set-up, the spaces,
the world's static geometry), which counts in tournaments of short matches.

An env whose match ended in a team's fault or a stall is dropped, not kept: a plugin that
raised or was interrupted mid-``act`` may have left state that its ``reset`` does not expect.
"""

from __future__ import annotations

import json
from collections import OrderedDict
from collections.abc import Callable, Mapping
from typing import Any

from teamenv.env import SoccerParallelEnv

#: envs kept per process: a worker of a round robin of up to 3 teams (6 ordered pairings) keeps
#: all of them; in larger ones the most recent pairings
DEFAULT_SIZE = 8


def env_key(left: str, right: str, left_config: Mapping[str, Any] | None,
            right_config: Mapping[str, Any] | None, env_kwargs: Mapping[str, Any],
            cycle_time_budget_s: float | None) -> str:
    """Everything a match's env is built from, as one string (configs hold lists and dicts,
    which do not hash; ``repr`` for values JSON cannot write, e.g. a ``RulesConfig``)."""
    return json.dumps([left, right, left_config or {}, right_config or {}, env_kwargs,
                       cycle_time_budget_s], sort_keys=True, default=repr)


class MatchEnvs:
    """Up to ``size`` envs, the least recently used dropped first (``size`` >= 1)."""

    def __init__(self, size: int = DEFAULT_SIZE) -> None:
        if isinstance(size, bool) or not isinstance(size, int) or size < 1:
            raise ValueError(f"MatchEnvs: size must be a positive int, got {size!r}")
        self.size = size
        self._envs: OrderedDict[str, SoccerParallelEnv] = OrderedDict()
        #: envs built and envs handed out again, since construction (for benchmarks and tests)
        self.built = 0
        self.reused = 0

    def __len__(self) -> int:
        return len(self._envs)

    def take(self, key: str, build: Callable[[], SoccerParallelEnv]) -> SoccerParallelEnv:
        """The env kept under ``key``, taken out (a match that fails never puts it back), or a
        new one from ``build()``."""
        env = self._envs.pop(key, None)
        if env is not None:
            self.reused += 1
            return env
        self.built += 1
        return build()

    def give_back(self, key: str, env: SoccerParallelEnv) -> None:
        """Keep ``env`` for the next match with ``key``; the oldest is closed when full."""
        self._envs[key] = env
        while len(self._envs) > self.size:
            _, oldest = self._envs.popitem(last=False)
            oldest.close()

    def clear(self) -> None:
        """Close and drop every kept env."""
        while self._envs:
            self._envs.popitem()[1].close()
