"""Pitch geometry the statistics share: thirds, where a kick crosses the goal line, the shot
cone (metres, radians, world frame; ``sign`` +1 for a side attacking +x)."""

from __future__ import annotations

import math

import numpy as np

THIRDS = ("defensive", "middle", "attacking")


def third_index(x: np.ndarray | float, sign: np.ndarray | float,
                half_length: float) -> np.ndarray:
    """0 (defensive), 1 (middle) or 2 (attacking) third of ``x`` for a side attacking towards
    ``sign``; the thirds split the pitch's length in three equal parts."""
    u = np.asarray(x, dtype=float) * sign
    edge = half_length / 3.0
    return np.where(u < -edge, 0, np.where(u > edge, 2, 1))


def goal_line_crossing(start: tuple[float, float], direction: float, sign: float,
                       half_length: float) -> tuple[float, float] | None:
    """(distance along ``direction``, y) where a ball going ``direction`` from ``start``
    crosses the goal line at ``sign * half_length``; None when it moves away from it."""
    c = math.cos(direction)
    if c * sign <= 1e-9:
        return None
    t = (sign * half_length - start[0]) / c
    if t < 0:
        return None
    return t, start[1] + t * math.sin(direction)


def goal_distance_angle(start: tuple[float, float], sign: float, half_length: float,
                        half_goal_width: float) -> tuple[float, float]:
    """(distance to the goal's centre, opening angle between the posts) seen from ``start``
    by a side attacking towards ``sign``: metres, radians in [0, pi]."""
    gx = sign * half_length
    dx, dy = gx - start[0], -start[1]
    distance = math.hypot(dx, dy)
    a1 = math.atan2(half_goal_width - start[1], dx * sign)
    a2 = math.atan2(-half_goal_width - start[1], dx * sign)
    return distance, abs(a1 - a2)


def in_shot_cone(start: tuple[float, float], points: np.ndarray, sign: float,
                 half_length: float, half_goal_width: float) -> np.ndarray:
    """Which ``points`` (k, 2) lie inside the triangle from ``start`` to the two posts of the
    goal a side attacking towards ``sign`` shoots at (the players who can block a shot)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    gx = sign * half_length
    a = np.asarray(start, dtype=float)
    b = np.array([gx, half_goal_width])
    c = np.array([gx, -half_goal_width])

    def cross(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
        return (q[0] - p[0]) * (r[:, 1] - p[1]) - (q[1] - p[1]) * (r[:, 0] - p[0])

    d1, d2, d3 = cross(a, b, pts), cross(b, c, pts), cross(c, a, pts)
    neg = (d1 < 0) | (d2 < 0) | (d3 < 0)
    pos = (d1 > 0) | (d2 > 0) | (d3 > 0)
    return ~(neg & pos)
