"""portable_math agrees with the correctly rounded value (mpmath, 120 bits) to a few ulp and
with NumPy's special values: signed zeros, infinities, NaN, the quadrants of arctan2."""

import math

import mpmath
import numpy as np
import pytest

import portable_math as pm

mpmath.mp.prec = 120
N = 400


def ulp_error(got, reference) -> float:
    got = np.asarray(got, dtype=np.float64)
    ref = np.asarray(reference, dtype=np.float64)
    return float(np.max(np.abs(got - ref) / np.spacing(np.abs(ref))))


def exact(fn, *args):
    return np.array([float(fn(*(mpmath.mpf(float(a[i])) for a in args)))
                     for i in range(len(args[0]))])


rng = np.random.default_rng(2024)
tiny = rng.uniform(-1, 1, N) * np.exp(rng.uniform(-40, 0, N))
wide = rng.uniform(-30, 30, N)
positive = np.exp(rng.uniform(-700, 700, N))
moderate = rng.uniform(0.01, 4.0, N)
unit = rng.uniform(-1, 1, N)

CASES = [
    ("exp", pm.exp, mpmath.exp, (wide,), 1),
    ("exp", pm.exp, mpmath.exp, (rng.uniform(-745, 709.7, N),), 1),
    ("exp2", pm.exp2, lambda a: mpmath.power(2, a), (rng.uniform(-1070, 1023.9, N),), 1),
    ("expm1", pm.expm1, mpmath.expm1, (tiny,), 1),
    ("expm1", pm.expm1, mpmath.expm1, (wide,), 1),
    ("tanh", pm.tanh, mpmath.tanh, (wide,), 2),
    ("tanh", pm.tanh, mpmath.tanh, (tiny,), 2),
    ("log", pm.log, mpmath.log, (positive,), 1),
    ("log", pm.log, mpmath.log, (moderate,), 1),
    ("log2", pm.log2, lambda a: mpmath.log(a, 2), (positive,), 1),
    ("log2", pm.log2, lambda a: mpmath.log(a, 2), (moderate,), 1),
    ("log10", pm.log10, mpmath.log10, (positive,), 2),
    ("log10", pm.log10, mpmath.log10, (moderate,), 2),
    ("power", pm.power, mpmath.power, (moderate, rng.uniform(-4, 4, N)), 2),
    ("power", pm.power, mpmath.power, (positive, rng.uniform(-1, 1, N)), 6),
    ("arctan", pm.arctan, mpmath.atan, (wide,), 1),
    ("arctan", pm.arctan, mpmath.atan, (tiny,), 1),
    ("arctan", pm.arctan, mpmath.atan, (1.0 / tiny,), 1),
    ("arctan2", pm.arctan2, mpmath.atan2, (wide, rng.uniform(-30, 30, N)), 1),
    ("arctan2", pm.arctan2, mpmath.atan2, (tiny, wide), 1),
    ("arctan2", pm.arctan2, mpmath.atan2, (wide, tiny), 1),
    ("arcsin", pm.arcsin, mpmath.asin, (unit,), 2),
    ("arccos", pm.arccos, mpmath.acos, (unit,), 2),
    ("arccos", pm.arccos, mpmath.acos, (1.0 - np.exp(rng.uniform(-40, 0, N)),), 2),
]


@pytest.mark.parametrize("path", ["public", "vectorised"])
@pytest.mark.parametrize("case", CASES, ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_within_a_few_ulp_of_the_correctly_rounded_value(case, path):
    name, ours, reference, args, max_ulp = case
    if path == "vectorised":   # the fallback of elements the C library refuses
        ours = getattr(pm, f"_vectorised_{name}")
    expected = exact(reference, *args)
    assert ulp_error(ours(*args), expected) <= max_ulp, name
    # and NumPy is no closer than one ulp better: the reference is right
    assert ulp_error(getattr(np, name)(*args), expected) <= 1.0


SPECIAL = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 1.0, -1.0, 0.5, -0.5, 2.0, -2.0,
                    1e-310, -1e-310, 5e-324, 1e300, -1e300, 709.8, -745.2, 1e-20, 3.0, -3.0,
                    0.1, 1.5, 2.5, -2.5])


def same_values(got, want, ulp: int = 4) -> bool:
    got, want = np.asarray(got), np.asarray(want)
    with np.errstate(invalid="ignore"):
        close = (got == want) | (np.isnan(got) & np.isnan(want))
        close |= np.abs(got - want) <= ulp * np.spacing(np.abs(want))
    return bool(np.all(close & (np.signbit(got) == np.signbit(want)) | np.isnan(want)))


