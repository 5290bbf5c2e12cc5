"""Per-object DBSCAN cluster statistics of sightings: the numerical core of the sighting
windows (``strategy.perception.filtering``) and of the heard reports
(``strategy.perception.team_sightings``).

DBSCAN's labels are exactly scikit-learn's ``DBSCAN``'s (``_exact_dbscan_labels``: one
compiled pass over each object's pairs, ``strategy.perception.dbscan``; tested label for label
against sklearn, which itself runs for non-integer weights).

The estimate of an object (``cluster_objects``):

- Only the *window* counts: per object, the sightings within ``max_age_s`` before its newest
  one (at or before ``now_s``); none once that newest one is ``max_age_s`` old. (Relative to
  the newest sighting, not to now: the window then changes only when a sighting arrives, and
  an object that left the view cone keeps its estimate, with a growing ``age_s``.)
- DBSCAN (``eps_m``, ``min_samples``; the sightings' own weights are its ``sample_weight``,
  so ``min_samples`` is a minimum total weight) splits them into clusters and noise.
- Each sighting also gets a *recency* factor ``0.5 ** (age / recency_half_life_s)``: the best
  cluster is the one with the largest recency-weighted total weight (ties: the one with the
  most recent sighting), so after the object jumps (a kick, a reset) the new cluster takes
  over within about one half-life instead of after half a window.
- Position = the recency-weighted mean of the best cluster's members. It is the position at
  ``time_s``, the recency-weighted mean time of the members (not "now"): for an object moving
  at constant velocity the mean position is exactly the least-squares line at the mean time,
  so ``position_at``/``latest_position`` move it along ``velocity`` without bias.
- Velocity = the weighted least-squares slope of position over time, None with fewer than 3
  members or when they span less than ``min_velocity_span_s`` (the slope would be noise).
- Spread = weighted RMS distance of the members from that fit (from the mean when there is no
  velocity): the noise, not the distance travelled by a rolling ball.
- Velocity sigma = the slope's standard error per axis (from the residuals): a still ball's
  fitted velocity is noise of about this size, so a consumer can tell rolling from still.

Cost: sklearn's ``DBSCAN.fit`` costs ~0.4-1.0 ms a call on 10-60 points, nearly all of it
fixed Python overhead (input checks, a neighbours index, a per-point loop); the compiled
labels (all-against-all within each object's window) cost tens of microseconds for a whole
team's windows, most of it the call itself. Clustering runs once per new sighting (not per cycle;
and once when an object goes out of date), never for a window whose total weight is below
``min_samples`` (no core point is possible) or that holds a single point, and once - not
once per object - for all the objects of a ``MultiObjectWindow`` (objects never share a
cluster: they are compared only within themselves, as if a third coordinate ``object * 2
eps`` kept them apart).

Determinism: no random state; the callers put the points in a canonical order (object, time,
slot), so the same sightings give the same answer bit for bit.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

import portable_math as pm

MAX_HALVINGS = 1000.0
"""Recency exponents are capped here: 0.5**1000 ~ 1e-301 is still a normal float, so weights
never underflow to zero (a division by zero) whatever the half-life."""


@lru_cache(maxsize=1)
def _dbscan_class() -> Any:
    """sklearn's DBSCAN, imported on first use: importing sklearn.cluster takes ~1 s."""
    from sklearn.cluster import DBSCAN

    return DBSCAN


def _integer_valued(weights: NDArray[np.float64]) -> bool:
    """Whether DBSCAN's weighted counts are exact whatever the order of summation: integer
    weights (every caller here: unit weights) whose sum is below 2**52."""
    return bool(len(weights) and np.all(weights == np.floor(weights))
                and float(weights.sum()) < 2.0**52)


def _dbscan_labels(points: NDArray[np.float64], weights: NDArray[np.float64], eps: float,
                   min_samples: int, groups: NDArray[np.int64] | None = None
                   ) -> NDArray[np.int64]:
    """DBSCAN labels (-1 = noise) of ``points``, exactly as sklearn's ``DBSCAN`` gives them.

    ``groups`` (optional, (n,) ints) says which points can be neighbours at all: points of
    different groups must be more than ``eps`` apart (``cluster_objects`` keeps objects
    apart so), and are then never compared. With integer-valued weights (every caller here:
    unit weights) the labels come from numpy (``_exact_dbscan_labels``), otherwise from
    sklearn itself (its weighted neighbourhood sums depend on its summation order)."""
    w = np.asarray(weights, dtype=np.float64)
    if _integer_valued(w):
        return _exact_dbscan_labels(points, w, eps, min_samples, groups)
    if groups is not None and points.ndim == 2:  # sklearn needs the groups kept apart
        points = np.column_stack([points, np.asarray(groups) * (2.0 * eps)])
    return _sklearn_dbscan_labels(points, w, eps, min_samples)


