"""``best_kick``'s candidate scoring as two compiled loops (numba), the same bits as NumPy.

``best_kick`` scores ~42 candidate kicks; as NumPy expressions that is ~60 operations on
arrays of that size, a few hundred microseconds of call overhead for a few microseconds of
arithmetic, once per team and cycle. Here each element goes through the IEEE operations of
those expressions in their order (each step names the expression it replaces), and the
elementary functions are the C library's (``math.atan2``, ``math.tanh``, ``math.cos``,
``math.sin``, ``math.hypot``: numba calls the functions Python's ``math`` calls, which is
what ``portable_math`` and NumPy's ``hypot``, ``cos`` and ``sin`` give; tested against the
NumPy expressions). SciPy's normal CDF (``ndtr``) stays SciPy's: ``candidates`` writes every
argument it needs into one array, the caller applies ``ndtr`` to it in one call, and
``choose`` finishes with the results.

Imported on first use: numba takes a few tenths of a second to import.
"""

from __future__ import annotations

import math

import numpy as np

from portable_math.jit import numba  # SVML off: the same bits on every machine

# rows of ``candidates``' per-candidate outputs
END_X, END_Y, LAND_X, MARGIN, RACE, USABLE, BLOCKED, FOLLOW_OK = range(8)
ROWS = 8


@numba.njit(inline="always")
def _minimum(a, b):
    """``np.minimum`` of two floats (a NaN wins)."""
    if math.isnan(a) or math.isnan(b):
        return a + b
    return a if a <= b else b


@numba.njit(inline="always")
def _maximum(a, b):
    """``np.maximum`` of two floats (a NaN wins)."""
    if math.isnan(a) or math.isnan(b):
        return a + b
    return a if a >= b else b


@numba.njit(inline="always")
def _earliest(x, y, players, usable, fallen, speed, getup_s):
    """The earliest any usable player reaches (x, y), seconds (a fallen one ``getup_s``
    later); inf where none is usable: the NumPy version's minimum over its players of
    ``hypot / speed + where(fallen, getup_s, 0.0)``."""
    earliest = np.inf
    first = True
    for m in range(players.shape[0]):
        if usable[m]:
            t = math.hypot(x - players[m, 0], y - players[m, 1]) / speed
            t = t + (getup_s if fallen[m] else 0.0)
            earliest = t if first else _minimum(earliest, t)
            first = False
    return earliest


