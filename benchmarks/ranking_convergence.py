"""How many matches each ranking metric needs to separate ``full`` from ``chaser`` at 95 %.

    python benchmarks/ranking_convergence.py --replay-dir /tmp/rank --matches 16 -j 2
    python benchmarks/ranking_convergence.py --replay-dir /tmp/rank --half-time 150 \\
        --matches 40 --stop-when-separated --json benchmarks/results/ranking_convergence.json

Plays ``full`` against ``chaser`` on ``mj7v7`` 7 v 7 (2 x ``--half-time`` s), analysis
seeds from 5000 (``--first-seed``; the tuning range of ``teamenv.seeds``: the question is
about the metrics, not a strength claim), sides alternating (full left on even offsets), each
recorded as a replay in ``--replay-dir`` (a replay already there is reused). For every match
it computes full's margin over chaser on each ranking metric of
``teamenv.analytics.ranking`` (goals, xG, composite, territory) and reports, per metric:

- *in order*: after how many matches (seed order) the 95 % t interval of the mean margin first
  excludes zero (``ranking.matches_to_separate``, at least 3 matches) — the sequential
  stopping rule ``--stop-when-separated`` applies while playing;
- *resampled*: the same count over ``--resamples`` bootstrap sequences (matches drawn with
  replacement from those played, ``numpy.random.default_rng(0)``): median, 90th percentile
  and the share of sequences that never separate within the number played.

``--goal-rarity`` adds the goals-only count for the full-length matches of
``benchmarks/results/goal_rarity.json`` (no replays, so no xG there).
"""

from __future__ import annotations

import argparse
import json
import os
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.analytics.ranking import RANK_METRICS, MatchMargins, matches_to_separate, separated


def match_job(job: tuple[str, int, float]) -> str:
    """Play (or reuse) the replay of match ``seed``: full left on even seeds offsets."""
    from teamenv.match import play_match

    replay_dir, seed, half_time = job
    left, right = ("full", "chaser") if seed % 2 == 0 else ("chaser", "full")
    path = Path(replay_dir) / f"{left}-{right}-{seed}.npz"
    if not path.exists():
        tmp = path.with_suffix(".tmp.npz")
        play_match(left, right, seed, {"field": "mj7v7", "team_size": 7,
                                       "half_time_s": half_time}, replay_path=tmp)
        os.replace(tmp, path)
    return str(path)


def full_margins(path: str) -> dict[str, Any]:
    """Full's numbers and margins over the chaser in one replay."""
    from teamenv.analytics.stats import replay_stats

    s = replay_stats(path)
    full, chaser = (s.left, s.right) if s.left.team == "full" else (s.right, s.left)
    m = MatchMargins("full", "chaser", {"goals": (full.goals, chaser.goals),
                                        "xg": (full.xg, chaser.xg),
                                        "territory": (full.territory_m, chaser.territory_m)})
    return {"seed": s.seed, "full_side": full.side, "goals": [full.goals, chaser.goals],
            "xg": [round(full.xg, 4), round(chaser.xg, 4)],
            "territory_m": [round(full.territory_m, 3), round(chaser.territory_m, 3)],
            "shots": [full.shots, chaser.shots],
            "margins": {k: m.margin(k) for k in RANK_METRICS}}


def resampled(margins: np.ndarray, resamples: int, rng: np.random.Generator) -> dict[str, Any]:
    """Matches needed over bootstrap sequences drawn from ``margins``."""
    n = len(margins)
    needed = []
    for _ in range(resamples):
        seq = margins[rng.integers(0, n, size=n)]
        needed.append(matches_to_separate(seq))
    hits = np.array([k for k in needed if k is not None], dtype=float)
    return {"median": float(np.median(hits)) if hits.size else None,
            "p90": float(np.percentile(hits, 90)) if hits.size else None,
            "never_pct": 100.0 * (len(needed) - hits.size) / len(needed)}


