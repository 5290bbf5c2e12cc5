"""Helpers for reading a Dict observation: absolute team-frame positions from egocentric ones."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from teamenv.sim.playmode import PlayMode


@dataclass(frozen=True)
class TeamView:
    """One agent's observation in its team frame (it attacks +x; metres, radians).

    ``teammates``/``opponents`` are (N, 2) positions with ``*_present``/``*_fallen`` masks;
    row k is uniform number k + 1. ``play_mode`` is team-relative (``_Left`` = own team).
    """

    position: np.ndarray
    heading: float
    velocity: np.ndarray
    fallen: bool
    ball: np.ndarray
    ball_velocity: np.ndarray
    teammates: np.ndarray
    teammates_present: np.ndarray
    teammates_fallen: np.ndarray
    opponents: np.ndarray
    opponents_present: np.ndarray
    opponents_fallen: np.ndarray
    play_mode: PlayMode
    time_s: float
    half: int
    score: tuple[int, int]


def _place(x: np.ndarray, y: np.ndarray, px: float, py: float, c: float, s: float) -> np.ndarray:
    """(N, 2) team-frame positions of body-frame offsets (x, y) seen from (px, py, heading)."""
    out = np.empty((x.shape[0], 2))
    out[:, 0] = c * x - s * y
    out[:, 1] = s * x + c * y
    out[:, 0] += px
    out[:, 1] += py
    return out


_new_view = object.__new__
_MODES = {int(m): m for m in PlayMode}


def play_mode_of(value: Any) -> PlayMode:
    """The ``PlayMode`` of an observation's ``play_mode`` entry (an int-like)."""
    try:
        return _MODES[int(value)]
    except KeyError:
        return PlayMode(int(value))  # raises the usual ValueError


def team_frame(obs: Mapping[str, Any]) -> TeamView:
    """Convert a Dict-form ``state`` observation to absolute team-frame positions."""
    # Scalar parts in Python floats and the (N, 2) parts with one numpy pass each: the same
    # IEEE operations as rotating with numpy, so the values are identical, only cheaper.
    me = obs["self"]
    me = me.tolist() if type(me) is np.ndarray else [float(v) for v in me]
    px, py, heading = me[0], me[1], me[2]
    c = float(np.cos(heading))
    s = float(np.sin(heading))
    ball = obs["ball"]
    bx, by, bvx, bvy = ball.tolist()[:4] if type(ball) is np.ndarray else \
        [float(v) for v in ball[:4]]
    # Teammates and opponents in one (2N, 5) float64 array, rotated in one pass.
    players = np.concatenate((obs["teammates"], obs["opponents"]), dtype=float)
    n = len(obs["teammates"])
    placed = _place(players[:, 0], players[:, 1], px, py, c, s)
    present = players[:, 4] > 0.5
    down = players[:, 3] > 0.5
    game = obs["game"]
    view = _new_view(TeamView)
    # A frozen dataclass: fill its instance dict directly (what __init__ would store).
    view.__dict__.update(
        position=np.array((px, py)), heading=heading, velocity=np.array((me[3], me[4])),
        fallen=me[6] > 0.5,
        ball=np.array((px + (c * bx - s * by), py + (s * bx + c * by))),
        ball_velocity=np.array((c * bvx - s * bvy, s * bvx + c * bvy)),
        teammates=placed[:n], teammates_present=present[:n], teammates_fallen=down[:n],
        opponents=placed[n:], opponents_present=present[n:], opponents_fallen=down[n:],
        play_mode=play_mode_of(obs["play_mode"]), time_s=float(game[0]), half=int(game[1]),
        score=(int(game[2]), int(game[3])),
    )
    return view
