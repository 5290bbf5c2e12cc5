"""Rankings on goals, expected goals or a composite, with confidence intervals, and the
sequential test that says when a pairing is separated.

A match gives each team a *margin* on a metric: its value minus the opponent's. Metrics:

- ``goals``: goals scored (the official score: a forfeit counts 0-3);
- ``xg``: expected goals (``teamenv.analytics.xg``), which varies less from match to match
  than goals;
- ``composite``: ``COMPOSITE_WEIGHTS`` · (goals, xG): half the goal margin plus half the xG
  margin — goals still count, the xG half damps their luck.

A team's rating is its mean margin per match, with a bootstrap percentile interval over its
matches. A pairing is *separated* once the t interval of the mean per-match margin excludes
zero (at least ``MIN_MATCHES`` matches; repeated looks make this a sequential rule whose
real error rate is above the nominal 5 %, see docs/analytics.md).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from teamenv.errors import ConfigError

RANK_METRICS = ("goals", "xg", "composite")
COMPOSITE_WEIGHTS = {"goals": 0.5, "xg": 0.5}
MIN_MATCHES = 3


@dataclass(frozen=True)
class MatchMargins:
    """One match from a ranking's point of view: team ``a`` vs ``b`` and each metric's value
    for both (``values[metric] = (a's, b's)``)."""

    a: str
    b: str
    values: dict[str, tuple[float, float]]

    def margin(self, metric: str) -> float:
        """a's value minus b's on ``metric``."""
        check_metric(metric)
        if metric == "composite":
            return sum(w * self.margin(m) for m, w in COMPOSITE_WEIGHTS.items())
        if metric not in self.values:
            raise ConfigError(f"ranking: match {self.a} vs {self.b} has no {metric!r} numbers")
        va, vb = self.values[metric]
        return float(va) - float(vb)


@dataclass(frozen=True)
class TeamRank:
    """A team's mean margin per match on the ranking metric and its interval."""

    team: str
    metric: str
    mean: float
    low: float
    high: float
    matches: int
    rank: int = 0


def check_metric(metric: str) -> str:
    if metric not in RANK_METRICS:
        raise ConfigError(f"rank by: {metric!r}; choose one of {list(RANK_METRICS)}")
    return metric


def rank_teams(matches: Iterable[MatchMargins], metric: str, teams: Sequence[str] | None = None,
               n_bootstrap: int = 1000, seed: int = 0, confidence: float = 0.95
               ) -> list[TeamRank]:
    """Teams by mean margin per match on ``metric`` (best first), each with a ``confidence``
    bootstrap percentile interval over its own matches (``n_bootstrap`` resamples drawn with
    ``numpy.random.default_rng(seed)``; 0: no interval, the mean itself)."""
    check_metric(metric)
    margins: dict[str, list[float]] = {t: [] for t in teams or ()}
    for m in matches:
        d = m.margin(metric)
        margins.setdefault(m.a, []).append(d)
        margins.setdefault(m.b, []).append(-d)
    rng = np.random.default_rng(seed)
    out = []
    for team in sorted(margins):
        x = np.asarray(margins[team], dtype=float)
        if x.size == 0:
            out.append(TeamRank(team, metric, math.nan, math.nan, math.nan, 0))
            continue
        low, high = bootstrap_interval(x, n_bootstrap, rng, confidence)
        out.append(TeamRank(team, metric, float(x.mean()), low, high, int(x.size)))
    out.sort(key=lambda r: (-(r.mean if not math.isnan(r.mean) else -math.inf), r.team))
    return [TeamRank(r.team, r.metric, r.mean, r.low, r.high, r.matches, k + 1)
            for k, r in enumerate(out)]


