"""A team's walk commands (``walk_batch.walk_commands``) as one compiled loop (numba).

Per agent a few dozen float operations and a handful of elementary functions: in Python and
NumPy that was ~30 µs per agent of call overhead. Each step here is written as the Python
(``navigation.approach``, ``walk_along``) or NumPy (the repulsion sum of ``field_vector``)
it replaces, in the same order of IEEE operations: Python's ``max``/``min`` and ``%`` (numba
keeps Python's float semantics), Python's own ``math.hypot`` (``py_hypot``), the NumPy sum over obstacles row by row from the first,
and the C library's ``atan2``, ``cos``, ``sin`` and ``pow`` (numba calls the
functions Python's ``math`` calls; ``pow``'s exponent comes as data, see
``walk_batch.REPULSION_EXPONENT``). Tested bit for bit against ``walk_command``.

Imported on first use: numba takes a few tenths of a second to import.
"""

from __future__ import annotations

import math

from portable_math.jit import numba  # SVML off: the same bits on every machine

# ``params``' entries (``walk_batch._packed`` writes them in this order)
(K_ATTRACT, K_REPULSE, INFLUENCE_M, MAX_SPEED, SLOW_DOWN_M, ARRIVE_M, TURN_GAIN,
 TURN_IN_PLACE_RAD, OMNI_M, MIN_SPEED, REPULSION_EXPONENT, SIDE_STEP_LEFT, SIDE_STEP_RIGHT,
 SIDE_STEP_SHARE) = range(14)

_PI = math.pi
_TWO_PI = 2.0 * math.pi
_THIRD_PI = math.pi / 3


@numba.njit(inline="always")
def _wrap(angle):
    """``strategy.geometry.wrap_angle``: Python's float ``%``, which numba keeps."""
    return (angle + _PI) % _TWO_PI - _PI


_DBL_MIN = 2.2250738585072014e-308
_SPLIT = 134217729.0  # 2^27 + 1, Dekker's splitter


@numba.njit(inline="always")
def _two_prod(a, b):
    """a * b = p + e exactly (Dekker; |a|, |b| < 1e300): the error term an FMA gives."""
    p = a * b
    ca, cb = _SPLIT * a, _SPLIT * b
    ah = ca - (ca - a)
    bh = cb - (cb - b)
    al, bl = a - ah, b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@numba.njit(inline="always")
def _norm2(x, y, largest):
    """CPython's ``vector_norm`` of two non-negative finite legs, the larger one normal:
    the squares summed in double length from a scaled start, a square root and one Newton
    correction."""
    _, e = math.frexp(largest)
    scale = math.ldexp(1.0, -e)
    csum, frac1, frac2 = 1.0, 0.0, 0.0
    for leg in (x, y):
        leg = leg * scale
        hi, lo = _two_prod(leg, leg)
        total = csum + hi
        frac1 += lo
        frac2 += hi - (total - csum)
        csum = total
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    hi, lo = _two_prod(-h, h)
    total = csum + hi
    frac1 += lo
    frac2 += hi - (total - csum)
    csum = total
    h += (csum - 1.0 + (frac1 + frac2)) / (2.0 * h)
    return h / scale


@numba.njit(cache=True)
def py_hypot(x, y):
    """Python's ``math.hypot(x, y)``, bit for bit: CPython computes it itself (more exactly
    than the C library's ``hypot``, which numba's ``math.hypot`` calls)."""
    x, y = abs(x), abs(y)
    largest = x if x > y else y
    if math.isinf(x) or math.isinf(y):
        return math.inf
    if math.isnan(x) or math.isnan(y):
        return math.nan
    if largest == 0.0:
        return largest
    if math.frexp(largest)[1] < -1023:  # ldexp(1, -e) would overflow: scaled up first
        return _DBL_MIN * _norm2(x / _DBL_MIN, y / _DBL_MIN, largest / _DBL_MIN)
    return _norm2(x, y, largest)


@numba.njit(inline="always")
def _py_max(a, b):
    """Python's ``max(a, b)`` of two floats."""
    return b if b > a else a


@numba.njit(inline="always")
def _py_min(a, b):
    """Python's ``min(a, b)`` of two floats."""
    return b if b < a else a