@numba.njit(cache=True)
def candidates(ball, goal, position, mates, mates_usable, mates_fallen, opps, opps_present,
               opps_fallen, directions, powers, shots, is_shot, field, body, cand, z):
    """Every candidate's end point, landing x, race margin and its tanh, whether it may be
    chosen, whether an opponent blocks its lane, and the arguments of every ``ndtr`` the
    choice needs, into ``z``: per candidate the shot's upper and lower aim bound and its
    distance, then the same for the follow-up shot of every pass, in candidate order.
    Returns whether a shot from the ball can score at all (the goal mouth ahead of it), and
    how many entries of ``z`` are used.

    ``field``: half length, half width, half goal width, the lane's half width (an opponent
    this near the ball's path takes it), the margin kept inside each post; ``body``: kick mean (m), walk speed
    (m/s), get-up (s), kick duration (s), aim s.d. and distance s.d. (both floored)."""
    hl, hw, hgw, lane_m, post = field[0], field[1], field[2], field[3], field[4]
    mean, speed, getup_s, duration_s = body[0], body[1], body[2], body[3]
    aim_sd, dist_sd = body[4], body[5]
    bx, by = ball[0], ball[1]
    n_dir = directions.shape[0]
    n_fan = n_dir * powers.shape[0]
    total = n_fan + shots.shape[0]
    # base = math.atan2(...); angles = base + DIRECTIONS; fan = (cos, sin) of angles;
    # end = ball + (POWERS * mean)[:, None, None] * fan, then the shots
    base = math.atan2(goal[1] - by, goal[0] - bx)
    for k in range(powers.shape[0]):
        reach = powers[k] * mean
        for d in range(n_dir):
            angle = base + directions[d]
            cand[END_X, k * n_dir + d] = bx + reach * math.cos(angle)
            cand[END_Y, k * n_dir + d] = by + reach * math.sin(angle)
    for s in range(shots.shape[0]):
        cand[END_X, n_fan + s] = shots[s, 0]
        cand[END_Y, n_fan + s] = shots[s, 1]
    # goal_chances from the ball: dx (1 where the goal is not ahead), the mouth's angles
    dx0 = hl - bx
    shot_ok = dx0 > 0
    if not shot_ok:
        dx0 = 1.0
    low0 = math.atan2(-hgw + post - by, dx0)
    high0 = math.atan2(hgw - post - by, dx0)
    shot_ok = shot_ok and high0 > low0
    shot_distance = math.hypot(dx0, by)
    any_opp = False
    for m in range(opps.shape[0]):
        any_opp = any_opp or opps_present[m]
    follow = 3 * total
    for i in range(total):
        ex, ey = cand[END_X, i], cand[END_Y, i]
        lx = _minimum(ex, hl)  # the landing point: a shot is raced for at the goal line
        cand[LAND_X, i] = lx
        on_pitch = (abs(ey) <= hw - 0.5) and (lx > -hl + 1.0) and (ex < hl - 0.5)
        # the race: the earliest usable teammate / present opponent at the landing point
        ours = _earliest(lx, ey, mates, mates_usable, mates_fallen, speed, getup_s)
        theirs = _earliest(lx, ey, opps, opps_present, opps_fallen, speed, getup_s)
        mine = duration_s + math.hypot(lx - position[0], ey - position[1]) / speed
        ours = _minimum(ours, mine)
        margin = _minimum(_maximum(theirs - ours, -10.0), 10.0)  # np.clip
        # the lane: a present opponent within lane_m of the path's first 90 %
        blocked = False
        if any_opp:
            sx, sy = lx - bx, ey - by
            length2 = _maximum(sx * sx + sy * sy, 1e-12)
            for m in range(opps.shape[0]):
                if opps_present[m]:
                    s = ((0.0 + (opps[m, 0] - bx) * sx) + (opps[m, 1] - by) * sy) / length2
                    s = _minimum(_maximum(s, 0.0), 0.9)
                    gap = math.hypot(opps[m, 0] - (bx + s * sx), opps[m, 1] - (by + s * sy))
                    blocked = blocked or (gap < lane_m and s > 0.0)
        if blocked:
            margin = -3.0
        cand[MARGIN, i] = margin
        cand[RACE, i] = math.tanh(margin / 2.0)
        cand[USABLE, i] = 1.0 if (on_pitch or is_shot[i]) else 0.0
        cand[BLOCKED, i] = 1.0 if blocked else 0.0
        # the shot's chance from the ball (goal_chances): aim bounds and distance
        power = powers[i // n_dir] if i < n_fan else 1.0
        to_aim = math.atan2(ey - by, ex - bx)
        z[3 * i] = (high0 - to_aim) / aim_sd
        z[3 * i + 1] = (low0 - to_aim) / aim_sd
        z[3 * i + 2] = (mean - shot_distance / _maximum(power, 1e-6)) / dist_sd
        # a pass: the follow-up shot from where it lands, at full power
        cand[FOLLOW_OK, i] = 0.0
        if on_pitch and not is_shot[i]:
            dx = hl - lx
            ahead = dx > 0
            if not ahead:
                dx = 1.0
            to_goal = math.atan2(goal[1] - ey, goal[0] - lx)
            low = math.atan2(-hgw + post - ey, dx)
            high = math.atan2(hgw - post - ey, dx)
            cand[FOLLOW_OK, i] = 1.0 if (ahead and high > low) else 0.0
            z[follow] = (high - to_goal) / aim_sd
            z[follow + 1] = (low - to_goal) / aim_sd
            z[follow + 2] = (mean - math.hypot(dx, ey) / 1.0) / dist_sd
            follow += 3
    return shot_ok, follow


@numba.njit(cache=True)
def choose(ball_x, cand, is_shot, shot_ok, cdf, weights, value, p_goal):
    """Each candidate's value and goal chance from ``candidates``' outputs and the normal
    CDF of its ``z`` (``cdf``); returns the best candidate (``np.argmax``: the first
    maximum, or the first NaN). ``weights``: possession, progress, goal, follow-up."""
    possession, progress, goal_w, follow_up = weights[0], weights[1], weights[2], weights[3]
    total = cand.shape[1]
    follow = 3 * total
    for i in range(total):
        # goal_chances(...) * where(blocked, 0.5, 1.0)
        chance = _maximum(cdf[3 * i] - cdf[3 * i + 1], 0.0) * cdf[3 * i + 2] if shot_ok \
            else 0.0
        p_goal[i] = chance * (0.5 if cand[BLOCKED, i] > 0.5 else 1.0)
        race = cand[RACE, i]
        v = possession * race + progress * (cand[LAND_X, i] - ball_x)
        usable = cand[USABLE, i] > 0.5
        if is_shot[i]:
            extra = p_goal[i]
        elif usable:  # a pass: follow_up * win * goal_chances(from its landing)
            chance = _maximum(cdf[follow] - cdf[follow + 1], 0.0) * cdf[follow + 2] \
                if cand[FOLLOW_OK, i] > 0.5 else 0.0
            extra = follow_up * (0.5 * (1.0 + race)) * chance
            follow += 3
        else:
            extra = 0.0
        v = v + goal_w * extra
        value[i] = v if usable else -np.inf
    best = 0
    for i in range(1, total):
        if math.isnan(value[best]):
            break
        if math.isnan(value[i]) or value[i] > value[best]:
            best = i
    return best
