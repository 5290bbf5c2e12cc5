"""The flat (Box) layouts of one agent's action and observation: which entry means what.

The one place these facts are written down:

- the 9 entries of the Box action (``ACTION_COLUMNS``) and how each becomes a walk, kick and
  beam command (``decode_box_actions``), with the Dict action's kick and beam ranges;
- the parts of the Box observation in order, with their shapes and column names: ``state``
  mode (``StateLayout``) and ``vision`` mode (``VisionLayout``), ``play_mode`` a one-hot
  there (an int in the Dict form), ``heard_text`` only in the Dict form;
- the shared play-mode/game block both modes write (``play_mode_and_game_block``), a Dict
  observation's Box row (``flatten_observation``) and the Dict parts of Box rows
  (``ObservationLayout.dict_parts``).

Who reads it: ``teamenv.actions`` (Box actions -> commands), ``teamenv.sim.perception`` and
``teamenv.sim.vision`` (they write observation rows at these offsets), ``teamenv.spaces``,
``teamenv.slots`` (a name per entry), ``teamenv.policy_team`` (Dict observations -> Box rows
for a policy, its Box actions -> Dict actions) and the league bridge. The env's docstring
describes the same layout to users; ``tests/teamenv/test_box_slots.py`` checks every column
name against the value found there.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any, NamedTuple

import numpy as np

from teamenv.sim.playmode import PlayMode

# -- the Box action --------------------------------------------------------------------------
#: The Box action's entries, each in [-1, 1].
ACTION_COLUMNS = ("walk.vx", "walk.vy", "walk.vturn", "kick.power", "kick.direction",
                  "beam_request", "beam.x", "beam.y", "beam.rot")
ACTION_SIZE = len(ACTION_COLUMNS)
WALK = slice(0, 3)
KICK_POWER, KICK_DIRECTION, BEAM_REQUEST = 3, 4, 5
BEAM = slice(6, 9)

#: The Dict action's kick range (power, direction in rad, body frame); the Box maps onto it.
KICK_LOW = (0.0, -math.pi)
KICK_HIGH = (1.0, math.pi)


def beam_bounds(half_length: float, half_width: float) -> tuple[tuple[float, ...],
                                                                tuple[float, ...]]:
    """The Dict action's beam range (x, y, rot), team frame: the own half."""
    return (-half_length, -half_width, -math.pi), (0.0, half_width, math.pi)


@dataclass(frozen=True)
class BoxCommands:
    """Box actions decoded, one row per agent (float64; ``beam_request`` bool)."""

    walk: np.ndarray  # (n, 3) vx, vy (m/s), vturn (rad/s)
    kick_power: np.ndarray  # (n,) 0 = no kick
    kick_direction: np.ndarray  # (n,) rad
    beam_request: np.ndarray  # (n,)
    beam: np.ndarray  # (n, 3) x, y, rot


def decode_box_actions(box: np.ndarray, walk_low: Sequence[float], walk_high: Sequence[float],
                       half_length: float, half_width: float) -> BoxCommands:
    """Box actions ``box`` (n, 9), finite and in [-1, 1], as commands: each walk entry scaled
    to the command range (asymmetric: -1 is ``walk_low``, +1 ``walk_high``), kick power <= 0
    no kick, kick direction * pi, beam_request > 0 beams, beam x -1..1 -> -half_length..0,
    beam y * half_width, beam rot * pi."""
    low = np.asarray(walk_low, dtype=float)
    high = np.asarray(walk_high, dtype=float)
    walk = box[:, WALK]
    beam = np.empty((len(box), 3))
    beam[:, 0] = (box[:, BEAM.start] - 1.0) * 0.5 * half_length
    beam[:, 1] = box[:, BEAM.start + 1] * half_width
    beam[:, 2] = box[:, BEAM.start + 2] * math.pi
    return BoxCommands(walk=np.where(walk >= 0, walk * high, -walk * low),
                       kick_power=np.maximum(box[:, KICK_POWER], 0.0),
                       kick_direction=box[:, KICK_DIRECTION] * math.pi,
                       beam_request=box[:, BEAM_REQUEST] > 0.0, beam=beam)


