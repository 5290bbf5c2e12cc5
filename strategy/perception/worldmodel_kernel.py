"""The arithmetic of ``team_world_models`` as one compiled loop (numba), the same bits.

A team's world models rotate every agent's egocentric rows into the team frame, round them to
the belief resolution and build the presence masks: ~40 NumPy operations on arrays of a few
hundred elements, mostly call overhead. Here each element goes through the operations of those
expressions in their order: the C library's ``cos`` and ``sin`` (what NumPy's give here and
what numba calls), ``(c * x - s * y) + px``, and ``np.round(v / r) * r + 0.0`` (round half to
even, which has one answer). Tested bit for bit against the NumPy expressions.

Imported on first use: numba takes a few tenths of a second to import.
"""

from __future__ import annotations

import math

import numpy as np

from portable_math.jit import numba  # SVML off: the same bits on every machine


@numba.njit(cache=True)
def team_rows(selfs, balls, players, n, me_rows, resolution, flat, present, mates_fallen,
              opponents_present, opponents_fallen, obstacle_mask):
    """Fill, per agent ``a``: ``flat[a]`` (count + 3, 2) = the players (teammates then
    opponents), own position, ball and ball velocity in the team frame, rounded to
    ``resolution`` (none when it is NaN), the own row = the own position; the masks of
    present and fallen teammates (own row: present, own fall) and opponents, and the
    obstacles (every present player but oneself). Returns False where a position or the
    ball is not finite (the caller then names the agent)."""
    count = players.shape[1]
    rounding = not math.isnan(resolution)
    for a in range(selfs.shape[0]):
        px, py, h = selfs[a, 0], selfs[a, 1], selfs[a, 2]
        c, s = math.cos(h), math.sin(h)
        bx, by = balls[a, 0], balls[a, 1]
        ball_x = px + (c * bx - s * by)
        ball_y = py + (s * bx + c * by)
        if not math.isfinite(px + py + ball_x + ball_y):
            return False
        for k in range(count):
            x, y = players[a, k, 0], players[a, k, 1]
            flat[a, k, 0] = (c * x - s * y) + px
            flat[a, k, 1] = (s * x + c * y) + py
        flat[a, count, 0], flat[a, count, 1] = px, py
        flat[a, count + 1, 0], flat[a, count + 1, 1] = ball_x, ball_y
        bvx, bvy = balls[a, 2], balls[a, 3]
        flat[a, count + 2, 0] = c * bvx - s * bvy
        flat[a, count + 2, 1] = s * bvx + c * bvy
        if rounding:
            for k in range(count + 3):
                for j in range(2):
                    flat[a, k, j] = np.round(flat[a, k, j] / resolution) * resolution + 0.0
        me = me_rows[a]
        flat[a, me, 0], flat[a, me, 1] = flat[a, count, 0], flat[a, count, 1]
        for k in range(n):
            present[a, k] = players[a, k, 4] > 0.5
            mates_fallen[a, k] = players[a, k, 3] > 0.5
            opponents_present[a, k] = players[a, n + k, 4] > 0.5
            opponents_fallen[a, k] = players[a, n + k, 3] > 0.5
        present[a, me] = True
        mates_fallen[a, me] = selfs[a, 6] > 0.5
        for k in range(n):
            obstacle_mask[a, k] = present[a, k]
            obstacle_mask[a, n + k] = opponents_present[a, k]
        obstacle_mask[a, me] = False
    return True
