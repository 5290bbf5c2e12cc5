"""Ranking fidelity (issue 14): does a ranking made in teamenv hold on the league server?

Skeleton: reads two tournaments stored in the tournament SQLite format — one played in teamenv
(`teamenv tournament run ...`), one on the league server (`teamenv league-tournament ...`) —
ranks the teams in each by points per match (3/1/0, official scores), and reports Spearman's rho
and Kendall's tau between the two rankings with percentile bootstrap intervals (matches
resampled with replacement within each world, independently, seeded).

    python benchmarks/fidelity_ranking.py --teamenv-db te.sqlite --teamenv-name rr \
        --league-db league.sqlite --league-name rr --bootstrap 1000 --seed 0 [--json out.json]

No league-server round robin has been run yet. The strategy plugins do play on the server now
(`teamenv league-match` / `league-tournament`), but our T1 walker falls about a second after it
starts walking there, so such a round robin would rank fallen robots (docs/league.md).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from scipy import stats


def points_per_match(records: Sequence[Any]) -> dict[str, float]:
    """Mean points per match (3 win, 1 draw, 0 loss; official scores) of every team."""
    pts: dict[str, list[int]] = defaultdict(list)
    for r in records:
        lo, ro = r.left_official, r.right_official
        pts[r.left_team].append(3 if lo > ro else 1 if lo == ro else 0)
        pts[r.right_team].append(3 if ro > lo else 1 if lo == ro else 0)
    return {t: float(np.mean(v)) for t, v in pts.items()}


def rank_agreement(a: dict[str, float], b: dict[str, float]) -> tuple[float, float]:
    """(Spearman rho, Kendall tau-b) between two team -> score maps over their common teams;
    NaN when either side has fewer than 2 teams or all its scores are equal."""
    teams = sorted(set(a) & set(b))
    if len(teams) < 2:
        return math.nan, math.nan
    xa, xb = [a[t] for t in teams], [b[t] for t in teams]
    if len(set(xa)) < 2 or len(set(xb)) < 2:
        return math.nan, math.nan
    return float(stats.spearmanr(xa, xb).statistic), float(stats.kendalltau(xa, xb).statistic)


@dataclass(frozen=True)
class Agreement:
    """Point estimates, 95 % percentile intervals, and how many resamples were usable."""

    teams: int
    rho: float
    rho_ci: tuple[float, float]
    tau: float
    tau_ci: tuple[float, float]
    resamples: int
    usable: int


def bootstrap_agreement(records_a: Sequence[Any], records_b: Sequence[Any], n_boot: int,
                        rng: np.random.Generator, level: float = 0.95) -> Agreement:
    """Rank agreement of two worlds' tournaments with bootstrap intervals (``rng`` passed in)."""
    if n_boot < 1:
        raise ValueError(f"n_boot must be >= 1, got {n_boot}")
    if not records_a or not records_b:
        raise ValueError("both tournaments need at least one match")
    pa, pb = points_per_match(records_a), points_per_match(records_b)
    rho, tau = rank_agreement(pa, pb)
    rhos, taus = [], []
    for _ in range(n_boot):
        sa = [records_a[i] for i in rng.integers(0, len(records_a), len(records_a))]
        sb = [records_b[i] for i in rng.integers(0, len(records_b), len(records_b))]
        r, t = rank_agreement(points_per_match(sa), points_per_match(sb))
        if not (math.isnan(r) or math.isnan(t)):
            rhos.append(r)
            taus.append(t)
    q = [50 * (1 - level), 50 * (1 + level)]

    def ci(v: list[float]) -> tuple[float, float]:
        return (math.nan, math.nan) if not v else tuple(float(x) for x in np.percentile(v, q))

    return Agreement(len(set(pa) & set(pb)), rho, ci(rhos), tau, ci(taus), n_boot, len(rhos))


def _records(db: str, name: str) -> list[Any]:
    from teamenv.tournament import ResultStore

    with ResultStore(db) as store:
        tid, _ = store.get_tournament(name)
        return store.matches(tid)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--teamenv-db", required=True)
    ap.add_argument("--teamenv-name", required=True)
    ap.add_argument("--league-db", required=True)
    ap.add_argument("--league-name", required=True)
    ap.add_argument("--bootstrap", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", default=None, help="write the result here")
    args = ap.parse_args(argv)
    a = _records(args.teamenv_db, args.teamenv_name)
    b = _records(args.league_db, args.league_name)
    result = bootstrap_agreement(a, b, args.bootstrap, np.random.default_rng(args.seed))
    print(f"{result.teams} teams: Spearman rho {result.rho:.3f} {result.rho_ci}, "
          f"Kendall tau {result.tau:.3f} {result.tau_ci} ({result.usable}/{result.resamples} "
          "usable resamples)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(asdict(result), f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
