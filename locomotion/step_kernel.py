"""``Bodies.step`` as one compiled loop (numba): the walk, falls, kicks, odometry and fall
timers of every body in one call instead of some sixty small NumPy operations.

It computes what the NumPy formulas of the model computed, operation for operation, so every
bit is the same: each product rounded, then the sum, in NumPy's order (no fused multiply-add,
no fast-math); ``sin``/``cos``/``pow`` are the C library's (the functions NumPy's float64
loops and ``portable_math`` call); ``np.interp`` is written out as NumPy's C code computes it,
and the float remainder is Python's (= NumPy's: exact). Random numbers are drawn from the env's own NumPy ``Generator``
(numba's port draws the same values and advances the same state), in the same order and the
same block sizes as before: ``n`` uniforms for impact falls, ``n`` for command-jump falls,
``k`` normals for the distances and ``k`` for the directions of ``k`` kicks, ``3 n`` for the
odometry noise. Imported on first use: compiling takes a few seconds once, then numba's disk
cache serves it.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba.typed import List

_EPS = 1e-9
_PI = math.pi
_TWO_PI = 2.0 * math.pi

# Indices into the kernel's parameter vector (``Bodies._params``).
(P_T, P_VX_FWD, P_VX_BACK, P_VY, P_TURN, P_EXPONENT, P_J_LO, P_J_HI, P_JUMP_THRESHOLD,
 P_JUMP_PROBABILITY, P_DOWN_TIME, P_KICK_SIGMA, P_KICK_MAX_ANGLE, P_KICK_PREP,
 P_KICK_DURATION, P_KICK_MEAN, P_KICK_STD, P_KICK_MIN, P_KICK_MAX, P_ODOMETRY_NOISY) = range(20)
N_PARAMS = 20
# Indices into the kernel's counters (``Bodies._counts``): bodies down, bodies kicking.
C_DOWN, C_KICKING = range(2)


@numba.njit(cache=True)
def rng_box(rng):
    """A typed list holding the ``Generator``: passing it costs ~1 µs a call, passing the
    Generator itself ~14 µs (numba unboxes its bit generator's function pointers each time).
    The list keeps a reference to the Python Generator, so its state stays alive."""
    box = List()
    box.append(rng)
    return box


@numba.njit(cache=True, inline="always")
def _interp(x: float, xp: np.ndarray, fp: np.ndarray) -> float:
    """``np.interp(x, xp, fp)`` for one value, as NumPy's C loop computes it."""
    n = xp.shape[0]
    if n == 1:
        return fp[0]
    if x > xp[n - 1]:
        return fp[n - 1]
    if x < xp[0]:
        return fp[0]
    if x == xp[n - 1]:
        return fp[n - 1]
    lo = 0
    hi = n - 1
    while hi - lo > 1:  # xp[lo] <= x < xp[hi]: lo ends at the last xp <= x
        mid = (lo + hi) // 2
        if xp[mid] <= x:
            lo = mid
        else:
            hi = mid
    j = lo
    if xp[j] == x:
        return fp[j]
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    out = slope * (x - xp[j]) + fp[j]
    if out != out:
        out = slope * (x - xp[j + 1]) + fp[j + 1]
        if out != out and fp[j] == fp[j + 1]:
            out = fp[j]
    return out


@numba.njit(cache=True, inline="always")
def _envelope_scale(vx: float, vy: float, w: float, prm: np.ndarray) -> float:
    """1 / max(||u||_p, 1) of ``walk.apply_envelope`` (p = 2: ``einsum``'s order, u0² + u2²
    first, then u1²)."""
    p = prm[P_EXPONENT]
    if p == 2.0:
        ix = 1.0 / prm[P_VX_FWD] if vx >= 0.0 else 1.0 / prm[P_VX_BACK]
        ux = vx * ix
        uy = vy * (1.0 / prm[P_VY])
        uw = w * (1.0 / prm[P_TURN])
        norm = math.sqrt((ux * ux + uw * uw) + uy * uy)
    else:
        ux = vx / (prm[P_VX_FWD] if vx >= 0.0 else prm[P_VX_BACK])
        norm = math.pow(
            (math.pow(abs(ux), p) + math.pow(abs(vy / prm[P_VY]), p))
            + math.pow(abs(w / prm[P_TURN]), p), 1.0 / p)
    return 1.0 / max(norm, 1.0)


@numba.njit(cache=True, inline="always")
def _omni(vx: float, vy: float, w: float, tau: float, out: np.ndarray, i: int) -> None:
    """``walk.omni_displacement`` of one body into ``out[i]``."""
    theta = w * tau
    half = 0.5 * theta
    h = 1e-300 if half == 0.0 else half
    s = math.sin(h)
    c = math.cos(h)
    f = s / h * tau
    out[i, 0] = f * (vx * c - vy * s)
    out[i, 1] = f * (vx * s + vy * c)
    out[i, 2] = theta


@numba.njit(cache=True)
def step_bodies(box, walk_cmd, kick_request, kick_power_in, kick_dir, impacts, push_fell,
                pushed, dt, prm, tables, dv, lim_fwd, lim_back, odo_scale, odo_noise,
                velocity, phase, down_left, kick_elapsed, kick_power, kick_aim, cache, cached_dt,
                counts, delta, odometry, kick_now, kick_distance, kick_direction, fallen, fell,
                can_act):
    """Advance every body by ``dt``: updates the state arrays (velocity ... cache, counts) in
    place and fills the outputs (delta ... can_act). ``cached_dt`` (1,): the dt of ``cache``
    (the displacement over dt at the current velocities; -1: invalid). ``tables`` (3, 2, m):
    each axis's tracking curve (commanded, achieved), padded by repeating its last point."""
    rng = box[0]
    n = velocity.shape[0]
    T = prm[P_T]
    # -- falls from collisions (then pushes, decided by the caller: no draws) ----------------
    any_down = counts[C_DOWN] > 0
    up = np.empty(n, dtype=np.bool_)
    for i in range(n):
        up[i] = down_left[i] <= 0.0 if any_down else True
        fell[i] = False
    fell_any = False
    j_lo = prm[P_J_LO]
    if impacts.max() > j_lo:
        u = rng.random(n)
        span = max(prm[P_J_HI] - j_lo, _EPS)
        for i in range(n):
            prob = min(max((impacts[i] - j_lo) / span, 0.0), 1.0)
            fell[i] = (impacts[i] > j_lo) and up[i] and (u[i] < prob)
            fell_any = fell_any or fell[i]
    if pushed:
        for i in range(n):
            fell[i] = fell[i] or push_fell[i]
            fell_any = fell_any or fell[i]
    # -- kick starts ------------------------------------------------------------------------
    kicking = np.zeros(n, dtype=np.bool_)
    kick_active = False
    requested = False
    for i in range(n):
        requested = requested or kick_request[i]
    if counts[C_KICKING] or requested:
        max_angle = prm[P_KICK_MAX_ANGLE]
        for i in range(n):
            start = kick_request[i] and kick_power_in[i] > 0.0 and kick_elapsed[i] < 0.0
            if max_angle < _PI:
                start = start and abs((kick_dir[i] + _PI) % _TWO_PI - _PI) <= max_angle
            if any_down:
                start = start and up[i]
            if fell_any:
                start = start and not fell[i]
            if start:
                kick_elapsed[i] = 0.0
                kick_power[i] = min(max(kick_power_in[i], 0.0), 1.0)
                kick_aim[i] = kick_dir[i]
            kicking[i] = kick_elapsed[i] >= 0.0
            kick_active = kick_active or kicking[i]
    all_walk = not (any_down or fell_any or kick_active)
    walking = np.empty(n, dtype=np.bool_)
    for i in range(n):
        walking[i] = all_walk or (up[i] and not (fell_any and fell[i])
                                  and not (kick_active and kicking[i]))
    # -- the walk: constant velocity within a step, the command taken at step boundaries -----
    boundary = np.empty(n, dtype=np.bool_)
    any_boundary = False
    for i in range(n):
        boundary[i] = phase[i] + dt >= T - _EPS and (all_walk or walking[i])
        any_boundary = any_boundary or boundary[i]
    cache_dt = cached_dt[0]
    if dt != cache_dt:  # displacement over dt at the current velocities
        for i in range(n):
            _omni(velocity[i, 0], velocity[i, 1], velocity[i, 2], dt, cache, i)
        cache_dt = dt
    if any_boundary:
        new_vel = np.empty((n, 3))
        tb = np.empty(n)
        risky = np.zeros(n, dtype=np.bool_)
        any_risky = False
        split = False
        threshold = prm[P_JUMP_THRESHOLD]
        for i in range(n):
            tb[i] = max(T - phase[i], 0.0) if boundary[i] else dt
            split = split or tb[i] < dt - _EPS
            if not boundary[i]:
                continue
            tx = _interp(walk_cmd[i, 0], tables[0, 0], tables[0, 1])
            ty = _interp(walk_cmd[i, 1], tables[1, 0], tables[1, 1])
            tw = _interp(walk_cmd[i, 2], tables[2, 0], tables[2, 1])
            scale = _envelope_scale(tx, ty, tw, prm)
            cx = tx * scale - velocity[i, 0]
            cy = ty * scale - velocity[i, 1]
            cw = tw * scale - velocity[i, 2]
            lim = lim_fwd if cx >= 0.0 else lim_back
            qx = cx / lim[0]
            qy = cy / lim[1]
            qw = cw / lim[2]
            jump = math.sqrt((qx * qx + qy * qy) + qw * qw)
            if jump > threshold:
                risky[i] = True
                any_risky = True
            vx = velocity[i, 0] + min(max(cx, -dv[0]), dv[0])
            vy = velocity[i, 1] + min(max(cy, -dv[1]), dv[1])
            vw = velocity[i, 2] + min(max(cw, -dv[2]), dv[2])
            scale = _envelope_scale(vx, vy, vw, prm)
            new_vel[i, 0] = vx * scale
            new_vel[i, 1] = vy * scale
            new_vel[i, 2] = vw * scale
        if any_risky:
            u = rng.random(n)
            prob = prm[P_JUMP_PROBABILITY]
            for i in range(n):
                fell[i] = fell[i] or (risky[i] and u[i] < prob)
                fell_any = fell_any or fell[i]
        if split:  # a boundary inside the cycle: split it exactly
            second = np.empty((n, 3))
            for i in range(n):
                _omni(velocity[i, 0], velocity[i, 1], velocity[i, 2], tb[i], delta, i)
                if boundary[i]:
                    velocity[i, 0] = new_vel[i, 0]
                    velocity[i, 1] = new_vel[i, 1]
                    velocity[i, 2] = new_vel[i, 2]
                _omni(velocity[i, 0], velocity[i, 1], velocity[i, 2], dt - tb[i], second, i)
                c = math.cos(delta[i, 2])
                s = math.sin(delta[i, 2])
                delta[i, 0] = delta[i, 0] + c * second[i, 0] - s * second[i, 1]
                delta[i, 1] = delta[i, 1] + s * second[i, 0] + c * second[i, 1]
                delta[i, 2] = delta[i, 2] + second[i, 2]
        else:  # every boundary falls at the end of the cycle (T a multiple of dt)
            for i in range(n):
                delta[i, 0] = cache[i, 0]
                delta[i, 1] = cache[i, 1]
                delta[i, 2] = cache[i, 2]
                if boundary[i]:
                    velocity[i, 0] = new_vel[i, 0]
                    velocity[i, 1] = new_vel[i, 1]
                    velocity[i, 2] = new_vel[i, 2]
        for i in range(n):
            phase[i] = max(phase[i] + dt - T, 0.0) if boundary[i] else phase[i] + dt
        cache_dt = -1.0
    else:
        for i in range(n):
            delta[i, 0] = cache[i, 0]
            delta[i, 1] = cache[i, 1]
            delta[i, 2] = cache[i, 2]
            phase[i] = phase[i] + dt
    if not all_walk or fell_any:
        for i in range(n):
            moving = walking[i] and not (fell_any and fell[i])
            m = 1.0 if moving else 0.0
            for k in range(3):
                delta[i, k] *= m
                velocity[i, k] = velocity[i, k] * m
            if not moving:
                phase[i] = T
    cached_dt[0] = cache_dt
    # -- kick contact and end (a fall cancels the kick) --------------------------------------
    for i in range(n):
        if fell_any and fell[i]:
            kick_elapsed[i] = -1.0
        kick_now[i] = False
        kick_distance[i] = 0.0
        kick_direction[i] = 0.0
    if not kick_active:
        counts[C_KICKING] = 0
    else:
        prep = prm[P_KICK_PREP]
        k = 0
        for i in range(n):
            e0 = kick_elapsed[i]
            if prep <= _EPS:
                kick_now[i] = e0 >= 0.0 and e0 <= _EPS
            else:
                kick_now[i] = e0 <= prep + _EPS and e0 > max(prep + _EPS - dt, -0.5)
            if kick_now[i]:
                k += 1
        if k:
            dist = rng.normal(prm[P_KICK_MEAN], prm[P_KICK_STD], k)
            aim_noise = rng.normal(0.0, prm[P_KICK_SIGMA], k)
            j = 0
            for i in range(n):
                if kick_now[i]:
                    d = min(max(dist[j], prm[P_KICK_MIN]), prm[P_KICK_MAX])
                    kick_distance[i] = kick_power[i] * d
                    kick_direction[i] = kick_aim[i] + aim_noise[j]
                    j += 1
        n_kicking = 0
        for i in range(n):
            e0 = kick_elapsed[i]
            e1 = e0 + dt
            if e0 < 0.0 or e1 >= prm[P_KICK_DURATION] - _EPS:
                e1 = -1.0
            kick_elapsed[i] = e1
            if e1 >= 0.0:
                n_kicking += 1
        counts[C_KICKING] = n_kicking
    # -- odometry: what the walking engine believes it moved ---------------------------------
    for i in range(n):
        for k in range(3):
            odometry[i, k] = delta[i, k] * odo_scale[k]
    if prm[P_ODOMETRY_NOISY] != 0.0:
        z = rng.standard_normal(3 * n)
        for i in range(n):
            for k in range(3):
                odometry[i, k] *= 1.0 + odo_noise[k] * z[3 * i + k]
    # -- fall timers -------------------------------------------------------------------------
    if not (any_down or fell_any):
        for i in range(n):
            fallen[i] = False
    else:
        n_down = 0
        for i in range(n):
            left = down_left[i] - dt
            if fell_any and fell[i]:
                left = prm[P_DOWN_TIME]
            if left <= _EPS:
                left = 0.0
            down_left[i] = left
            fallen[i] = left > 0.0
            if fallen[i]:
                n_down += 1
        counts[C_DOWN] = n_down
    kicking_after = counts[C_KICKING] > 0
    for i in range(n):
        can_act[i] = not (fallen[i] or (kicking_after and kick_elapsed[i] >= 0.0))

