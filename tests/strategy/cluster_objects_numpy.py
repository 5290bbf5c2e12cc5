"""The NumPy ``cluster_objects`` that ``strategy.perception.cluster_kernel`` replaced, kept as
the oracle of the kernel's test (``test_cluster_kernel.py``): the same statistics, expression
for expression, as the project computed them before the kernel."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from strategy.perception.clustering import _dbscan_labels, _recency, _starts


def _runs(keys: NDArray[np.int64]) -> NDArray[np.intp] | None:
    """The start of each run of equal ``keys`` when they are sorted (non-empty), else None
    (a per-key maximum or minimum is then one ``reduceat``, exactly ``ufunc.at``'s)."""
    if len(keys) == 0 or not bool((keys[1:] >= keys[:-1]).all()):
        return None
    return _starts(keys)


def cluster_objects_numpy(times: NDArray[np.float64], xy: NDArray[np.float64],
                    weights: NDArray[np.float64], objects: NDArray[np.int64], n_objects: int,
                    eps: float, min_samples: int, half_life: float,
                    min_velocity_span: float) -> dict[str, NDArray]:
    """Per-object DBSCAN cluster statistics of fresh sightings (the windows' core).

    Args:
        times, xy, weights, objects: (n,), (n, 2), (n,) > 0, (n,) in [0, n_objects): the
            sightings, sorted by object then time (the caller's canonical order).
        eps, min_samples, half_life, min_velocity_span: as ``FilterParams``'s ``eps_m``,
            ``min_samples``, ``recency_half_life_s``, ``min_velocity_span_s``.

    Returns the arrays of ``MultiEstimate`` except ``age_s`` (which depends on the time of
    the call, not on the sightings, so the result can be cached), by field name.
    """
    out: dict[str, NDArray] = {
        "known": np.zeros(n_objects, dtype=bool),
        "positions": np.full((n_objects, 2), np.nan),
        "time_s": np.full(n_objects, np.nan),
        "newest_s": np.full(n_objects, np.nan),
        "spread": np.full(n_objects, np.nan),
        "n": np.zeros(n_objects, dtype=np.int64),
        "outliers": np.zeros(n_objects, dtype=np.int64),
        "rejected": np.zeros(n_objects, dtype=np.int64),
        "velocities": np.full((n_objects, 2), np.nan),
        "velocity_sigma": np.full(n_objects, np.nan),
    }
    labels = np.full(len(times), -1, dtype=np.int64)
    # an object whose total weight is below min_samples has no core point: all noise
    dense = np.bincount(objects, weights, n_objects)[objects] >= min_samples
    if dense.sum() == 1:  # one point heavy enough to be core alone: its own cluster
        labels[dense] = 0
    elif dense.any():
        # objects never share a cluster: each is clustered on its own (as if a third
        # coordinate of 2 eps per object kept them apart)
        labels[dense] = _dbscan_labels(xy[dense], weights[dense], eps, min_samples,
                                       objects[dense] if n_objects > 1 else None)
    noise = labels < 0
    out["outliers"] = np.bincount(objects[noise], minlength=n_objects).astype(np.int64)
    if noise.all():
        return out

    runs = _runs(objects)
    if runs is not None and not noise.any() and int(labels.max()) + 1 == len(runs):
        # the usual case: each object's sightings are one cluster (clusters never span
        # objects): it is the best, numbered like its object's run; the same statistics
        best_object = objects[runs]
        best_newest = np.maximum.reduceat(times, runs)
        best_size = np.diff(runs, append=len(times))
        out["known"][best_object] = True
        out["n"][best_object] = best_size
        obj = objects
        dt = times - best_newest[labels]
        w = weights * _recency(-dt, half_life)
        p = xy
    else:
        # cluster scores: recency relative to each object's newest sighting
        last_of_object = np.full(n_objects, -np.inf)
        if runs is None:
            np.maximum.at(last_of_object, objects, times)
        else:  # sorted by object (the callers' order): one reduceat, the same maxima
            last_of_object[objects[runs]] = np.maximum.reduceat(times, runs)
        score_w = weights * _recency(last_of_object[objects] - times, half_life)
        members = ~noise
        cl = labels[members]
        n_clusters = int(cl.max()) + 1
        cluster_score = np.bincount(cl, score_w[members], n_clusters)
        by_cluster = np.argsort(cl, kind="stable")
        cl_runs = _starts(cl[by_cluster])
        cluster_newest = np.maximum.reduceat(times[members][by_cluster], cl_runs)
        cluster_object = np.zeros(n_clusters, dtype=np.int64)
        cluster_object[cl] = objects[members]  # one object per cluster (kept apart)
        cluster_size = np.bincount(cl, minlength=n_clusters)
        # best per object: largest score, then newest sighting, then lowest label
        order = np.lexsort((np.arange(n_clusters), -cluster_newest, -cluster_score,
                            cluster_object))
        best = order[_starts(cluster_object[order])]
        best_object = cluster_object[best]
        best_newest, best_size = cluster_newest[best], cluster_size[best]
        in_best = np.zeros(n_clusters, dtype=bool)
        in_best[best] = True
        out["known"][best_object] = True
        out["n"][best_object] = best_size
        clustered = np.bincount(objects[members], minlength=n_objects)
        out["rejected"] = (clustered - out["n"]).astype(np.int64)

        # statistics of the best clusters; times relative to the cluster's newest member,
        # and recency relative to it too (a common factor: the means do not depend on it)
        sel = np.zeros(len(times), dtype=bool)
        sel[members] = in_best[cl]
        obj = objects[sel]
        dt = times[sel] - cluster_newest[labels[sel]]
        w = weights[sel] * _recency(-dt, half_life)
        p = xy[sel]
    total = np.bincount(obj, w, n_objects)[best_object]
    t_mean = np.bincount(obj, w * dt, n_objects)[best_object] / total
    mean = np.column_stack([np.bincount(obj, w * p[:, i], n_objects)[best_object]
                            for i in (0, 1)]) / total[:, None]
    slot = np.empty(n_objects, dtype=np.int64)
    slot[best_object] = np.arange(len(best_object))
    k = slot[obj]
    dp = p - mean[k]
    if math.isinf(min_velocity_span):  # no velocity is ever fitted: the spread about the mean
        spread = np.sqrt(np.bincount(k, w * (dp * dp).sum(axis=1), len(best_object)) / total)
        velocity = np.full((len(best_object), 2), np.nan)
        velocity_sigma = np.full(len(best_object), np.nan)
    else:
        ddt = dt - t_mean[k]
        s_tt = np.bincount(k, w * ddt * ddt, len(best_object))
        s_tp = np.column_stack([np.bincount(k, w * ddt * dp[:, i], len(best_object))
                                for i in (0, 1)])
        oldest = np.full(len(best_object), np.inf)
        k_runs = _runs(k)
        if k_runs is None:
            np.minimum.at(oldest, k, dt)
        else:
            oldest[k[k_runs]] = np.minimum.reduceat(dt, k_runs)
        with_velocity = (best_size >= 3) & (-oldest >= min_velocity_span) & (s_tt > 0)
        velocity = np.full((len(best_object), 2), np.nan)
        velocity[with_velocity] = s_tp[with_velocity] / s_tt[with_velocity][:, None]
        residual = dp - np.where(with_velocity[k][:, None], velocity[k] * ddt[:, None], 0.0)
        spread = np.sqrt(np.bincount(k, w * (residual * residual).sum(axis=1),
                                     len(best_object)) / total)
        # weighted least squares: var(slope) = s2 * sum(w^2 dt^2) / s_tt^2, with s2 the residual
        # variance per axis (2 parameters fitted per axis: n - 2 degrees of freedom)
        n_members = best_size.astype(np.float64)
        s2 = spread**2 / 2.0 * n_members / np.maximum(n_members - 2.0, 1.0)
        s_wwtt = np.bincount(k, w * w * ddt * ddt, len(best_object))
        velocity_sigma = np.full(len(best_object), np.nan)
        velocity_sigma[with_velocity] = np.sqrt(
            s2[with_velocity] * s_wwtt[with_velocity]) / s_tt[with_velocity]

    out["positions"][best_object] = mean
    out["newest_s"][best_object] = best_newest
    out["time_s"][best_object] = best_newest + t_mean
    out["spread"][best_object] = spread
    out["velocities"][best_object] = velocity
    out["velocity_sigma"][best_object] = velocity_sigma
    return out
