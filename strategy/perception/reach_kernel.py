"""How far each teammate must walk to meet the ball, for several beliefs in one compiled pass
(numba, imported on first use): the rows of ``FieldPlayerDecisionMaker.ball_reach``.

A ball at rest (slower than the caller's threshold): each upright teammate's distance to it.
A rolling ball: the earliest time each can be where the ball is (``WorldModel.intercepts``:
the ball's path sampled every ``step`` seconds until it stops), times the running speed.
Absent or fallen teammates: inf.

The same bits as the NumPy expressions (tested against them on random beliefs): ``np.hypot``
and numba's ``math.hypot`` both call the C library's ``hypot``; ``np.arange(0, h + step,
step)`` is ``i * step`` for ``i < ceil((h + step) / step)``; the ball's travel keeps NumPy's
order of operations, with the C library's ``exp``; numba fuses no multiply-add. The ball's
speed, direction and stop time (Python's own ``math.hypot`` and ``log1p``) come from the
caller.
"""

from __future__ import annotations

import math

import numpy as np

from portable_math.jit import numba  # SVML off: the same bits on every machine


@numba.njit(cache=True)
def reach_rows(balls: np.ndarray, directions: np.ndarray, speeds: np.ndarray,
               horizons: np.ndarray, rolling: np.ndarray, mates: np.ndarray,
               upright: np.ndarray, drags: np.ndarray, decels: np.ndarray, run_speed: float,
               step: float, out: np.ndarray) -> None:
    """``out[r, j]``: teammate ``j``'s walking distance to the ball of belief ``r``.

    Args: per belief ``r``: ``balls`` (R, 2), the rolling ball's ``directions`` (R, 2; unit),
    ``speeds`` (R,) and stop times ``horizons`` (R,), ``rolling`` (R,) whether it counts as
    rolling; teammates ``mates`` (R, N, 2), ``upright`` (R, N) present and not fallen; the
    roll, ``drags`` (R,; 1/s) and ``decels`` (R,; m/s^2). ``run_speed`` (m/s); ``step`` (s)."""
    n_rows, n = upright.shape
    for r in range(n_rows):
        bx, by = balls[r, 0], balls[r, 1]
        for j in range(n):
            out[r, j] = math.hypot(mates[r, j, 0] - bx, mates[r, j, 1] - by) \
                if upright[r, j] else np.inf
        if not rolling[r]:
            continue
        speed, horizon, drag, decel = speeds[r], horizons[r], drags[r], decels[r]
        ux, uy = directions[r, 0], directions[r, 1]
        count = int(math.ceil((horizon + step) / step))
        for j in range(n):
            if not upright[r, j]:
                continue
            px, py = mates[r, j, 0], mates[r, j, 1]
            when = -1.0
            reach = 0.0
            t = 0.0
            for i in range(count):
                t = i * step
                # BallRoll.travel(speed, t), its time clipped at the stop
                clipped = min(t, horizon)
                if drag > 1e-9:
                    v_inf = decel / drag
                    travel = (speed + v_inf) * (1.0 - math.exp(-drag * clipped)) / drag \
                        - v_inf * clipped
                else:
                    travel = speed * clipped - 0.5 * decel * clipped * clipped
                reach = math.hypot(px - (bx + travel * ux), py - (by + travel * uy)) / run_speed
                if reach <= t:
                    when = max(reach, t)
                    break
            if when < 0.0:  # never in time: meet it where it stops
                when = max(reach, t)
            out[r, j] = when * run_speed