# -- the Box observation ---------------------------------------------------------------------
SELF_COLUMNS = ("x", "y", "heading", "vx", "vy", "omega", "fallen")
BALL_COLUMNS = ("rel_x", "rel_y", "rel_vx", "rel_vy")
PLAYER_COLUMNS = ("rel_x", "rel_y", "rel_heading", "fallen", "present")
GAME_COLUMNS = ("time_s", "half", "own_score", "opponent_score")
HEARD_COLUMNS = ("present", "from_self", "from_teammate", "direction")
SIGHTING_COLUMNS = ("present", "distance", "azimuth", "elevation")
LINE_COLUMNS = ("present", "distance_1", "azimuth_1", "elevation_1", "distance_2", "azimuth_2",
                "elevation_2")
VISION_COLUMNS = ("fresh", "cycles_since_update")
COUNTS_COLUMNS = ("landmarks", "players", "lines", "ball")
ODOMETRY_COLUMNS = ("dx", "dy", "dpsi")
GYRO_COLUMNS = ("dpsi",)
BODY_COLUMNS = ("fallen", "head_pan")
#: The play-mode one-hot's columns (team-relative: ``_Left`` is the own team).
PLAY_MODE_COLUMNS = tuple(mode.name for mode in PlayMode)

SELF_DIM, BALL_DIM, PLAYER_DIM = len(SELF_COLUMNS), len(BALL_COLUMNS), len(PLAYER_COLUMNS)
GAME_DIM, HEARD_DIM = len(GAME_COLUMNS), len(HEARD_COLUMNS)
SIGHTING_DIM, LINE_DIM = len(SIGHTING_COLUMNS), len(LINE_COLUMNS)
N_PLAY_MODES = len(PLAY_MODE_COLUMNS)


class ObservationLayout:
    """Where each part lies in one agent's Box observation; ``parts`` lists ``(key, shape)``
    in Box order (a subclass says which)."""

    @property
    def parts(self) -> tuple[tuple[str, tuple[int, ...]], ...]:
        raise NotImplementedError

    @cached_property
    def offsets(self) -> dict[str, tuple[int, int]]:
        """``key -> (start, stop)`` in the flat vector."""
        out, at = {}, 0
        for key, shape in self.parts:
            size = math.prod(shape)
            out[key] = (at, at + size)
            at += size
        return out

    @property
    def size(self) -> int:
        return sum(math.prod(shape) for _, shape in self.parts)

    def dict_parts(self, rows: np.ndarray) -> dict[str, np.ndarray]:
        """The Dict form's arrays of Box ``rows`` (n, size): ``key -> (n, *shape)`` views, in
        Box order, for every part but ``play_mode`` (an int in the Dict form)."""
        out, n = {}, len(rows)
        for key, shape in self.parts:
            if key != "play_mode":
                start, stop = self.offsets[key]
                out[key] = rows[:, start:stop].reshape((n, *shape))
        return out


@dataclass(frozen=True)
class StateLayout(ObservationLayout):
    """The ``state`` mode's Box observation: self, ball, teammates, opponents, play mode
    (one-hot), game, heard."""

    team_size: int
    heard_slots: int

    @property
    def parts(self) -> tuple[tuple[str, tuple[int, ...]], ...]:
        n = self.team_size
        return (
            ("self", (SELF_DIM,)),
            ("ball", (BALL_DIM,)),
            ("teammates", (n, PLAYER_DIM)),
            ("opponents", (n, PLAYER_DIM)),
            ("play_mode", (N_PLAY_MODES,)),
            ("game", (GAME_DIM,)),
            ("heard", (self.heard_slots, HEARD_DIM)),
        )


