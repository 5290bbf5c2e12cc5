"""portable_math's compiled loops give every element the bits of Python's ``math`` module
called on it alone (the same C library functions), NaN payloads, signed zeros, infinities and
the elements where ``math`` raises included, for any shape, dtype and broadcast."""

import math

import numpy as np
import pytest

import portable_math as pm
from portable_math import _one_by_one

rng = np.random.default_rng(77)
SPECIAL = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, -np.nan, 5e-324, -5e-324,
                    2.2250738585072014e-308, 1.7976931348623157e308, -1.7976931348623157e308,
                    1.0, -1.0, 0.5, 2.0, 709.78, 709.79, -745.2, -745.1, 1e-300, 1e300,
                    0.9999999999999999, 1.0000000000000002, 3.0, -3.0, 0.1, 1024.0, -1075.0])
# signalling and payload-carrying NaNs, as a bit pattern from anywhere could be
ODD_NANS = np.array([0x7FF0000000000001, 0x7FF4000000000000, 0xFFF8000000000123,
                     0x7FF8DEADBEEF0000], dtype=np.uint64).view(np.float64)


def values(n: int = 60_000) -> np.ndarray:
    return np.concatenate([
        SPECIAL, ODD_NANS, rng.uniform(-10, 10, n), rng.uniform(-1, 1, n // 4),
        rng.standard_normal(n // 4) * 800, np.exp(rng.uniform(-700, 700, n // 4)),
        -np.exp(rng.uniform(-700, 700, n // 4)),
        rng.integers(-2**62, 2**62, n // 8).view(np.float64)])


UNARY = [(pm.exp, math.exp), (pm.exp2, lambda v: math.pow(2.0, v)), (pm.expm1, math.expm1),
         (pm.tanh, math.tanh), (pm.log, math.log), (pm.log2, math.log2),
         (pm.log10, math.log10), (pm.arctan, math.atan), (pm.arcsin, math.asin),
         (pm.arccos, math.acos)]
BINARY = [(pm.arctan2, math.atan2), (pm.power, math.pow)]


def one_by_one(function, vectorised, *columns) -> np.ndarray:
    return _one_by_one(function, vectorised, [np.asarray(c, dtype=np.float64) for c in columns])


def same_bits(a, b) -> bool:
    return np.asarray(a, np.float64).tobytes() == np.asarray(b, np.float64).tobytes()


@pytest.mark.parametrize(("function", "scalar"), UNARY, ids=lambda f: getattr(f, "__name__", ""))
def test_unary_functions_give_maths_bits(function, scalar):
    x = values()
    got = function(x)
    want = one_by_one(scalar, function.__wrapped__, x)
    bad = np.flatnonzero(got.view(np.int64) != want.view(np.int64))
    assert not len(bad), (x[bad[:5]], got[bad[:5]], want[bad[:5]])


@pytest.mark.parametrize(("function", "scalar"), BINARY, ids=lambda f: getattr(f, "__name__", ""))
def test_binary_functions_give_maths_bits(function, scalar):
    x = values()
    y = np.concatenate([x[::-1][: len(x) // 2], rng.uniform(-3, 3, len(x) - len(x) // 2)])
    y[:40] = np.round(y[:40])  # integral exponents: pow of negative bases
    got = function(x, y)
    want = one_by_one(scalar, pm._power.__wrapped__ if function is pm.power
                      else function.__wrapped__, x, y)
    bad = np.flatnonzero(got.view(np.int64) != want.view(np.int64))
    assert not len(bad), (x[bad[:5]], y[bad[:5]], got[bad[:5]], want[bad[:5]])


def test_where_math_raises_the_vectorised_value_is_used():
    # log(0) and exp(1000) raise in math; C99's values come back, as before the loops
    assert pm.log(0.0) == -np.inf and pm.exp(1000.0) == np.inf
    assert np.isnan(pm.arcsin(2.0)) and pm.power(0.0, -1.0) == np.inf
    assert same_bits(pm.log(np.array([0.0, 1.0, -0.0])), [-np.inf, 0.0, -np.inf])


def test_shapes_dtypes_and_broadcasting():
    x = rng.uniform(-3, 3, (4, 5))
    assert pm.exp(x).shape == (4, 5) and same_bits(pm.exp(x).ravel(), pm.exp(x.ravel()))
    assert isinstance(pm.exp(0.5), float) and pm.exp(0.5) == math.exp(0.5)
    assert same_bits(pm.exp(x.astype(np.float32)), pm.exp(x.astype(np.float32).astype(float)))
    assert same_bits(pm.exp(np.arange(5)), [math.exp(k) for k in range(5)])
    assert same_bits(pm.exp(x.T), pm.exp(np.ascontiguousarray(x.T)))  # non-contiguous input
    row = rng.uniform(-3, 3, 5)
    got = pm.arctan2(x, row)
    assert got.shape == (4, 5)
    assert same_bits(got, [[math.atan2(a, b) for a, b in zip(r, row, strict=True)] for r in x])
    assert pm.exp(np.empty(0)).shape == (0,)
