"""The statistics of ``cluster_objects`` (``strategy.perception.clustering``) after DBSCAN, in
one compiled pass (numba, imported on first use).

Given every sighting's DBSCAN label, it picks each object's best cluster (largest
recency-weighted weight, then newest sighting, then lowest label) and fits it: the
recency-weighted mean position and time, the weighted least-squares velocity and its
standard error, the spread. The arithmetic is NumPy's, operation for operation, so the bits
are the same (tested against the NumPy expressions on random windows):

- ``np.bincount(k, w)`` adds each point's weight to its bin in index order: so do these loops;
- products keep NumPy's association (``w * ddt * ddt`` is ``(w * ddt) * ddt``) and numba
  contracts no multiply-add into a fused one unless asked to;
- the recency factor ``0.5 ** age`` is ``pow(2, -age)`` from the C library as
  ``portable_math.exp2`` computes it, with the base read from an array so that the compiler
  cannot turn it into ``exp2`` (which rounds differently); ages are never negative here, so
  ``pow`` neither overflows nor returns NaN;
- ``np.sqrt`` and division are IEEE 754's, correctly rounded everywhere.
"""

from __future__ import annotations

import math

import numpy as np

from portable_math.jit import numba  # SVML off: the same bits on every machine
from strategy.perception.dbscan import grouped_labels


@numba.njit(inline="always")
def _recency(age: float, half_life: float, base_cap: np.ndarray) -> float:
    if math.isinf(half_life):
        return 1.0
    return math.pow(base_cap[0], -min(age / half_life, base_cap[1]))


