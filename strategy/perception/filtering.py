"""DBSCAN filtering of noisy sightings over a sliding window (seed 002 §2.3).

In ``vision`` mode an agent sees the ball and other players only inside its view cone, every
2-3 cycles, with noise, and places them in its team frame through a particle-filter pose that
is now and then wrong. A mean of recent sightings would be dragged by those wrong ones; the
seed's answer is to keep a short window of sightings per object and cluster it with DBSCAN:
the dense cluster is the object, isolated points are noise. This module does that with
DBSCAN's labels exactly as scikit-learn's ``DBSCAN`` gives them (``_exact_dbscan_labels``:
the within-eps pairs and core points with numpy, the clusters with SciPy's
``connected_components``; tested label for label against sklearn, which itself runs for
non-integer weights) and numpy:

- ``SightingWindow``: the window of one object (the ball), ``estimate(now_s)`` ->
  ``FilteredEstimate`` (position, spread, members, age, outliers, velocity).
- ``MultiObjectWindow``: one window per identified object (opponents by uniform number),
  all clustered in one DBSCAN call -> ``MultiEstimate`` with a ``known`` mask.
- ``FilterParams``: the parameters, validated (``FilterParamsError`` names field and value).

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
fixed Python overhead (input checks, a neighbours index, a per-point loop); the numpy labels
(all-against-all within each object's window, the objects padded into one array) cost
~0.1 ms for a whole team's windows. Clustering runs once per new sighting (not per cycle;
and once when an object goes out of date), never for a window whose total weight is below
``min_samples`` (no core point is possible) or that holds a single point, and once - not
once per object - for all the objects of a ``MultiObjectWindow`` (objects never share a
cluster: they are compared only within themselves, as if a third coordinate ``object * 2
eps`` kept them apart).

Determinism: no random state; the points are put in a canonical order (object, time, slot)
before DBSCAN, so the same sightings give the same answer bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

import portable_math as pm
from paramkit.checks import check_fields, in_range, positive
from teamenv.config import build_config
from teamenv.errors import ConfigError, TeamEnvError

_MAX_HALVINGS = 1000.0
"""Recency exponents are capped here: 0.5**1000 ~ 1e-301 is still a normal float, so weights
never underflow to zero (a division by zero) whatever the half-life."""

_CACHE_SIZE = 4
"""Clusterings kept per window, by content: enough for a caller alternating between "now" and
"when last seen" (``BallBelief``) without re-running sklearn."""


class FilterParamsError(ConfigError):
    """A ``FilterParams`` value is not valid; the message names the field and the value.

    A ``ConfigError``, hence a ``TeamEnvError`` and a ``ValueError``.
    """


class SightingError(TeamEnvError, ValueError):
    """A sighting or report is malformed (shape, NaN/inf, weight <= 0, unknown object)."""


@dataclass(frozen=True)
class FilterParams:
    """Parameters of the sighting filter and of the ball belief (metres, seconds).

    Window and DBSCAN (``SightingWindow``, ``MultiObjectWindow``):
        eps_m: DBSCAN neighbourhood radius. Must exceed the sighting noise (a few sigma) and
            the distance a rolling ball travels between two sightings (so a rolling ball's
            trail stays one cluster), and stay below the size of a typical pose error.
        min_samples: DBSCAN's minimum (weighted) neighbourhood of a core point, itself
            included; seed 002 used 6 at ~20 frames/s, we see an object only every 2-3 cycles.
        max_age_s: the window: sightings this much older than the object's newest one are
            dropped, and all of them once the newest is this old (seed 002: 10 s for goal
            posts, which do not move; the ball does).
        max_len: at most this many sightings per object (the oldest is dropped).
        recency_half_life_s: a sighting's weight halves every this many seconds of age
            relative to the newest one (``math.inf``: all weigh the same).
        min_velocity_span_s: a velocity is estimated only from members spanning this long.
    Ball belief (``strategy.perception.ball_belief.BallBelief``):
        own_trust_s: own sightings younger than this win over anything heard.
        still_sigmas: a ball whose fitted speed is below this many standard errors
            (``velocity_sigma``) is believed still: velocity 0, position the mean (a noisy
            slope would otherwise make a still ball "roll"; 2.5: ~4 % of still balls roll).
        heard_eps_m: clustering radius of teammates' reports (their noise plus ours).
        heard_max_age_s: reports of sightings older than this are ignored.
        confidence_half_life_s: the belief's confidence halves every this many seconds.
        heard_confidence: confidence factor of a heard ball, in (0, 1].
        forget_after_s: a ball not seen or heard of for this long is no longer believed
            (``math.inf``: never forgotten).
    """

    eps_m: float = 0.5
    min_samples: int = field(default=3, metadata=in_range(1))
    max_age_s: float = 0.6
    max_len: int = field(default=32, metadata=in_range(1))
    recency_half_life_s: float = field(default=0.3, metadata=positive(infinite=True))
    min_velocity_span_s: float = 0.1
    own_trust_s: float = 0.3
    still_sigmas: float = 2.5
    heard_eps_m: float = 1.0
    heard_max_age_s: float = 2.0
    confidence_half_life_s: float = 1.0
    heard_confidence: float = field(default=0.7, metadata=in_range(0.0, 1.0, low_open=True))
    forget_after_s: float = field(default=10.0, metadata=positive(infinite=True))

    def __post_init__(self) -> None:
        check_fields(self, FilterParamsError, default=positive())  # a number: > 0 unless declared

    @classmethod
    def from_overrides(cls, overrides: Mapping[str, Any]) -> FilterParams:
        """The defaults with ``overrides`` applied; an unknown key names the known ones."""
        return build_config(cls, overrides, section="filter params", error=FilterParamsError)


@dataclass(frozen=True, eq=False)
class FilteredEstimate:
    """The filtered estimate of one object (team frame, metres, seconds).

    Attributes:
        position: (2,) recency-weighted mean of the best cluster; the position at ``time_s``.
        time_s: the recency-weighted mean time of the members.
        newest_s: time of the newest member.
        age_s: ``now_s - newest_s`` at the ``estimate`` call.
        spread: weighted RMS distance of the members from the fit (m).
        n: members of the best cluster.
        outliers: fresh sightings DBSCAN called noise.
        rejected: fresh sightings in other, lighter clusters.
        velocity: (2,) least-squares velocity (m/s), or None (see the module docstring).
        velocity_sigma: standard error of each velocity component (m/s), NaN without one.
    """

    position: NDArray[np.float64]
    time_s: float
    newest_s: float
    age_s: float
    spread: float
    n: int
    outliers: int
    rejected: int
    velocity: NDArray[np.float64] | None
    velocity_sigma: float = math.nan

    def position_at(self, time_s: float) -> NDArray[np.float64]:
        """The fitted line at ``time_s`` (constant velocity; the mean without a velocity).

        Meant for times within the window (``latest_position``); a rolling ball slows down,
        so predicting further ahead needs a roll model (``BallBelief`` takes one).
        """
        if self.velocity is None:
            return self.position.copy()
        return self.position + self.velocity * (time_s - self.time_s)

    @property
    def latest_position(self) -> NDArray[np.float64]:
        """The fitted position at the newest member's time: no lag behind a moving object."""
        return self.position_at(self.newest_s)