@numba.njit(cache=True)
def walk_commands(position, heading, target, face, has_face, speed, has_speed, players, avoid,
                  has_avoid, params, out):
    """``out[i]`` = the walk command (vx, vy, vturn) of goal ``i``: ``position`` (B, 2),
    ``heading`` (B,), ``target`` (B, 2), ``face`` (B, 2) where ``has_face``, ``speed`` (B,)
    where ``has_speed`` (else the top speed), the belief's ``players`` (B, M, 2) and the rows
    to walk round, ``avoid`` (B, M), where ``has_avoid``."""
    top_default = params[MAX_SPEED]
    gain = params[TURN_GAIN]
    for i in range(position.shape[0]):
        p0, p1 = position[i, 0], position[i, 1]
        h = heading[i]
        dx, dy = target[i, 0] - p0, target[i, 1] - p1
        dist = py_hypot(dx, dy)
        top = speed[i] if has_speed[i] else top_default
        # navigation.approach: turn to face when arrived, walk straight when near
        facing = False
        face_angle = 0.0
        if has_face[i]:
            fx, fy = face[i, 0] - p0, face[i, 1] - p1
            if fx * fx + fy * fy > 0.0025:
                facing = True
                face_angle = math.atan2(fy, fx)
        if dist < params[ARRIVE_M]:
            turn = _wrap(face_angle - h) if facing else 0.0
            out[i, 0], out[i, 1], out[i, 2] = 0.0, 0.0, gain * turn
            continue
        v = _py_max(_py_min(top, params[MIN_SPEED]),
                    top * _py_min(1.0, dist / _py_max(params[SLOW_DOWN_M], 1e-9)))
        if dist < params[OMNI_M]:
            c, s = math.cos(h), math.sin(h)
            local_x, local_y = c * dx + s * dy, -s * dx + c * dy
            # a side-step the body does not make: walk as if far (navigation.approach)
            if not ((params[SIDE_STEP_LEFT] == 0.0 and local_y > params[SIDE_STEP_SHARE] * dist)
                    or (params[SIDE_STEP_RIGHT] == 0.0
                        and -local_y > params[SIDE_STEP_SHARE] * dist)):
                turn = _wrap(face_angle - h) if facing else 0.0
                out[i, 0], out[i, 1], out[i, 2] = (v * local_x / dist, v * local_y / dist,
                                                   gain * turn)
                continue
        # the potential field (field_vector, direction_to), then walk_along
        straight = math.atan2(dy, dx)
        if dist < 1e-9:
            vx = vy = 0.0
        else:
            scale = params[K_ATTRACT] / dist / dist
            vx, vy = dx * scale, dy * scale
            if has_avoid[i]:
                first = True
                sx = sy = 0.0
                limit = dist + 0.3
                for m in range(players.shape[1]):
                    if not avoid[i, m]:
                        continue
                    rx, ry = players[i, m, 0] - p0, players[i, m, 1] - p1
                    d = math.sqrt(rx * rx + ry * ry)
                    if d < params[INFLUENCE_M] and d > 1e-6 and d < limit:
                        w = params[K_REPULSE] / math.pow(d, params[REPULSION_EXPONENT])
                        if first:
                            sx, sy = w * rx, w * ry
                            first = False
                        else:
                            sx, sy = sx + w * rx, sy + w * ry
                if not first:
                    vx, vy = vx + sx, vy + sy
        if vx != 0.0 or vy != 0.0 or vx != vx or vy != vy:  # ndarray.any(): NaN counts
            theta = math.atan2(vy, vx)
            error = _wrap(theta - straight)
            if abs(error) > _THIRD_PI:
                theta = straight + math.copysign(_THIRD_PI, error if error != 0 else 1.0)
        else:
            theta = straight
        error = _wrap(theta - h)
        turn = gain * error
        if abs(error) > params[TURN_IN_PLACE_RAD]:
            out[i, 0], out[i, 1], out[i, 2] = 0.0, 0.0, turn
            continue
        out[i, 0] = v * _py_max(0.0, math.cos(error))
        out[i, 1] = v * math.sin(error) * 0.3
        out[i, 2] = turn
