"""``Bodies.step`` as compiled loops (numba): the walk, falls, kicks, odometry and fall timers
of every body in one to three calls instead of some sixty small NumPy operations.

It computes what the NumPy formulas of the model computed, operation for operation, so every
bit is the same: each product rounded, then the sum, in NumPy's order (no fused multiply-add,
no fast-math); ``sin``/``cos``/``pow`` are the C library's (the functions NumPy's float64
loops and ``portable_math`` call); ``np.interp`` is written out as NumPy's C code computes it,
and the float remainder is Python's (= NumPy's: exact).

Random numbers are drawn by the caller from the env's own NumPy ``Generator``, in the same
order and block sizes as the NumPy step drew them, and handed in: the kernel never sees the
generator (numba unboxes a ``Generator`` argument through Python on every call, some 10 µs,
more with cold caches inside a match). The step is one resumable kernel: ``step_bodies``
runs from ``stage`` until it needs numbers that depend on its own state so far, and says
which (``NEED_JUMP_DRAWS``: ``n`` uniforms for the command-jump falls; ``NEED_KICK_DRAWS``:
``k`` normals for the distances, then ``k`` for the directions of the ``k`` kicks that touch
now, ``k`` in ``counts[F_KICKS]``); the caller draws them and calls again from there, until
``DONE``. The impact uniforms (known from the impacts alone) are drawn before the first call,
the odometry noise (``3 n`` normals, the last draw) after the last. Imported on first use:
compiling takes a few seconds once, then numba's disk cache serves it.
"""

from __future__ import annotations

import math

import numpy as np

from portable_math.jit import numba  # SVML off: the same bits on every machine

_EPS = 1e-9
_PI = math.pi
_TWO_PI = 2.0 * math.pi

# Indices into the kernel's parameter vector (``Bodies._params``).
(P_T, P_VX_FWD, P_VX_BACK, P_VY, P_TURN, P_EXPONENT, P_J_LO, P_J_HI, P_JUMP_THRESHOLD,
 P_JUMP_PROBABILITY, P_DOWN_TIME, P_KICK_SIGMA, P_KICK_MAX_ANGLE, P_KICK_PREP,
 P_KICK_DURATION, P_KICK_MEAN, P_KICK_STD, P_KICK_MIN, P_KICK_MAX) = range(19)
N_PARAMS = 19
# Rows of the kernel's vector table (``Bodies._vectors``), 3 columns each.
V_DV, V_LIM_FWD, V_LIM_BACK, V_ODOMETRY_SCALE = range(4)
# The kernel's counters and flags (``Bodies._counts``): the first two persist between steps
# (bodies down, bodies kicking), the rest carry a step from one stage to the next.
(C_DOWN, C_KICKING, F_ANY_DOWN, F_FELL_ANY, F_KICK_ACTIVE, F_ALL_WALK, F_ANY_BOUNDARY,
 F_SPLIT, F_KICKS) = range(9)
N_COUNTS = 9
# Rows of the per-body scratch the stages hand on: bool (``Bodies._flags``) and float.
B_WALKING, B_BOUNDARY, B_RISKY = range(3)
S_TB, S_VX, S_VY, S_VW = range(4)
# Stages (where a call starts) and answers (what the call needs to go on).
START, AFTER_JUMP_DRAWS, AFTER_KICK_DRAWS, NEED_JUMP_DRAWS, NEED_KICK_DRAWS, DONE = range(6)


@numba.njit(cache=True)
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


@numba.njit(cache=True)
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


@numba.njit(cache=True)
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
def step_bodies(stage, draws, walk_cmd, kick_request, kick_power_in, kick_dir, impacts,
                push_fell, pushed, dt, prm, tables, vectors, velocity, phase, down_left,
                kick_elapsed, kick_power, kick_aim, cache, cache_dt, counts, flags, scratch,
                delta, odometry, kick_now, kick_distance, kick_direction, fallen, fell,
                can_act):
    """Advance every body by ``dt`` from ``stage`` (see the module doc); returns
    ``NEED_JUMP_DRAWS``, ``NEED_KICK_DRAWS`` or ``DONE``.

    ``draws``: at ``START`` the ``n`` impact uniforms (empty when no impact exceeds the
    profile's low impulse), else what the last answer asked for. Updates the state arrays
    (velocity ... cache) in place and fills the outputs (delta ... can_act); ``odometry`` is
    the scaled displacement, before the noise the caller multiplies in. ``cache_dt`` (1,): the
    dt of ``cache`` (the displacement over dt at the current velocities; -1: invalid).
    ``tables`` (3, 2, m): each axis's tracking curve (commanded, achieved), padded by
    repeating its last point."""
    if stage == START:
        if _start(draws, walk_cmd, kick_request, kick_power_in, kick_dir, impacts, push_fell,
                  pushed, dt, prm, tables, vectors, velocity, phase, down_left, kick_elapsed,
                  kick_power, kick_aim, cache, cache_dt, counts, flags, scratch, fell):
            return NEED_JUMP_DRAWS
        stage = AFTER_JUMP_DRAWS
        draws = draws[:0]
    if stage == AFTER_JUMP_DRAWS:
        if _walk(draws, dt, prm, velocity, phase, kick_elapsed, cache, cache_dt, counts, flags,
                 scratch, delta, kick_now, fell):
            return NEED_KICK_DRAWS
        draws = draws[:0]
    _finish(draws, dt, prm, vectors, down_left, kick_elapsed, kick_power, kick_aim, counts,
            delta, odometry, kick_now, kick_distance, kick_direction, fallen, fell, can_act)
    return DONE


