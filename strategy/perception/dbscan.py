"""DBSCAN labels of small groups of points in one compiled pass (numba).

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

import numba
import numpy as np
from numpy.typing import NDArray


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
def _labels(points: np.ndarray, weights: np.ndarray, starts: np.ndarray, eps2: float,
            min_samples: float, original: np.ndarray, out: np.ndarray) -> None:
    n = points.shape[0]
    groups = starts.size
    weight = weights.copy()  # each point's neighbourhood weight, itself included
    for g in range(groups):
        end = starts[g + 1] if g + 1 < groups else n
        for j in range(starts[g] + 1, end):
            for i in range(starts[g], j):
                if _near(points, i, j, eps2):
                    weight[i] += weights[j]
                    weight[j] += weights[i]
    core = weight >= min_samples
    parent = np.arange(n)
    for g in range(groups):
        end = starts[g + 1] if g + 1 < groups else n
        for j in range(starts[g] + 1, end):
            if not core[j]:
                continue
            for i in range(starts[g], j):
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
    for g in range(groups):  # a border point: the first cluster among its core neighbours
        end = starts[g + 1] if g + 1 < groups else n
        for j in range(starts[g] + 1, end):
            for i in range(starts[g], j):
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


def grouped_dbscan_labels(points: NDArray[np.float64], weights: NDArray[np.float64],
                          eps: float, min_samples: int,
                          groups: NDArray[np.int64] | None = None) -> NDArray[np.int64]:
    """(n,) DBSCAN labels (-1: noise) of ``points`` (n,) or (n, d) with integer-valued
    ``weights``, each point compared only with the points of its own group (``groups``:
    (n,) ints; None: one group); see the module doc."""
    pts = np.asarray(points, dtype=np.float64)
    n = len(pts)
    out = np.full(n, -1, dtype=np.int64)
    if n == 0:
        return out
    pts = np.ascontiguousarray(pts.reshape(n, -1))
    w = np.ascontiguousarray(weights, dtype=np.float64)
    original = np.arange(n)
    if groups is None:
        starts = np.zeros(1, dtype=np.int64)
    else:
        g = np.asarray(groups)
        if n > 1 and not bool((g[1:] >= g[:-1]).all()):
            original = np.argsort(g, kind="stable")  # within a group, the callers' order
            g, pts, w = g[original], pts[original], w[original]
        starts = np.concatenate(([0], np.flatnonzero(g[1:] != g[:-1]) + 1)).astype(np.int64)
    _labels(pts, w, starts, float(eps) * float(eps), float(min_samples), original, out)
    return out
