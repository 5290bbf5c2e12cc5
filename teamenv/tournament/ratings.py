"""Ratings from match results: Elo and Bradley–Terry, with bootstrap confidence intervals.

Both are reported on the Elo scale (points; 400 points = 10:1 odds, mean 1500). A match
counts as a win (1), draw (0.5) or loss (0) by its official score (forfeits count as losses).
Confidence intervals are percentile intervals over bootstrap resamples of whole matches.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize
from scipy.special import expit, log_expit

from teamenv.tournament.errors import TournamentConfigError

ELO_SCALE = 400.0 / math.log(10.0)  # Elo points per logit
ELO_MEAN = 1500.0


@dataclass(frozen=True)
class Game:
    """One match from the ratings' point of view: ``score`` is 1/0.5/0 for team ``a``."""

    a: str
    b: str
    score: float


@dataclass(frozen=True)
class Rating:
    """A team's rating (Elo-scale points) and its bootstrap confidence interval."""

    team: str
    rating: float
    low: float
    high: float


@dataclass(frozen=True)
class Ratings:
    """Elo and Bradley–Terry ratings of every team, best first by Bradley–Terry."""

    elo: dict[str, Rating]
    bradley_terry: dict[str, Rating]
    n_games: int
    n_bootstrap: int
    confidence: float

    def to_json(self) -> dict:
        def dump(d: dict[str, Rating]) -> dict:
            return {t: {"rating": r.rating, "low": r.low, "high": r.high} for t, r in d.items()}
        return {"elo": dump(self.elo), "bradley_terry": dump(self.bradley_terry),
                "n_games": self.n_games, "n_bootstrap": self.n_bootstrap,
                "confidence": self.confidence}


def games_from_records(records: Iterable) -> list[Game]:
    """Games (left team as ``a``) from stored MatchRecords, in the order given."""
    out = []
    for r in records:
        left, right = r.left_official, r.right_official
        out.append(Game(r.left_team, r.right_team, 1.0 if left > right else
                        0.5 if left == right else 0.0))
    return out


def elo(games: Sequence[Game], teams: Sequence[str], k: float = 20.0,
        initial: float = ELO_MEAN) -> np.ndarray:
    """Sequential Elo over ``games`` in order (K-factor ``k`` points); one rating per team."""
    index = _index(teams)
    r = np.full(len(teams), float(initial))
    for g in games:
        i, j = index[g.a], index[g.b]
        expected = 1.0 / (1.0 + 10.0 ** ((r[j] - r[i]) / 400.0))
        delta = k * (g.score - expected)
        r[i] += delta
        r[j] -= delta
    return r


def bradley_terry(games: Sequence[Game], teams: Sequence[str],
                  prior_sigma: float | None = 2.0, weights: np.ndarray | None = None) -> np.ndarray:
    """Bradley–Terry strengths on the Elo scale (mean 1500); draws count as half a win.

    P(a beats b) = 1 / (1 + exp(-(s_a - s_b))) with s in logits. The fit is the maximum a
    posteriori under an independent N(0, ``prior_sigma``^2) prior per team (logits), which
    keeps a team that wins or loses every game finite; ``prior_sigma=None`` gives the plain
    maximum likelihood (centred), which is finite only when no team is unbeaten or winless.
    ``weights``: how many times each game counts (default once; used by the bootstrap).
    """
    index = _index(teams)
    n = len(teams)
    if not games:
        return np.full(n, ELO_MEAN)
    rows = np.array([(index[g.a], index[g.b], g.score) for g in games], dtype=float)
    w = np.ones(len(games)) if weights is None else np.asarray(weights, dtype=float)
    # Identical games only add weight: fit over the distinct (a, b, score) rows.
    unique, inverse = np.unique(rows, axis=0, return_inverse=True)
    w = np.bincount(inverse.ravel(), w, len(unique))
    keep = w > 0
    ia, ib = unique[keep, 0].astype(int), unique[keep, 1].astype(int)
    y, w = unique[keep, 2], w[keep]
    precision = 0.0 if prior_sigma is None else 1.0 / prior_sigma ** 2

    def objective(s: np.ndarray) -> tuple[float, np.ndarray]:
        d = s[ia] - s[ib]
        nll = -np.sum(w * (y * log_expit(d) + (1.0 - y) * log_expit(-d)))
        g = w * (expit(d) - y)
        grad = np.bincount(ia, g, n) - np.bincount(ib, g, n) + precision * s
        return float(nll + 0.5 * precision * s @ s), grad

    fit = minimize(objective, np.zeros(n), jac=True, method="L-BFGS-B",
                   options={"maxiter": 1000, "gtol": 1e-9})
    s = fit.x - fit.x.mean()
    return ELO_MEAN + ELO_SCALE * s


