"""What an env's agents observe, as one value: the egocentric true state, or the league's
restricted vision with its profile and camera.

The env, the simulation, the team host and the teams' context all read the mode from an
``ObservationMode`` (``is_vision``), so that "which observations does this match make" has one
answer instead of a string here, ``perception is not None`` there and ``sim.vision is not
None`` elsewhere. The public arguments stay as they are (``observation_mode="vision",
vision="mj", perception={...}``); ``ObservationMode.build`` turns them into the value.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from teamenv.config import PerceptionConfig, perception_config
from teamenv.errors import ConfigError

#: The names of the modes (``observation_mode=``).
OBSERVATION_MODES = ("state", "vision")


@dataclass(frozen=True)
class ObservationMode:
    """``name``: "state" (egocentric true state) or "vision" (the league's vision).

    In ``vision`` mode ``vision`` is the profile's name (``teamenv.config.VISION_PROFILES``)
    and ``perception`` its camera with any overrides; both are None in ``state`` mode.
    """

    name: str = "state"
    vision: str | None = None
    perception: PerceptionConfig | None = None

    def __post_init__(self) -> None:
        if self.name not in OBSERVATION_MODES:
            raise ConfigError(f"observation_mode: must be one of {list(OBSERVATION_MODES)}, "
                              f"got {self.name!r}")
        if self.is_vision != (self.perception is not None) or \
                self.is_vision != (self.vision is not None):
            raise ConfigError(f"observation mode {self.name!r}: a vision profile and camera go "
                              f"with 'vision' mode only, got vision={self.vision!r}, "
                              f"perception={self.perception!r}")

    @property
    def is_vision(self) -> bool:
        """True in ``vision`` mode (sightings, localization), False in ``state`` mode."""
        return self.name == "vision"

    @classmethod
    def build(cls, observation_mode: str = "state", vision: str | None = None,
              perception: PerceptionConfig | Mapping[str, Any] | None = None
              ) -> ObservationMode:
        """The mode of the env's arguments: ``vision`` (a profile name, None: "simspark") and
        ``perception`` (overrides of its camera) are for ``observation_mode="vision"`` only."""
        if observation_mode not in OBSERVATION_MODES:
            raise ConfigError(f"observation_mode: must be one of {list(OBSERVATION_MODES)}, "
                              f"got {observation_mode!r}")
        if observation_mode == "vision":
            return cls(observation_mode, "simspark" if vision is None else vision,
                       perception_config(vision, perception))
        for name, value in (("vision", vision), ("perception", perception)):
            if value is not None:
                raise ConfigError(f"{name}: {value!r} given, but observation_mode is "
                                  f"{observation_mode!r}; it applies to "
                                  "observation_mode='vision' only")
        return STATE_MODE


#: The default: every agent sees the true state.
STATE_MODE = ObservationMode()