@numba.njit(cache=True)
def _start(draws, walk_cmd, kick_request, kick_power_in, kick_dir, impacts, push_fell, pushed,
           dt, prm, tables, vectors, velocity, phase, down_left, kick_elapsed, kick_power,
           kick_aim, cache, cache_dt, counts, flags, scratch, fell) -> bool:
    """Falls from collisions and pushes, kick starts, the walk's step boundaries and their
    new velocities. Returns whether a command jump may topple a body (draws needed)."""
    n = velocity.shape[0]
    T = prm[P_T]
    # -- falls from collisions (the caller drew the uniforms), then pushes (no draws) --------
    any_down = counts[C_DOWN] > 0
    fell_any = False
    j_lo = prm[P_J_LO]
    span = max(prm[P_J_HI] - j_lo, _EPS)
    for i in range(n):
        up = down_left[i] <= 0.0 if any_down else True
        f = False
        if draws.shape[0]:
            prob = min(max((impacts[i] - j_lo) / span, 0.0), 1.0)
            f = (impacts[i] > j_lo) and up and (draws[i] < prob)
        if pushed:
            f = f or push_fell[i]
        fell[i] = f
        fell_any = fell_any or f
    # -- kick starts ------------------------------------------------------------------------
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
                start = start and down_left[i] <= 0.0
            if fell_any:
                start = start and not fell[i]
            if start:
                kick_elapsed[i] = 0.0
                kick_power[i] = min(max(kick_power_in[i], 0.0), 1.0)
                kick_aim[i] = kick_dir[i]
            kick_active = kick_active or kick_elapsed[i] >= 0.0
    all_walk = not (any_down or fell_any or kick_active)
    walking = flags[B_WALKING]
    for i in range(n):
        up = down_left[i] <= 0.0 if any_down else True
        walking[i] = all_walk or (up and not (fell_any and fell[i])
                                  and not (kick_active and kick_elapsed[i] >= 0.0))
    # -- the walk's step boundaries: the command taken, the new velocity, the jump ----------
    boundary = flags[B_BOUNDARY]
    risky = flags[B_RISKY]
    any_boundary = False
    for i in range(n):
        boundary[i] = phase[i] + dt >= T - _EPS and (all_walk or walking[i])
        any_boundary = any_boundary or boundary[i]
    if dt != cache_dt[0]:  # displacement over dt at the current velocities
        for i in range(n):
            _omni(velocity[i, 0], velocity[i, 1], velocity[i, 2], dt, cache, i)
        cache_dt[0] = dt
    any_risky = False
    split = False
    if any_boundary:
        tb = scratch[S_TB]
        threshold = prm[P_JUMP_THRESHOLD]
        dv = vectors[V_DV]
        for i in range(n):
            risky[i] = False
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
            lim = vectors[V_LIM_FWD] if cx >= 0.0 else vectors[V_LIM_BACK]
            qx = cx / lim[0]
            qy = cy / lim[1]
            qw = cw / lim[2]
            if math.sqrt((qx * qx + qy * qy) + qw * qw) > threshold:
                risky[i] = True
                any_risky = True
            vx = velocity[i, 0] + min(max(cx, -dv[0]), dv[0])
            vy = velocity[i, 1] + min(max(cy, -dv[1]), dv[1])
            vw = velocity[i, 2] + min(max(cw, -dv[2]), dv[2])
            scale = _envelope_scale(vx, vy, vw, prm)
            scratch[S_VX, i] = vx * scale
            scratch[S_VY, i] = vy * scale
            scratch[S_VW, i] = vw * scale
    counts[F_ANY_DOWN] = any_down
    counts[F_FELL_ANY] = fell_any
    counts[F_KICK_ACTIVE] = kick_active
    counts[F_ALL_WALK] = all_walk
    counts[F_ANY_BOUNDARY] = any_boundary
    counts[F_SPLIT] = split
    return any_risky