@dataclass(frozen=True, eq=False)
class MultiEstimate:
    """Filtered estimates of N identified objects (row k = object k); arrays are read-only.

    Attributes:
        known: (N,) bool, False for an object with no cluster among its fresh sightings.
        positions: (N, 2), NaN where unknown. The position at ``time_s``.
        time_s, newest_s: (N,) mean / newest member time, NaN where unknown.
        age_s: (N,) ``now_s - newest_s``, inf where unknown.
        spread: (N,), NaN where unknown.
        n, outliers, rejected: (N,) int counts (``FilteredEstimate``).
        velocities: (N, 2), NaN where there is no velocity estimate (``has_velocity``).
        velocity_sigma: (N,) standard error of each velocity component, NaN without one.
    """

    known: NDArray[np.bool_]
    positions: NDArray[np.float64]
    time_s: NDArray[np.float64]
    newest_s: NDArray[np.float64]
    age_s: NDArray[np.float64]
    spread: NDArray[np.float64]
    n: NDArray[np.int64]
    outliers: NDArray[np.int64]
    rejected: NDArray[np.int64]
    velocities: NDArray[np.float64]
    velocity_sigma: NDArray[np.float64]

    @property
    def has_velocity(self) -> NDArray[np.bool_]:
        return ~np.isnan(self.velocities[:, 0])

    def latest_positions(self) -> NDArray[np.float64]:
        """(N, 2) fitted positions at each object's newest member time (NaN where unknown)."""
        step = np.where(self.has_velocity[:, None],
                        self.velocities * (self.newest_s - self.time_s)[:, None], 0.0)
        return self.positions + step

    def get(self, k: int) -> FilteredEstimate | None:
        """Object ``k``'s estimate, or None where unknown."""
        if not self.known[k]:
            return None
        v = self.velocities[k]
        return FilteredEstimate(
            position=self.positions[k].copy(), time_s=float(self.time_s[k]),
            newest_s=float(self.newest_s[k]), age_s=float(self.age_s[k]),
            spread=float(self.spread[k]), n=int(self.n[k]), outliers=int(self.outliers[k]),
            rejected=int(self.rejected[k]),
            velocity=None if math.isnan(v[0]) else v.copy(),
            velocity_sigma=float(self.velocity_sigma[k]))


