"""Ranking fidelity: does a ranking made in teamenv hold on the league server?

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


def goal_diff_per_match(records: Sequence[Any]) -> dict[str, float]:
    """Mean goal difference per match (official scores) of every team: finer than points when
    most matches are draws."""
    gd: dict[str, list[int]] = defaultdict(list)
    for r in records:
        lo, ro = r.left_official, r.right_official
        gd[r.left_team].append(lo - ro)
        gd[r.right_team].append(ro - lo)
    return {t: float(np.mean(v)) for t, v in gd.items()}


METRICS = {"points": points_per_match, "goal_diff": goal_diff_per_match}
#: rankings on a per-match statistic instead of goals (mean difference for - against per
#: match): for short humanoid matches where nearly every score is 0-0
STAT_METRICS = {"xg_diff": "xg", "progress_diff": "ball_progress_m"}


def stat_records(records: Sequence[Any], team_stats: dict[int, dict[str, dict]],
                 key: str) -> list[Any]:
    """The matches with statistic ``key`` in place of the official goals (matches without
    statistics are left out), so ``goal_diff_per_match`` ranks the teams on it."""
    from types import SimpleNamespace

    out = []
    for r in records:
        sides = team_stats.get(r.id)
        if sides and "left" in sides and "right" in sides:
            out.append(SimpleNamespace(left_team=r.left_team, right_team=r.right_team,
                                       left_official=float(sides["left"].get(key) or 0.0),
                                       right_official=float(sides["right"].get(key) or 0.0)))
    return out

#: per-match game statistics compared side by side (teamenv.analytics.stats, per team)
STAT_KEYS = ("goals", "kicks", "shots", "xg", "possession_pct", "ball_progress_m", "falls",
             "distance_walked_m")


def world_stats(team_stats: dict[int, dict[str, dict]]) -> dict[str, float]:
    """Means over a tournament's matches of the per-match totals (both teams) of
    ``STAT_KEYS`` (possession: the mean of the two teams' shares), and the share of PlayOn
    time the ball spent in the attacking third of either team (``attacking_third_pct``)
    and in the middle third (``middle_third_pct``). ``team_stats``: ``ResultStore.team_stats``
    (match id -> side -> the team's statistics)."""
    if not team_stats:
        return {}
    rows = []
    for sides in team_stats.values():
        teams = [sides[s] for s in ("left", "right") if s in sides]
        row = {k: float(sum(t.get(k) or 0.0 for t in teams)) for k in STAT_KEYS}
        row["possession_pct"] /= max(len(teams), 1)
        row["attacking_third_pct"] = float(sum(t["third_pct"]["attacking"] for t in teams))
        row["middle_third_pct"] = float(np.mean([t["third_pct"]["middle"] for t in teams]))
        rows.append(row)
    return {k: float(np.mean([r[k] for r in rows])) for k in rows[0]} | {"matches": len(rows)}


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
                        rng: np.random.Generator, level: float = 0.95,
                        metric: str = "points") -> Agreement:
    """Rank agreement of two worlds' tournaments with bootstrap intervals (``rng`` passed in);
    teams ranked by ``metric`` (``METRICS``)."""
    if metric not in METRICS:
        raise ValueError(f"metric must be one of {sorted(METRICS)}, got {metric!r}")
    score = METRICS[metric]
    if n_boot < 1:
        raise ValueError(f"n_boot must be >= 1, got {n_boot}")
    if not records_a or not records_b:
        raise ValueError("both tournaments need at least one match")
    pa, pb = score(records_a), score(records_b)
    rho, tau = rank_agreement(pa, pb)
    rhos, taus = [], []
    for _ in range(n_boot):
        sa = [records_a[i] for i in rng.integers(0, len(records_a), len(records_a))]
        sb = [records_b[i] for i in rng.integers(0, len(records_b), len(records_b))]
        r, t = rank_agreement(score(sa), score(sb))
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


def _team_stats(db: str, name: str) -> dict[int, dict[str, dict]]:
    from teamenv.tournament import ResultStore

    with ResultStore(db) as store:
        tid, _ = store.get_tournament(name)
        return store.team_stats(tid)


def _restricted(records: Sequence[Any], team_stats: dict[int, dict[str, dict]],
                pairings: set[tuple[str, str]]) -> tuple[list[Any], dict[int, dict[str, dict]]]:
    """The matches of ``records`` (and their statistics) whose (left, right) is in
    ``pairings``."""
    kept = [r for r in records if (r.left_team, r.right_team) in pairings]
    ids = {r.id for r in kept}
    return kept, {k: v for k, v in team_stats.items() if k in ids}


def league_falls(records: Sequence[Any], team_stats: dict[int, dict[str, dict]],
                 near_m: float = 1.0, early_s: float = 2.0) -> dict[str, float]:
    """One pass over the league matches' replays. Recounts each match's falls in
    ``team_stats`` with ``latch_falls`` (replays recorded before the latch counted a robot
    flickering across the fall test as several falls; a no-op for newer ones), and says where
    the robots fell: falls per match, the share with another robot within ``near_m`` just
    before (5 cycles), and the share in the first ``early_s`` of play."""
    from pathlib import Path

    from teamenv.league.replay import fall_events, latch_falls
    from teamenv.replay import load_replay

    falls = near = early = matches = 0
    for r in records:
        if not r.replay_path or not Path(r.replay_path).is_file():
            continue
        replay = load_replay(r.replay_path)
        matches += 1
        fallen = latch_falls(replay.fallen).astype(np.int8)
        sides = team_stats.get(r.id)
        if sides:
            per_robot = (np.diff(fallen, axis=0) == 1).sum(axis=0) + fallen[0]
            n = replay.team_size
            sides["left"]["falls"] = int(per_robot[:n].sum())
            sides["right"]["falls"] = int(per_robot[n:].sum())
        kick_off = int(np.argmax(replay.play_mode != 0))
        for fall in fall_events(replay):
            falls += 1
            near += fall.nearest_m < near_m
            early += (fall.row - kick_off) * float(replay.metadata["cycle_s"]) < early_s
    if not falls:
        return {"matches": matches, "falls": 0}
    return {"matches": matches, "falls_per_match": falls / max(matches, 1),
            f"share_within_{near_m:g}_m": near / falls, f"share_first_{early_s:g}_s": early / falls}


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--teamenv-db", default=None, help="the teamenv tournament (optional when "
                    "--calibrated-db is given)")
    ap.add_argument("--teamenv-name", default=None)
    ap.add_argument("--league-db", required=True)
    ap.add_argument("--league-name", required=True,
                    help="league tournament name; several, comma-separated, pool their matches")
    ap.add_argument("--calibrated-db", default=None,
                    help="a second teamenv tournament (e.g. with the t1_league profile)")
    ap.add_argument("--calibrated-name", default=None)
    ap.add_argument("--bootstrap", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", default=None, help="write the result here")
    ap.add_argument("--common-pairings", action="store_true",
                    help="only the pairings (left team, right team) every world has played: a "
                    "study still under way compared on what it has in common")
    args = ap.parse_args(argv)
    worlds = {}
    if args.teamenv_db:
        worlds["teamenv"] = (args.teamenv_db, args.teamenv_name)
    if args.calibrated_db:
        worlds["teamenv calibrated"] = (args.calibrated_db,
                                        args.calibrated_name or args.teamenv_name)
    if not worlds:
        ap.error("give --teamenv-db or --calibrated-db (or both)")
    league = []
    league_stats: dict[int, dict[str, dict]] = {}
    for name in args.league_name.split(","):   # several league tournaments pool their matches
        recs = _records(args.league_db, name)
        league += recs
        league_stats |= _team_stats(args.league_db, name)
    loaded = {world: (_records(db, name), _team_stats(db, name))
              for world, (db, name) in worlds.items()}
    if args.common_pairings:
        common = set.intersection(*({(r.left_team, r.right_team) for r in recs}
                                    for recs in [league] + [r for r, _ in loaded.values()]))
        league, league_stats = _restricted(league, league_stats, common)
        loaded = {world: _restricted(recs, stats, common)
                  for world, (recs, stats) in loaded.items()}
        print(f"pairings played in every world: {len(common)}")
    out: dict[str, Any] = {"league_matches": len(league), "agreement": {}, "stats": {},
                           "ranking": {}, "league_falls": league_falls(league, league_stats)}
    print("league falls:", {k: round(v, 3) for k, v in out["league_falls"].items()})

    def rankings(records, team_stats):
        """metric -> (the matches it ranks on, the ranking function)."""
        sets = {m: (records, METRICS[m]) for m in METRICS}
        for m, key in STAT_METRICS.items():
            sets[m] = (stat_records(records, team_stats, key), goal_diff_per_match)
        return sets

    league_sets = rankings(league, league_stats)
    out["ranking"]["league"] = {m: fn(recs) for m, (recs, fn) in league_sets.items() if recs}
    for world, (records, world_team_stats) in loaded.items():
        sets = rankings(records, world_team_stats)
        out["ranking"][world] = {m: fn(recs) for m, (recs, fn) in sets.items() if recs}
        for metric, (recs, _) in sets.items():
            league_recs = league_sets[metric][0]
            if not recs or not league_recs:
                continue
            result = bootstrap_agreement(
                recs, league_recs, args.bootstrap, np.random.default_rng(args.seed),
                metric="points" if metric == "points" else "goal_diff")
            out["agreement"][f"{world} vs league, {metric}"] = asdict(result)
            print(f"{world} ({len(recs)} matches) vs league ({len(league_recs)}), by {metric}: "
                  f"{result.teams} teams, Spearman rho {result.rho:.3f} "
                  f"[{result.rho_ci[0]:.2f}, {result.rho_ci[1]:.2f}], Kendall tau "
                  f"{result.tau:.3f} [{result.tau_ci[0]:.2f}, {result.tau_ci[1]:.2f}] "
                  f"({result.usable}/{result.resamples} usable resamples)")
    for world in out["ranking"]:
        for metric, table in out["ranking"][world].items():
            order = sorted(table, key=lambda t: -table[t])
            print(f"  {world:<20} by {metric:<13}: " + ", ".join(f"{t} {table[t]:+.2f}"
                                                                    for t in order))
    for world, (_, world_team_stats) in loaded.items():
        out["stats"][world] = world_stats(world_team_stats)
    out["stats"]["league"] = world_stats(league_stats)
    keys = [k for k in next(iter(out["stats"].values()), {}) if k != "matches"]
    if keys:
        print("per match (both teams):" + "".join(f"{w:>22}" for w in out["stats"]))
        for k in keys:
            print(f"  {k:<22}" + "".join(f"{out['stats'][w].get(k, math.nan):>22.2f}"
                                         for w in out["stats"]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
