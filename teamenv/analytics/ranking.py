"""Rankings on goals, expected goals, a composite or territory, with confidence intervals,
and the sequential test that says when a pairing is separated.

A match gives each team a *margin* on a metric: its value minus the opponent's. Metrics:

- ``goals``: goals scored (the official score: a forfeit counts 0-3);
- ``xg``: expected goals (``teamenv.analytics.xg``), which varies less from match to match
  than goals;
- ``composite``: ``COMPOSITE_WEIGHTS`` · (goals, xG): half the goal margin plus half the xG
  margin — goals still count, the xG half damps their luck;
- ``territory``: how far past the centre line, towards the opponent's goal, the ball was on
  average over the match (``TeamStats.territory_m``, metres; football's "field tilt"; the
  margin is twice a side's value, as the opponent's is its negative). It has a
  value in every match, goal or not, so it separates unequal teams in far fewer matches than
  goals (docs/analytics.md); it measures who keeps the play in the other half, not who scores
  — a team can hold ground and never shoot.

A team's rating is its mean margin per match, with a bootstrap percentile interval. The
bootstrap resamples each opponent's matches separately (stratified by opponent): a round
robin fixes who plays whom, so the luck to be measured is within each pairing, and pooling
the matches would add the spread between a strong and a weak opponent to every interval. A pairing is *separated* once the t interval of the mean per-match margin excludes
zero (at least ``MIN_MATCHES`` matches; repeated looks make this a sequential rule whose
real error rate is above the nominal 5 %, see docs/analytics.md).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from teamenv.errors import ConfigError

RANK_METRICS = ("goals", "xg", "composite", "territory")
# The TeamStats field a stored-statistics metric reads (goals come from the official score).
STATS_FIELD = {"xg": "xg", "territory": "territory_m"}
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
    bootstrap percentile interval over its own matches, resampled within each opponent
    (``n_bootstrap`` resamples drawn with ``numpy.random.default_rng(seed)``; 0: no interval,
    the mean itself)."""
    check_metric(metric)
    by_opponent: dict[str, dict[str, list[float]]] = {t: {} for t in teams or ()}
    for m in matches:
        d = m.margin(metric)
        by_opponent.setdefault(m.a, {}).setdefault(m.b, []).append(d)
        by_opponent.setdefault(m.b, {}).setdefault(m.a, []).append(-d)
    rng = np.random.default_rng(seed)
    out = []
    for team in sorted(by_opponent):
        groups = [np.asarray(by_opponent[team][o], dtype=float) for o in sorted(by_opponent[team])]
        n = sum(g.size for g in groups)
        if n == 0:
            out.append(TeamRank(team, metric, math.nan, math.nan, math.nan, 0))
            continue
        mean = float(np.concatenate(groups).mean())
        low, high = stratified_bootstrap_interval(groups, n_bootstrap, rng, confidence)
        out.append(TeamRank(team, metric, mean, low, high, n))
    out.sort(key=lambda r: (-(r.mean if not math.isnan(r.mean) else -math.inf), r.team))
    return [TeamRank(r.team, r.metric, r.mean, r.low, r.high, r.matches, k + 1)
            for k, r in enumerate(out)]


def stratified_bootstrap_interval(groups: Sequence[np.ndarray], n_bootstrap: int,
                                  rng: np.random.Generator, confidence: float = 0.95
                                  ) -> tuple[float, float]:
    """Percentile interval of the mean of all values when each group is resampled on its own
    (its size kept): the interval of a mean over a fixed design. A group of one value adds
    no spread."""
    sizes = [g.size for g in groups]
    total = sum(sizes)
    mean = float(np.concatenate(groups).mean()) if total else math.nan
    if total < 2 or n_bootstrap < 1:
        return mean, mean
    sums = np.zeros(n_bootstrap)
    for g in groups:
        sums += g[rng.integers(0, g.size, size=(n_bootstrap, g.size))].sum(axis=1)
    tail = (1.0 - confidence) / 2.0 * 100.0
    low, high = np.percentile(sums / total, [tail, 100.0 - tail])
    return float(low), float(high)


def head_to_head(matches: Iterable[MatchMargins], metric: str, confidence: float = 0.95,
                 min_matches: int = MIN_MATCHES) -> list[PairingMargin]:
    """Each pairing's mean margin (first team named over the second, teams in sorted order)
    with its ``confidence`` t interval and whether it is ``separated``."""
    check_metric(metric)
    margins: dict[tuple[str, str], list[float]] = {}
    for m in matches:
        d = m.margin(metric)
        a, b = sorted((m.a, m.b))
        margins.setdefault((a, b), []).append(d if m.a == a else -d)
    out = []
    for (a, b), x in sorted(margins.items()):
        mean, low, high = t_interval(x, confidence)
        out.append(PairingMargin(a, b, metric, mean, low, high, len(x),
                                 separated(x, confidence, min_matches)))
    return out


@dataclass(frozen=True)
class PairingMargin:
    """``a``'s mean margin over ``b`` per match on ``metric``, its t interval, the number of
    matches and whether the pairing is separated."""

    a: str
    b: str
    metric: str
    mean: float
    low: float
    high: float
    matches: int
    separated: bool

    def leader(self) -> str | None:
        """The team ahead once separated, else None."""
        if not self.separated:
            return None
        return self.a if self.mean > 0 else self.b


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
    official score, xG and territory from ``team_stats`` (``ResultStore.team_stats``)
    where stored."""
    out = []
    for r in records:
        values = {"goals": (float(r.left_official), float(r.right_official))}
        sides = (team_stats or {}).get(r.id)
        if sides and "left" in sides and "right" in sides:
            for metric, name in STATS_FIELD.items():
                if name in sides["left"] and name in sides["right"]:
                    values[metric] = (float(sides["left"][name]), float(sides["right"][name]))
        out.append(MatchMargins(r.left_team, r.right_team, values))
    return out


def has_numbers(match: MatchMargins, metric: str) -> bool:
    """Whether ``match`` has the values ``metric`` needs."""
    check_metric(metric)
    need = set(COMPOSITE_WEIGHTS) if metric == "composite" else {metric}
    return need <= set(match.values)


def usable(matches: Sequence[MatchMargins], metric: str) -> list[MatchMargins]:
    """The matches that have the numbers ``metric`` needs; none at all is a clear error."""
    keep = [m for m in matches if has_numbers(m, metric)]
    if matches and not keep:
        what = "territory" if metric == "territory" else "expected goals"
        raise ConfigError(f"rank by {metric}: no stored match has {what}; they are "
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
