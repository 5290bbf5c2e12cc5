"""The compiled cluster statistics give the NumPy expressions' bits (``cluster_objects``)."""

from __future__ import annotations

import numpy as np
import pytest

from strategy.perception.clustering import cluster_objects
from tests.strategy.cluster_objects_numpy import cluster_objects_numpy


def _window(rng: np.random.Generator, n_objects: int, weights: str):
    """Random sightings of ``n_objects`` objects in the callers' order (object, then time):
    still or rolling objects, jumps (a second cluster), stray points (noise), repeated times."""
    times, xy, objects = [], [], []
    for o in range(n_objects):
        count = int(rng.integers(0, 14))
        t = np.sort(rng.choice(np.arange(0.0, 1.0, 0.02), count, replace=count > 50))
        if rng.random() < 0.2 and count > 1:
            t[1] = t[0]  # two sightings at one time
        start = rng.uniform(-8.0, 8.0, 2) + o * 40.0  # objects kept more than 2 eps apart
        velocity = rng.uniform(-3.0, 3.0, 2) if rng.random() < 0.5 else np.zeros(2)
        p = start + np.outer(t, velocity) + rng.normal(0.0, rng.choice([0.0, 0.02, 0.15]),
                                                      (count, 2))
        if count > 4 and rng.random() < 0.4:  # a jump: the later sightings elsewhere
            p[count // 2:] += rng.uniform(1.0, 3.0, 2)
        if count > 2 and rng.random() < 0.3:  # a stray sighting
            p[int(rng.integers(0, count))] += rng.uniform(2.0, 4.0, 2)
        times.append(t)
        xy.append(p)
        objects.append(np.full(count, o, dtype=np.int64))
    times_a = np.concatenate(times)
    if weights == "unit":
        w = np.ones(len(times_a))
    elif weights == "integer":
        w = rng.integers(1, 4, len(times_a)).astype(np.float64)
    else:
        w = rng.uniform(0.2, 2.0, len(times_a))
    return times_a, np.concatenate(xy).reshape(-1, 2), w, np.concatenate(objects)


def _same(a: dict, b: dict) -> None:
    assert a.keys() == b.keys()
    for name in a:
        x, y = np.asarray(a[name]), np.asarray(b[name])
        assert x.dtype == y.dtype and x.shape == y.shape, name
        assert x.tobytes() == y.tobytes(), (name, x, y)  # bit for bit, NaN and -0.0 included


@pytest.mark.parametrize("weights", ["unit", "integer", "real"])
def test_the_kernel_gives_the_numpy_statistics_bit_for_bit(weights: str) -> None:
    rng = np.random.default_rng(20261127)
    cases = 0
    kinds = set()
    for _ in range(400):
        n_objects = int(rng.integers(1, 9))
        times, xy, w, objects = _window(rng, n_objects, weights)
        eps = float(rng.choice([0.3, 0.5, 1.0]))
        min_samples = int(rng.integers(1, 5))
        half_life = float(rng.choice([0.05, 0.3, 1.0, np.inf]))
        span = float(rng.choice([0.0, 0.1, 0.5, np.inf]))
        args = (times, xy, w, objects, n_objects, eps, min_samples, half_life, span)
        got, want = cluster_objects(*args), cluster_objects_numpy(*args)
        _same(got, want)
        cases += 1
        kinds.add(("noise", bool(want["outliers"].any())))
        kinds.add(("rejected", bool(want["rejected"].any())))
        kinds.add(("velocity", bool(np.isfinite(want["velocities"]).any())))
        kinds.add(("unknown", bool((~want["known"]).any())))
    # the draws reached every branch: noise, a second cluster, fitted velocities, no estimate
    assert kinds >= {(k, True) for k in ("noise", "rejected", "velocity", "unknown")}
    assert cases == 400


def test_no_sightings_and_all_noise() -> None:
    empty = (np.zeros(0), np.zeros((0, 2)), np.zeros(0), np.zeros(0, dtype=np.int64), 3, 0.5, 2,
             0.3, 0.1)
    _same(cluster_objects(*empty), cluster_objects_numpy(*empty))
    lonely = (np.array([0.0, 0.5]), np.array([[0.0, 0.0], [9.0, 9.0]]), np.ones(2),
              np.array([0, 1]), 2, 0.5, 2, 0.3, 0.1)
    got = cluster_objects(*lonely)
    _same(got, cluster_objects_numpy(*lonely))
    assert not got["known"].any() and got["outliers"].tolist() == [1, 1]


def test_ties_keep_the_lowest_label() -> None:
    """Two clusters of one object, equal in weight and newest sighting: the first is best."""
    times = np.array([0.0, 0.0, 0.1, 0.1])
    xy = np.array([[0.0, 0.0], [5.0, 5.0], [0.1, 0.0], [5.1, 5.0]])
    args = (times, xy, np.ones(4), np.zeros(4, dtype=np.int64), 1, 0.5, 2, 0.3, 0.1)
    got = cluster_objects(*args)
    _same(got, cluster_objects_numpy(*args))
    assert got["positions"][0, 0] < 1.0 and got["rejected"].tolist() == [2]
