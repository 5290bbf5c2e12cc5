"""Float64 elementary functions that give the same bits on every x86-64 CPU with AVX2.

NumPy picks a kernel for ``exp``, ``log``, ``arctan2``, ``tanh``, ``power`` ... by the CPU it
runs on (AVX-512, AVX2, SSE), and the kernels round the last bit differently; a simulation
that feeds such bits back into itself (chaos) then plays another match on another machine.
Every element goes through the C library's scalar functions, the ones Python's ``math`` module
calls, which choose their code path by FMA/AVX2 support only (the same on every AVX2 machine),
whatever the size of the array it is in: an agent's value is the same computed alone or in a
team's batch. They are called from compiled loops (``c_library_loops``, numba), which give
every element the bits ``math`` gives it, without a Python call per element (``exp`` of 400
elements takes ~5.5 µs instead of ~33; of 50, ~3 instead of ~6).
Where ``math`` raises instead of returning C99's special value (``log(0)``, ``exp(1000)``,
``asin(2)``, ``pow(0, -1)``), that element takes a vectorised path computed only with
operations IEEE 754 rounds exactly — ``+ - * /``, ``sqrt``, ``floor``, ``ldexp``/``frexp``,
comparisons, ``copysign`` — within 1-2 ulp of the correctly rounded value (tested against
mpmath), which gives C99's special values (signed zeros, infinities, NaN).

So the same input gives the same output on every such machine with the same NumPy and C
library. Functions take scalars or
arrays (any float dtype; computed in float64) and return float64 like the NumPy function of
the same name. This package is a leaf below ``comms`` and ``locomotion``: it imports nothing
but NumPy (and numba, for its loops, on the first call).
"""

from __future__ import annotations

import math
from functools import cache, partial, wraps
from typing import Any

import numpy as np

__all__ = ["arccos", "arcsin", "arctan", "arctan2", "exp", "exp2", "expm1", "log", "log2",
           "log10", "matmul", "power", "tanh"]

# Constants split hi + lo (hi + lo = the value to ~2^-106); the HI parts of ln 2 and log10(2)
# end in zero bits so that k * HI is exact for every binary exponent k.
_LN2_HI = 6.931471803691238e-01
_LN2_LO = 1.9082149292705877e-10
_INV_LN2 = 1.4426950408889634
_INV_LN10 = 0.4342944819032518
_LOG10_2_HI = 3.010299955494702e-01
_LOG10_2_LO = 1.1451100898021838e-10
_PI_HI, _PI_LO = 3.141592653589793, 1.2246467991473532e-16
_PIO2_HI, _PIO2_LO = 1.5707963267948966, 6.123233995736766e-17
_SQRT_HALF = 0.7071067811865476
# atan(k/8), k = 0..8, as hi + lo (computed with mpmath at 200 bits)
_ATAN_HI = np.array([0.0, 0.12435499454676144, 0.24497866312686414, 0.35877067027057225,
                     0.4636476090008061, 0.5585993153435624, 0.6435011087932844,
                     0.7188299996216245, 0.7853981633974483])
_ATAN_LO = np.array([0.0, -3.1253241424539383e-18, 1.0698755618734451e-17,
                     -2.4623815582638635e-17, 2.2698777452961687e-17, -5.4556305485916264e-18,
                     1.5834785051444286e-17, -2.1478388444456983e-17, 3.061616997868383e-17])
# expm1(r) = r + r^2 * q(r), q's Taylor coefficients 1/2!, 1/3!, ... 1/14! (|r| <= ln2 / 2)
_EXPM1_Q = tuple(1.0 / float(np.prod(np.arange(1, k + 1, dtype=np.float64))) for k in
                 range(14, 1, -1))