# the public functions (the C library element by element, C99's values where it raises) and
# the vectorised fallback on its own
PATHS = {"public": "{}", "vectorised": "_vectorised_{}"}


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("name", ["exp", "exp2", "expm1", "tanh", "log", "log2", "log10",
                                  "arctan", "arcsin", "arccos"])
def test_one_argument_special_values_as_numpy(name, path):
    x = np.tile(SPECIAL, 4)
    with np.errstate(all="ignore"):
        want = getattr(np, name)(x)
    got = getattr(pm, PATHS[path].format(name))(x)
    bad = [(a, g, w) for a, g, w in zip(x, got, want, strict=True) if not same_values(g, w)]
    assert not bad, bad


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("name", ["arctan2", "power"])
def test_two_argument_special_values_as_numpy(name, path):
    x, y = np.meshgrid(SPECIAL, SPECIAL)
    x, y = x.ravel(), y.ravel()  # one call, 625 elements
    with np.errstate(all="ignore"):
        want = getattr(np, name)(x, y)
        got = getattr(pm, PATHS[path].format(name))(x, y)
    ulp = 32 if name == "power" else 4  # power(1.5, 709.8): |y log x| = 288 (see its docstring)
    bad = [(a, b, g, w) for a, b, g, w in zip(x.ravel(), y.ravel(), got.ravel(), want.ravel(),
                                              strict=True)
           if not same_values(g, w, ulp)]
    assert not bad, bad[:10]


@pytest.mark.parametrize("name, libm", [("exp", math.exp), ("log", math.log),
                                        ("tanh", math.tanh), ("arctan", math.atan),
                                        ("log10", math.log10), ("expm1", math.expm1)])
def test_every_input_takes_the_c_library_scalar_functions(name, libm):
    x = np.abs(wide[:1000]) + 0.5
    assert getattr(pm, name)(x).tolist() == [libm(v) for v in x.tolist()]
    assert getattr(pm, name)(float(x[0])) == libm(float(x[0]))
    assert pm.arctan2(wide[:5], tiny[:5]).tolist() == list(map(math.atan2, wide[:5], tiny[:5]))
    assert pm.power(x, 1.7).tolist() == [math.pow(v, 1.7) for v in x.tolist()]


def test_arctan2_quadrants_and_signed_zeros():
    assert pm.arctan2(0.0, -0.0) == math.pi and pm.arctan2(-0.0, -0.0) == -math.pi
    assert math.copysign(1, pm.arctan2(-0.0, 0.0)) == -1 and pm.arctan2(0.0, 0.0) == 0.0
    assert pm.arctan2(1.0, 0.0) == math.pi / 2 and pm.arctan2(-1.0, -0.0) == -math.pi / 2
    assert pm.arctan2(np.inf, -np.inf) == 3 * math.pi / 4
    assert pm.arctan2(-np.inf, np.inf) == -math.pi / 4
    angles = np.linspace(-math.pi + 1e-9, math.pi - 1e-9, 1001)
    back = pm.arctan2(np.sin(angles) * 3.0, np.cos(angles) * 3.0)
    assert np.max(np.abs(back - angles)) < 1e-14


def test_scalars_give_numpy_scalars_and_float32_is_computed_in_float64():
    assert isinstance(pm.exp(1.0), np.float64) and abs(pm.exp(1.0) - math.e) <= 4.5e-16
    assert pm.log2(8.0) == 3.0 and pm.exp2(-3.0) == 0.125 and pm.power(2.0, 10.0) == 1024.0
    assert pm.arctan2(np.float32(1.0), np.float32(1.0)).dtype == np.float64
    assert pm.power(np.arange(4.0), 2.5).shape == (4,)


@pytest.mark.parametrize("name", ["exp", "log", "tanh", "arctan", "arcsin", "arctan2", "power"])
def test_a_value_is_the_same_alone_and_in_a_batch(name):
    """One agent's value computed alone equals its value in the team's batch (the batched
    decision layer relies on it), special values included."""
    rng = np.random.default_rng(3)
    x = np.concatenate([rng.uniform(-3, 3, 300), SPECIAL])
    args = (x, np.abs(x[::-1]) + 0.1) if name in ("arctan2", "power") else (np.abs(x) + 0.01
                                                                             if name == "log"
                                                                             else x,)
    if name == "arcsin":
        args = (np.clip(x, -1.5, 1.5),)
    with np.errstate(all="ignore"):
        batch = getattr(pm, name)(*args)
        alone = np.array([getattr(pm, name)(*(a[i] for a in args)) for i in range(len(x))])
    assert batch.tobytes() == alone.tobytes()