def bootstrap_intervals(games: Sequence[Game], teams: Sequence[str],
                        fit: Callable[..., np.ndarray], n_bootstrap: int,
                        rng: np.random.Generator, confidence: float = 0.95,
                        weighted: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Percentile interval of ``fit`` over ``n_bootstrap`` resamples of the games (with
    replacement). ``weighted``: call ``fit(games, teams, weights=counts)`` instead of on the
    resampled list (order-free fits); a resampled list keeps the original order (Elo)."""
    m = len(games)
    if m == 0 or n_bootstrap < 1:
        point = fit(games, teams)
        return point.copy(), point.copy()
    samples = np.empty((n_bootstrap, len(teams)))
    for b in range(n_bootstrap):
        pick = np.sort(rng.integers(0, m, size=m))
        if weighted:
            samples[b] = fit(games, teams, weights=np.bincount(pick, minlength=m))
        else:
            samples[b] = fit([games[i] for i in pick], teams)
    tail = (1.0 - confidence) / 2.0 * 100.0
    low, high = np.percentile(samples, [tail, 100.0 - tail], axis=0)
    return low, high


def compute_ratings(records: Sequence, teams: Sequence[str] | None = None,
                    n_bootstrap: int = 200, seed: int = 0, confidence: float = 0.95,
                    k: float = 20.0, prior_sigma: float | None = 2.0) -> Ratings:
    """Elo (K = ``k``, games in schedule order) and Bradley–Terry ratings of stored matches,
    each with a ``confidence`` bootstrap interval from ``n_bootstrap`` resamples drawn with
    ``numpy.random.default_rng(seed)``."""
    if not 0.0 < confidence < 1.0:
        raise TournamentConfigError(f"confidence: must be in (0, 1), got {confidence!r}")
    games = games_from_records(records)
    if teams is None:
        teams = sorted({g.a for g in games} | {g.b for g in games})
    teams = list(teams)

    def fit_elo(gs: Sequence[Game], ts: Sequence[str]) -> np.ndarray:
        return elo(gs, ts, k=k)

    def fit_bt(gs: Sequence[Game], ts: Sequence[str], weights: np.ndarray | None = None
               ) -> np.ndarray:
        return bradley_terry(gs, ts, prior_sigma=prior_sigma, weights=weights)

    rng = np.random.default_rng(seed)
    out = {}
    for name, fit in (("elo", fit_elo), ("bt", fit_bt)):
        point = fit(games, teams)
        low, high = bootstrap_intervals(games, teams, fit, n_bootstrap, rng, confidence,
                                        weighted=name == "bt")
        out[name] = {t: Rating(t, float(point[i]), float(low[i]), float(high[i]))
                     for i, t in enumerate(teams)}
    order = sorted(teams, key=lambda t: -out["bt"][t].rating)
    return Ratings(elo={t: out["elo"][t] for t in order},
                   bradley_terry={t: out["bt"][t] for t in order}, n_games=len(games),
                   n_bootstrap=n_bootstrap, confidence=confidence)


def _index(teams: Sequence[str]) -> dict[str, int]:
    return {t: i for i, t in enumerate(teams)}