@lru_cache(maxsize=1)
def _dbscan_class() -> Any:
    """sklearn's DBSCAN, imported on first use: importing sklearn.cluster takes ~1 s."""
    from sklearn.cluster import DBSCAN

    return DBSCAN


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
    if len(w) and bool(np.all(w == np.floor(w))) and float(w.sum()) < 2.0**52:
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
    """sklearn's DBSCAN labels computed with numpy, for integer-valued weights.

    The same decisions as sklearn (``sklearn.cluster._dbscan_inner``): a point's
    neighbourhood is every point whose squared distance, summed over the coordinates in
    order (its ``euclidean`` reduced distance), is at most ``eps * eps``, itself included;
    a core point has a neighbourhood weight of at least ``min_samples`` (integer weights:
    the sum is exact in any order); clusters are the connected components of the core
    points, numbered in the order of their first point; a non-core point within reach of
    core points joins the lowest-numbered of their clusters (the first to reach it), else
    it is noise. Within a group every pair of points is compared (groups are small: one
    object's window), as one flat array of pairs (small arrays: no page faults)."""
    pts = np.asarray(points, dtype=np.float64)
    n = len(pts)
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    if pts.ndim == 1:
        pts = pts[:, None]
    order = None
    if groups is None:
        starts = np.zeros(1, dtype=np.intp)
        counts = np.full(1, n, dtype=np.intp)
    else:
        g = np.asarray(groups)
        if len(g) > 1 and not bool((g[1:] >= g[:-1]).all()):
            order = np.argsort(g, kind="stable")
            g = g[order]
            pts = pts[order]
        starts = _starts(g)
        counts = np.diff(starts, append=n)
    w = np.asarray(weights, dtype=np.float64)
    if order is not None:
        w = w[order]
    a, b = _group_pairs(starts, counts)
    near = _near(pts, a, b, eps)
    if near.all():  # every group is a clique (the usual case): one cluster or all noise
        dense = np.add.reduceat(w, starts) >= min_samples  # integer weights: exact sums
        dense_groups = np.flatnonzero(dense)
        number = _numbered(len(starts), dense_groups,
                           None if order is None else order[starts[dense_groups]])
        return _unsorted(np.repeat(number, counts), order)
    a, b = a[near], b[near]
    if min_samples <= 1:  # every weight is at least 1: every point is a core point
        core = np.ones(n, dtype=bool)
    elif bool((w == 1.0).all()):
        core = 1 + np.bincount(a, minlength=n) + np.bincount(b, minlength=n) >= min_samples
    else:
        core = w + np.bincount(a, w[b], n) + np.bincount(b, w[a], n) >= min_samples
    # components of the core points (SciPy's connected_components over the core-core
    # pairs; a non-core point is a component of its own), each named by its first
    # (smallest) point, as sklearn numbers its clusters
    big = n
    linked = core[a] & core[b]
    graph = coo_matrix((np.ones(int(linked.sum()), dtype=np.int8), (a[linked], b[linked])),
                       shape=(n, n))
    count, component = connected_components(graph, directed=False)
    first = np.full(count, big)
    np.minimum.at(first, component, np.arange(n))
    parent = first[component]
    root = np.where(core, parent, big)
    # a border point: the first cluster among its core neighbours (clusters are numbered
    # in the order of their first point, so the smallest root)
    label_root = root.copy()
    to_a = core[b] & ~core[a]
    np.minimum.at(label_root, a[to_a], root[b[to_a]])
    to_b = core[a] & ~core[b]
    np.minimum.at(label_root, b[to_b], root[a[to_b]])
    labels = np.full(n, -1, dtype=np.int64)
    member = label_root < big
    if member.any():
        roots = np.flatnonzero(root == np.arange(n))  # (sorted) positions of first points
        number = _numbered(n, roots, None if order is None else order[roots])
        labels[member] = number[label_root[member]]
    return _unsorted(labels, order)


