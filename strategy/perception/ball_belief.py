"""Where one agent believes the ball is: its own filtered sightings, else its teammates' reports.

In ``vision`` mode an agent sees the ball only inside its view cone; when it looks away, the
teammates who see the ball tell it (position and age of their sighting, over the say channel).
``BallBelief`` merges the two for one agent:

1. Own sightings (``see``), DBSCAN-filtered in a ``SightingWindow``, win while the newest
   member of their cluster is younger than ``own_trust_s``: they are what the agent acts on
   most directly, and carry a velocity. A velocity within ``still_sigmas`` standard errors
   of zero is taken as a still ball (velocity 0, position the cluster's mean); otherwise the
   position is the fitted one at the newest sighting (no lag behind a rolling ball).
2. Otherwise the freshest of: the own estimate, the teammates' reports, and the last belief
   returned. Each is remembered: once its window has gone out of date, the own estimate is
   the one at the newest own sighting and the heard one that at the newest report. A ball
   last seen 2 s ago is still a better guess than none, but a fresher report beats it.
3. Teammates' reports are clustered too (``heard_eps_m``, every report can start a cluster),
   each teammate with one vote - its latest report - so one teammate with a bad pose, however
   often it speaks, is outvoted by two who agree.

Ages grow with the time since the sighting (not since the report was heard), and the
confidence halves every ``confidence_half_life_s``. The ball's velocity comes from the own
sightings only (a report carries none). Predicting a rolling ball forward is left to a roll
model passed in (``roll``), so this module needs no physics: for instance
``lambda p, v, dt: (roll.positions(p, v, np.array([dt]))[0], v)`` over
``strategy.geometry.BallRoll`` (that one keeps the velocity; a full model slows it too).
Without one, the position is the fitted position at the newest sighting.

Like ``filtering``, it imports only numpy, sklearn (through ``filtering``) and
``teamenv.errors``; no random state.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from strategy.perception.clustering import cluster_objects
from strategy.perception.filtering import (
    FilteredEstimate,
    FilterParams,
    SightingError,
    SightingWindow,
)

BallSource = Literal["own", "heard", "none"]

RollModel = Callable[[NDArray[np.float64], NDArray[np.float64], float],
                     tuple[NDArray[np.float64], NDArray[np.float64]]]
"""``roll(position, velocity, dt_s) -> (position, velocity)`` of a ball rolling for dt_s."""


@dataclass(frozen=True, eq=False)
class BallEstimate:
    """One agent's belief about the ball (team frame, metres, seconds).

    Attributes:
        position: (2,), or None when ``source`` is "none".
        velocity: (2,) m/s from own sightings (zeros: believed still), or None (heard,
            too few sightings or too short a span, none).
        age_s: time since the sighting it rests on (inf when "none").
        source: "own" (own sightings), "heard" (teammates' reports) or "none".
        confidence: in [0, 1]: the cluster's share of the fresh sightings / reports, times
            ``heard_confidence`` for a heard ball, halved every ``confidence_half_life_s``
            of age. A heuristic for "should I look for the ball", not a probability.
        support: members of the cluster (own sightings, or teammates who agree).
    """

    position: NDArray[np.float64] | None
    velocity: NDArray[np.float64] | None
    age_s: float
    source: BallSource
    confidence: float
    support: int


NO_BALL = BallEstimate(None, None, math.inf, "none", 0.0, 0)


@dataclass(frozen=True, eq=False)
class _Basis:
    """What a belief rests on: a position at ``time_s`` (the newest sighting) and more."""

    position: NDArray[np.float64]
    velocity: NDArray[np.float64] | None
    time_s: float
    source: BallSource
    share: float  # the cluster's share of the fresh sightings / reports
    support: int


class BallBelief:
    """Own ball sightings plus teammates' reports -> one ``BallEstimate`` (see module doc).

    Call ``see`` for each own sighting, ``hear`` for each teammate report, and ``belief``
    once per cycle. ``belief`` remembers its answer, so a ball that has left every window is
    still believed where it was last seen (with a growing age) until ``forget_after_s``.
    """

    def __init__(self, params: FilterParams | None = None,
                 roll: RollModel | None = None) -> None:
        self.params = FilterParams() if params is None else params
        self.roll = roll
        self._own = SightingWindow(self.params)
        self._heard: dict[Hashable, tuple[float, NDArray[np.float64]]] = {}
        self._heard_version = 0
        self._heard_cache: dict[tuple[int, bytes], _Basis | None] = {}
        self._last: _Basis | None = None

    def clear(self) -> None:
        """Forget everything (a new half)."""
        self._own.clear()
        self._heard.clear()
        self._heard_version += 1
        self._last = None

    def see(self, time_s: float, xy: ArrayLike, weight: float = 1.0) -> None:
        """An own (noisy) sighting of the ball at ``xy`` at ``time_s``."""
        self._own.add(time_s, xy, weight)

    def hear(self, time_s: float, xy: ArrayLike, age_s: float, sender: Hashable) -> None:
        """A teammate's report, heard at ``time_s``, of a sighting made ``age_s`` earlier.

        Only the sender's freshest sighting is kept (one vote per teammate). Do not pass the
        agent's own reports back in: its sightings already are in ``see``.
        """
        point = np.asarray(xy, dtype=np.float64)
        if point.shape != (2,) or not np.isfinite(point).all():
            raise SightingError(f"heard ball xy from {sender!r} must be 2 finite numbers, "
                                f"got {xy!r}")
        if not (math.isfinite(time_s) and math.isfinite(age_s) and age_s >= 0):
            raise SightingError(f"heard ball report from {sender!r}: time_s must be finite "
                                f"and age_s finite and >= 0, got {time_s!r}, {age_s!r}")
        seen_at = time_s - age_s
        previous = self._heard.get(sender)
        if previous is None or seen_at >= previous[0]:
            self._heard[sender] = (seen_at, point.copy())
            self._heard_version += 1

    def own_estimate(self, now_s: float) -> FilteredEstimate | None:
        """The filtered own sightings alone (for a caller that wants the details)."""
        return self._own.estimate(now_s)

    def belief(self, now_s: float) -> BallEstimate:
        """The ball as this agent believes it at ``now_s`` (see the module docstring)."""
        return self.choose(now_s, self._own_basis(now_s), self._heard_basis(now_s))

    def choose(self, now_s: float, own: _Basis | None, heard: _Basis | None) -> BallEstimate:
        """The belief from the own and the heard basis (``belief`` computes both itself;
        ``TeamBallBeliefs`` computes them for a whole team in batched DBSCAN calls)."""
        p = self.params
        if own is not None and now_s - own.time_s <= p.own_trust_s:
            chosen: _Basis | None = own
        else:
            # freshest first; on a tie: own, then heard, then the remembered one
            candidates = [b for b in (own, heard, self._last) if b is not None]
            chosen = max(candidates, key=lambda b: b.time_s) if candidates else None
        if chosen is None or now_s - chosen.time_s > p.forget_after_s:
            self._last = None
            return NO_BALL
        self._last = chosen
        return self._estimate(chosen, now_s)

    def _estimate(self, basis: _Basis, now_s: float) -> BallEstimate:
        age = max(0.0, now_s - basis.time_s)
        position, velocity = basis.position.copy(), basis.velocity
        if velocity is not None and self.roll is not None and age > 0:
            rolled, velocity = self.roll(position, velocity.copy(), age)
            position = np.asarray(rolled, dtype=np.float64)
            velocity = np.asarray(velocity, dtype=np.float64)
        elif velocity is not None:
            velocity = velocity.copy()
        factor = 1.0 if basis.source == "own" else self.params.heard_confidence
        confidence = basis.share * factor * math.pow(0.5, age / self.params.confidence_half_life_s)
        return BallEstimate(position, velocity, age, basis.source, float(confidence),
                            basis.support)

    def _own_basis(self, now_s: float) -> _Basis | None:
        """The own estimate now, else as it was at the newest own sighting (the memory)."""
        est = self._own.estimate(now_s)
        newest = self._own.newest_s
        if est is None and newest is not None and newest <= now_s:
            est = self._own.estimate(newest)
        return self.own_basis(est)

    def own_basis(self, est: FilteredEstimate | None) -> _Basis | None:
        """What an own-sightings estimate ``est`` says (None: nothing)."""
        if est is None:
            return None
        share = est.n / (est.n + est.outliers + est.rejected)
        velocity, position = est.velocity, est.latest_position
        if velocity is not None and float(np.hypot(*velocity)) < \
                self.params.still_sigmas * est.velocity_sigma:
            velocity, position = np.zeros(2), est.position  # still: the mean is steadier
        return _Basis(position, velocity, est.newest_s, "own", share, est.n)

    def _heard_basis(self, now_s: float) -> _Basis | None:
        """The reports' cluster now, else as it was at the newest report (the memory)."""
        basis = self._heard_cluster(now_s)
        if basis is None and self._heard:
            basis = self.heard_memory(now_s)
        return basis

    def has_heard(self) -> bool:
        """Any report held (fresh or not)."""
        return bool(self._heard)

    def heard_memory(self, now_s: float) -> _Basis | None:
        """The reports' cluster as it was at the newest report (all of them out of date)."""
        newest = max(t for t, _ in self._heard.values())
        return self._heard_cluster(newest) if newest <= now_s else None

    def _heard_cluster(self, now_s: float) -> _Basis | None:
        """The best cluster of the senders' latest fresh reports (cached on their content)."""
        key, times, xy = self.heard_inputs(now_s)
        if key in self._heard_cache:
            return self._heard_cache[key]
        stats = None
        if len(times):
            # min_samples 1: every report counts, even a lone teammate's
            p = self.params
            stats = cluster_objects(times, xy, np.ones(len(times)),
                                    np.zeros(len(times), dtype=np.int64), 1, p.heard_eps_m,
                                    1, p.recency_half_life_s, math.inf)
        return self.heard_result(key, stats, 0, len(times))

    def heard_inputs(self, now_s: float) -> tuple[tuple[int, bytes], NDArray[np.float64],
                                                    NDArray[np.float64]]:
        """(cache key, times, xy) of the fresh reports at ``now_s``, oldest first."""
        p = self.params
        reports = list(self._heard.values())  # insertion order: deterministic
        times = np.array([t for t, _ in reports], dtype=np.float64)
        fresh = (times >= now_s - p.heard_max_age_s) & (times <= now_s)
        key = (self._heard_version, fresh.tobytes())
        index = np.flatnonzero(fresh)
        index = index[np.argsort(times[index], kind="stable")]
        xy = np.array([reports[i][1] for i in index]).reshape(-1, 2)
        return key, times[index], xy

    def heard_cached(self, key: tuple[int, bytes]) -> tuple[bool, _Basis | None]:
        """(found, basis) of the heard cluster cached under ``key``."""
        return key in self._heard_cache, self._heard_cache.get(key)

    def heard_result(self, key: tuple[int, bytes], stats: dict | None, row: int,
                     count: int) -> _Basis | None:
        """Cache and return the heard basis from ``cluster_objects`` statistics (row
        ``row``, over ``count`` fresh reports; None stats: no fresh report)."""
        basis = None
        if stats is not None and count:
            n = int(stats["n"][row])
            basis = _Basis(stats["positions"][row].copy(), None, float(stats["newest_s"][row]),
                           "heard", n / count, n)
        if len(self._heard_cache) >= 4:  # "now" and "at the newest report", a few versions
            del self._heard_cache[next(iter(self._heard_cache))]
        self._heard_cache[key] = basis
        return basis
