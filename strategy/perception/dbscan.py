"""DBSCAN labels of small groups of points in one compiled pass (numba), for
``strategy.perception.clustering``.

The decisions are scikit-learn's (``sklearn.cluster._dbscan_inner``), for integer-valued
weights: a point's neighbourhood is every point of its group whose squared distance, summed
over the coordinates in order (sklearn's ``euclidean`` reduced distance), is at most
``eps * eps``, itself included; a core point's neighbourhood weighs at least ``min_samples``
(integer weights: every order of summation gives the same sum); clusters are the connected
components of the core points, numbered in the order of their first point; a non-core point
next to core points joins the lowest-numbered of their clusters, else it is noise (-1).

Points of different groups are never compared (as if a third coordinate of ``2 eps`` per
group kept them apart). Groups are small (one object's window of sightings: tens of points),
so every pair within a group is compared; a union-find over the core pairs, each component
named by its smallest point, gives the clusters. Only comparisons and the reduced distances
(``+ - *``, which IEEE 754 rounds exactly, without fused multiply-adds: numba contracts none
unless asked to) decide, so the labels are the same on every CPU.
"""

from __future__ import annotations

import numpy as np

from portable_math.jit import numba  # SVML off: the same bits on every machine


@numba.njit(inline="always")
def _near(points: np.ndarray, i: int, j: int, eps2: float) -> bool:
    rd = 0.0
    for k in range(points.shape[1]):
        d = points[i, k] - points[j, k]
        rd += d * d
    return rd <= eps2


@numba.njit(inline="always")
def _find(parent: np.ndarray, i: int) -> int:
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@numba.njit(cache=True)
def grouped_labels(points: np.ndarray, weights: np.ndarray, bounds: np.ndarray, eps2: float,
                   min_samples: float, original: np.ndarray, out: np.ndarray) -> None:
    """``out[original[i]]``: the label of point ``i`` of ``points`` (n, d) with integer-valued
    ``weights`` (n,), its group the points ``bounds[g]`` to ``bounds[g + 1] - 1`` (``bounds``:
    the groups' starts, then n); clusters numbered in the order of their first point's
    ``original`` index."""
    n = points.shape[0]
    weight = weights.copy()  # each point's neighbourhood weight, itself included
    for g in range(bounds.size - 1):
        for j in range(bounds[g] + 1, bounds[g + 1]):
            for i in range(bounds[g], j):
                if _near(points, i, j, eps2):
                    weight[i] += weights[j]
                    weight[j] += weights[i]
    core = weight >= min_samples
    parent = np.arange(n)
    for g in range(bounds.size - 1):
        for j in range(bounds[g] + 1, bounds[g + 1]):
            if not core[j]:
                continue
            for i in range(bounds[g], j):
                if core[i] and _near(points, i, j, eps2):
                    a, b = _find(parent, i), _find(parent, j)
                    if a < b:  # the smaller point names the component
                        parent[b] = a
                    elif b < a:
                        parent[a] = b
    root = np.full(n, n)  # each point's cluster by its first point; n: noise
    for i in range(n):
        if core[i]:
            root[i] = _find(parent, i)
    for g in range(bounds.size - 1):  # a border point: the first cluster of its core neighbours
        for j in range(bounds[g] + 1, bounds[g + 1]):
            for i in range(bounds[g], j):
                if core[i] != core[j] and _near(points, i, j, eps2):
                    if core[i]:
                        root[j] = min(root[j], root[i])
                    else:
                        root[i] = min(root[i], root[j])
    # clusters numbered in the order of their first point in the callers' order
    firsts = np.flatnonzero(root == np.arange(n))
    number = np.full(n + 1, -1)
    by_original = np.argsort(original[firsts], kind="mergesort")
    for k in range(by_original.size):
        number[firsts[by_original[k]]] = k
    for i in range(n):
        out[original[i]] = number[root[i]]