@numba.njit(cache=True, error_model="numpy")  # 0 / 0 is NaN, as in NumPy
def cluster_stats(times: np.ndarray, xy: np.ndarray, weights: np.ndarray, objects: np.ndarray,
                  labels: np.ndarray, half_life: float, min_velocity_span: float,
                  recency: np.ndarray, known: np.ndarray, positions: np.ndarray,
                  time_s: np.ndarray, newest_s: np.ndarray, spread: np.ndarray,
                  n_out: np.ndarray, outliers: np.ndarray, rejected: np.ndarray,
                  velocities: np.ndarray, velocity_sigma: np.ndarray) -> None:
    """Fill the per-object outputs (filled beforehand with ``NO_SIGHTINGS``'s values) from
    the sightings ``times`` (n,), ``xy`` (n, 2), ``weights`` (n,), ``objects`` (n,) and their
    DBSCAN ``labels`` (n,; -1 noise; a cluster never spans two objects). ``recency``: [2.0, the
    largest number of halvings of the recency (``clustering.MAX_HALVINGS``)]."""
    n = times.size
    n_objects = known.size
    n_clusters = 0
    for i in range(n):
        if labels[i] < 0:
            outliers[objects[i]] += 1
        elif labels[i] + 1 > n_clusters:
            n_clusters = labels[i] + 1
    if n_clusters == 0:
        return
    # cluster scores: recency relative to each object's newest sighting (noise included)
    last_of_object = np.full(n_objects, -np.inf)
    for i in range(n):
        last_of_object[objects[i]] = max(last_of_object[objects[i]], times[i])
    score = np.zeros(n_clusters)
    newest = np.full(n_clusters, -np.inf)
    size = np.zeros(n_clusters, dtype=np.int64)
    owner = np.zeros(n_clusters, dtype=np.int64)
    clustered = np.zeros(n_objects, dtype=np.int64)
    for i in range(n):
        c = labels[i]
        if c < 0:
            continue
        score[c] += weights[i] * _recency(last_of_object[objects[i]] - times[i], half_life,
                                          recency)
        newest[c] = max(newest[c], times[i])
        size[c] += 1
        owner[c] = objects[i]
        clustered[objects[i]] += 1
    # best per object: largest score, then newest sighting, then lowest label
    best = np.full(n_objects, -1)
    for c in range(n_clusters):
        if size[c] == 0:
            continue
        o = owner[c]
        b = best[o]
        if b < 0 or score[c] > score[b] or (score[c] == score[b] and newest[c] > newest[b]):
            best[o] = c
    for o in range(n_objects):
        if best[o] >= 0:
            known[o] = True
            n_out[o] = size[best[o]]
            rejected[o] = clustered[o] - size[best[o]]
    # the best clusters' members in index order, their times relative to the cluster's
    # newest member and their weights times their recency; and their sums
    member = np.empty(n, dtype=np.int64)
    member_dt = np.empty(n)
    member_w = np.empty(n)
    m = 0
    for i in range(n):
        c = labels[i]
        if c >= 0 and best[objects[i]] == c:
            member[m] = i
            member_dt[m] = times[i] - newest[c]
            member_w[m] = weights[i] * _recency(-member_dt[m], half_life, recency)
            m += 1
    total = np.zeros(n_objects)
    t_sum = np.zeros(n_objects)
    p_sum = np.zeros((n_objects, 2))
    for k in range(m):
        i, dt, w = member[k], member_dt[k], member_w[k]
        o = objects[i]
        total[o] += w
        t_sum[o] += w * dt
        p_sum[o, 0] += w * xy[i, 0]
        p_sum[o, 1] += w * xy[i, 1]
    t_mean = np.empty(n_objects)
    mean = np.empty((n_objects, 2))
    for o in range(n_objects):
        t_mean[o] = t_sum[o] / total[o]
        mean[o, 0] = p_sum[o, 0] / total[o]
        mean[o, 1] = p_sum[o, 1] / total[o]
    fit = not math.isinf(min_velocity_span)
    s_tt = np.zeros(n_objects)
    s_tp = np.zeros((n_objects, 2))
    s_wwtt = np.zeros(n_objects)
    oldest = np.full(n_objects, np.inf)
    square_sum = np.zeros(n_objects)
    if fit:
        for k in range(m):
            i, dt, w = member[k], member_dt[k], member_w[k]
            o = objects[i]
            ddt = dt - t_mean[o]
            s_tt[o] += w * ddt * ddt
            s_tp[o, 0] += w * ddt * (xy[i, 0] - mean[o, 0])
            s_tp[o, 1] += w * ddt * (xy[i, 1] - mean[o, 1])
            s_wwtt[o] += w * w * ddt * ddt
            oldest[o] = min(oldest[o], dt)
    with_velocity = np.zeros(n_objects, dtype=np.bool_)
    velocity = np.full((n_objects, 2), np.nan)
    for o in range(n_objects):
        c = best[o]
        if fit and c >= 0 and size[c] >= 3 and -oldest[o] >= min_velocity_span and s_tt[o] > 0:
            with_velocity[o] = True
            velocity[o, 0] = s_tp[o, 0] / s_tt[o]
            velocity[o, 1] = s_tp[o, 1] / s_tt[o]
    # the spread: about the fitted line, or about the mean without a velocity
    for k in range(m):
        i, dt, w = member[k], member_dt[k], member_w[k]
        o = objects[i]
        r0 = xy[i, 0] - mean[o, 0]
        r1 = xy[i, 1] - mean[o, 1]
        if fit:
            ddt = dt - t_mean[o]
            r0 = r0 - (velocity[o, 0] * ddt if with_velocity[o] else 0.0)
            r1 = r1 - (velocity[o, 1] * ddt if with_velocity[o] else 0.0)
        square_sum[o] += w * (r0 * r0 + r1 * r1)
    for o in range(n_objects):
        c = best[o]
        if c < 0:
            continue
        s = np.sqrt(square_sum[o] / total[o])
        positions[o, 0] = mean[o, 0]
        positions[o, 1] = mean[o, 1]
        newest_s[o] = newest[c]
        time_s[o] = newest[c] + t_mean[o]
        spread[o] = s
        if with_velocity[o]:
            velocities[o, 0] = velocity[o, 0]
            velocities[o, 1] = velocity[o, 1]
            # weighted least squares: var(slope) = s2 sum(w^2 dt^2) / s_tt^2, s2 the residual
            # variance per axis (2 parameters fitted per axis: n - 2 degrees of freedom)
            members = float(size[c])
            s2 = s * s / 2.0 * members / max(members - 2.0, 1.0)
            velocity_sigma[o] = np.sqrt(s2 * s_wwtt[o]) / s_tt[o]


@numba.njit(cache=True)
def group_labels(points: np.ndarray, weights: np.ndarray, groups: np.ndarray, eps2: float,
                 min_samples: float) -> np.ndarray:
    """``dbscan.grouped_labels`` of ``points`` (n, d) with integer-valued ``weights``, each
    point compared only with the points of its own group (``groups``: (n,) ints, in any
    order; within a group, the callers' order counts)."""
    n = points.shape[0]
    out = np.full(n, -1)
    if n == 0:
        return out
    original = np.arange(n)
    for k in range(1, n):
        if groups[k] < groups[k - 1]:
            original = np.argsort(groups, kind="mergesort")  # stable
            break
    g = groups[original]
    bounds = [0]
    for k in range(1, n):
        if g[k] != g[k - 1]:
            bounds.append(k)
    bounds.append(n)
    grouped_labels(np.ascontiguousarray(points[original]), weights[original],
                   np.array(bounds), eps2, min_samples, original, out)
    return out
