"""teamenv: a multi-agent robot-soccer team-strategy environment (PettingZoo/Gymnasium).

Imports comms and locomotion; must never import strategy (teams are entry-point plugins).
Layout and import rules: docs/architecture.md.

Importing the package loads only light modules (field, config, errors, scenarios, play modes),
so a team plugin's ``import teamenv.field`` stays cheap. The env, and with it PettingZoo and
pymunk, loads on first use of ``SoccerParallelEnv``, ``parallel_env`` or ``env()``.
"""

from __future__ import annotations

import sys
import types
from typing import TYPE_CHECKING, Any

from teamenv.config import VISION_PROFILES, PerceptionConfig
from teamenv.errors import (
    ActionError,
    ConfigError,
    MessageError,
    MissingExtraError,
    TeamEnvError,
    TeamFault,
    TeamLoadError,
)
from teamenv.field import FIELD_PRESETS, FieldSpec, field_preset
from teamenv.registration import register_envs
from teamenv.scenarios import SCENARIOS, scenario_names
from teamenv.sim.playmode import PLAY_MODES, PlayMode

if TYPE_CHECKING:
    from teamenv.env import SoccerParallelEnv, parallel_env

__version__ = "0.1.0"

register_envs()  # gymnasium.make("teamenv/Player-v0"), "teamenv/Team-v0"

_FROM_ENV = ("SoccerParallelEnv", "parallel_env")  # loaded on first use (PEP 562)


def __getattr__(name: str) -> Any:
    if name in _FROM_ENV:
        from teamenv.env import SoccerParallelEnv, parallel_env

        globals().update(SoccerParallelEnv=SoccerParallelEnv, parallel_env=parallel_env)
        return globals()[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_FROM_ENV})


def env(**kwargs: Any):
    """The AEC form of ``parallel_env`` (PettingZoo's parallel_to_aec conversion)."""
    from pettingzoo.utils.conversions import parallel_to_aec

    from teamenv.env import parallel_env

    return parallel_to_aec(parallel_env(**kwargs))


class _Package(types.ModuleType):
    """``teamenv`` itself. Python binds a submodule to its package's attribute when it first
    loads it; the submodule ``teamenv.env`` now loads after this file, and would replace the
    AEC constructor ``teamenv.env()`` above. The module stays ``sys.modules["teamenv.env"]``."""

    def __setattr__(self, name: str, value: Any) -> None:
        if name == "env" and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package

__all__ = [
    "ActionError", "ConfigError", "FIELD_PRESETS", "FieldSpec", "MessageError",
    "MissingExtraError", "PLAY_MODES", "PerceptionConfig", "PlayMode", "SCENARIOS",
    "SoccerParallelEnv", "TeamEnvError", "VISION_PROFILES", "scenario_names",
    "TeamFault", "TeamLoadError", "env", "field_preset", "parallel_env",
]
