"""Where to kick: every kick is a race to where the ball stops.

A kick sends the ball as far as the body kicks (``BodyCapabilities``: the profile's mean and
s.d. of a full-power kick, e.g. 8.92 m +- 3.82 m for ``t1_mj``, 1.17 m +- 0.91 m for
``t1_league``, and its aim error), and players walk at the body's real speed, so whoever is
first at the landing point has the ball next. ``best_kick`` scores candidate landing points
(a fan of directions at a few powers, plus shots at the goal mouth) by

    value = possession_weight * tanh(margin / 2) + progress_weight * forward gain
            + goal_weight * P(goal)                               (a shot)
            + goal_weight * follow_up * P(we win) * P(goal from there)   (any other kick)

where ``margin`` (s) is how much sooner our nearest teammate than their nearest player can
reach the landing point (the kicker stands for the kick's duration first; a fallen player
needs its get-up time first), and ``P(goal)`` is the chance the kick's distance and aim
spread put the ball inside the goal mouth; a pass is also worth part (``follow_up``) of the
shot its receiver can take next. A lane an opponent stands in gives the ball to them. Kicks
at the goal mouth are raced for, and credited with ground, at the goal line (see
``best_kick``): a deliberate bias towards kicking at the goal. Every body fact comes from the
``body`` argument (the team's ``TeamContext.body``); this module holds none.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.special import ndtr

import portable_math as pm
from strategy.perception.worldmodel import WorldModel
from teamenv.capabilities import BodyCapabilities

LANE_M = 0.45
"""An opponent this close to the ball's path (before it stops) takes the ball."""

MIN_SHOT_CHANCE = 0.05
"""A kick at the goal with less chance than this is reported as a long kick, not a shot."""

DIRECTIONS = np.deg2rad(np.arange(-90, 91, 15))
POWERS = (0.5, 0.75, 1.0)


@dataclass(frozen=True)
class KickChoice:
    """A kick: aim point (team frame), power, its value, the race margin (s), whether it is
    aimed at the goal mouth, and its chance of a goal."""

    target: NDArray[np.float64]
    power: float
    value: float
    margin_s: float
    shot: bool
    goal_chance: float = 0.0


def _reach_times(points: NDArray[np.float64],
                 sides: Sequence[tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_]]],
                 speed: float, fallen_s: float) -> list[NDArray[np.float64]]:
    """Per side (players, usable, fallen): (P,) the earliest any of its usable players
    reaches each point, seconds (a fallen one starts ``fallen_s`` late); inf where it has
    none. Both sides' distances in one pass."""
    rows = [players[usable] for players, usable, _ in sides]
    p = np.concatenate(rows)
    t = np.hypot(points[:, None, 0] - p[None, :, 0], points[:, None, 1] - p[None, :, 1]) / speed
    t += np.where(np.concatenate([fallen[usable] for _, usable, fallen in sides]),
                  fallen_s, 0.0)[None, :]
    out, start = [], 0
    for r in rows:
        out.append(t[:, start:start + len(r)].min(axis=1) if len(r)
                   else np.full(len(points), np.inf))
        start += len(r)
    return out


def _lane_blocked(ball: NDArray[np.float64], ends: NDArray[np.float64],
                  opponents: NDArray[np.float64]) -> NDArray[np.bool_]:
    """(P,) an opponent stands within ``LANE_M`` of the path from ``ball`` to each end (its
    first 90 %: the last part is the race)."""
    if len(opponents) == 0:
        return np.zeros(len(ends), dtype=bool)
    seg = ends - ball  # (P, 2)
    length2 = np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-12)
    rel = opponents[None, :, :] - ball[None, None, :]  # (1, M, 2)
    s = np.clip(np.einsum("pmj,pj->pm", np.broadcast_to(rel, (len(ends),) + rel.shape[1:]),
                          seg) / length2[:, None], 0.0, 0.9)
    closest = ball[None, None, :] + s[:, :, None] * seg[:, None, :]
    gap = np.hypot(*(opponents[None, :, :] - closest).transpose(2, 0, 1))
    # an opponent behind the ball (s clipped to 0) is not in the lane
    return ((gap < LANE_M) & (s > 0.0)).any(axis=1)


def goal_probability(wm: WorldModel, aim: NDArray[np.float64], power: float,
                     body: BodyCapabilities) -> float:
    """Chance a kick by ``body`` from the ball at ``aim`` with ``power`` ends in the goal:
    the aim error must keep it inside the posts and the distance must carry it over the
    line."""
    return float(goal_chances(wm.field.half_length, wm.field.half_goal_width,
                              wm.ball[None, :], np.asarray(aim, dtype=np.float64)[None, :],
                              np.array([power]), body)[0])