def bootstrap_interval(x: np.ndarray, n_bootstrap: int, rng: np.random.Generator,
                       confidence: float = 0.95) -> tuple[float, float]:
    """Percentile interval of the mean of ``x`` over ``n_bootstrap`` resamples."""
    x = np.asarray(x, dtype=float)
    if x.size < 2 or n_bootstrap < 1:
        return float(x.mean()), float(x.mean())
    means = x[rng.integers(0, x.size, size=(n_bootstrap, x.size))].mean(axis=1)
    tail = (1.0 - confidence) / 2.0 * 100.0
    low, high = np.percentile(means, [tail, 100.0 - tail])
    return float(low), float(high)


def t_interval(x: Sequence[float], confidence: float = 0.95) -> tuple[float, float, float]:
    """(mean, low, high): the t interval of the mean of ``x`` (one value: the value)."""
    from scipy.stats import t as student_t

    a = np.asarray(x, dtype=float)
    mean = float(a.mean())
    if a.size < 2:
        return mean, mean, mean
    half = float(student_t.ppf(0.5 + confidence / 2.0, a.size - 1) * a.std(ddof=1)
                 / math.sqrt(a.size))
    return mean, mean - half, mean + half


def separated(margins: Sequence[float], confidence: float = 0.95,
              min_matches: int = MIN_MATCHES) -> bool:
    """True once the t interval of the mean margin excludes zero (and there are at least
    ``min_matches`` margins): the sequential stopping rule of a pairing."""
    if len(margins) < min_matches:
        return False
    _, low, high = t_interval(margins, confidence)
    return low > 0.0 or high < 0.0


def matches_to_separate(margins: Sequence[float], confidence: float = 0.95,
                        min_matches: int = MIN_MATCHES) -> int | None:
    """The number of matches, in the order given, after which ``separated`` first holds
    (None: never within them)."""
    for k in range(min_matches, len(margins) + 1):
        if separated(margins[:k], confidence, min_matches):
            return k
    return None


def match_margins(records: Iterable, team_stats: dict[int, dict[str, dict]] | None = None
                  ) -> list[MatchMargins]:
    """MatchMargins of stored matches (``MatchRecord``s; left team as ``a``): goals from the
    official score, xG from ``team_stats`` (``ResultStore.team_stats``) where stored."""
    out = []
    for r in records:
        values = {"goals": (float(r.left_official), float(r.right_official))}
        sides = (team_stats or {}).get(r.id)
        if sides and "left" in sides and "right" in sides:
            values["xg"] = (float(sides["left"]["xg"]), float(sides["right"]["xg"]))
        out.append(MatchMargins(r.left_team, r.right_team, values))
    return out


def usable(matches: Sequence[MatchMargins], metric: str) -> list[MatchMargins]:
    """The matches that have the numbers ``metric`` needs; none at all is a clear error."""
    check_metric(metric)
    need = {"goals"} if metric == "goals" else ({"xg"} if metric == "xg" else
                                                set(COMPOSITE_WEIGHTS))
    keep = [m for m in matches if need <= set(m.values)]
    if matches and not keep:
        raise ConfigError(f"rank by {metric}: no stored match has expected goals; they are "
                          "stored when a tournament runs with statistics on (the default "
                          "since teamenv.analytics; older databases have none)")
    return keep


def separated_pairings(records: Sequence, team_stats: dict[int, dict[str, dict]] | None,
                       metric: str, confidence: float = 0.95,
                       min_matches: int = MIN_MATCHES) -> set[str]:
    """The pairings ("A vs B", ``MatchRecord.pairing``) whose stored matches already separate
    A from B on ``metric`` (``separated``); matches without the metric's numbers are left out."""
    check_metric(metric)
    margins: dict[str, list[float]] = {}
    for record, match in zip(records, match_margins(records, team_stats), strict=True):
        try:
            d = match.margin(metric)
        except ConfigError:  # no statistics stored for this match
            continue
        margins.setdefault(record.pairing, []).append(-d if record.swapped else d)
    return {p for p, d in margins.items() if separated(d, confidence, min_matches)}
