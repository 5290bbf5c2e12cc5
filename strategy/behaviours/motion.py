"""Motion behaviours: walk to a point around other players, hold a position, face the ball,
search for it, beam, and keep out of a circle (the referee's distance at the other side's set plays)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

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
    over). One agent: ``keep_off_teammates_all`` with n = 1."""
    return keep_off_teammates_all([wm], np.asarray(target, dtype=np.float64)[None],
                                  clearance)[0]


def keep_off_teammates_all(wms: Sequence[WorldModel], targets: NDArray[np.float64],
                           clearance: float) -> NDArray[np.float64]:
    """(n, 2) ``keep_off_teammates`` of each agent ``wms[i]`` and its ``targets[i]``: the
    distance tests of all agents in one pass over (agents x teammates), the rare step-aside
    per agent. Each row depends only on that agent's own belief."""
    out = np.array(targets, dtype=np.float64)  # a copy: rows are replaced below
    mates = np.array([wm.teammates_present for wm in wms])
    every = np.arange(len(wms))
    mates[every, [wm.me for wm in wms]] = False
    rows = np.array([wm.teammates for wm in wms])  # (n, N, 2)
    gap = np.hypot(rows[:, :, 0] - out[:, None, 0], rows[:, :, 1] - out[:, None, 1])
    own = np.array([wm.position for wm in wms]) - out
    mine = np.array([math.hypot(dx, dy) for dx, dy in own.tolist()])
    holding = mates & (gap < clearance) & (gap < mine[:, None])
    for i in np.flatnonzero(holding.any(axis=1)).tolist():
        occupant = rows[i, int(np.argmin(np.where(holding[i], gap[i], np.inf)))]
        target = out[i].copy()
        away = target - occupant
        if math.hypot(away[0], away[1]) < 1e-6:  # the target is the teammate: stop on our side
            away = wms[i].position - occupant
        norm = math.hypot(away[0], away[1])
        if norm > 1e-9:
            out[i] = occupant + away * (clearance / norm)
    return out


def walk_goals(wms: Sequence[WorldModel], targets: NDArray[np.float64], skills: Skills,
               faces: Sequence[ArrayLike | None] | None = None, speed: float | None = None,
               avoid: bool = True) -> list[WalkGoal]:
    """Each agent's ``WalkGoal`` to ``targets[i]`` (see ``go_to``), the teammate keep-off of
    all agents in one pass."""
    if not wms:
        return []
    points = np.asarray(targets, dtype=np.float64)
    if avoid:
        points = keep_off_teammates_all(wms, points,
                                        2.0 * skills.body.body_radius + KEEP_OFF_MARGIN_M)
    faces = faces if faces is not None else [None] * len(wms)
    return [WalkGoal(wm.position, wm.heading, point,
                     *wm.obstacle_rows() if avoid else (_NO_PLAYERS, None),
                     face=None if face is None else np.asarray(face, dtype=np.float64),
                     speed=speed, params=skills.navigation)
            for wm, point, face in zip(wms, points, faces, strict=True)]


def go_to(wm: WorldModel, target: ArrayLike, skills: Skills, face: ArrayLike | None = None,
          speed: float | None = None, avoid: bool = True,
          behaviour: str = "go_to") -> ControlRequest:
    """Walk to ``target`` (team frame), around the other players when ``avoid`` (potential
    field; then also stopping beside a teammate that already holds the target,
    ``keep_off_teammates``), turning to face ``face`` near the target. The walk command is
    computed when first read, or with the team's (``resolve_walks``). One agent:
    ``walk_goals`` with n = 1."""
    goal = walk_goals([wm], np.asarray(target, dtype=np.float64)[None], skills, [face],
                      speed, avoid)[0]
    return ControlRequest.walking(goal, behaviour)


def face_ball(wm: WorldModel, skills: Skills) -> ControlRequest:
    """Stand and turn towards the ball."""
    error = wrap_angle(math.atan2(wm.ball[1] - wm.position[1], wm.ball[0] - wm.position[0])
                 - wm.heading)
    return ControlRequest(walk=np.array([0.0, 0.0, skills.navigation.turn_gain * error]),
                          behaviour="face_ball")


class Hold(NamedTuple):
    """A decision to hold ``target`` (walk there, face the ball), credited to ``behaviour``:
    decision makers return it so that a team resolves all its holds in one pass
    (``resolve_holds``)."""

    target: NDArray[np.float64]
    behaviour: str = "hold_position"


def hold_position(wm: WorldModel, target: ArrayLike, skills: Skills,
                  behaviour: str = "hold_position") -> ControlRequest:
    """Go to a formation (or marking) position and face the ball there. One agent:
    ``hold_positions`` with n = 1."""
    return hold_positions([wm], [Hold(np.asarray(target, dtype=np.float64), behaviour)],
                          skills)[0]


def hold_positions(wms: Sequence[WorldModel], holds: Sequence[Hold],
                   skills: Skills) -> list[ControlRequest]:
    """``hold_position`` of each agent ``wms[i]`` at ``holds[i]``: who has arrived (stands
    and turns to the ball) and the walks of the others (``walk_goals``) in one pass."""
    if not holds:
        return []
    targets = np.array([hold.target for hold in holds], dtype=np.float64)
    offsets = targets - np.array([wm.position for wm in wms])
    near = skills.navigation.arrive_m * 2
    arrived = [math.hypot(dx, dy) < near for dx, dy in offsets.tolist()]
    walking = [i for i, done in enumerate(arrived) if not done]
    goals = iter(walk_goals([wms[i] for i in walking], targets[walking], skills,
                            [wms[i].ball for i in walking]))
    return [ControlRequest(walk=face_ball(wm, skills).walk, behaviour=hold.behaviour) if done
            else ControlRequest.walking(next(goals), hold.behaviour)
            for wm, hold, done in zip(wms, holds, arrived, strict=True)]


def resolve_holds(wms: Sequence[WorldModel], plans: Sequence[ControlRequest | Hold],
                  skills: Skills) -> list[ControlRequest]:
    """The decision makers' ``plans`` as requests: every ``Hold`` of the team resolved
    together (``hold_positions``), the requests as they are."""
    held = [i for i, plan in enumerate(plans) if isinstance(plan, Hold)]
    out = list(plans)
    for i, request in zip(held, hold_positions([wms[i] for i in held],
                                               [plans[i] for i in held], skills), strict=True):
        out[i] = request
    return out  # type: ignore[return-value]


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
