"""The agent's small geometry: angle wrapping, body <-> team frames, and the ball's roll.

Where a rolling ball goes is the pitch's drag model solved in closed form: teamenv's ball slows by ``dv/dt = -linear_drag * v - rolling_decel`` (``PhysicsConfig``;
the team is told both numbers in its ``TeamContext``), so where it stops and when can be
computed instead of guessed. Players use it to run to where the ball will be, not where it is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

import portable_math as pm
from teamenv.config import PhysicsConfig

MAX_ROLL_S = 20.0
"""Horizon for a drag-free ball (both coefficients 0 never stops)."""


def wrap_angle(angle: float) -> float:
    """``angle`` wrapped to [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def wrap_angles(angles: ArrayLike) -> NDArray[np.float64]:
    """Elementwise ``wrap_angle`` of an array."""
    return (np.asarray(angles, dtype=np.float64) + np.pi) % (2.0 * np.pi) - np.pi


def to_body(dx: float, dy: float, heading: float) -> tuple[float, float]:
    """A team-frame offset (dx, dy) in the body frame of a player facing ``heading``."""
    c, s = math.cos(heading), math.sin(heading)
    return c * dx + s * dy, -s * dx + c * dy


def to_team(forward: float, left: float, heading: float) -> tuple[float, float]:
    """A body-frame offset (forward, left) in the team frame (the inverse of ``to_body``)."""
    c, s = math.cos(heading), math.sin(heading)
    return c * forward - s * left, s * forward + c * left


def body_points_to_team(points: NDArray[np.floating], x: float, y: float,
                        heading: float) -> NDArray[np.float64]:
    """(M, 2) team-frame positions of body-frame points (M, >=2: forward, left) seen from a
    player at (x, y) facing ``heading``."""
    c, s = math.cos(heading), math.sin(heading)
    f, left = points[:, 0], points[:, 1]
    return np.column_stack((x + c * f - s * left, y + s * f + c * left))


def bearing(dx: float, dy: float, heading: float) -> float:
    """The angle of the team-frame offset (dx, dy) seen from ``heading``, in [-pi, pi)."""
    return wrap_angle(math.atan2(dy, dx) - heading)


@dataclass(frozen=True)
class BallRoll:
    """The ball's rolling drag: ``linear_drag`` (1/s) and ``rolling_decel`` (m/s²)."""

    linear_drag: float = PhysicsConfig.ball_linear_drag  # the world's defaults, not copies
    rolling_decel: float = PhysicsConfig.ball_rolling_decel

    def stop_time(self, speed: float) -> float:
        """Seconds until a ball rolling at ``speed`` m/s stops."""
        a, c = self.linear_drag, self.rolling_decel
        if speed <= 0.0:
            return 0.0
        if a > 1e-9 and c > 1e-9:
            return min(MAX_ROLL_S, math.log1p(speed * a / c) / a)
        if c > 1e-9:
            return min(MAX_ROLL_S, speed / c)
        return MAX_ROLL_S

    def travel(self, speed: float, seconds: float | NDArray[np.float64]):
        """Distance rolled after ``seconds`` (scalar or array) from ``speed`` m/s."""
        t = np.minimum(np.asarray(seconds, dtype=np.float64), self.stop_time(speed))
        a, c = self.linear_drag, self.rolling_decel
        if a > 1e-9:
            v_inf = c / a
            return (speed + v_inf) * (1.0 - pm.exp(-a * t)) / a - v_inf * t
        return speed * t - 0.5 * c * t * t

    def positions(self, ball: NDArray[np.float64], velocity: NDArray[np.float64],
                  times: NDArray[np.float64]) -> NDArray[np.float64]:
        """(len(times), 2) ball positions at each time (seconds from now)."""
        speed = math.hypot(velocity[0], velocity[1])
        if speed < 1e-6:
            return np.broadcast_to(ball, (len(times), 2)).copy()
        direction = velocity / speed
        return ball + np.outer(self.travel(speed, times), direction)

    def advance(self, ball: NDArray[np.float64], velocity: NDArray[np.float64],
                seconds: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Where a ball at ``ball`` rolling with ``velocity`` is after ``seconds``, and its
        velocity then (a ``strategy.perception.ball_belief.RollModel``)."""
        speed = math.hypot(velocity[0], velocity[1])
        if speed < 1e-6:
            return np.array(ball, dtype=np.float64), np.zeros(2)
        t = min(float(seconds), self.stop_time(speed))
        a, c = self.linear_drag, self.rolling_decel
        later = (speed + c / a) * math.exp(-a * t) - c / a if a > 1e-9 else speed - c * t
        direction = velocity / speed
        return (ball + direction * float(self.travel(speed, t)),
                direction * max(0.0, later))

    def rest_point(self, ball: NDArray[np.float64],
                   velocity: NDArray[np.float64]) -> NDArray[np.float64]:
        """Where the ball stops (on a free pitch)."""
        return self.rest_points(np.asarray(ball)[None], np.asarray(velocity)[None])[0]

    def rest_points(self, balls: NDArray[np.float64],
                    velocities: NDArray[np.float64]) -> NDArray[np.float64]:
        """(A, 2) where each of the balls (A, 2) rolling with ``velocities`` (A, 2) stops, in
        one pass (each row the bits ``travel`` gives it alone: elementwise IEEE operations and
        ``portable_math``)."""
        balls = np.array(balls, dtype=np.float64)
        velocities = np.asarray(velocities, dtype=np.float64)
        speeds = [math.hypot(vx, vy) for vx, vy in velocities.tolist()]
        rolling = [k for k, speed in enumerate(speeds) if speed >= 1e-6]
        if rolling:
            speed = np.array([speeds[k] for k in rolling])
            t = np.array([self.stop_time(speeds[k]) for k in rolling])
            a, c = self.linear_drag, self.rolling_decel
            if a > 1e-9:
                v_inf = c / a
                travel = (speed + v_inf) * (1.0 - pm.exp(-a * t)) / a - v_inf * t
            else:
                travel = speed * t - 0.5 * c * t * t
            balls[rolling] += velocities[rolling] / speed[:, None] * travel[:, None]
        return balls
