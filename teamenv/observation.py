"""Helpers for reading a Dict observation: absolute team-frame positions from egocentric ones."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

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


def _rotate(points: np.ndarray, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * points[..., 0] - s * points[..., 1],
                     s * points[..., 0] + c * points[..., 1]], axis=-1)


def team_frame(obs: Mapping[str, Any]) -> TeamView:
    """Convert a Dict-form ``state`` observation to absolute team-frame positions."""
    me = np.asarray(obs["self"], dtype=float)
    pos, heading = me[:2], float(me[2])
    ball = np.asarray(obs["ball"], dtype=float)
    mates = np.asarray(obs["teammates"], dtype=float)
    opps = np.asarray(obs["opponents"], dtype=float)
    game = np.asarray(obs["game"], dtype=float)
    return TeamView(
        position=pos.copy(), heading=heading, velocity=me[3:5].copy(), fallen=bool(me[6] > 0.5),
        ball=pos + _rotate(ball[:2], heading), ball_velocity=_rotate(ball[2:4], heading),
        teammates=pos + _rotate(mates[:, :2], heading), teammates_present=mates[:, 4] > 0.5,
        teammates_fallen=mates[:, 3] > 0.5,
        opponents=pos + _rotate(opps[:, :2], heading), opponents_present=opps[:, 4] > 0.5,
        opponents_fallen=opps[:, 3] > 0.5,
        play_mode=PlayMode(int(obs["play_mode"])), time_s=float(game[0]), half=int(game[1]),
        score=(int(game[2]), int(game[3])),
    )
