"""A team's sightings filtered in batched DBSCAN calls; each agent's beliefs stay its own.

scikit-learn's DBSCAN costs ~0.5 ms per call, almost all of it fixed overhead, and a team in
``vision`` mode has up to 11 agents, each filtering the ball and 11 opponents. Calling it per
agent and per object would take most of a 20 ms cycle. ``TeamSightings`` keeps every agent's
windows as separate objects of one ``MultiObjectWindow`` (object = agent * (1 + N) + slot,
slot 0 the ball, slot 1 + j opponent j), which ``cluster_objects`` keeps apart, so one call
per vision cycle filters them all; and it clusters every agent's heard ball reports in one
more call. Agent k's results depend only on agent k's sightings and the reports agent k heard.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from strategy.perception.ball_belief import BallBelief, BallEstimate, RollModel
from strategy.perception.filtering import (
    FilterParams,
    MultiEstimate,
    MultiObjectWindow,
    cluster_objects,
)


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

    def clear_ball(self) -> None:
        """Every agent forgets the ball (the referee moved it: a kick-off or set play)."""
        for ball in self.balls:
            ball.clear()
        self._own_memory = [None] * self.n_agents
        self.window.clear_objects(np.arange(self.n_agents) * self.stride)
        self._estimate = None

    # -- input ------------------------------------------------------------------------------
    def see(self, time_s: float, agent: int, ball: ArrayLike | None,
            opponents: ArrayLike, opponent_xy: ArrayLike) -> None:
        """Agent ``agent``'s sightings of one vision cycle: the ball (or None) and opponents
        ``opponents`` (uniform index) at ``opponent_xy`` (team frame)."""
        ids = np.asarray(opponents, dtype=np.int64) + 1
        xy = np.asarray(opponent_xy, dtype=np.float64).reshape(-1, 2)
        if ball is not None:
            ids = np.r_[0, ids]
            xy = np.vstack((np.asarray(ball, dtype=np.float64)[None], xy))
        if len(ids):
            self.window.add(time_s, agent * self.stride + ids, xy)
            self._estimate = None

    def hear(self, time_s: float, agent: int, xy: ArrayLike, age_s: float,
             sender: int) -> None:
        """Agent ``agent`` heard ``sender`` report the ball at ``xy``, seen ``age_s`` ago."""
        self.balls[agent].hear(time_s, xy, age_s, sender)

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
        est = self.estimate(now_s)
        rows = slice(agent * self.stride + 1, (agent + 1) * self.stride)
        known = est.known[rows].copy()
        return np.where(known[:, None], est.latest_positions()[rows], 0.0), known

    def ball_beliefs(self, now_s: float) -> list[BallEstimate]:
        """Every agent's ball belief at ``now_s`` (own sightings, else heard reports)."""
        est = self.estimate(now_s)
        heard = self._heard_bases(now_s)
        out = []
        for k, ball in enumerate(self.balls):
            own = est.get(k * self.stride)
            if own is None:  # out of date: the estimate at the newest sighting remembered
                own = self._own_memory[k]
            else:
                self._own_memory[k] = own
            out.append(ball.choose(now_s, ball.own_basis(own), heard[k]))
        return out

    def _heard_bases(self, now_s: float) -> list:
        """Each agent's heard-report cluster, the uncached ones in one DBSCAN call."""
        p = self.params
        bases: list = [None] * self.n_agents
        todo, times, xy, objects, counts = [], [], [], [], []
        for k, ball in enumerate(self.balls):
            key, t, pts = ball.heard_inputs(now_s)
            found, basis = ball.heard_cached(key)
            if found:
                bases[k] = basis
            elif len(t) == 0:
                bases[k] = ball.heard_result(key, None, 0, 0)
            else:
                todo.append((k, key, len(todo)))
                times.append(t)
                xy.append(pts)
                objects.append(np.full(len(t), len(todo) - 1, dtype=np.int64))
                counts.append(len(t))
        if todo:
            stats = cluster_objects(np.concatenate(times), np.concatenate(xy),
                                    np.ones(sum(counts)), np.concatenate(objects), len(todo),
                                    p.heard_eps_m, 1, p.recency_half_life_s, np.inf)
            for (k, key, row), count in zip(todo, counts, strict=True):
                bases[k] = self.balls[k].heard_result(key, stats, row, count)
        for k, ball in enumerate(self.balls):
            if bases[k] is None and ball.has_heard():
                bases[k] = ball.heard_memory(now_s)  # all reports out of date: the last one
        return bases
