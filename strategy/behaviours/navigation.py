"""Potential-field navigation (ITAndroids TDP 2016, seed 001 eq. 6-10) and walk commands.

Every object on the pitch puts a potential at the walker's position ``p``:

* the target attracts, ``V = k_att / d`` with ``k_att > 0`` (eq. 7);
* each obstacle (another player) repels, ``V = k_rep / d**3`` with ``k_rep < 0`` (eq. 6);

where ``d`` is the distance between the object and ``p``. Each potential is split along the
unit vector from ``p`` to the object (eq. 8-9: ``V_x = (x0 - x) / d * V``; with the sign
convention above an attractive potential points at its object and a repulsive one away from
it), the components are summed over all objects, and the walking direction is
``theta = atan2(V_y, V_x)`` (eq. 10). Obstacles farther than ``influence_m`` (or beyond the
target) are ignored, so open ground is crossed in a straight line.

``walk_command`` turns a direction and a distance into a body-frame (vx, vy, vturn) command for
a humanoid: it walks forward and turns, side-steps only near the target, and turns on the
spot when the direction is far behind it (a real walk cannot go fast sideways or backwards).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from paramkit.checks import check_fields, in_range, non_negative, positive
from strategy.geometry import to_body, wrap_angle
from teamenv.capabilities import BodyCapabilities
from teamenv.errors import ConfigError


@dataclass(frozen=True)
class NavigationParams:
    """Gains of the potential field and of the walk controller.

    Attributes:
        k_attract: attraction constant of the target (eq. 7), > 0.
        k_repulse: repulsion constant of an obstacle (eq. 6), < 0 (m^2 relative to k_attract).
        influence_m: obstacles farther than this from the walker are ignored, metres.
        max_speed: forward speed asked for far from the target, m/s.
        slow_down_m: the speed falls linearly to 0 within this distance of the target, metres.
        arrive_m: closer than this the walker stands (only turns to face), metres.
        turn_gain: vturn = turn_gain * heading error, 1/s.
        turn_in_place_rad: a heading error above this turns on the spot first, radians.
        omni_m: within this distance of the target the walker side-steps and walks backwards
            instead of turning towards the target (a humanoid side-steps slowly), metres.
        min_speed: the slowest approach asked for outside ``arrive_m`` (the walk tracks very
            small commands poorly), m/s.
        search_turn: turning rate while searching for the ball (``vision`` mode), rad/s.
        side_step_left, side_step_right: whether the walker side-steps to that side within
            ``omni_m``; False: a target more than 30 degrees off the body's axis on that side
            is walked to as a far one is (turn towards it, walk forward). A team may set them
            from its body (``for_body``; ``full``: ``nav_side_steps="body"``): a humanoid
            whose walk barely moves to one side stands still when asked for that side-step.
    """

    k_attract: float = field(default=1.0, metadata=positive())
    k_repulse: float = field(default=-0.35, metadata=in_range(high=0.0, high_open=True))
    influence_m: float = field(default=1.6, metadata=non_negative())
    max_speed: float = field(default=1.2, metadata=non_negative())
    slow_down_m: float = field(default=0.8, metadata=non_negative())
    arrive_m: float = field(default=0.08, metadata=non_negative())
    turn_gain: float = field(default=2.0, metadata=non_negative())
    turn_in_place_rad: float = field(default=1.2, metadata=non_negative())
    omni_m: float = field(default=0.4, metadata=non_negative())
    min_speed: float = field(default=0.35, metadata=non_negative())
    search_turn: float = field(default=0.9, metadata=non_negative())
    side_step_left: bool = True
    side_step_right: bool = True

    def __post_init__(self) -> None:
        check_fields(self, ConfigError)

    def for_body(self, body: BodyCapabilities) -> NavigationParams:
        """These gains, side-stepping only to the sides where ``body`` (the locomotion
        profile's tracking table) walks at least ``MIN_SIDE_STEP_M_S`` when asked for its
        largest side-step."""
        left = body.side_speed(float(body.walk_high[1])) >= MIN_SIDE_STEP_M_S
        right = -body.side_speed(float(body.walk_low[1])) >= MIN_SIDE_STEP_M_S
        if (left, right) == (self.side_step_left, self.side_step_right):
            return self
        return replace(self, side_step_left=left, side_step_right=right)


#: a side-step slower than this (m/s) takes over 8 s for the ``omni_m`` zone: the body is
#: treated as unable to side-step that way (the league network's left: 0.006 m/s)
MIN_SIDE_STEP_M_S = 0.05
#: within ``omni_m``, a target on a side the body cannot side-step to is walked to as a far
#: one once it lies more than this far off the body's axis (sin 30 degrees of the distance)
SIDE_STEP_SHARE = 0.5


def field_vector(position: ArrayLike, target: ArrayLike, obstacles: ArrayLike,
                 params: NavigationParams) -> NDArray[np.float64]:
    """The summed potential vector (V_x, V_y) at ``position`` (eq. 6-9), team frame.

    Args:
        position: (2,) the walker, metres.
        target: (2,) where it wants to go, metres.
        obstacles: (M, 2) positions of the players to walk around, metres (M may be 0).
        params: the gains.
    """
    p = np.asarray(position, dtype=np.float64)
    t = np.asarray(target, dtype=np.float64)
    to_target = t - p
    d_target = math.hypot(to_target[0], to_target[1])
    if d_target < 1e-9:
        return np.zeros(2)
    # eq. 7 and 8-9: k/d along the unit vector to the target
    vector = to_target * (params.k_attract / d_target / d_target)
    obs = np.asarray(obstacles, dtype=np.float64).reshape(-1, 2)
    if len(obs):
        rel = obs - p
        d = np.sqrt(rel[:, 0] * rel[:, 0] + rel[:, 1] * rel[:, 1])
        near = (d < params.influence_m) & (d > 1e-6) & (d < d_target + 0.3)
        if near.any():
            dn = d[near]
            # eq. 6 and 8-9: k/d^3 (k < 0) along the unit vector to the obstacle = away from it
            vector = vector + ((params.k_repulse / dn**4)[:, None] * rel[near]).sum(axis=0)
    return vector


def direction_to(position: ArrayLike, target: ArrayLike, obstacles: ArrayLike,
                 params: NavigationParams) -> float:
    """The walking direction theta (eq. 10), radians in the team frame."""
    v = field_vector(position, target, obstacles, params)
    t = np.asarray(target, dtype=np.float64) - np.asarray(position, dtype=np.float64)
    straight = math.atan2(t[1], t[0])
    if not v.any():
        return straight
    theta = math.atan2(v[1], v[0])
    # A potential field has local minima: obstacles squarely ahead cancel the attraction and
    # the walker stalls. When the field points more than 60 degrees off the target, go round
    # (60 degrees to the side the field leans to, left on an exact tie).
    error = wrap_angle(theta - straight)
    if abs(error) > math.pi / 3:
        return straight + math.copysign(math.pi / 3, error if error != 0 else 1.0)
    return theta


def walk_command(position: ArrayLike, heading: float, target: ArrayLike,
                 obstacles: ArrayLike, params: NavigationParams,
                 face: ArrayLike | None = None, speed: float | None = None) -> NDArray[np.float64]:
    """Body-frame walk command (vx, vy, vturn) towards ``target`` around ``obstacles``.

    Far from the target the walker follows the potential field's direction, walking forward
    and turning; within ``params.omni_m`` it walks straight at the target in any direction
    while turning to face ``face`` (a point; default: keep walking heading). The caller clips
    the result to the command range.
    """
    command, _, v = approach(position, heading, target, params, face, speed)
    if command is not None:
        return command
    p = np.asarray(position, dtype=np.float64)
    t = np.asarray(target, dtype=np.float64)
    return walk_along(direction_to(p, t, obstacles, params), heading, v, params)


def approach(position: ArrayLike, heading: float, target: ArrayLike, params: NavigationParams,
             face: ArrayLike | None = None, speed: float | None = None
             ) -> tuple[NDArray[np.float64] | None, float, float]:
    """The part of ``walk_command`` that needs no obstacles: ``(command, distance, speed)``,
    where ``command`` is the walk when the walker has arrived (turn to face ``face``) or is
    within ``omni_m`` (walk straight at the target), else None (follow the potential field
    at ``speed``)."""
    p0, p1 = float(position[0]), float(position[1])
    dx, dy = float(target[0]) - p0, float(target[1]) - p1
    dist = math.hypot(dx, dy)
    top = params.max_speed if speed is None else speed
    face_angle = None
    if face is not None:
        fx, fy = float(face[0]) - p0, float(face[1]) - p1
        if fx * fx + fy * fy > 0.0025:
            face_angle = math.atan2(fy, fx)
    if dist < params.arrive_m:
        turn = 0.0 if face_angle is None else wrap_angle(face_angle - heading)
        return np.array([0.0, 0.0, params.turn_gain * turn]), dist, 0.0
    v = max(min(top, params.min_speed), top * min(1.0, dist / max(params.slow_down_m, 1e-9)))
    if dist < params.omni_m:
        local_x, local_y = to_body(dx, dy, heading)
        if (not params.side_step_left and local_y > SIDE_STEP_SHARE * dist) or (
                not params.side_step_right and -local_y > SIDE_STEP_SHARE * dist):
            return None, dist, v  # a side-step the body does not make: walk as if far
        turn = 0.0 if face_angle is None else wrap_angle(face_angle - heading)
        return (np.array([v * local_x / dist, v * local_y / dist, params.turn_gain * turn]),
                dist, v)
    return None, dist, v


def walk_along(theta: float, heading: float, speed: float,
               params: NavigationParams) -> NDArray[np.float64]:
    """The command that walks in team-frame direction ``theta`` at up to ``speed``: turn on
    the spot when it is more than ``turn_in_place_rad`` off the heading, else walk forward
    (slower the further off, a little side-step) while turning towards it."""
    error = wrap_angle(theta - heading)
    turn = params.turn_gain * error
    if abs(error) > params.turn_in_place_rad:
        return np.array([0.0, 0.0, turn])
    # Forward speed falls off with the heading error (cos), a little side-step helps.
    forward = speed * max(0.0, math.cos(error))
    side = speed * math.sin(error) * 0.3
    return np.array([forward, side, turn])