def goal_chances(half_length: float, half_goal_width: float, balls: NDArray[np.float64],
                 aims: NDArray[np.float64], powers: NDArray[np.float64],
                 body: BodyCapabilities) -> NDArray[np.float64]:
    """(P,) ``goal_probability`` for kicks from ``balls`` (P, 2) at ``aims`` (P, 2)."""
    dx = half_length - balls[:, 0]
    ahead = dx > 0
    dx = np.where(ahead, dx, 1.0)
    to_aim = pm.arctan2(aims[:, 1] - balls[:, 1], aims[:, 0] - balls[:, 0])
    low = pm.arctan2(-half_goal_width + 0.15 - balls[:, 1], dx)
    high = pm.arctan2(half_goal_width - 0.15 - balls[:, 1], dx)
    aim_sd = max(body.kick_aim_sd_rad, 1e-9)
    p_aim = ndtr((high - to_aim) / aim_sd) - ndtr((low - to_aim) / aim_sd)
    needed = np.hypot(dx, balls[:, 1]) / np.maximum(powers, 1e-6)
    p_far = ndtr((body.kick_distance_mean_m - needed) / max(body.kick_distance_sd_m, 1e-9))
    return np.where(ahead & (high > low), np.maximum(p_aim, 0.0) * p_far, 0.0)


def best_kick(wm: WorldModel, body: BodyCapabilities, walk_speed: float,
              possession_weight: float, progress_weight: float, goal_weight: float,
              follow_up: float = 0.0, exclude: tuple[int, ...] = ()) -> KickChoice:
    """The most valuable kick by ``body`` from where the ball is (see the module doc);
    ``walk_speed`` (m/s): how fast players really run to the landing point."""
    f = wm.field
    ball = wm.ball
    goal = wm.opponent_goal
    base = math.atan2(goal[1] - ball[1], goal[0] - ball[0])
    angles = base + DIRECTIONS
    fan = np.column_stack([np.cos(angles), np.sin(angles)])
    reaches = np.array(POWERS) * body.kick_distance_mean_m
    shots, power_arr, is_shot = _candidates(f.half_length, f.half_goal_width)
    end = np.concatenate(((ball + reaches[:, None, None] * fan).reshape(-1, 2), shots))
    # A kick at the goal mouth is credited (race and ground gained) at the goal line, not
    # where a mean kick would stop: a deliberate bias towards kicking at the goal. The ball
    # goes in, goes out for a corner or goal kick, or is fought for in their box; against
    # the built-in opponents this beat racing it at the mean kick length (2-0 vs 0-0).
    landing = end.copy()
    landing[:, 0] = np.minimum(landing[:, 0], f.half_length)
    on_pitch = ((np.abs(landing[:, 1]) <= f.half_width - 0.5)
                & (landing[:, 0] > -f.half_length + 1.0) & (end[:, 0] < f.half_length - 0.5))

    mates_usable = wm.teammates_present.copy()
    for k in exclude:
        mates_usable[k] = False
    mates_usable[wm.me] = False
    # A player seen lying needs its get-up (its fall is mostly over when it is seen down).
    ours, theirs = _reach_times(
        landing, ((wm.teammates, mates_usable, wm.teammates_fallen),
                  (wm.opponents, wm.opponents_present, wm.opponents_fallen)),
        walk_speed, body.getup_s)
    mine = body.kick_duration_s + np.hypot(*(landing - wm.position).T) / walk_speed
    ours = np.minimum(ours, mine)
    margin = np.clip(theirs - ours, -10.0, 10.0)
    blocked = _lane_blocked(ball, landing, wm.opponents[wm.opponents_present])
    margin = np.where(blocked, -3.0, margin)
    race = pm.tanh(margin / 2.0)
    value = possession_weight * race + progress_weight * (landing[:, 0] - ball[0])
    # a shot through a crowd still has its chance (deflections): halved, not lost (one ball
    # for every candidate: its goal-mouth angles are computed once)
    p_goal = goal_chances(f.half_length, f.half_goal_width, ball[None, :], end, power_arr,
                          body) * np.where(blocked, 0.5, 1.0)
    # a pass is worth the shot the receiver can take from where it wins the ball (only the
    # kicks that can be chosen: the others' values are -inf below)
    passes = on_pitch & ~is_shot
    win = 0.5 * (1.0 + race[passes])
    follow = np.zeros(len(end))
    follow[passes] = follow_up * win * goal_chances(
        f.half_length, f.half_goal_width, landing[passes], goal[None, :], _FULL_POWER, body)
    value += goal_weight * np.where(is_shot, p_goal, follow)
    value = np.where(on_pitch | is_shot, value, -np.inf)
    k = int(np.argmax(value))
    return KickChoice(end[k], float(power_arr[k]), float(value[k]), float(margin[k]),
                      bool(is_shot[k]), float(p_goal[k]) if is_shot[k] else 0.0)


_FULL_POWER = np.ones(1)
_CANDIDATES: dict[tuple[float, float], tuple[NDArray[np.float64], NDArray[np.float64],
                                             NDArray[np.bool_]]] = {}


def _candidates(half_length: float, half_goal_width: float
                ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """The fixed part of ``best_kick``'s candidates on a pitch: the shots' aim points at the
    goal mouth, every candidate's power and which are shots (after the fan of directions at
    each of ``POWERS``). Held per pitch; do not modify."""
    key = (half_length, half_goal_width)
    fixed = _CANDIDATES.get(key)
    if fixed is None:
        ys = np.linspace(-0.6, 0.6, 3) * half_goal_width
        shots = np.column_stack([np.full(len(ys), half_length + 1.0), ys])
        powers = np.array([p for p in POWERS for _ in DIRECTIONS] + [1.0] * len(shots))
        is_shot = np.zeros(len(powers), dtype=bool)
        is_shot[-len(shots):] = True
        fixed = _CANDIDATES[key] = (shots, powers, is_shot)
    return fixed
