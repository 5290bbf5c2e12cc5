"""Names of the slots of the flat (Box) action and observation vectors, in vector order.

``observation_slot_names(env)[k]`` names entry ``k`` of the env's Box observation (state or
vision mode), ``action_slot_names()[k]`` entry ``k`` of the Box action, e.g. ``"self.x"``,
``"ball.rel_x"``, ``"teammate_2.rel_y"``, ``"landmark_flag_own_left.distance"``,
``"play_mode.PlayOn"``, ``"heard_0.direction"``. A name is ``part.component`` where ``part`` is
the Dict form's key (one row of it for tables: players by uniform number, landmarks by name,
lines and heard messages by index) and ``component`` that row's column: the columns and the
order of the parts are ``teamenv.box_layout``'s (tests/teamenv/test_box_slots.py checks each
name against the value found at its place).
"""

from __future__ import annotations

from typing import Any

from teamenv.box_layout import (
    ACTION_COLUMNS,
    BALL_COLUMNS,
    BODY_COLUMNS,
    COUNTS_COLUMNS,
    GAME_COLUMNS,
    GYRO_COLUMNS,
    HEARD_COLUMNS,
    LINE_COLUMNS,
    ODOMETRY_COLUMNS,
    PLAY_MODE_COLUMNS,
    PLAYER_COLUMNS,
    SELF_COLUMNS,
    SIGHTING_COLUMNS,
    VISION_COLUMNS,
    StateLayout,
    VisionLayout,
)
from teamenv.landmarks import landmarks


def _rows(prefix: str, labels: Any, columns: tuple[str, ...]) -> list[str]:
    return [f"{prefix}{label}.{column}" for label in labels for column in columns]


def _players(team_size: int, columns: tuple[str, ...]) -> list[str]:
    """Teammates then opponents, each by uniform number 1..team_size (own row included)."""
    uniforms = range(1, team_size + 1)
    return _rows("teammate_", uniforms, columns) + _rows("opponent_", uniforms, columns)


def _common_tail(heard_slots: int) -> list[str]:
    """Play-mode one-hot (team-relative: ``_Left`` is the own team), game, heard slots."""
    return ([f"play_mode.{mode}" for mode in PLAY_MODE_COLUMNS]
            + [f"game.{column}" for column in GAME_COLUMNS]
            + _rows("heard_", range(heard_slots), HEARD_COLUMNS))


def action_slot_names() -> tuple[str, ...]:
    """The 9 entries of the Box action, each in [-1, 1] (see the README's Box form)."""
    return ACTION_COLUMNS


def state_slot_names(team_size: int, heard_slots: int) -> tuple[str, ...]:
    """The Box observation of ``state`` mode: self, ball, teammates, opponents, play mode,
    game, heard."""
    names = ([f"self.{column}" for column in SELF_COLUMNS]
             + [f"ball.{column}" for column in BALL_COLUMNS]
             + _players(team_size, PLAYER_COLUMNS) + _common_tail(heard_slots))
    assert len(names) == StateLayout(team_size, heard_slots).size
    return tuple(names)


def vision_slot_names(layout: VisionLayout, landmark_names: tuple[str, ...]) -> tuple[str, ...]:
    """The Box observation of ``vision`` mode, in ``layout.parts`` order; ``landmark_names``
    are the rows of ``teamenv.landmarks.landmarks(field, kind)``."""
    if len(landmark_names) != layout.n_landmarks:
        raise ValueError(f"{len(landmark_names)} landmark names for {layout.n_landmarks} rows")
    by_part = {
        "landmarks": _rows("landmark_", landmark_names, SIGHTING_COLUMNS),
        "ball": [f"ball.{column}" for column in SIGHTING_COLUMNS],
        "teammates": _rows("teammate_", range(1, layout.team_size + 1), SIGHTING_COLUMNS),
        "opponents": _rows("opponent_", range(1, layout.team_size + 1), SIGHTING_COLUMNS),
        "lines": _rows("line_", range(layout.n_lines), LINE_COLUMNS),
        "vision": [f"vision.{column}" for column in VISION_COLUMNS],
        "counts": [f"counts.{column}" for column in COUNTS_COLUMNS],
        "odometry": [f"odometry.{column}" for column in ODOMETRY_COLUMNS],
        "gyro": [f"gyro.{column}" for column in GYRO_COLUMNS],
        "body": [f"body.{column}" for column in BODY_COLUMNS],
        "play_mode": [f"play_mode.{mode}" for mode in PLAY_MODE_COLUMNS],
        "game": [f"game.{column}" for column in GAME_COLUMNS],
        "heard": _rows("heard_", range(layout.heard_slots), HEARD_COLUMNS),
    }
    names = [name for key, _shape in layout.parts for name in by_part[key]]
    assert len(names) == layout.size
    return tuple(names)


def observation_slot_names(env: Any, agent: str | None = None) -> tuple[str, ...]:
    """Names of the entries of ``env``'s Box observation (``observation_format="box"``; the
    names are those of the same layout for a Dict env), the same for every agent.

    ``env``: a ``teamenv.parallel_env`` or ``teamenv.env`` (AEC); ``agent``, if given, must be
    one of its possible agents (``ActionError`` otherwise)."""
    env = env.unwrapped
    if agent is not None:
        env.observation_space(agent)  # raises ActionError for an unknown agent
    heard_slots = env.sim.heard_slots
    if not env.obs_mode.is_vision:
        return state_slot_names(env.team_size, heard_slots)
    return vision_slot_names(env.sim.vision.layout,
                             landmarks(env.field, env.obs_mode.perception.landmark_kind).names)
