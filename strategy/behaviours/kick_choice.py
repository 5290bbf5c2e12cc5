"""Where to kick: every kick is a race to where the ball stops.

A kick sends the ball ~9 m (seed 000 Table 1: mean 8.92 m, s.d. 3.82 m at full power,
~11 degrees of aim error), and players walk ~1 m/s, so whoever is first at the landing point
has the ball next. ``best_kick`` scores candidate landing points (a fan of directions at a few
powers, plus shots at the goal mouth) by

    value = possession_weight * tanh(margin / 2) + progress_weight * forward gain
            + goal_weight * P(goal)

where ``margin`` (s) is how much sooner our nearest teammate than their nearest player can
reach the landing point (the kicker stands for the kick's duration first), and ``P(goal)`` is
the chance the kick's distance and aim spread put the ball inside the goal mouth. A lane an
opponent stands in gives the ball to them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from strategy.worldmodel import WorldModel

AIM_SIGMA_RAD = 0.189
"""Aim error s.d.: seed 000 Table 1 puts 64.5 % of kicks within 10 degrees."""

KICK_MEAN_M, KICK_SD_M = 8.92, 3.82
"""Full-power kick distance, seed 000 Table 1."""

FALLEN_PENALTY_S = 3.0
"""A fallen player needs about this long (fall + get-up) before it can run."""

KICKER_BUSY_S = 1.5
"""The kicker stands still this long after the kick (the kick's duration)."""

LANE_M = 0.45
"""An opponent this close to the ball's path (before it stops) takes the ball."""

DIRECTIONS = np.deg2rad(np.arange(-90, 91, 15))
POWERS = (0.5, 0.75, 1.0)


@dataclass(frozen=True)
class KickChoice:
    """A kick: aim point (team frame), power, its value and the race margin (s)."""

    target: NDArray[np.float64]
    power: float
    value: float
    margin_s: float
    shot: bool


def _reach_times(points: NDArray[np.float64], players: NDArray[np.float64],
                 usable: NDArray[np.bool_], fallen: NDArray[np.bool_],
                 speed: float) -> NDArray[np.float64]:
    """(P,) the earliest any usable player reaches each point, seconds."""
    if not usable.any():
        return np.full(len(points), np.inf)
    p = players[usable]
    t = np.hypot(points[:, None, 0] - p[None, :, 0], points[:, None, 1] - p[None, :, 1]) / speed
    t += np.where(fallen[usable], FALLEN_PENALTY_S, 0.0)[None, :]
    return t.min(axis=1)


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


def goal_probability(wm: WorldModel, aim: NDArray[np.float64], power: float) -> float:
    """Chance a kick from the ball at ``aim`` with ``power`` ends in the goal: the aim error
    must keep it inside the posts and the distance must carry it over the line."""
    f = wm.field
    dx = f.half_length - wm.ball[0]
    if dx <= 0:
        return 0.0
    to_aim = math.atan2(aim[1] - wm.ball[1], aim[0] - wm.ball[0])
    low = math.atan2(-f.half_goal_width + 0.15 - wm.ball[1], dx)
    high = math.atan2(f.half_goal_width - 0.15 - wm.ball[1], dx)
    if high <= low:
        return 0.0
    p_aim = _normal_cdf((high - to_aim) / AIM_SIGMA_RAD) - _normal_cdf((low - to_aim) / AIM_SIGMA_RAD)
    needed = math.hypot(dx, wm.ball[1]) / max(power, 1e-6)
    p_far = 1.0 - _normal_cdf((needed - KICK_MEAN_M) / KICK_SD_M)
    return max(0.0, p_aim) * p_far


def _normal_cdf(z: float) -> float:
    return 0.5 * (1.0 + math.erf(z / math.sqrt(2.0)))


def best_kick(wm: WorldModel, walk_speed: float, possession_weight: float,
              progress_weight: float, goal_weight: float,
              exclude: tuple[int, ...] = ()) -> KickChoice:
    """The most valuable kick from where the ball is (see the module doc)."""
    f = wm.field
    ball = wm.ball
    goal = wm.opponent_goal
    base = math.atan2(goal[1] - ball[1], goal[0] - ball[0])
    angles = base + DIRECTIONS
    ends, powers = [], []
    for power in POWERS:
        reach = power * KICK_MEAN_M
        ends.append(ball + reach * np.column_stack([np.cos(angles), np.sin(angles)]))
        powers.extend([power] * len(angles))
    ys = np.linspace(-0.6, 0.6, 3) * f.half_goal_width
    shots = np.column_stack([np.full(len(ys), f.half_length + 1.0), ys])
    ends.append(shots)
    powers.extend([1.0] * len(shots))
    end = np.concatenate(ends)
    power_arr = np.asarray(powers)
    is_shot = np.zeros(len(end), dtype=bool)
    is_shot[-len(shots):] = True
    # A landing point beyond the goal line (a shot) is raced for where it crosses the line.
    landing = end.copy()
    landing[:, 0] = np.minimum(landing[:, 0], f.half_length)
    on_pitch = ((np.abs(landing[:, 1]) <= f.half_width - 0.5)
                & (landing[:, 0] > -f.half_length + 1.0) & (end[:, 0] < f.half_length - 0.5))

    mates_usable = wm.teammates_present.copy()
    for k in exclude:
        mates_usable[k] = False
    mates_usable[wm.me] = False
    ours = _reach_times(landing, wm.teammates, mates_usable, wm.teammates_fallen, walk_speed)
    mine = KICKER_BUSY_S + np.hypot(*(landing - wm.position).T) / walk_speed
    ours = np.minimum(ours, mine)
    theirs = _reach_times(landing, wm.opponents, wm.opponents_present, wm.opponents_fallen,
                          walk_speed)
    margin = np.clip(theirs - ours, -10.0, 10.0)
    blocked = _lane_blocked(ball, landing, wm.opponents[wm.opponents_present])
    margin = np.where(blocked, -3.0, margin)
    value = possession_weight * np.tanh(margin / 2.0) \
        + progress_weight * (landing[:, 0] - ball[0])
    for k in np.flatnonzero(is_shot):
        # a shot through a crowd still has its chance (deflections): halved, not lost
        p_goal = goal_probability(wm, end[k], power_arr[k]) * (0.5 if blocked[k] else 1.0)
        value[k] += goal_weight * p_goal
    value = np.where(on_pitch | is_shot, value, -np.inf)
    k = int(np.argmax(value))
    return KickChoice(end[k], float(power_arr[k]), float(value[k]), float(margin[k]),
                      bool(is_shot[k]))