def _numbered(size: int, which: NDArray[np.intp],
              original_first: NDArray[np.intp] | None) -> NDArray[np.int64]:
    """(size,) cluster numbers: -1, except 0, 1, ... at ``which`` (the clusters), numbered in
    the order of their first point's index before sorting (``original_first``; None: the
    points were not reordered), as sklearn numbers its clusters."""
    number = np.full(size, -1, dtype=np.int64)
    if original_first is not None:
        which = which[np.argsort(original_first, kind="stable")]
    number[which] = np.arange(len(which))
    return number


def _unsorted(labels: NDArray[np.int64], order: NDArray[np.intp] | None) -> NDArray[np.int64]:
    """``labels`` of points sorted by ``order`` put back in the callers' point order."""
    if order is None:
        return labels
    out = np.empty(len(labels), dtype=np.int64)
    out[order] = labels
    return out


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


def _runs(keys: NDArray[np.int64]) -> NDArray[np.intp] | None:
    """The start of each run of equal ``keys`` when they are sorted (non-empty), else None
    (a per-key maximum or minimum is then one ``reduceat``, exactly ``ufunc.at``'s)."""
    if len(keys) == 0 or not bool((keys[1:] >= keys[:-1]).all()):
        return None
    return _starts(keys)


def _starts(keys: NDArray) -> NDArray[np.intp]:
    """Where each run of equal values of the (non-empty) ``keys`` starts."""
    out = np.flatnonzero(keys[1:] != keys[:-1])
    out += 1
    return np.concatenate((_ZERO, out))


_ZERO = np.zeros(1, dtype=np.intp)


def _recency(age: NDArray[np.float64], half_life: float) -> NDArray[np.float64]:
    if math.isinf(half_life):
        return np.ones_like(age)
    return pm.exp2(-np.minimum(age / half_life, _MAX_HALVINGS))


