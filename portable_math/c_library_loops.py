"""The C library's scalar functions over whole arrays in compiled loops (numba).

numba compiles ``math.exp(x)`` and the like to calls of the same C library functions that
Python's ``math`` module calls, so each element gets the bits ``math`` gives it (tested on
millions of values, special values included), without a Python call per element. The loop
flags the elements it cannot answer as ``math`` does, and the caller computes those one by
one as before: where ``math`` would raise (a finite argument whose result is infinite, or a
NaN result of non-NaN arguments: ``log(0)``, ``exp(1000)``, ``asin(2)``, ``pow(0, -1)``), and
where an argument is NaN (``math`` hands some NaNs back as they came, payload and sign; the C
library returns its own).

The base of ``exp2`` (``pow(2, x)``) is an argument, not a constant: with a constant base the
compiler may turn ``pow(2, x)`` into the C library's ``exp2``, which rounds differently.
Imported on first use: numba takes a few tenths of a second to import.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(inline="always")
def _raises(result: float, x: float) -> bool:
    """Whether the element is left to ``math``: a NaN argument or result, or an infinite
    result of a finite argument (where ``math`` raises)."""
    return math.isnan(result) or math.isnan(x) or (math.isinf(result) and math.isfinite(x))


@numba.njit(inline="always")
def _raises2(result: float, x: float, y: float) -> bool:
    return math.isnan(result) or math.isnan(x) or math.isnan(y) or (
        math.isinf(result) and math.isfinite(x) and math.isfinite(y))


# One loop per function (numba caches a function on disk, not a closure over another).
@numba.njit(cache=True)
def exp(x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(x.size):
        out[i] = r = math.exp(x[i])
        failed[i] = f = _raises(r, x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def expm1(x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(x.size):
        out[i] = r = math.expm1(x[i])
        failed[i] = f = _raises(r, x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def tanh(x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(x.size):
        out[i] = r = math.tanh(x[i])
        failed[i] = f = _raises(r, x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def log(x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(x.size):
        out[i] = r = math.log(x[i])
        failed[i] = f = _raises(r, x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def log2(x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(x.size):
        out[i] = r = math.log2(x[i])
        failed[i] = f = _raises(r, x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def log10(x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(x.size):
        out[i] = r = math.log10(x[i])
        failed[i] = f = _raises(r, x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def atan(x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(x.size):
        out[i] = r = math.atan(x[i])
        failed[i] = f = _raises(r, x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def asin(x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(x.size):
        out[i] = r = math.asin(x[i])
        failed[i] = f = _raises(r, x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def acos(x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(x.size):
        out[i] = r = math.acos(x[i])
        failed[i] = f = _raises(r, x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def atan2(y: np.ndarray, x: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    bad = False
    for i in range(y.size):
        out[i] = r = math.atan2(y[i], x[i])
        failed[i] = f = _raises2(r, y[i], x[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def pow(x: np.ndarray, y: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:  # noqa: A001
    bad = False
    for i in range(x.size):
        out[i] = r = math.pow(x[i], y[i])
        failed[i] = f = _raises2(r, x[i], y[i])
        bad |= f
    return bad


@numba.njit(cache=True)
def pow_of(base: float, y: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    """``pow(base, y)`` element by element (``exp2`` with ``base`` 2.0, given at run time)."""
    bad = False
    for i in range(y.size):
        out[i] = r = math.pow(base, y[i])
        failed[i] = f = _raises2(r, base, y[i])
        bad |= f
    return bad


def pow2(y: np.ndarray, out: np.ndarray, failed: np.ndarray) -> bool:
    """``exp2`` as ``pow(2, y)``: the base passed at run time (see the module doc)."""
    return pow_of(2.0, y, out, failed)
