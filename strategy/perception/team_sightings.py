"""A team's sightings filtered in batched DBSCAN calls; each agent's beliefs stay its own.

scikit-learn's DBSCAN costs ~0.5 ms per call, almost all of it fixed overhead, and a team in
``vision`` mode has up to 11 agents, each filtering the ball and 11 opponents. Calling it per
agent and per object would take most of a 20 ms cycle. ``TeamSightings`` keeps every agent's
windows as separate objects of one ``MultiObjectWindow`` (object = agent * (1 + N) + slot,
slot 0 the ball, slot 1 + j opponent j), which ``cluster_objects`` keeps apart, so one call
per vision cycle filters them all (``see_many`` adds a whole team's sightings in one go); and
it clusters every agent's heard ball reports in one more call, from an (agents x senders)
table of the latest reports, so finding what changed is one array pass, not a loop over
agents. Agent k's results depend only on agent k's sightings and the reports agent k heard.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from strategy.perception.ball_belief import BallBelief, BallEstimate, RollModel, _Basis
from strategy.perception.clustering import clique_means, cluster_objects
from strategy.perception.filtering import FilterParams, MultiEstimate, MultiObjectWindow


class TeamSightings:
    """Own sightings of the ball and opponents, and heard ball reports, for ``n_agents``
    agents who each track ``n_opponents`` opponents (see the module docstring)."""

    def __init__(self, n_agents: int, n_opponents: int, params: FilterParams | None = None,
                 roll: RollModel | None = None) -> None:
        self.params = FilterParams() if params is None else params
        self.n_agents, self.n_opponents = int(n_agents), int(n_opponents)
        self.stride = 1 + self.n_opponents
        self.window = MultiObjectWindow(self.n_agents * self.stride, self.params)
        self.balls = [BallBelief(self.params, roll) for _ in range(self.n_agents)]
        self._own_memory: list = [None] * self.n_agents
        self._estimate: MultiEstimate | None = None
        self._estimate_time = np.nan
        # the own bases of the last clustering (keyed by its arrays: a new clustering makes
        # new ones), and the opponents of the last estimate
        self._own_of: NDArray | None = None
        self._own_bases: list = [None] * self.n_agents
        self._opponents_of: NDArray | None = None
        self._opponents: tuple[NDArray[np.float64], NDArray[np.bool_]] | None = None
        # heard reports: each agent's latest report per sender (the same as its BallBelief
        # holds), as arrays: seen-at time (NaN: none), position, the order the sender was
        # first heard in (BallBelief's dict order), a version per agent
        self._senders: dict = {}
        self._heard_t = np.full((self.n_agents, self.n_agents), np.nan)
        self._heard_xy = np.zeros((self.n_agents, self.n_agents, 2))
        self._heard_seq = np.zeros((self.n_agents, self.n_agents), dtype=np.int64)
        self._heard_next = np.zeros(self.n_agents, dtype=np.int64)
        self._heard_version = np.zeros(self.n_agents, dtype=np.int64)
        self._heard_key: list = [None] * self.n_agents
        self._heard_basis: list = [None] * self.n_agents

    def clear_ball(self) -> None:
        """Every agent forgets the ball (the referee moved it: a kick-off or set play)."""
        for ball in self.balls:
            ball.clear()
        self._own_memory = [None] * self.n_agents
        self.window.clear_objects(np.arange(self.n_agents) * self.stride)
        self._estimate = None
        self._own_of = None
        self._heard_t.fill(np.nan)
        self._heard_next.fill(0)
        self._heard_version += 1

    # -- input ------------------------------------------------------------------------------
    def see(self, time_s: float, agent: int, ball: ArrayLike | None,
            opponents: ArrayLike, opponent_xy: ArrayLike) -> None:
        """Agent ``agent``'s sightings of one vision cycle: the ball (or None) and opponents
        ``opponents`` (uniform index) at ``opponent_xy`` (team frame)."""
        ids = np.asarray(opponents, dtype=np.int64) + 1
        xy = np.asarray(opponent_xy, dtype=np.float64).reshape(-1, 2)
        if ball is not None:
            ids = np.concatenate((np.zeros(1, dtype=np.int64), ids))
            xy = np.vstack((np.asarray(ball, dtype=np.float64)[None], xy))
        if len(ids):
            self.window.add(time_s, agent * self.stride + ids, xy)
            self._estimate = None

    def see_many(self, time_s: float, objects: NDArray[np.int64],
                 xy: NDArray[np.float64]) -> None:
        """Several agents' sightings of one vision cycle at once: ``objects`` (distinct)
        are window rows ``agent * (1 + N) + slot`` (slot 0 the ball, 1 + j opponent j) seen
        at ``xy`` (team frame); the same as ``see`` for each agent."""
        if len(objects):
            self.window.add(time_s, objects, xy)
            self._estimate = None

    def hear(self, time_s: float, agent: int, xy: ArrayLike, age_s: float,
             sender: int) -> None:
        """Agent ``agent`` heard ``sender`` report the ball at ``xy``, seen ``age_s`` ago."""
        ball = self.balls[agent]
        ball.hear(time_s, xy, age_s, sender)  # checks the report; keeps the memory's copy
        col = self._senders.get(sender)
        if col is None:
            col = self._senders[sender] = len(self._senders)
            if col >= self._heard_t.shape[1]:  # more senders than agents: grow the table
                grow = self._heard_t.shape[1]
                self._heard_t = np.pad(self._heard_t, ((0, 0), (0, grow)),
                                       constant_values=np.nan)
                self._heard_xy = np.pad(self._heard_xy, ((0, 0), (0, grow), (0, 0)))
                self._heard_seq = np.pad(self._heard_seq, ((0, 0), (0, grow)))
        seen_at = time_s - age_s
        previous = self._heard_t[agent, col]
        if math.isnan(previous) or seen_at >= previous:  # as BallBelief.hear
            if math.isnan(previous):
                self._heard_seq[agent, col] = self._heard_next[agent]
                self._heard_next[agent] += 1
            self._heard_t[agent, col] = seen_at
            self._heard_xy[agent, col] = np.asarray(xy, dtype=np.float64)
            self._heard_version[agent] += 1

    # -- output -----------------------------------------------------------------------------
    def estimate(self, now_s: float) -> MultiEstimate:
        """All agents' filtered own sightings (one DBSCAN call when something changed)."""
        if self._estimate is None or self._estimate_time != now_s:
            self._estimate = self.window.estimate(now_s)
            self._estimate_time = now_s
        return self._estimate

    def opponents(self, now_s: float, agent: int) -> tuple[NDArray[np.float64],
                                                            NDArray[np.bool_]]:
        """Agent ``agent``'s opponents: (N, 2) positions (zeros where unknown), (N,) known."""
        positions, known = self.all_opponents(now_s)
        return positions[agent].copy(), known[agent].copy()

    def all_opponents(self, now_s: float) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Every agent's opponents: (A, N, 2) positions (zeros where unknown), (A, N) known
        (row k is agent k's own; fresh copies every call, computed once per clustering)."""
        est = self.estimate(now_s)
        if self._opponents_of is not est.known:  # a new clustering (the age does not matter)
            shape = (self.n_agents, self.stride)
            known = est.known.reshape(shape)[:, 1:].copy()
            latest = est.latest_positions().reshape(shape + (2,))[:, 1:]
            positions = np.where(known[:, :, None], latest, 0.0)
            self._opponents_of, self._opponents = est.known, (positions, known)
        assert self._opponents is not None
        positions, known = self._opponents
        return positions.copy(), known.copy()

    def ball_beliefs(self, now_s: float) -> list[BallEstimate]:
        """Every agent's ball belief at ``now_s`` (own sightings, else heard reports)."""
        est = self.estimate(now_s)
        heard = self._heard_bases(now_s)
        if self._own_of is not est.known:  # a new clustering: the own bases again
            for k, ball in enumerate(self.balls):
                own = est.get(k * self.stride)
                if own is None:  # out of date: the estimate at the newest sighting remembered
                    own = self._own_memory[k]
                else:
                    self._own_memory[k] = own
                self._own_bases[k] = ball.own_basis(own)
            self._own_of = est.known
        return [ball.choose(now_s, own, h)
                for ball, own, h in zip(self.balls, self._own_bases, heard, strict=True)]

    def _heard_bases(self, now_s: float) -> list:
        """Each agent's heard-report cluster, the changed ones in one clustering call (the
        same as ``BallBelief``'s own: its reports, freshest per sender, within
        ``heard_max_age_s`` of ``now_s``, ordered by time then by when the sender was first
        heard)."""
        p = self.params
        t = self._heard_t
        with np.errstate(invalid="ignore"):  # NaN: no report
            fresh = (t >= now_s - p.heard_max_age_s) & (t <= now_s)
        any_fresh = fresh.any(axis=1).tolist()
        versions = self._heard_version.tolist()
        bases: list = [None] * self.n_agents
        todo = []
        for k in range(self.n_agents):
            if not any_fresh[k]:
                self._heard_key[k] = None
                continue
            key = (versions[k], fresh[k].tobytes())
            if key == self._heard_key[k]:
                bases[k] = self._heard_basis[k]
            else:
                self._heard_key[k] = key
                todo.append(k)
        if todo:
            rows = np.asarray(todo)
            sub = fresh[rows]
            r, c = np.nonzero(sub)
            src = rows[r]
            times = t[src, c]
            order = np.lexsort((self._heard_seq[src, c], times, r))
            r, times = r[order], times[order]
            xy = self._heard_xy[src[order], c[order]]
            counts = np.bincount(r, minlength=len(todo)).tolist()
            objects = r.astype(np.int64)
            # the usual case first: every agent's reports agree within heard_eps_m (one
            # cluster each; the same bits as the clustering, which handles the rest)
            stats = clique_means(times, xy, objects, p.heard_eps_m, p.recency_half_life_s)
            if stats is None:
                stats = cluster_objects(times, xy, np.ones(len(times)), objects, len(todo),
                                        p.heard_eps_m, 1, p.recency_half_life_s, np.inf)
            n_members = stats["n"].tolist()
            newest = stats["newest_s"].tolist()
            for row, k in enumerate(todo):
                n = n_members[row]
                bases[k] = self._heard_basis[k] = _Basis(
                    stats["positions"][row].copy(), None, newest[row], "heard",
                    n / counts[row], n)
        for k, ball in enumerate(self.balls):
            if bases[k] is None and ball.has_heard():
                bases[k] = ball.heard_memory(now_s)  # all reports out of date: the last one
        return bases