_UNKNOWN = {"known": False, "positions": np.nan, "time_s": np.nan, "newest_s": np.nan,
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


def _frozen(a: NDArray) -> NDArray:
    a.setflags(write=False)
    return a


class MultiObjectWindow:
    """Sliding windows of sightings of ``n_objects`` identified objects (row k = object k).

    For the opponents (by uniform number) or teammates seen in ``vision`` mode. Storage is
    one (N, max_len) ring per field, so adding a frame's sightings and finding the fresh ones
    are array operations, and all objects are clustered in one DBSCAN call. An object with no
    cluster among its fresh sightings is unknown (``known`` False).
    """

    def __init__(self, n_objects: int, params: FilterParams | None = None) -> None:
        if isinstance(n_objects, bool) or not isinstance(n_objects, (int, np.integer)) \
                or n_objects < 1:
            raise FilterParamsError(f"filter window: n_objects must be an integer >= 1, "
                                    f"got {n_objects!r}")
        self.params = FilterParams() if params is None else params
        self.n_objects = int(n_objects)
        size = (self.n_objects, self.params.max_len)
        self._times = np.full(size, -np.inf)  # -inf = empty slot
        self._xy = np.zeros(size + (2,))
        self._weights = np.zeros(size)
        self._version = 0
        self._max_time = -np.inf  # at least the latest sighting time held
        # (version, newest per object, alive, fresh, key) of the last window when every
        # sighting held was in the past, so an unchanged window is recognised cheaply
        self._fresh_memo: tuple | None = None
        # a few clusterings by content key: a caller may alternate between two times
        self._cache: dict[tuple[int, bytes], dict[str, NDArray]] = {}
        self._last: tuple[int, NDArray[np.bool_], dict[str, NDArray]] | None = None
        self.derive_stale = True
        self.clusterings = 0
        """How many times the window has clustered (for cost accounting and tests)."""
        """Drop objects that went out of date from the last clustering instead of running
        DBSCAN again (the same result; False forces a new clustering, for tests)."""

    def clear(self) -> None:
        """Forget every sighting (a new half, a reset)."""
        self._times.fill(-np.inf)
        self._version += 1

    def clear_objects(self, objects: ArrayLike) -> None:
        """Forget every sighting of ``objects`` (e.g. the ball, moved by the referee)."""
        self._times[np.asarray(objects, dtype=np.intp)] = -np.inf
        self._version += 1

    def add(self, time_s: float, objects: ArrayLike, xy: ArrayLike,
            weights: ArrayLike | None = None) -> None:
        """Add one frame: object ``objects[i]`` seen at ``xy[i]`` at ``time_s``.

        ``objects`` must be distinct (one sighting per object per frame). A full ring drops
        its oldest sighting; a sighting older than everything in a full ring is dropped.
        """
        ids = np.asarray(objects)
        points = np.asarray(xy, dtype=np.float64)
        if ids.ndim != 1 or ids.dtype.kind not in "iu":
            raise SightingError(f"sighting objects must be a 1-D integer array, got {ids!r}")
        if points.shape != (len(ids), 2):
            raise SightingError(f"sighting xy must have shape ({len(ids)}, 2), "
                                f"got {points.shape}")
        if not math.isfinite(time_s):
            raise SightingError(f"sighting time_s must be finite, got {time_s!r}")
        if len(ids) == 0:
            return
        if ids.min() < 0 or ids.max() >= self.n_objects:
            raise SightingError(f"sighting objects must be in [0, {self.n_objects}), "
                                f"got {ids.tolist()}")
        if len(np.unique(ids)) != len(ids):
            raise SightingError(f"sighting objects must be distinct, got {ids.tolist()}")
        if not np.isfinite(points).all():
            raise SightingError(f"sighting xy must be finite, got {points.tolist()}")
        w = np.ones(len(ids)) if weights is None else \
            np.broadcast_to(np.asarray(weights, dtype=np.float64), (len(ids),))
        if not (np.isfinite(w).all() and (w > 0).all()):
            raise SightingError(f"sighting weights must be finite and > 0, got {w.tolist()}")
        rows = self._times[ids]
        slot = rows.argmin(axis=1)  # an empty slot (-inf) first, else the oldest sighting
        keep = rows[np.arange(len(ids)), slot] <= time_s
        ids, slot = ids[keep], slot[keep]
        self._times[ids, slot] = time_s
        if len(ids):
            self._max_time = max(self._max_time, time_s)
        self._xy[ids, slot] = points[keep]
        self._weights[ids, slot] = w[keep]
        self._version += 1

    def prune(self, now_s: float) -> None:
        """Free the slots of sightings out of the window at ``now_s`` (``estimate`` ignores
        them anyway; sightings later than ``now_s`` are kept)."""
        stale = ~self._fresh(now_s) & (self._times <= now_s)
        # no version bump: the fresh sightings are untouched, so cached clusterings stay
        # valid (a cache key is the version plus the fresh slots)
        self._times[stale] = -np.inf
        self._fresh_memo = None

    def fresh_count(self, now_s: float) -> NDArray[np.int64]:
        """(N,) number of fresh sightings per object."""
        return self._fresh(now_s).sum(axis=1)

    def _fresh(self, now_s: float) -> NDArray[np.bool_]:
        """The window at ``now_s``: per object, the sightings within ``max_age_s`` before its
        newest one (at or before ``now_s``), none once that newest one is older than
        ``max_age_s``. Relative to the newest sighting rather than to now, so the window
        changes only when a sighting arrives or the object has been out of sight for
        ``max_age_s``: sklearn runs once per sighting, not also once per sighting ageing out,
        and an object out of sight keeps its estimate (with a growing age) until then."""
        max_age = self.params.max_age_s
        past = self._times <= now_s
        newest = np.where(past, self._times, -np.inf).max(axis=1)
        alive = now_s - newest <= max_age  # False for an object with no sighting (-inf)
        return past & (self._times >= (newest - max_age)[:, None]) & alive[:, None]

    def estimate(self, now_s: float) -> MultiEstimate:
        """Every object's filtered estimate from its fresh sightings (DBSCAN, best cluster).

        The clustering is cached on the window's content (the version of the sightings
        held plus which of them are in the window), so calling this every cycle costs
        sklearn only when a sighting arrived or an object went out of date.
        """
        if not math.isfinite(now_s):
            raise SightingError(f"estimate time now_s must be finite, got {now_s!r}")
        memo = self._fresh_memo
        if memo is not None and memo[0] == self._version and self._max_time <= now_s and \
                np.array_equal(now_s - memo[1] <= self.params.max_age_s, memo[2]):
            # nothing added and no object went out of date: the same window as last time
            fresh, key = memo[3], memo[4]
        else:
            fresh = self._fresh(now_s)
            key = (self._version, fresh.tobytes())
            self._fresh_memo = None
            if self._max_time <= now_s:  # every sighting held is past: newest = row maximum
                newest = self._times.max(axis=1)
                self._fresh_memo = (self._version, newest, now_s - newest <= self.params.max_age_s,
                                    fresh, key)
        stats = self._cache.get(key)
        if stats is None:
            stats = self._without_stale_objects(fresh)
        if stats is None:
            self.clusterings += 1
            obj, slot = np.nonzero(fresh)
            times = self._times[obj, slot]
            order = np.lexsort((slot, times, obj))  # canonical: object, time, slot
            obj, slot, times = obj[order], slot[order], times[order]
            p = self.params
            stats = cluster_objects(times, self._xy[obj, slot], self._weights[obj, slot],
                                    obj.astype(np.int64), self.n_objects, p.eps_m,
                                    p.min_samples, p.recency_half_life_s,
                                    p.min_velocity_span_s)
            stats = {name: _frozen(a) for name, a in stats.items()}
        if len(self._cache) >= _CACHE_SIZE and key not in self._cache:
            del self._cache[next(iter(self._cache))]  # the oldest entry
        self._cache[key] = stats
        self._last = (self._version, fresh, stats)
        age = np.where(stats["known"], now_s - stats["newest_s"], np.inf)
        return MultiEstimate(age_s=_frozen(age), **stats)

    def _without_stale_objects(self, fresh: NDArray[np.bool_]) -> dict[str, NDArray] | None:
        """The last clustering with the objects that went out of date since dropped, when
        nothing else changed (None otherwise). Objects never share a cluster (they are kept
        2 eps apart), so an object's statistics do not depend on the others' sightings: this
        is what clustering again would give, without sklearn's fixed cost."""
        if not self.derive_stale or self._last is None or self._last[0] != self._version:
            return None
        _, last_fresh, last = self._last
        if last_fresh.shape != fresh.shape:
            return None
        same = (fresh == last_fresh).all(axis=1)
        gone = ~fresh.any(axis=1)
        if not (same | gone).all():
            return None
        dropped = gone & ~same
        stats = {name: a.copy() for name, a in last.items()}
        for name, a in stats.items():
            a[dropped] = _UNKNOWN[name]
        return {name: _frozen(a) for name, a in stats.items()}


class SightingWindow:
    """The sliding window of sightings of one object (the ball); see the module docstring."""

    def __init__(self, params: FilterParams | None = None) -> None:
        self._window = MultiObjectWindow(1, params)

    @property
    def params(self) -> FilterParams:
        return self._window.params

    def __len__(self) -> int:
        """Sightings held (fresh or not yet pruned)."""
        return int(np.isfinite(self._window._times).sum())

    @property
    def newest_s(self) -> float | None:
        """Time of the newest sighting held, None when empty."""
        newest = float(self._window._times.max())
        return None if math.isinf(newest) else newest

    @property
    def version(self) -> int:
        """Changes whenever the sightings held change (add, prune, clear): a cache key."""
        return self._window._version

    def clear(self) -> None:
        """Forget every sighting."""
        self._window.clear()

    def add(self, time_s: float, xy: ArrayLike, weight: float = 1.0) -> None:
        """Add one sighting at ``xy`` (team frame, m) at ``time_s``; ``weight`` > 0."""
        point = np.asarray(xy, dtype=np.float64)
        if point.shape != (2,):
            raise SightingError(f"sighting xy must have shape (2,), got {point.shape}")
        self._window.add(time_s, np.zeros(1, dtype=np.int64), point[None], weight)

    def prune(self, now_s: float) -> None:
        """Free the slots of sightings out of the window at ``now_s``."""
        self._window.prune(now_s)

    def estimate(self, now_s: float) -> FilteredEstimate | None:
        """The best cluster's estimate from the fresh sightings, or None (no cluster)."""
        return self._window.estimate(now_s).get(0)
