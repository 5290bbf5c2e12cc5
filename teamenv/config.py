"""Frozen config dataclasses, one per concern; building one from a dict rejects unknown keys."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any, Mapping, TypeVar

from teamenv.errors import ConfigError

T = TypeVar("T")


@dataclass(frozen=True)
class RulesConfig:
    """Referee rules (seconds of game time, metres)."""

    half_time_s: float = 300.0
    halves: int = 2
    before_kickoff_s: float = 0.2
    goal_pause_s: float = 3.0
    kickoff_timeout_s: float = 15.0
    set_play_timeout_s: float = 15.0
    set_play_distance: float = 2.0
    change_sides_at_half_time: bool = False
    beam_noise_xy: float = 0.05
    beam_noise_rot: float = 0.05

    def __post_init__(self) -> None:
        _positive(self, "half_time_s", "goal_pause_s", "kickoff_timeout_s", "set_play_timeout_s",
                  "set_play_distance")
        _non_negative(self, "before_kickoff_s", "beam_noise_xy", "beam_noise_rot")
        if self.halves not in (1, 2):
            raise ConfigError(f"rules.halves: must be 1 or 2, got {self.halves!r}")


@dataclass(frozen=True)
class PhysicsConfig:
    """The 2D world: ball (SimSpark ball: radius 0.042 m, 26 g), rolling drag, substeps.

    The ball's speed decays each cycle as ``v <- max(0, v*exp(-linear_drag*dt) - rolling_decel*dt)``,
    so a ball launched at about 5.2 m/s rolls 9 m (the source documents' strong kick).
    """

    cycle_s: float = 0.02
    ball_radius: float = 0.042
    ball_mass: float = 0.026
    ball_linear_drag: float = 0.4
    ball_rolling_decel: float = 0.3
    ball_max_speed: float = 12.0
    ball_elasticity: float = 0.6
    player_elasticity: float = 0.2
    max_substep_travel: float = 0.04
    world_margin: float = 1.5

    def __post_init__(self) -> None:
        _positive(self, "cycle_s", "ball_radius", "ball_mass", "ball_max_speed",
                  "max_substep_travel", "world_margin")
        _non_negative(self, "ball_linear_drag", "ball_rolling_decel")
        for name in ("ball_elasticity", "player_elasticity"):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise ConfigError(f"physics.{name}: must be in [0, 1], got {value!r}")


def _positive(obj: Any, *names: str) -> None:
    for name in names:
        value = getattr(obj, name)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ConfigError(f"{_section(obj)}.{name}: must be a finite number > 0, got {value!r}")


def _non_negative(obj: Any, *names: str) -> None:
    for name in names:
        value = getattr(obj, name)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
            raise ConfigError(f"{_section(obj)}.{name}: must be a finite number >= 0, got {value!r}")


def _section(obj: Any) -> str:
    return _section_name(type(obj))


def build_config(cls: type[T], value: T | Mapping[str, Any] | None) -> T:
    """Return ``value`` as a ``cls``: None gives the defaults, a mapping overrides them.

    Unknown keys are an error, never ignored.
    """
    if value is None:
        return cls()
    if isinstance(value, cls):
        return value
    if not isinstance(value, Mapping):
        raise ConfigError(f"{cls.__name__}: expected a mapping or {cls.__name__}, got {value!r}")
    known = {f.name for f in fields(cls)}  # type: ignore[arg-type]
    unknown = sorted(set(value) - known)
    if unknown:
        raise ConfigError(
            f"{_section_name(cls)}: unknown key(s) {unknown}; known keys are {sorted(known)}"
        )
    return replace(cls(), **dict(value))


def _section_name(cls: type) -> str:
    return cls.__name__.removesuffix("Config").lower()