# log(1+f) = f - f^2/2 + s * (f^2/2 + R(s^2)), s = f / (2 + f): R's series 2/3 z + 2/5 z^2 ...
_LOG_R = tuple(2.0 / (2 * k + 1) for k in range(10, 0, -1))
# atan(t) = t + t * z * P(z), z = t^2, |t| <= 1/16: P = -1/3 + z/5 - z^2/7 ...
_ATAN_P = tuple((-1.0) ** k / (2 * k + 1) for k in range(7, 0, -1))
_SPLIT = 134217729.0  # 2^27 + 1, Dekker's splitter


def _array(x: Any) -> np.ndarray:
    return np.asarray(x, dtype=np.float64)


def _out(result: np.ndarray) -> Any:
    return result[()] if result.ndim == 0 else result


def _horner(z: np.ndarray, coefficients: tuple[float, ...]) -> np.ndarray:
    p = z * coefficients[0] + coefficients[1]
    for c in coefficients[2:]:
        p = p * z + c
    return p


def _two_prod(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """a * b = p + e exactly (Dekker, no fused multiply-add; |a|, |b| < 1e300)."""
    p = a * b
    ca, cb = _SPLIT * a, _SPLIT * b
    ah = ca - (ca - a)
    bh = cb - (cb - b)
    al, bl = a - ah, b - bh
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e


def _clamp(x: np.ndarray, low: float, high: float) -> np.ndarray:
    return np.minimum(np.maximum(x, low), high)  # keeps NaN


# NaN flows through the arithmetic below; casting it to an integer exponent is harmless (the
# mantissa is NaN already) but warns, hence the errstate around each function's body.
_QUIET = dict(invalid="ignore", over="ignore", under="ignore", divide="ignore")


# -- exp family ------------------------------------------------------------------------------
def _reduce_exp(hi: np.ndarray, lo: np.ndarray | float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """hi + lo = n ln2 + r with n integral and |r| <= ln2/2 (hi within the finite range)."""
    n = np.floor(hi * _INV_LN2 + 0.5)
    r = (hi - n * _LN2_HI) + (lo - n * _LN2_LO)
    return n.astype(np.int32), r


def _expm1_reduced(r: np.ndarray) -> np.ndarray:
    return r + r * r * _horner(r, _EXPM1_Q)


def _exp_hi_lo(hi: np.ndarray, lo: np.ndarray | float = 0.0) -> np.ndarray:
    """exp(hi + lo); overflows to inf and underflows to 0 (call under _QUIET)."""
    n, r = _reduce_exp(_clamp(hi, -746.0, 710.0), lo)
    return np.ldexp(1.0 + _expm1_reduced(r), n)


_pow2 = partial(math.pow, 2.0)
"""``math.pow(2.0, x)``: a partial is called from C, without a Python frame per element."""


def _vectorised_exp(x: Any) -> Any:
    """e**x."""
    x = _array(x)
    with np.errstate(**_QUIET):
        return _out(_exp_hi_lo(x))


def _vectorised_exp2(x: Any) -> Any:
    """2**x."""
    x = _array(x)
    with np.errstate(**_QUIET):
        xc = _clamp(x, -1100.0, 1100.0)
        n = np.floor(xc + 0.5)
        f = xc - n  # exact
        r = f * _LN2_HI + f * _LN2_LO
        return _out(np.ldexp(1.0 + _expm1_reduced(r), n.astype(np.int32)))


def _vectorised_expm1(x: Any) -> Any:
    """e**x - 1, accurate near 0."""
    x = _array(x)
    with np.errstate(**_QUIET):
        n, r = _reduce_exp(_clamp(x, -60.0, 710.0))
        em = _expm1_reduced(r)
        y = np.where(n == 0, em, np.ldexp(em, n) + (np.ldexp(1.0, n) - 1.0))
        return _out(np.where(x == 0.0, x, y))  # expm1(-0) = -0


def _vectorised_tanh(x: Any) -> Any:
    """Hyperbolic tangent, from expm1(-2|x|)."""
    x = _array(x)
    with np.errstate(**_QUIET):
        em = _array(expm1(-2.0 * np.abs(x)))
        return _out(np.copysign(-em / (em + 2.0), x))


# -- log family ------------------------------------------------------------------------------
def _log_parts(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """x = 2^k (1 + f), |f| <= sqrt(2) - 1, for positive finite x: k, f, hfsq = f^2/2 and the
    small correction c with log(1 + f) = f - hfsq + c."""
    m, k = np.frexp(x)
    low = m < _SQRT_HALF
    m = m + m * low
    f = m - 1.0
    s = f / (2.0 + f)
    z = s * s
    hfsq = 0.5 * f * f
    c = s * (hfsq + z * _horner(z, _LOG_R))
    return k - low, f, hfsq, c


def _log_domain(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """C99's special values of log-like functions (0, inf, negative, NaN) in ``y``."""
    if ((x > 0.0) & (x < np.inf)).all():
        return y
    y = np.where(x > 0.0, y, np.where(x == 0.0, -np.inf, np.nan))
    return np.where(x == np.inf, np.inf, y)


def _vectorised_log(x: Any) -> Any:
    """Natural logarithm."""
    x = _array(x)
    with np.errstate(**_QUIET):
        k, f, hfsq, c = _log_parts(x)
        return _out(_log_domain(x, k * _LN2_HI - ((hfsq - (c + k * _LN2_LO)) - f)))


def _vectorised_log2(x: Any) -> Any:
    """Base-2 logarithm (exact for powers of two)."""
    x = _array(x)
    with np.errstate(**_QUIET):
        k, f, hfsq, c = _log_parts(x)
        return _out(_log_domain(x, k + (f - (hfsq - c)) * _INV_LN2))


def _vectorised_log10(x: Any) -> Any:
    """Base-10 logarithm."""
    x = _array(x)
    with np.errstate(**_QUIET):
        k, f, hfsq, c = _log_parts(x)
        y = k * _LOG10_2_HI + ((f - (hfsq - c)) * _INV_LN10 + k * _LOG10_2_LO)
        return _out(_log_domain(x, y))


def _log_hi_lo(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """log(a) = hi + lo to ~2^-62 relative, for positive finite a."""
    k, f, _, c = _log_parts(a)
    p, pe = _two_prod(f, f)
    hp, hpe = 0.5 * p, 0.5 * pe
    t = f - hp                      # |hp| <= |f| / 4: fast two-sum
    t_err = (f - t) - hp
    kh = k * _LN2_HI                # exact
    s = kh + t                      # two-sum
    bb = s - kh
    s_err = (kh - (s - bb)) + (t - bb)
    lo = s_err + (t_err - hpe + c + k * _LN2_LO)
    hi = s + lo
    return hi, lo - (hi - s)


def _vectorised_power(x: Any, y: Any) -> Any:
    """x**y with C99's special cases (negative x only with integral y).

    Within 2 ulp while |y log x| <= 10; log x carries ~2^-62 relative error, so the error grows
    by about 1 ulp per 35 of |y log x| (up to ~20 ulp near overflow)."""
    x = _array(x)
    y = _array(y)
    with np.errstate(**_QUIET):
        a = np.abs(x)
        regular = (a > 0.0) & (a < np.inf)
        hi, lo = _log_hi_lo(np.where(regular, a, 1.0))
        yc = _clamp(y, -1e290, 1e290)
        ph, pl = _two_prod(yc, hi)
        pl = pl + yc * lo
        r = _exp_hi_lo(ph, np.where(np.abs(ph) < 800.0, pl, 0.0))
        if not (regular.all() and np.isfinite(y).all()):
            log_a = np.where(a == 0.0, -np.inf, np.where(a == np.inf, np.inf, 0.0))
            r = np.where(regular, r, _exp_hi_lo(y * log_a))  # 0, inf, NaN: no rounding
            r = np.where((a == 1.0) & np.isinf(y), 1.0, r)  # (-1) ** +-inf
        if (x < 0.0).any() or np.signbit(x).any():
            integral = np.floor(y) == y
            odd = integral & np.isfinite(y) & (np.fmod(y, 2.0) != 0.0)
            r = np.where(np.signbit(x) & odd, -r, r)
            r = np.where((x < 0.0) & np.isfinite(x) & ~integral & np.isfinite(y), np.nan, r)
        r = np.where(np.isnan(x) | np.isnan(y), np.nan, r)
        return _out(np.where((y == 0.0) | (x == 1.0), 1.0, r))


# -- inverse trigonometric ------------------------------------------------------------------
def _atan_unit(a: np.ndarray) -> np.ndarray:
    """atan(a) for a in [0, 1]: atan(k/8) + atan(t), t = (a - k/8) / (1 + a k/8), |t| <= 1/16."""
    k = np.floor(a * 8.0 + 0.5)
    c = k * 0.125
    t = (a - c) / (1.0 + a * c)
    z = t * t
    i = k.astype(np.intp)
    return _ATAN_HI[i] + (_ATAN_LO[i] + (t + t * z * _horner(z, _ATAN_P)))


def _vectorised_arctan2(y: Any, x: Any) -> Any:
    """Angle of the point (x, y), in [-pi, pi], with C99's signed zeros and infinities."""
    y, x = _array(y), _array(x)
    with np.errstate(**_QUIET):
        ay, ax = np.abs(y), np.abs(x)
        a = np.minimum(ay, ax) / np.maximum(ay, ax)
        special = np.isnan(a)  # 0/0, inf/inf or a NaN argument
        if special.any():
            a = np.where(np.isinf(ax) & np.isinf(ay), 1.0, a)
            a = np.where((ax == 0.0) & (ay == 0.0), 0.0, a)
            special = np.isnan(a)
            a = np.where(special, 0.0, a)
        base = _atan_unit(a)
        steep = ay > ax
        th = np.where(steep, _PIO2_HI - (np.copysign(base, x) - _PIO2_LO),
                      np.where(np.signbit(x), _PI_HI - (base - _PI_LO), base))
        if special.any():
            th = np.where(special, np.nan, th)
        return _out(np.copysign(th, y))


def _vectorised_arctan(x: Any) -> Any:
    """Inverse tangent, in [-pi/2, pi/2]."""
    x = _array(x)
    with np.errstate(**_QUIET):
        a = np.abs(x)
        big = a > 1.0
        u = np.where(big, 1.0 / a, a)
        nan = np.isnan(u)
        base = _atan_unit(np.where(nan, 0.0, u))
        th = np.where(big, _PIO2_HI - (base - _PIO2_LO), base)
        th = np.where(nan, np.nan, th)
        return _out(np.copysign(th, x))


def _cosine_side(x: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        return np.sqrt((1.0 - x) * (1.0 + x))


def _vectorised_arcsin(x: Any) -> Any:
    """Inverse sine, in [-pi/2, pi/2]; NaN outside [-1, 1]."""
    x = _array(x)
    return arctan2(x, _cosine_side(x))


def _vectorised_arccos(x: Any) -> Any:
    """Inverse cosine, in [0, pi]; NaN outside [-1, 1]."""
    x = _array(x)
    return arctan2(_cosine_side(x), x)


# -- products without BLAS ------------------------------------------------------------------
def matmul(a: Any, b: Any) -> Any:
    """``a @ b`` (NumPy's matmul rules, any dtype) summed by ``np.einsum``, not by BLAS.

    OpenBLAS picks its kernels (and with them the order of the sums) by CPU, so ``@``,
    ``np.dot`` and ``np.matmul`` round differently on different machines; einsum's loops are
    chosen when NumPy is built, not at run time."""
    a, b = np.asarray(a), np.asarray(b)
    if a.ndim == 0 or b.ndim == 0:
        raise ValueError("matmul: scalar operands are not allowed, use *")
    if a.ndim == 1 and b.ndim == 1:
        return np.einsum("i,i->", a, b)
    if b.ndim == 1:
        return np.einsum("...ij,j->...i", a, b)
    if a.ndim == 1:
        return np.einsum("j,...jk->...k", a, b)
    return np.einsum("...ij,...jk->...ik", a, b)


# -- the public functions: the C library element by element -------------------------------
@cache
def _loop(name: str) -> Any:
    """The compiled loop of ``math.<name>``, imported on the first call: numba takes a few
    tenths of a second to import."""
    from portable_math import c_library_loops

    return c_library_loops.function(name)


def _one_by_one(function: Any, vectorised: Any, columns: list[np.ndarray]) -> np.ndarray:
    """``function`` (a ``math`` function) on each element of the flat ``columns``; where it
    raises, ``vectorised`` (C99's value)."""
    lists = [c.tolist() for c in columns]
    try:
        return np.array(list(map(function, *lists)), dtype=np.float64)
    except (ValueError, OverflowError):
        pass
    values, failed = [], []
    for items in zip(*lists, strict=True):
        try:
            values.append(function(*items))
            failed.append(False)
        except (ValueError, OverflowError):
            values.append(0.0)
            failed.append(True)
    out = np.array(values, dtype=np.float64)
    mask = np.array(failed, dtype=bool)
    with np.errstate(**_QUIET):
        out[mask] = vectorised(*(c[mask] for c in columns))
    return out


def _elementwise(function: Any, vectorised: Any, name: str, loop: str) -> Any:
    """``function`` (a ``math`` function of one or two floats) on every element of its
    broadcast arguments, through the compiled loop of ``math.<loop>`` (``c_library_loops``:
    the same C calls); the elements the loop leaves (NaN, or where ``function`` raises) one
    by one with ``function``, and where it raises ``vectorised`` (C99's value)."""

    @wraps(vectorised)
    def portable(*args: Any) -> Any:
        arrays = [_array(a) for a in args]
        # broadcasting costs a few microseconds even when there is nothing to broadcast
        if len(arrays) > 1 and any(a.shape != arrays[0].shape for a in arrays[1:]):
            arrays = np.broadcast_arrays(*arrays)
        shape = arrays[0].shape
        columns = [np.ascontiguousarray(a).ravel() for a in arrays]
        out = np.empty(columns[0].size)
        left = np.empty(columns[0].size, dtype=bool)
        if _loop(loop)(*columns, out, left):
            where = np.flatnonzero(left)
            out[where] = _one_by_one(function, vectorised, [c[where] for c in columns])
        return _out(out.reshape(shape))

    portable.__name__ = portable.__qualname__ = name
    return portable


exp = _elementwise(math.exp, _vectorised_exp, "exp", "exp")
exp2 = _elementwise(_pow2, _vectorised_exp2, "exp2", "pow2")
expm1 = _elementwise(math.expm1, _vectorised_expm1, "expm1", "expm1")
tanh = _elementwise(math.tanh, _vectorised_tanh, "tanh", "tanh")
log = _elementwise(math.log, _vectorised_log, "log", "log")
log2 = _elementwise(math.log2, _vectorised_log2, "log2", "log2")
log10 = _elementwise(math.log10, _vectorised_log10, "log10", "log10")
arctan2 = _elementwise(math.atan2, _vectorised_arctan2, "arctan2", "atan2")
arctan = _elementwise(math.atan, _vectorised_arctan, "arctan", "atan")
arcsin = _elementwise(math.asin, _vectorised_arcsin, "arcsin", "asin")
arccos = _elementwise(math.acos, _vectorised_arccos, "arccos", "acos")
_power = _elementwise(math.pow, _vectorised_power, "power", "pow")


def power(x: Any, y: Any) -> Any:
    """x**y with C99's special cases (negative x only with integral y); ``y == 2`` is ``x * x``
    (exact, as NumPy's own fast path)."""
    if np.ndim(y) == 0 and float(y) == 2.0:
        x = _array(x)
        return _out(x * x)
    return _power(x, y)