def _sklearn_dbscan_labels(points: NDArray[np.float64], weights: NDArray[np.float64],
                           eps: float, min_samples: int) -> NDArray[np.int64]:
    """sklearn's DBSCAN labels (~0.5 ms a call, nearly all of it fixed overhead)."""
    import sklearn

    dbscan = _dbscan_class()
    # inputs are validated on add(): skip sklearn's per-call checks (most of its cost)
    with sklearn.config_context(skip_parameter_validation=True, assume_finite=True):
        # a ball tree: brute force runs an OpenMP pool that stalls on 2 busy cores (~30 ms a
        # call) and grows quadratically with a batched team window
        # unit weights are passed as None: with weights sklearn sums each neighbourhood's
        # weights in a Python loop (one np.sum per point), which dominated a team's cost
        unit = bool(np.all(weights == 1.0))
        model = dbscan(eps=eps, min_samples=min_samples, algorithm="ball_tree").fit(
            points, sample_weight=None if unit else weights)
    return np.asarray(model.labels_, dtype=np.int64)


@lru_cache(maxsize=64)
def _pair_table(size: int) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """The pairs ``i < j`` of ``size`` points, ordered by ``j`` then ``i``, so that the pairs
    of the first ``c`` points are the first ``c (c - 1) / 2`` (read-only, cached)."""
    j, i = np.triu_indices(size, 1)
    i = i.astype(np.intp)
    j = j.astype(np.intp)
    # triu_indices gives (row, col), row < col, row-major; as (col, row) with col < row
    # swapped: pairs (i, j) with i > j ... order by the larger index, then the smaller
    big, small = np.maximum(i, j), np.minimum(i, j)
    order = np.lexsort((small, big))
    small, big = small[order], big[order]
    small.setflags(write=False)
    big.setflags(write=False)
    return small, big


def _exact_dbscan_labels(points: NDArray[np.float64], weights: NDArray[np.float64],
                         eps: float, min_samples: int,
                         groups: NDArray[np.int64] | None = None) -> NDArray[np.int64]:
    """sklearn's DBSCAN labels for integer-valued weights, in one compiled pass over each
    group's pairs (``strategy.perception.dbscan``, imported on first use: numba takes a few
    tenths of a second to import): each point compared only with the points of its own group
    (``groups``: (n,) ints; None: one group)."""
    from strategy.perception.cluster_kernel import group_labels  # numba: on first use

    pts = np.asarray(points, dtype=np.float64)
    n = len(pts)
    if n == 0:
        return np.full(0, -1, dtype=np.int64)
    pts = np.ascontiguousarray(pts.reshape(n, -1))
    g = np.zeros(n, dtype=np.int64) if groups is None else \
        np.ascontiguousarray(groups, dtype=np.int64)
    return group_labels(pts, np.ascontiguousarray(weights, dtype=np.float64), g,
                        float(eps) * float(eps), float(min_samples))


