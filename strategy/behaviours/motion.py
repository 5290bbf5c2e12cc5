"""Motion behaviours: walk to a point around other players, hold a position, face the ball,
search for it, beam, and keep out of a circle (the referee's distance at the other side's set plays)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

import portable_math as pm
from strategy.behaviours.control import ControlRequest
from strategy.behaviours.skills import Skills
from strategy.behaviours.walk_batch import WalkGoal
from strategy.geometry import wrap_angle
from strategy.perception.worldmodel import WorldModel

_NO_PLAYERS = np.zeros((0, 2))

KEEP_OFF_MARGIN_M = 0.2
"""A walker stops this far beyond body contact (two body radii) from a teammate that already
holds its target."""


def keep_off_teammates(wm: WorldModel, target: NDArray[np.float64],
                       clearance: float) -> NDArray[np.float64]:
    """``target``, or, when a teammate that is nearer to it than this agent stands within
    ``clearance`` of it, the point ``clearance`` from that teammate on the way in: the
    teammate that got there first keeps the spot and the other stops beside it instead of
    walking into it (two teammates sent to one spot meet there and may knock each other
    over)."""
    mates = wm.teammates_present.copy()
    mates[wm.me] = False
    if not mates.any():
        return target
    rows = wm.teammates[mates]
    gap = np.hypot(rows[:, 0] - target[0], rows[:, 1] - target[1])
    mine = math.hypot(wm.position[0] - target[0], wm.position[1] - target[1])
    holding = (gap < clearance) & (gap < mine)
    if not holding.any():
        return target
    occupant = rows[int(np.argmin(np.where(holding, gap, np.inf)))]
    away = target - occupant
    if math.hypot(away[0], away[1]) < 1e-6:  # the target is the teammate: stop on our side
        away = wm.position - occupant
    norm = math.hypot(away[0], away[1])
    return occupant + away * (clearance / norm) if norm > 1e-9 else target


def go_to(wm: WorldModel, target: ArrayLike, skills: Skills, face: ArrayLike | None = None,
          speed: float | None = None, avoid: bool = True,
          behaviour: str = "go_to") -> ControlRequest:
    """Walk to ``target`` (team frame), around the other players when ``avoid`` (potential
    field; then also stopping beside a teammate that already holds the target,
    ``keep_off_teammates``), turning to face ``face`` near the target. The walk command is
    computed when first read, or with the team's (``resolve_walks``)."""
    goal_point = np.asarray(target, dtype=np.float64)
    if avoid:
        goal_point = keep_off_teammates(wm, goal_point,
                                        2.0 * skills.body.body_radius + KEEP_OFF_MARGIN_M)
    goal = WalkGoal(wm.position, wm.heading, goal_point,
                    *wm.obstacle_rows() if avoid else (_NO_PLAYERS, None),
                    face=None if face is None else np.asarray(face, dtype=np.float64),
                    speed=speed, params=skills.navigation)
    return ControlRequest.walking(goal, behaviour)


def face_ball(wm: WorldModel, skills: Skills) -> ControlRequest:
    """Stand and turn towards the ball."""
    error = wrap_angle(math.atan2(wm.ball[1] - wm.position[1], wm.ball[0] - wm.position[0])
                 - wm.heading)
    return ControlRequest(walk=np.array([0.0, 0.0, skills.navigation.turn_gain * error]),
                          behaviour="face_ball")


def hold_position(wm: WorldModel, target: ArrayLike, skills: Skills,
                  behaviour: str = "hold_position") -> ControlRequest:
    """Go to a formation (or marking) position and face the ball there."""
    t = np.asarray(target, dtype=np.float64)
    if wm.distance(t) < skills.navigation.arrive_m * 2:
        request = face_ball(wm, skills)
        return ControlRequest(walk=request.walk, behaviour=behaviour)
    return go_to(wm, t, skills, face=wm.ball, behaviour=behaviour)


def search_ball(wm: WorldModel, skills: Skills) -> ControlRequest:
    """Turn on the spot to bring the ball (and landmarks) into the view cone (``vision``
    mode, when the agent has no idea where the ball is)."""
    del wm
    return ControlRequest(walk=np.array([0.0, 0.0, skills.navigation.search_turn]),
                          behaviour="search_ball")


def beam_to(pose: ArrayLike) -> ControlRequest:
    """Ask to be beamed to ``pose`` = (x, y, rotation) in the team frame (own half)."""
    x, y, rot = (float(v) for v in pose)
    return ControlRequest(beam=(x, y, rot), behaviour="beam")


def keep_clear(target: ArrayLike, center: ArrayLike, radius: float) -> NDArray[np.float64]:
    """``target`` moved radially out of the circle (``center``, ``radius``) if inside it."""
    t = np.asarray(target, dtype=np.float64)
    c = np.asarray(center, dtype=np.float64)
    d = t - c
    dist = math.hypot(d[0], d[1])
    if dist >= radius:
        return t
    if dist < 1e-9:
        d, dist = np.array([-1.0, 0.0]), 1.0  # exactly on the spot: towards our goal
    return c + d * (radius / dist)


def detour(position: ArrayLike, target: ArrayLike, center: ArrayLike,
           radius: float, margin: float = 0.3) -> NDArray[np.float64]:
    """A waypoint that takes a walk from ``position`` to ``target`` around the circle
    (``center``, ``radius``): ``target`` itself when the straight path does not enter it,
    else the tangent point of the circle of ``radius + margin`` on the target's side (the
    straight walk to a tangent point stays outside that circle)."""
    p = np.asarray(position, dtype=np.float64)
    t = np.asarray(target, dtype=np.float64)
    c = np.asarray(center, dtype=np.float64)
    seg = t - p
    length2 = float(pm.matmul(seg, seg))
    if length2 < 1e-12:
        return keep_clear(t, c, radius)
    s = min(1.0, max(0.0, float(pm.matmul(c - p, seg)) / length2))
    gap = p + s * seg - c
    if math.hypot(gap[0], gap[1]) >= radius:
        return t
    outer = radius + margin
    rel = p - c
    rp = math.hypot(rel[0], rel[1])
    if rp <= outer * 1.001:  # inside or on the ring: step straight out first
        if rp < 1e-9:
            rel, rp = np.array([-1.0, 0.0]), 1.0
        return c + rel * ((outer + 0.1) / rp)
    a_p = math.atan2(rel[1], rel[0])
    a_t = math.atan2(t[1] - c[1], t[0] - c[0])
    turn = wrap_angle(a_t - a_p)
    side = 1.0 if turn > 0 or (turn == 0 and rel[0] * seg[1] - rel[1] * seg[0] <= 0) else -1.0
    angle = a_p + side * math.acos(outer / rp)
    return c + outer * np.array([math.cos(angle), math.sin(angle)])