@dataclass(frozen=True)
class VisionLayout(ObservationLayout):
    """The ``vision`` mode's Box observation (``teamenv.sim.vision.vision_layout`` sizes it for
    a field and camera): landmarks, ball, teammates, opponents, lines, vision, counts,
    odometry, gyro, body, play mode (one-hot), game, heard."""

    n_landmarks: int
    team_size: int
    n_lines: int
    heard_slots: int

    @property
    def parts(self) -> tuple[tuple[str, tuple[int, ...]], ...]:
        n = self.team_size
        return (
            ("landmarks", (self.n_landmarks, SIGHTING_DIM)),
            ("ball", (SIGHTING_DIM,)),
            ("teammates", (n, SIGHTING_DIM)),
            ("opponents", (n, SIGHTING_DIM)),
            ("lines", (self.n_lines, LINE_DIM)),
            ("vision", (len(VISION_COLUMNS),)),
            ("counts", (len(COUNTS_COLUMNS),)),
            ("odometry", (len(ODOMETRY_COLUMNS),)),
            ("gyro", (len(GYRO_COLUMNS),)),
            ("body", (len(BODY_COLUMNS),)),
            ("play_mode", (N_PLAY_MODES,)),
            ("game", (GAME_DIM,)),
            ("heard", (self.heard_slots, HEARD_DIM)),
        )


#: The parts of each mode in Box order (the shapes aside).
STATE_PARTS = tuple(key for key, _ in StateLayout(0, 0).parts)
VISION_PARTS = tuple(key for key, _ in VisionLayout(0, 0, 0, 0).parts)


def play_mode_and_game_block(team_of: np.ndarray, modes: Sequence[int], half: int,
                             score: Sequence[int]) -> np.ndarray:
    """Every agent's play-mode one-hot and game part, side by side (n, N_PLAY_MODES +
    GAME_DIM): ``team_of`` (n,) 0 left / 1 right, ``modes`` the team-relative mode of each
    team; the game time (the game part's first column) is left 0 for the caller, it changes
    every cycle."""
    n = len(team_of)
    block = np.zeros((n, N_PLAY_MODES + GAME_DIM))
    block[np.arange(n), np.take(modes, team_of)] = 1.0
    g = N_PLAY_MODES
    own_score = np.asarray(score, dtype=float)
    block[:, g + 1] = half
    block[:, g + 2] = own_score[team_of]
    block[:, g + 3] = own_score[1 - team_of]
    return block


def flatten_observation(obs: Mapping[str, Any]) -> np.ndarray:
    """One Dict-form observation as the env's Box row (float32): its numeric parts in Box
    order, ``play_mode`` one-hot, ``heard_text`` left out (state or vision mode)."""
    parts = []
    for key in STATE_PARTS if "self" in obs else VISION_PARTS:
        value = obs[key]
        if key == "play_mode":
            one_hot = np.zeros(N_PLAY_MODES, dtype=np.float32)
            one_hot[int(value)] = 1.0
            parts.append(one_hot)
        else:
            parts.append(np.asarray(value, dtype=np.float32).ravel())
    return np.concatenate(parts)


class StackedState(NamedTuple):
    """Several agents' ``state`` observations as rows (``ObservationRows.stacked``).

    Attributes:
        values: (k, width) float32, each agent's flat observation (``StateLayout``).
        heard_texts: per agent, its ``heard_text`` tuple.
        play_modes: per agent, its ``play_mode`` (int, its team's view of the mode).
        spans: where ``ball``, the players, ``play_mode``, ``game`` and ``heard`` start in
            a row (``self`` starts at 0).
        team_size: players per team (teammates, then opponents, in the player block).
        heard_shape: (slots, columns) of ``heard``.
    """

    values: np.ndarray
    heard_texts: list
    play_modes: list
    spans: tuple
    team_size: int
    heard_shape: tuple