def goal_rarity_goals(path: Path) -> dict[str, Any] | None:
    """Goals-only convergence of the full-length full:chaser matches of goal_rarity.json."""
    if not path.exists():
        return None
    data = json.loads(path.read_text())
    for run in data.get("runs", [data]):
        if run.get("field") != "mj7v7":
            continue
        for p in run["pairings"]:
            if (p["a"], p["b"]) == ("full", "chaser"):
                matches = sorted(p["matches"], key=lambda m: m["seed"])
                d = [m["a"]["goals"] - m["b"]["goals"] for m in matches]
                return {"matches": len(d), "half_time_s": run["half_time_s"],
                        "goal_margins": d, "in_order": matches_to_separate(d)}
    return None


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--replay-dir", type=Path, required=True)
    parser.add_argument("--matches", type=int, default=16, help="matches to play at most")
    parser.add_argument("--half-time", type=float, default=300.0)
    parser.add_argument("--first-seed", type=int, default=5000)
    parser.add_argument("-j", "--jobs", type=int, default=2)
    parser.add_argument("--stop-when-separated", action="store_true",
                        help="stop playing once every metric has separated the pair")
    parser.add_argument("--resamples", type=int, default=1000)
    parser.add_argument("--goal-rarity", type=Path,
                        default=Path(__file__).parent / "results" / "goal_rarity.json")
    parser.add_argument("--json", type=Path, help="write every match's numbers and the counts")
    args = parser.parse_args(argv)
    args.replay_dir.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    rows: list[dict[str, Any]] = []
    seeds = [args.first_seed + k for k in range(args.matches)]
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for b in range(0, len(seeds), max(1, args.jobs)):
            batch = seeds[b:b + max(1, args.jobs)]
            for path in pool.map(match_job, [(str(args.replay_dir), s, args.half_time)
                                             for s in batch]):
                rows.append(full_margins(path))
                print(f"seed {rows[-1]['seed']}: full {rows[-1]['full_side']}, goals "
                      f"{rows[-1]['goals']}, xG {rows[-1]['xg']}", flush=True)
            if args.stop_when_separated and all(
                    separated([r["margins"][m] for r in rows]) for m in RANK_METRICS):
                print(f"every metric separated after {len(rows)} matches: stopping")
                break
    from teamenv.analytics.xg import XGModel

    rng = np.random.default_rng(0)
    report: dict[str, Any] = {"field": "mj7v7", "team_size": 7, "half_time_s": args.half_time,
                              "first_seed": args.first_seed,
                              "xg_model": XGModel.load().fitted.get("data", ""),
                              "matches": rows, "metrics": {},
                              "wall_s": time.perf_counter() - start}
    print(f"\nfull vs chaser, mj7v7 7 v 7, 2 x {args.half_time:g} s, {len(rows)} matches "
          f"(seeds {args.first_seed}..{args.first_seed + len(rows) - 1})")
    print(f"{'metric':10s} {'mean margin':>12s} {'in order':>9s} {'resampled median':>17s} "
          f"{'p90':>5s} {'never %':>8s}")
    for metric in RANK_METRICS:
        d = np.array([r["margins"][metric] for r in rows])
        res = resampled(d, args.resamples, rng)
        report["metrics"][metric] = {"mean_margin": float(d.mean()),
                                     "in_order": matches_to_separate(d), **res}
        print(f"{metric:10s} {d.mean():12.3f} {str(matches_to_separate(d)):>9s} "
              f"{str(res['median']):>17s} {str(res['p90']):>5s} {res['never_pct']:8.1f}")
    reference = goal_rarity_goals(args.goal_rarity)
    if reference:
        report["goal_rarity_full_length"] = reference
        print(f"goals, full-length matches of goal_rarity.json ({reference['matches']} matches,"
              f" 2 x {reference['half_time_s']:g} s): separated after "
              f"{reference['in_order']} (margins {reference['goal_margins']})")
    if args.json:
        args.json.write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()
