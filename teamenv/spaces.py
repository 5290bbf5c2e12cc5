"""Gymnasium spaces of the env: Dict and flat-Box forms of actions and observations."""

from __future__ import annotations

import base64
import binascii
import math
import string
from typing import Any

import numpy as np
from gymnasium import spaces

from teamenv.box_layout import (
    ACTION_SIZE,
    KICK_HIGH,
    KICK_LOW,
    N_PLAY_MODES,
    ObservationLayout,
    StateLayout,
    VisionLayout,
    beam_bounds,
)
from teamenv.field import FieldSpec


class Base64Text(spaces.Text):
    """Text that is the padded base64 of at most ``payload_bytes`` bytes (the ``mj`` channel's
    say payload); ``sample`` draws random payloads, ``contains`` checks the encoding too."""

    def __init__(self, payload_bytes: int, seed: int | None = None) -> None:
        self.payload_bytes = payload_bytes
        max_length = 4 * math.ceil(payload_bytes / 3)
        super().__init__(max_length=max_length, min_length=0,
                         charset=string.ascii_letters + string.digits + "+/=", seed=seed)

    def sample(self, mask: Any = None, probability: Any = None) -> str:
        n = int(self.np_random.integers(0, self.payload_bytes + 1))
        return base64.b64encode(self.np_random.bytes(n)).decode("ascii")

    def contains(self, x: Any) -> bool:
        if not super().contains(x):
            return False
        try:
            return len(base64.b64decode(x, validate=True)) <= self.payload_bytes
        except (binascii.Error, ValueError):
            return False


def say_space(channel_profile: Any) -> spaces.Text:
    """The ``say`` space of a channel profile: legal characters and length (base64 for mj)."""
    if getattr(channel_profile, "base64_payload", False):
        return Base64Text(int(channel_profile.payload_bytes))
    return spaces.Text(max_length=channel_profile.max_chars, min_length=0,
                       charset=channel_profile.charset)


def _box(shape: tuple[int, ...], low: float = -np.inf, high: float = np.inf) -> spaces.Box:
    return spaces.Box(low=low, high=high, shape=shape, dtype=np.float32)


def dict_action_space(field: FieldSpec, command_low: np.ndarray, command_high: np.ndarray,
                      channel_profile: Any) -> spaces.Dict:
    """walk (vx, vy, vturn), kick (power, direction), beam (x, y, rot), beam_request, say."""
    beam_low, beam_high = beam_bounds(field.half_length, field.half_width)
    return spaces.Dict({
        "walk": spaces.Box(np.asarray(command_low, np.float32), np.asarray(command_high, np.float32),
                           dtype=np.float32),
        "kick": spaces.Box(np.array(KICK_LOW, np.float32), np.array(KICK_HIGH, np.float32),
                           dtype=np.float32),
        "beam": spaces.Box(np.array(beam_low, np.float32), np.array(beam_high, np.float32),
                           dtype=np.float32),
        "beam_request": spaces.Discrete(2),
        "say": say_space(channel_profile),
    })


def box_action_space() -> spaces.Box:
    """Flat action in [-1, 1]^9 (``teamenv.box_layout.ACTION_COLUMNS``)."""
    return spaces.Box(-1.0, 1.0, shape=(ACTION_SIZE,), dtype=np.float32)


def _layout_dict_space(layout: ObservationLayout, channel_profile: Any) -> spaces.Dict:
    """The Dict form of ``layout``'s observation: its parts (``play_mode`` an int) and the
    heard texts."""
    parts: dict[str, spaces.Space] = {}
    for key, shape in layout.parts:
        parts[key] = spaces.Discrete(N_PLAY_MODES) if key == "play_mode" else _box(shape)
    parts["heard_text"] = spaces.Tuple([say_space(channel_profile)] * layout.heard_slots)
    return spaces.Dict(parts)


def dict_observation_space(team_size: int, heard_slots: int, channel_profile: Any) -> spaces.Dict:
    """The Dict form of a ``state`` observation (``teamenv.box_layout.StateLayout``)."""
    return _layout_dict_space(StateLayout(team_size, heard_slots), channel_profile)


def box_observation_space(team_size: int, heard_slots: int) -> spaces.Box:
    return _box((StateLayout(team_size, heard_slots).size,))


def vision_dict_observation_space(layout: VisionLayout, channel_profile: Any) -> spaces.Dict:
    """The Dict form of a ``vision`` observation (``teamenv.box_layout.VisionLayout``)."""
    return _layout_dict_space(layout, channel_profile)


def vision_box_observation_space(layout: VisionLayout) -> spaces.Box:
    """The flat (Box) form of a ``vision`` observation, ``layout.size`` float32 values."""
    return _box((layout.size,))


def state_space(size: int) -> spaces.Box:
    return _box((size,))