@numba.njit(cache=True)
def _walk(draws, dt, prm, velocity, phase, kick_elapsed, cache, cache_dt, counts, flags,
          scratch, delta, kick_now, fell) -> bool:
    """Falls from command jumps (``draws``: their uniforms, or empty), the displacement over
    the cycle, kick contact. Returns whether kicks touch the ball now (draws needed)."""
    n = velocity.shape[0]
    T = prm[P_T]
    fell_any = counts[F_FELL_ANY] != 0
    walking, boundary, risky = flags[B_WALKING], flags[B_BOUNDARY], flags[B_RISKY]
    if draws.shape[0]:
        prob = prm[P_JUMP_PROBABILITY]
        for i in range(n):
            fell[i] = fell[i] or (risky[i] and draws[i] < prob)
            fell_any = fell_any or fell[i]
    if counts[F_ANY_BOUNDARY]:
        tb = scratch[S_TB]
        if counts[F_SPLIT]:  # a boundary inside the cycle: split it exactly
            for i in range(n):
                _omni(velocity[i, 0], velocity[i, 1], velocity[i, 2], tb[i], delta, i)
                if boundary[i]:
                    velocity[i, 0] = scratch[S_VX, i]
                    velocity[i, 1] = scratch[S_VY, i]
                    velocity[i, 2] = scratch[S_VW, i]
                d0, d1, d2 = delta[i, 0], delta[i, 1], delta[i, 2]
                _omni(velocity[i, 0], velocity[i, 1], velocity[i, 2], dt - tb[i], delta, i)
                c = math.cos(d2)
                s = math.sin(d2)
                e0, e1, e2 = delta[i, 0], delta[i, 1], delta[i, 2]
                delta[i, 0] = d0 + c * e0 - s * e1
                delta[i, 1] = d1 + s * e0 + c * e1
                delta[i, 2] = d2 + e2
        else:  # every boundary falls at the end of the cycle (T a multiple of dt)
            for i in range(n):
                delta[i, 0] = cache[i, 0]
                delta[i, 1] = cache[i, 1]
                delta[i, 2] = cache[i, 2]
                if boundary[i]:
                    velocity[i, 0] = scratch[S_VX, i]
                    velocity[i, 1] = scratch[S_VY, i]
                    velocity[i, 2] = scratch[S_VW, i]
        for i in range(n):
            phase[i] = max(phase[i] + dt - T, 0.0) if boundary[i] else phase[i] + dt
        cache_dt[0] = -1.0
    else:
        for i in range(n):
            delta[i, 0] = cache[i, 0]
            delta[i, 1] = cache[i, 1]
            delta[i, 2] = cache[i, 2]
            phase[i] = phase[i] + dt
    if not counts[F_ALL_WALK] or fell_any:
        for i in range(n):
            moving = walking[i] and not (fell_any and fell[i])
            m = 1.0 if moving else 0.0
            for k in range(3):
                delta[i, k] *= m
                velocity[i, k] = velocity[i, k] * m
            if not moving:
                phase[i] = T
    counts[F_FELL_ANY] = fell_any
    # -- kick contact (a fall cancels the kick) ----------------------------------------------
    kicks = 0
    for i in range(n):
        if fell_any and fell[i]:
            kick_elapsed[i] = -1.0
        kick_now[i] = False
    if counts[F_KICK_ACTIVE]:
        prep = prm[P_KICK_PREP]
        for i in range(n):
            e0 = kick_elapsed[i]
            if prep <= _EPS:
                kick_now[i] = e0 >= 0.0 and e0 <= _EPS
            else:
                kick_now[i] = e0 <= prep + _EPS and e0 > max(prep + _EPS - dt, -0.5)
            if kick_now[i]:
                kicks += 1
    counts[F_KICKS] = kicks
    return kicks > 0


@numba.njit(cache=True)
def _finish(draws, dt, prm, vectors, down_left, kick_elapsed, kick_power, kick_aim, counts,
            delta, odometry, kick_now, kick_distance, kick_direction, fallen, fell, can_act):
    """The kicks' distances and directions (``draws``: k distance normals, then k direction
    normals), the kicks' clocks, the odometry (before its noise), the fall timers."""
    n = down_left.shape[0]
    kicks = counts[F_KICKS]
    j = 0
    for i in range(n):
        kick_distance[i] = 0.0
        kick_direction[i] = 0.0
        if kicks and kick_now[i]:
            d = min(max(draws[j], prm[P_KICK_MIN]), prm[P_KICK_MAX])
            kick_distance[i] = kick_power[i] * d
            kick_direction[i] = kick_aim[i] + draws[kicks + j]
            j += 1
    if not counts[F_KICK_ACTIVE]:
        counts[C_KICKING] = 0
    else:
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
    scale = vectors[V_ODOMETRY_SCALE]
    for i in range(n):
        for k in range(3):
            odometry[i, k] = delta[i, k] * scale[k]
    fell_any = counts[F_FELL_ANY] != 0
    if not (counts[F_ANY_DOWN] or fell_any):
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


