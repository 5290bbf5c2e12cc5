"""``best_kick`` as NumPy expressions: the reference its compiled loops (``kick_kernel``) are
tested against, bit for bit (``test_kick_kernel.py``)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

import portable_math as pm
from strategy.behaviours import kick_choice
from strategy.behaviours.kick_choice import DIRECTIONS, POWERS, KickChoice
from strategy.perception.worldmodel import WorldModel
from teamenv.capabilities import BodyCapabilities


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
    """(P,) an opponent stands within ``kick_choice.LANE_M`` of the path from ``ball`` to each end (its
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
    return ((gap < kick_choice.LANE_M) & (s > 0.0)).any(axis=1)


def best_kick_numpy(wm: WorldModel, body: BodyCapabilities, walk_speed: float,
              possession_weight: float, progress_weight: float, goal_weight: float,
              follow_up: float = 0.0, exclude: tuple[int, ...] = ()) -> KickChoice:
    """``kick_choice.best_kick`` as the NumPy expressions it was before its compiled loops."""
    f = wm.field
    ball = wm.ball
    goal = wm.opponent_goal
    base = math.atan2(goal[1] - ball[1], goal[0] - ball[0])
    angles = base + DIRECTIONS
    fan = np.column_stack([np.cos(angles), np.sin(angles)])
    reaches = np.array(POWERS) * body.kick_distance_mean_m
    shots, power_arr, is_shot = kick_choice._candidates(f.half_length, f.half_goal_width)
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
    p_goal = kick_choice.goal_chances(f.half_length, f.half_goal_width, ball[None, :], end, power_arr,
                          body) * np.where(blocked, 0.5, 1.0)
    # a pass is worth the shot the receiver can take from where it wins the ball (only the
    # kicks that can be chosen: the others' values are -inf below)
    passes = on_pitch & ~is_shot
    win = 0.5 * (1.0 + race[passes])
    follow = np.zeros(len(end))
    follow[passes] = follow_up * win * kick_choice.goal_chances(
        f.half_length, f.half_goal_width, landing[passes], goal[None, :], np.ones(1), body)
    value += goal_weight * np.where(is_shot, p_goal, follow)
    value = np.where(on_pitch | is_shot, value, -np.inf)
    k = int(np.argmax(value))
    return KickChoice(end[k], float(power_arr[k]), float(value[k]), float(margin[k]),
                      bool(is_shot[k]), float(p_goal[k]) if is_shot[k] else 0.0)
