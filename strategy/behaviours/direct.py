"""Direct behaviours: walk straight to a point, kick towards one. They return the raw walk
command and kick arrays of an action (no navigation around players, no ``ControlRequest``),
which is all the simple built-in teams (``chaser``, ``static``) need."""

from __future__ import annotations

import math

import numpy as np

from strategy.geometry import to_body, wrap_angle
from strategy.perception.worldmodel import WorldModel


def walk_to(view: WorldModel, target: np.ndarray, low: tuple, high: tuple,
            face: np.ndarray | None = None, speed: float = 1.0) -> np.ndarray:
    """Body-frame walk command (vx, vy, vturn) towards ``target`` (team frame, metres),
    turning to face ``face`` (defaults to the direction of travel), clipped to [low, high]."""
    delta = np.asarray(target, dtype=float) - view.position
    dist = float(np.hypot(*delta))
    local = np.array(to_body(delta[0], delta[1], view.heading))
    look = delta if face is None else np.asarray(face, dtype=float) - view.position
    turn = wrap_angle(math.atan2(look[1], look[0]) - view.heading) if np.hypot(*look) > 0.05 else 0.0
    if dist < 0.05:
        return np.clip(np.array([0.0, 0.0, 1.5 * turn]), low, high)
    direction = local / dist
    scale = min(speed, 1.5 * dist)
    # Walk forward fast, sideways and backwards slowly, as the humanoid can.
    command = np.array([direction[0] * scale, direction[1] * scale * 0.4, 1.5 * turn])
    return np.clip(command, low, high)


def kick_toward(view: WorldModel, target: np.ndarray, power: float = 1.0) -> np.ndarray:
    """Kick (power, body-frame direction) sending the ball towards ``target`` (team frame)."""
    delta = np.asarray(target, dtype=float) - view.ball
    return np.array([power, wrap_angle(math.atan2(delta[1], delta[0]) - view.heading)])
