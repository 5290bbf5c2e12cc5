"""The C library's scalar functions over whole arrays in compiled loops (numba).

numba compiles ``math.exp(x)`` and the like to calls of the same C library functions that
Python's ``math`` module calls, so each element gets the bits ``math`` gives it (tested on
millions of values, special values included), without a Python call per element. The loop
flags the elements it cannot answer as ``math`` does, and the caller computes those one by
one as before: where ``math`` would raise (a finite argument whose result is infinite, or a
NaN result of non-NaN arguments: ``log(0)``, ``exp(1000)``, ``asin(2)``, ``pow(0, -1)``), and
where an argument is NaN (``math`` hands some NaNs back as they came, payload and sign; the C
library returns its own).

The base of ``exp2`` (``pow(2, x)``) is an array, not a constant: with a constant base the
compiler may turn ``pow(2, x)`` into the C library's ``exp2``, which rounds differently.
Imported on first use: numba takes a few tenths of a second to import.
"""

from __future__ import annotations

import math

import numpy as np

from portable_math.jit import numba  # SVML off: the same bits on every machine


@numba.njit(inline="always")
def _raises(result: float, x: float, y: float) -> bool:
    """Whether the element is left to ``math``: a NaN argument or result, or an infinite
    result of finite arguments (where ``math`` raises). One-argument functions pass their
    argument twice."""
    return math.isnan(result) or math.isnan(x) or math.isnan(y) or (
        math.isinf(result) and math.isfinite(x) and math.isfinite(y))


# The functions by number: one cached loop for all (numba caches a function on disk, not a
# closure over another); the branch on ``which`` is the same for every element.
EXP, EXPM1, TANH, LOG, LOG2, LOG10, ATAN, ASIN, ACOS = range(9)
ATAN2, POW = range(2)


@numba.njit(inline="always")
def _unary(which: int, x: float) -> float:
    if which == EXP:
        return math.exp(x)
    if which == EXPM1:
        return math.expm1(x)
    if which == TANH:
        return math.tanh(x)
    if which == LOG:
        return math.log(x)
    if which == LOG2:
        return math.log2(x)
    if which == LOG10:
        return math.log10(x)
    if which == ATAN:
        return math.atan(x)
    if which == ASIN:
        return math.asin(x)
    return math.acos(x)


@numba.njit(cache=True)
def unary(which: int, x: np.ndarray, out: np.ndarray, left: np.ndarray) -> bool:
    """``out[i] = f(x[i])`` for the function numbered ``which``; ``left[i]``: the element is
    the caller's (see the module doc). Returns whether any is."""
    any_left = False
    for i in range(x.size):
        out[i] = r = _unary(which, x[i])
        left[i] = f = _raises(r, x[i], x[i])
        any_left |= f
    return any_left


@numba.njit(cache=True)
def binary(which: int, x: np.ndarray, y: np.ndarray, out: np.ndarray,
           left: np.ndarray) -> bool:
    """``out[i] = f(x[i], y[i])`` (``atan2(x, y)`` or ``pow(x, y)``); as ``unary``."""
    any_left = False
    for i in range(x.size):
        r = math.atan2(x[i], y[i]) if which == ATAN2 else math.pow(x[i], y[i])
        out[i] = r
        left[i] = f = _raises(r, x[i], y[i])
        any_left |= f
    return any_left


def function(name: str):
    """The loop of ``math.<name>`` (``pow2``: ``pow(2, y)``): ``loop(*columns, out, left)``."""
    if name == "pow2":
        # the base is an array, not a constant: see the module doc
        return lambda y, out, left: binary(POW, np.full(y.size, 2.0), y, out, left)
    if name in ("atan2", "pow"):
        which = ATAN2 if name == "atan2" else POW
        return lambda x, y, out, left: binary(which, x, y, out, left)
    which = globals()[name.upper()]
    return lambda x, out, left: unary(which, x, out, left)
