"""Compiled kernels (numba) of the simulation's per-cycle array work: every agent's flat
observation row (``StatePerception.observe``) and the heard slots of every listener
(``Simulation._deliver``), each in one loop instead of some ten to thirty small NumPy
operations of about a microsecond each.

They compute exactly what the NumPy formulas computed, operation for operation (each product
rounded, then the sum; no fused multiply-add, no fast-math), so every bit is the same: the
cosines and sines of the headings come in from NumPy (float64 ``cos``/``sin`` are the same on
every CPU), and the angle wrap is ``(a + pi) % 2 pi - pi`` with Python's (= NumPy's) float
remainder, which is exact. Imported on first use, not with ``teamenv``: importing
numba takes a few tenths of a second, compiling once (then cached on disk) a few seconds.
"""

from __future__ import annotations

import math

import numpy as np

from portable_math.jit import numba  # SVML off: the same bits on every machine

_PI = math.pi
_TWO_PI = 2.0 * math.pi


@numba.njit(cache=True, error_model="numpy")
def _wrap(angle: float) -> float:
    return (angle + _PI) % _TWO_PI - _PI


@numba.njit(cache=True, error_model="numpy")
def state_rows(poses: np.ndarray, velocities: np.ndarray, ball: np.ndarray,
               fallen: np.ndarray, cos_h: np.ndarray, sin_h: np.ndarray, sign: np.ndarray,
               cols: np.ndarray, block: np.ndarray, time_s: float, heard: np.ndarray,
               offsets: np.ndarray, out: np.ndarray) -> None:
    """Fill ``out`` (n, width) float32 with the rows of ``StateLayout``.

    poses, velocities (n, 3), ball (4,) world frame; fallen (n,) 0/1; cos_h, sin_h (n,) of the
    headings; sign (n,) +1 / -1 the attack direction of each agent's team; cols (n, n) the
    player order of each agent (own team first); block (n, o_heard - o_mode) the play-mode
    one-hot and game part (its time column is overwritten); heard (n, K * HEARD_DIM);
    offsets: ball, players, play mode, game, heard columns; player columns are 5 wide
    (x, y, heading, fallen, present).
    """
    n = poses.shape[0]
    o_ball, o_players, o_mode, o_game, o_heard = (offsets[0], offsets[1], offsets[2],
                                                  offsets[3], offsets[4])
    n_block = o_heard - o_mode
    n_heard = heard.shape[1]
    for i in range(n):
        row = out[i]
        sg = sign[i]
        x = poses[i, 0]
        y = poses[i, 1]
        h = poses[i, 2]
        row[0] = sg * x
        row[1] = sg * y
        row[2] = h if sg > 0.0 else _wrap(h + _PI)
        row[3] = sg * velocities[i, 0]
        row[4] = sg * velocities[i, 1]
        row[5] = velocities[i, 2]
        row[6] = fallen[i]
        # body frame: x' = c dx + s dy, y' = (-s) dx + c dy
        c = cos_h[i]
        s = sin_h[i]
        ms = -s
        dx = ball[0] - x
        dy = ball[1] - y
        row[o_ball] = c * dx + s * dy
        row[o_ball + 1] = ms * dx + c * dy
        row[o_ball + 2] = c * ball[2] + s * ball[3]
        row[o_ball + 3] = ms * ball[2] + c * ball[3]
        for k in range(n):
            j = cols[i, k]
            dx = poses[j, 0] - x
            dy = poses[j, 1] - y
            p = o_players + 5 * k
            row[p] = c * dx + s * dy
            row[p + 1] = ms * dx + c * dy
            row[p + 2] = _wrap(poses[j, 2] - h)
            row[p + 3] = fallen[j]
            row[p + 4] = 1.0
        for k in range(n_block):
            row[o_mode + k] = block[i, k]
        row[o_game] = time_s
        for k in range(n_heard):
            row[o_heard + k] = heard[i, k]


@numba.njit(cache=True)
def fill_heard(listener: np.ndarray, is_self: np.ndarray, teammate: np.ndarray,
               direction: np.ndarray, heard: np.ndarray, slot: np.ndarray) -> None:
    """Write (listener, message) pairs, sorted by listener, into the heard slots: slot =
    rank within the listener; ``heard`` (n, K, 4) rows become (1, is_self, teammate,
    direction) and ``slot`` (P,) gets each pair's slot."""
    first = 0
    for k in range(listener.shape[0]):
        li = listener[k]
        if k == 0 or li != listener[k - 1]:
            first = k
        s = k - first
        slot[k] = s
        heard[li, s, 0] = 1.0
        heard[li, s, 1] = 1.0 if is_self[k] else 0.0
        heard[li, s, 2] = 1.0 if teammate[k] else 0.0
        heard[li, s, 3] = direction[k]


@numba.njit(cache=True, error_model="numpy")
def world_velocities(delta: np.ndarray, poses: np.ndarray, dt: float, out: np.ndarray) -> None:
    """The world-frame velocity of each body that moved ``delta`` (n, 3), body frame at the
    cycle's start, over ``dt``: ``out`` (n, 3) = ((c dx - s dy) / dt, (s dx + c dy) / dt,
    dpsi / dt), c, s the cosine and sine of the heading ``poses[:, 2]`` (the C library's, as
    NumPy's float64 ``cos``/``sin``)."""
    for i in range(delta.shape[0]):
        h = poses[i, 2]
        c = math.cos(h)
        s = math.sin(h)
        dx = delta[i, 0]
        dy = delta[i, 1]
        out[i, 0] = (c * dx - s * dy) / dt
        out[i, 1] = (s * dx + c * dy) / dt
        out[i, 2] = delta[i, 2] / dt
