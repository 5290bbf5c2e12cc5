"""A self-play league: frozen snapshots, PFSP opponents, ratings from the tournament runner.

``teamenv selfplay run`` (``teamenv.selfplay.cli``) or ``run_league`` (``league``) trains a
team generation by generation: a learner (``learner.Learner``; SB3 PPO in ``sb3_learner``)
(``imitation``: PPO warm-started by cloning a scripted teacher in ``teacher_env``)
trains against opponents drawn by prioritized fictitious self-play (``pfsp``) from the
built-in teams and its own earlier snapshots (``snapshots``), each new snapshot is rated in a
gauntlet by ``teamenv.tournament`` (``rating``), and the ratings pick the next opponents. A
run is deterministic given its seed and resumes after a kill with the same pool and ratings
(``league``). docs/selfplay.md has the commands and the design.

Modules load on first use, so ``import teamenv.selfplay`` costs nothing and team specs that
name ``teamenv.selfplay.egocentric_team`` load neither torch nor the tournament runner.
"""

from __future__ import annotations

import importlib
from typing import Any

_EXPORTS = {
    "LeagueConfig": "config", "RatingSetup": "rating", "TrainingSetup": "training_setup",
    "ActionSetup": "training_setup", "League": "league", "LeagueSummary": "league",
    "run_league": "league", "OpponentMix": "pfsp", "pfsp_probabilities": "pfsp",
    "TeamBatchEnv": "batch_env", "Learner": "learner", "PolicyWeights": "learner",
    "SnapshotPool": "snapshots", "LeagueStore": "league_store",
    "TeacherBatchEnv": "teacher_env", "ImitationPPOLearner": "imitation",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'teamenv.selfplay' has no attribute {name!r}")
    return getattr(importlib.import_module(f"teamenv.selfplay.{module}"), name)
