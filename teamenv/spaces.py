"""Gymnasium spaces of the env: Dict and flat-Box forms of actions and observations."""

from __future__ import annotations

import math

import numpy as np
from gymnasium import spaces

from teamenv.actions import BOX_SIZE
from teamenv.field import FieldSpec
from teamenv.sim.perception import (
    BALL_DIM, GAME_DIM, HEARD_DIM, N_PLAY_MODES, PLAYER_DIM, SELF_DIM, flat_observation_size,
)


def _box(shape: tuple[int, ...], low: float = -np.inf, high: float = np.inf) -> spaces.Box:
    return spaces.Box(low=low, high=high, shape=shape, dtype=np.float32)


def dict_action_space(field: FieldSpec, command_low: np.ndarray, command_high: np.ndarray,
                      max_chars: int, charset: str) -> spaces.Dict:
    """walk (vx, vy, vturn), kick (power, direction), beam (x, y, rot), beam_request, say."""
    return spaces.Dict({
        "walk": spaces.Box(np.asarray(command_low, np.float32), np.asarray(command_high, np.float32),
                           dtype=np.float32),
        "kick": spaces.Box(np.array([0.0, -math.pi], np.float32),
                           np.array([1.0, math.pi], np.float32), dtype=np.float32),
        "beam": spaces.Box(np.array([-field.half_length, -field.half_width, -math.pi], np.float32),
                           np.array([0.0, field.half_width, math.pi], np.float32), dtype=np.float32),
        "beam_request": spaces.Discrete(2),
        "say": spaces.Text(max_length=max_chars, min_length=0, charset=charset),
    })


def box_action_space() -> spaces.Box:
    """Flat action in [-1, 1]^9 (see the env docstring for the layout)."""
    return spaces.Box(-1.0, 1.0, shape=(BOX_SIZE,), dtype=np.float32)


def dict_observation_space(team_size: int, heard_slots: int, max_chars: int,
                           charset: str) -> spaces.Dict:
    text = spaces.Text(max_length=max_chars, min_length=0, charset=charset)
    return spaces.Dict({
        "self": _box((SELF_DIM,)),
        "ball": _box((BALL_DIM,)),
        "teammates": _box((team_size, PLAYER_DIM)),
        "opponents": _box((team_size, PLAYER_DIM)),
        "play_mode": spaces.Discrete(N_PLAY_MODES),
        "game": _box((GAME_DIM,)),
        "heard_text": spaces.Tuple([text] * heard_slots),
        "heard": _box((heard_slots, HEARD_DIM)),
    })


def box_observation_space(team_size: int, heard_slots: int) -> spaces.Box:
    return _box((flat_observation_size(team_size, heard_slots),))


def state_space(size: int) -> spaces.Box:
    return _box((size,))
