"""DBSCAN filtering of noisy sightings over a sliding window (seed 002 §2.3).

In ``vision`` mode an agent sees the ball and other players only inside its view cone, every
2-3 cycles, with noise, and places them in its team frame through a particle-filter pose that
is now and then wrong. A mean of recent sightings would be dragged by those wrong ones; the
seed's answer is to keep a short window of sightings per object and cluster it with DBSCAN:
the dense cluster is the object, isolated points are noise. This module keeps the windows;
``strategy.perception.clustering`` clusters them, with DBSCAN's labels exactly as
scikit-learn's ``DBSCAN`` gives them:

- ``SightingWindow``: the window of one object (the ball), ``estimate(now_s)`` ->
  ``FilteredEstimate`` (position, spread, members, age, outliers, velocity).
- ``MultiObjectWindow``: one window per identified object (opponents by uniform number),
  all clustered in one DBSCAN call -> ``MultiEstimate`` with a ``known`` mask.
- ``FilterParams``: the parameters, validated (``FilterParamsError`` names field and value).

How an object's estimate comes from its window (DBSCAN, recency weights, velocity, spread,
cost) is written in ``strategy.perception.clustering`` (``cluster_objects``), which computes it
for all of a window's objects at once.

Determinism: no random state; the points are put in a canonical order (object, time, slot)
before DBSCAN, so the same sightings give the same answer bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from paramkit.checks import check_fields, in_range, positive
from strategy.perception.clustering import NO_SIGHTINGS, cluster_objects
from teamenv.config import build_config
from teamenv.errors import ConfigError, TeamEnvError

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
        # per object, bumped whenever its sightings change: which objects to cluster again
        self._object_versions = np.zeros(self.n_objects, dtype=np.int64)
        self._max_time = -np.inf  # at least the latest sighting time held
        # (version, newest per object, alive, fresh, key) of the last window when every
        # sighting held was in the past, so an unchanged window is recognised cheaply
        self._fresh_memo: tuple | None = None
        # a few clusterings by content key: a caller may alternate between two times
        self._cache: dict[tuple[int, bytes], dict[str, NDArray]] = {}
        # (object versions, fresh, statistics) of the last clustering
        self._last: tuple[NDArray[np.int64], NDArray[np.bool_], dict[str, NDArray]] | None = None
        self.derive_stale = True
        """Cluster again only the objects whose window changed since the last clustering and
        keep the others' statistics (the same result; False clusters every object, for
        tests)."""
        self.clusterings = 0
        """How many times the window has clustered (for cost accounting and tests)."""

    def clear(self) -> None:
        """Forget every sighting (a new half, a reset)."""
        self._times.fill(-np.inf)
        self._version += 1
        self._object_versions += 1

    def clear_objects(self, objects: ArrayLike) -> None:
        """Forget every sighting of ``objects`` (e.g. the ball, moved by the referee)."""
        rows = np.asarray(objects, dtype=np.intp)
        self._times[rows] = -np.inf
        self._version += 1
        self._object_versions[rows] += 1

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
        self._object_versions[ids] += 1

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
            stats = self._cluster(fresh)
        if len(self._cache) >= _CACHE_SIZE and key not in self._cache:
            del self._cache[next(iter(self._cache))]  # the oldest entry
        self._cache[key] = stats
        self._last = (self._object_versions.copy(), fresh, stats)
        age = np.where(stats["known"], now_s - stats["newest_s"], np.inf)
        return MultiEstimate(age_s=_frozen(age), **stats)

    def _cluster(self, fresh: NDArray[np.bool_]) -> dict[str, NDArray]:
        """The statistics of the window ``fresh``: the last clustering's for every object
        whose fresh sightings did not change since, ``NO_SIGHTINGS`` for an object with none,
        DBSCAN for the rest. Objects never share a cluster (they are kept 2 eps apart) and
        each object's sums run over its own sightings in the same order, so an object's
        statistics do not depend on the others': this is what clustering every object again
        would give, bit for bit, with DBSCAN on fewer sightings or not at all."""
        changed = np.ones(self.n_objects, dtype=bool)
        last = None
        if self.derive_stale and self._last is not None and self._last[1].shape == fresh.shape:
            last_versions, last_fresh, last = self._last
            changed = (self._object_versions != last_versions) | \
                (fresh != last_fresh).any(axis=1)
        redo = fresh & changed[:, None]
        if last is not None and not changed.all():
            stats = {name: a.copy() for name, a in last.items()}
            for name, a in stats.items():
                a[changed] = NO_SIGHTINGS[name]
        else:
            stats = None
        if redo.any() or stats is None:
            self.clusterings += 1
            obj, slot = np.nonzero(redo)
            times = self._times[obj, slot]
            order = np.lexsort((slot, times, obj))  # canonical: object, time, slot
            obj, slot, times = obj[order], slot[order], times[order]
            p = self.params
            fitted = cluster_objects(times, self._xy[obj, slot], self._weights[obj, slot],
                                     obj.astype(np.int64), self.n_objects, p.eps_m,
                                     p.min_samples, p.recency_half_life_s,
                                     p.min_velocity_span_s)
            if stats is None:
                stats = fitted
            else:
                for name, a in stats.items():
                    a[changed] = fitted[name][changed]
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
