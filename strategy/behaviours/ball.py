"""Ball behaviours: approach the ball from behind, kick it to a point, dribble, shoot, pass,
clear. All positions are team frame (we attack +x), metres."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

import portable_math as pm
from strategy.behaviours.control import ControlRequest
from strategy.behaviours.motion import go_to
from strategy.behaviours.skills import Skills
from strategy.geometry import wrap_angle
from strategy.perception.worldmodel import WorldModel

BEHIND_M = 0.45
"""Where the approach lines up: this far behind the ball on the line from the aim point."""

STEP_IN_M = 0.04
"""The approach walks this far into the ball's contact distance (``Skills.contact_m``), so
the foot meets it."""


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    n = math.hypot(v[0], v[1])
    return v / n if n > 1e-9 else np.array([1.0, 0.0])


def approach_ball(wm: WorldModel, aim: ArrayLike, skills: Skills,
                  behaviour: str = "approach_ball") -> tuple[ControlRequest, bool]:
    """Walk to the ball so as to face ``aim`` with the ball in front of the feet.

    Returns the request and whether the agent is lined up (ball within reach, in front, and
    the aim within ``skills.kick_max_angle`` of the heading): ready to kick or push.
    """
    ball = wm.ball
    u = _unit(np.asarray(aim, dtype=np.float64) - ball)
    to_ball = ball - wm.position
    dist = math.hypot(to_ball[0], to_ball[1])
    aim_angle = math.atan2(u[1], u[0])
    heading_error = wrap_angle(aim_angle - wm.heading)
    # How far the agent is behind the ball along the aim line (> 0: on the right side).
    behind = -float(pm.matmul(wm.position - ball, u))
    lateral = abs(float(pm.matmul(wm.position - ball, np.array([-u[1], u[0]]))))
    ball_bearing = abs(wrap_angle(math.atan2(to_ball[1], to_ball[0]) - wm.heading)) if dist > 1e-6 \
        else 0.0
    lined_up = (dist <= skills.kick_reach * 0.95 and ball_bearing < 1.2
                and abs(heading_error) < skills.kick_max_angle)
    if lined_up:
        return ControlRequest(behaviour=behaviour), True
    if dist > 0.3 and abs(wrap_angle(aim_angle - math.atan2(to_ball[1], to_ball[0]))) < \
            skills.kick_max_angle - 0.2:
        # The aim can be kicked from the direction we come from: straight to the ball.
        target = ball - to_ball / dist * (skills.contact_m - STEP_IN_M)
        return go_to(wm, target, skills, face=ball, avoid=dist > 1.5,
                     behaviour=behaviour), False
    if behind > 0.2 and lateral < 0.25 and dist < 0.9:
        # On the line behind the ball: step in, facing the aim.
        target = ball - u * (skills.contact_m - STEP_IN_M)
        return go_to(wm, target, skills, face=ball + u, speed=0.6, avoid=False,
                     behaviour=behaviour), False
    spot = ball - u * BEHIND_M
    if behind < 0.1 and dist < 1.2:
        # In front of the ball: walk round it on the near side, not through it.
        side = np.array([-u[1], u[0]])
        if float(pm.matmul(wm.position - ball, side)) < 0:
            side = -side
        spot = ball + side * 0.6 - u * 0.3
        return go_to(wm, spot, skills, face=ball, avoid=False, behaviour=behaviour), False
    return go_to(wm, spot, skills, face=ball + u, behaviour=behaviour), False


def kick_to(wm: WorldModel, target: ArrayLike, skills: Skills, power: float | None = None,
            behaviour: str = "kick_to") -> ControlRequest:
    """Kick the ball towards ``target``; ``power`` None = enough to reach it (at most 1)."""
    t = np.asarray(target, dtype=np.float64)
    request, ready = approach_ball(wm, t, skills, behaviour=behaviour)
    if not ready:
        return request
    if power is None:
        power = min(1.0, max(0.25, math.hypot(*(t - wm.ball)) / skills.kick_distance_m))
    direction = wrap_angle(math.atan2(t[1] - wm.ball[1], t[0] - wm.ball[0]) - wm.heading)
    return ControlRequest(kick=(float(power), direction), behaviour=behaviour)


def dribble_aim(wm: WorldModel, target: ArrayLike, blocked_m: float = 1.5) -> NDArray[np.float64]:
    """Where to push the ball: straight at ``target`` unless an opponent stands within
    ``blocked_m`` ahead of the ball (within 35 degrees of that line); then the most open of
    the directions 30 and 60 degrees either side."""
    t = np.asarray(target, dtype=np.float64)
    base = math.atan2(t[1] - wm.ball[1], t[0] - wm.ball[0])
    opps = wm.opponents[wm.opponents_present]
    if len(opps) == 0:
        return t
    rel = opps - wm.ball
    dist = np.hypot(rel[:, 0], rel[:, 1])
    bearing = np.abs(pm.arctan2(rel[:, 1], rel[:, 0]) - base)
    bearing = np.minimum(bearing, 2 * math.pi - bearing)
    if not ((dist < blocked_m) & (bearing < 0.6)).any():
        return t
    best, best_gap = t, -math.inf
    for offset in (0.52, -0.52, 1.05, -1.05):
        angle = base + offset
        u = np.array([math.cos(angle), math.sin(angle)])
        ahead = pm.matmul(rel, u)
        side = np.abs(pm.matmul(rel, np.array([-u[1], u[0]])))
        gap = float(np.min(np.where(ahead > 0, side + 0.3 * ahead, np.inf)))
        edge = wm.field.half_width - abs(wm.ball[1] + 2.0 * u[1])
        if edge < 0.5:
            continue
        if gap > best_gap + 1e-9:
            best, best_gap = wm.ball + 3.0 * u, gap
    return best


def open_aim(wm: WorldModel, target: ArrayLike, length_m: float = 8.0) -> NDArray[np.float64]:
    """A point ``length_m`` from the ball in the most open direction near ``target``'s: of
    the directions 0, 20, 40 and 60 degrees either side, the one whose kick line passes
    farthest from every opponent (a little preference for straight), staying on the pitch."""
    t = np.asarray(target, dtype=np.float64)
    base = math.atan2(t[1] - wm.ball[1], t[0] - wm.ball[0])
    opps = wm.opponents[wm.opponents_present]
    f = wm.field
    best, best_score = t, -math.inf
    for offset in (0.0, 0.35, -0.35, 0.7, -0.7, 1.05, -1.05):
        angle = base + offset
        end = wm.ball + length_m * np.array([math.cos(angle), math.sin(angle)])
        if abs(end[1]) > f.half_width - 1.0:
            continue
        gap = _min_distance_to_segment(opps, wm.ball, end) if len(opps) else 10.0
        score = min(gap, 4.0) - 0.8 * abs(offset)
        if score > best_score + 1e-9:
            best, best_score = end, score
    return best


def in_kick_reach(wm: WorldModel, skills: Skills) -> bool:
    """The ball is within reach and in front of the body (within 70 degrees of the heading)."""
    to_ball = wm.ball - wm.position
    dist = math.hypot(to_ball[0], to_ball[1])
    if dist > skills.kick_reach * 0.95:
        return False
    return dist < 1e-6 or abs(wrap_angle(math.atan2(to_ball[1], to_ball[0]) - wm.heading)) < 1.2


def quick_kick(wm: WorldModel, skills: Skills, preferred: ArrayLike | None = None,
               length_m: float | None = None) -> ControlRequest | None:
    """Kick now, in the best direction the body can kick from where it stands, or None.

    Candidates: ``preferred`` (if within ``skills.kick_max_angle`` of the heading) and the
    directions every 15 degrees within that angle. A direction is worth its gain towards
    their goal plus its clearance from the opponents (capped), never backwards (towards our
    goal line by more than 1 m) and never off the pitch, judged at ``length_m`` from the ball
    (None: the body's mean full-power kick). None when the ball is out of reach or every
    direction is worthless.
    """
    if not in_kick_reach(wm, skills):
        return None
    if length_m is None:  # where a full-power kick of this body rolls
        length_m = skills.kick_distance_m
    f = wm.field
    opps = wm.opponents[wm.opponents_present]
    angles = list(wm.heading + np.arange(-skills.kick_max_angle, skills.kick_max_angle + 1e-9,
                                         0.26))
    bonus = {}
    if preferred is not None:
        p = np.asarray(preferred, dtype=np.float64)
        pa = math.atan2(p[1] - wm.ball[1], p[0] - wm.ball[0])
        if abs(wrap_angle(pa - wm.heading)) <= skills.kick_max_angle:
            angles.insert(0, pa)
            bonus[0] = 2.0
    best, best_score = None, 0.0
    for k, angle in enumerate(angles):
        end = wm.ball + length_m * np.array([math.cos(angle), math.sin(angle)])
        if abs(end[1]) > f.half_width - 0.5 or end[0] < wm.ball[0] - 1.0:
            continue
        if end[0] < -f.half_length + 1.0:
            continue
        gap = _min_distance_to_segment(opps, wm.ball, end) if len(opps) else 4.0
        score = (end[0] - wm.ball[0]) / length_m * 3.0 + min(gap, 4.0) + bonus.get(k, 0.0)
        if score > best_score + 1e-9:
            best, best_score = angle, score
    if best is None:
        return None
    return ControlRequest(kick=(1.0, wrap_angle(best - wm.heading)), behaviour="quick_kick")


def dribble(wm: WorldModel, target: ArrayLike, skills: Skills,
            speed: float = 0.8) -> ControlRequest:
    """Push the ball towards ``target`` by walking through it, lined up behind it (round an
    opponent standing in the way: ``dribble_aim``)."""
    aim = dribble_aim(wm, target)
    u = _unit(aim - wm.ball)
    request, ready = approach_ball(wm, aim, skills, behaviour="dribble")
    if not ready:
        return request
    return go_to(wm, wm.ball + u * 1.5, skills, face=wm.ball + u * 3.0, speed=speed,
                 avoid=False, behaviour="dribble")


def shot_target(wm: WorldModel) -> NDArray[np.float64]:
    """The point of the opponents' goal mouth farthest from the opponents near it."""
    f = wm.field
    ys = np.linspace(-0.7, 0.7, 5) * f.half_goal_width
    points = np.column_stack([np.full(len(ys), f.half_length), ys])
    opps = wm.opponents[wm.opponents_present]
    if len(opps) == 0:
        return points[len(ys) // 2]
    # Distance of each candidate's shot line to the nearest opponent.
    clearance = np.array([_min_distance_to_segment(opps, wm.ball, p) for p in points])
    return points[int(np.argmax(clearance))]


def shoot(wm: WorldModel, skills: Skills) -> ControlRequest:
    """Kick at the opponents' goal, full power, at its most open point."""
    return kick_to(wm, shot_target(wm), skills, power=1.0, behaviour="shoot")


def choose_pass(wm: WorldModel, min_gain_m: float, max_distance_m: float, lane_m: float,
                free_m: float, exclude: tuple[int, ...] = (0,)) -> int | None:
    """The teammate to pass to, or None: one who is at least ``min_gain_m`` closer to the
    opponents' goal than the ball, within ``max_distance_m`` and 2 m of it, with no opponent
    within ``lane_m`` of the pass line and none within ``free_m`` of the receiver; the best
    by gain minus a fifth of the pass length."""
    goal = wm.opponent_goal
    ball_to_goal = math.hypot(*(goal - wm.ball))
    opps = wm.opponents[wm.opponents_present]
    best, best_score = None, -math.inf
    for k in np.flatnonzero(wm.teammates_present & ~wm.teammates_fallen):
        k = int(k)
        if k == wm.me or k in exclude:
            continue
        mate = wm.teammates[k]
        length = math.hypot(*(mate - wm.ball))
        if not 2.0 <= length <= max_distance_m:
            continue
        gain = ball_to_goal - math.hypot(*(goal - mate))
        if gain < min_gain_m:
            continue
        if len(opps):
            if float(np.min(np.hypot(*(opps - mate).T))) < free_m:
                continue
            if _min_distance_to_segment(opps, wm.ball, mate) < lane_m:
                continue
        score = gain - 0.2 * length
        if score > best_score:
            best, best_score = k, score
    return best


def pass_to(wm: WorldModel, mate: int, skills: Skills) -> ControlRequest:
    """Kick the ball to teammate ``mate``, a little ahead of it (towards the goal)."""
    target = wm.teammates[mate] + np.array([0.8, 0.0])
    return kick_to(wm, target, skills, behaviour="pass")


def clear_ball(wm: WorldModel, skills: Skills) -> ControlRequest:
    """Kick the ball far from our goal, towards the touchline on the ball's side."""
    f = wm.field
    side = 1.0 if wm.ball[1] >= 0 else -1.0
    target = np.array([wm.ball[0] + f.half_length * 0.6, side * f.half_width * 0.7])
    return kick_to(wm, target, skills, power=1.0, behaviour="clear")


def _min_distance_to_segment(points: NDArray[np.float64], a: NDArray[np.float64],
                             b: NDArray[np.float64]) -> float:
    seg = b - a
    length2 = float(pm.matmul(seg, seg))
    if length2 < 1e-12:
        return float(np.min(np.hypot(*(points - a).T)))
    s = np.clip(pm.matmul(points - a, seg) / length2, 0.0, 1.0)
    closest = a + s[:, None] * seg
    return float(np.min(np.hypot(*(points - closest).T)))