def _group_pairs(starts: NDArray[np.intp], counts: NDArray[np.intp]
                 ) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Every pair ``a < b`` of points within each group (group g: points ``starts[g]`` ..
    ``starts[g] + counts[g] - 1``), sorted by ``b`` then ``a``."""
    pi, pj = _pair_table(int(counts.max()))
    if len(counts) == 1:
        m = int(counts[0]) * (int(counts[0]) - 1) // 2
        return starts[0] + pi[:m], starts[0] + pj[:m]
    # group g: the first counts[g] (counts[g] - 1) / 2 pairs of the table
    per = counts * (counts - 1) // 2
    total = int(per.sum())
    offset = np.repeat(np.cumsum(per) - per, per)
    k = np.arange(total) - offset
    first = np.repeat(starts, per)
    return first + pi[k], first + pj[k]


def _near(points: NDArray[np.float64], a: NDArray[np.intp], b: NDArray[np.intp],
          eps: float) -> NDArray[np.bool_]:
    """Whether each pair is within ``eps``: sklearn's euclidean reduced distance (squares
    summed over the coordinates in order) against ``eps * eps``."""
    rd = np.zeros(len(a))
    for j in range(points.shape[1]):
        c = points[:, j]
        d = c[a] - c[b]
        rd += d * d
    return rd <= eps * eps


def clique_means(times: NDArray[np.float64], xy: NDArray[np.float64],
                 objects: NDArray[np.int64], eps: float, half_life: float
                 ) -> dict[str, NDArray] | None:
    """``cluster_objects``'s ``n``, ``positions`` and ``newest_s`` for unit weights and
    ``min_samples`` 1 when every object's sightings lie within ``eps`` of each other (one
    cluster each: the usual heard reports), with the same arithmetic, hence the same bits;
    None otherwise. ``objects`` must be sorted, non-empty and cover ``0..max`` (the rows),
    ``times`` sorted within each object."""
    n = len(times)
    starts = _starts(objects)
    counts = np.diff(starts, append=n)
    if len(starts) != int(objects[-1]) + 1 or objects[0] != 0:
        return None
    if counts.max() > 1:
        a, b = _group_pairs(starts, counts)
        if not _near(xy, a, b, eps).all():
            return None
    newest = np.maximum.reduceat(times, starts)
    dt = times - newest[objects]
    w = _recency(-dt, half_life)  # = unit weights * recency (x * 1.0 is x)
    total = np.bincount(objects, w, len(starts))
    mean = np.column_stack([np.bincount(objects, w * xy[:, i], len(starts))
                            for i in (0, 1)]) / total[:, None]
    return {"n": counts.astype(np.int64), "positions": mean, "newest_s": newest}


def _starts(keys: NDArray) -> NDArray[np.intp]:
    """Where each run of equal values of the (non-empty) ``keys`` starts."""
    out = np.flatnonzero(keys[1:] != keys[:-1])
    out += 1
    return np.concatenate((_ZERO, out))


_ZERO = np.zeros(1, dtype=np.intp)


def _recency(age: NDArray[np.float64], half_life: float) -> NDArray[np.float64]:
    if math.isinf(half_life):
        return np.ones_like(age)
    return pm.exp2(-np.minimum(age / half_life, MAX_HALVINGS))


NO_SIGHTINGS = {"known": False, "positions": np.nan, "time_s": np.nan, "newest_s": np.nan,
            "spread": np.nan, "n": 0, "outliers": 0, "rejected": 0, "velocities": np.nan,
            "velocity_sigma": np.nan}
"""What ``cluster_objects`` reports for an object with no sightings."""


def cluster_objects(times: NDArray[np.float64], xy: NDArray[np.float64],
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
    times = np.ascontiguousarray(times, dtype=np.float64)
    xy = np.ascontiguousarray(xy, dtype=np.float64).reshape(len(times), 2)
    weights = np.ascontiguousarray(weights, dtype=np.float64)
    objects = np.ascontiguousarray(objects, dtype=np.int64)
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
    from strategy.perception.cluster_kernel import cluster_stats  # numba: on first use

    # the best cluster of each object and its fit, in one compiled pass (the same bits as
    # the NumPy expressions it replaced: ``strategy.perception.cluster_kernel``)
    cluster_stats(times, xy, weights, objects, labels, float(half_life),
                  float(min_velocity_span), _RECENCY, out["known"], out["positions"],
                  out["time_s"], out["newest_s"], out["spread"], out["n"], out["outliers"],
                  out["rejected"], out["velocities"], out["velocity_sigma"])
    return out


# the recency's base and cap, read from an array: see cluster_kernel
_RECENCY = np.array([2.0, MAX_HALVINGS])


def prepare_kernels() -> None:
    """Compile (or load from numba's cache) the clustering's kernels now, before a match's
    first cycle runs under its stall watchdog: two objects of two sightings each."""
    cluster_objects(np.array([0.0, 0.02, 0.0, 0.02]),
                    np.array([[0.0, 0.0], [0.01, 0.0], [9.0, 9.0], [9.0, 9.01]]), np.ones(4),
                    np.array([0, 0, 1, 1], dtype=np.int64), 2, 0.5, 1, 0.3, 0.01)
