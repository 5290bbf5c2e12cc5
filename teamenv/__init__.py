"""teamenv: a multi-agent robot-soccer team-strategy environment (PettingZoo/Gymnasium).

Imports comms and locomotion; must never import strategy (teams are entry-point plugins).
"""

from __future__ import annotations

from typing import Any

from teamenv.config import VISION_PROFILES, PerceptionConfig
from teamenv.env import SoccerParallelEnv, parallel_env
from teamenv.errors import (
    ActionError, ConfigError, MessageError, MissingExtraError, TeamEnvError, TeamFault,
    TeamLoadError,
)
from teamenv.field import FIELD_PRESETS, FieldSpec, field_preset
from teamenv.registration import register_envs
from teamenv.scenarios import SCENARIOS, scenario_names
from teamenv.sim.playmode import PLAY_MODES, PlayMode

__version__ = "0.1.0"

register_envs()  # gymnasium.make("teamenv/Player-v0"), "teamenv/Team-v0"


def env(**kwargs: Any):
    """The AEC form of ``parallel_env`` (PettingZoo's parallel_to_aec conversion)."""
    from pettingzoo.utils.conversions import parallel_to_aec

    return parallel_to_aec(parallel_env(**kwargs))


__all__ = [
    "ActionError", "ConfigError", "FIELD_PRESETS", "FieldSpec", "MessageError",
    "MissingExtraError", "PLAY_MODES", "PerceptionConfig", "PlayMode", "SCENARIOS",
    "SoccerParallelEnv", "TeamEnvError", "VISION_PROFILES", "scenario_names",
    "TeamFault", "TeamLoadError", "env", "field_preset", "parallel_env",
]
