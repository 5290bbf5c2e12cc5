"""Strength of the built-in teams: seeded head-to-head matches with confidence intervals.

    python benchmarks/strategy_strength.py      # 40 full-length 7 v 7 matches per pairing
    python benchmarks/strategy_strength.py --seeds 20 --jobs 2 --json out/strength.json
    python benchmarks/strategy_strength.py --observation vision --pairings full:chaser
    python benchmarks/strategy_strength.py --pairings full:chaser,silent:chaser
        # + the paired difference against chaser
    python benchmarks/strategy_strength.py --seed-range tuning --seeds 10 --half-time 60

Seeds come from ``teamenv.seeds``: by default the evaluation range (100,000 up), which nobody
tunes on; ``--seed-range tuning`` for experiments while changing a team, ``--offset`` to take
seeds further into the range. Matches are full length (2 x 300 s) by default: in two-minute
matches a side kicks ~10 times and nearly all of them end 0-0.

Each pairing plays one match per seed with sides alternating (``teamenv.headtohead``), on the
``mj7v7`` pitch with 7 players a side by default, and prints the aggregate score, the record
and the mean goal difference per match with a 95 % bootstrap confidence interval
(``scipy.stats.bootstrap``, BCa, over matches). Goals are rare: read the interval, not the
aggregate. Two pairings against the same
opponent (``full:chaser,silent:chaser``) are also compared seed by seed: the mean of the
difference of their goal differences, with its interval (a paired comparison: both teams met
the same opponent on the same seeds from the same sides).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
from scipy.stats import bootstrap

from teamenv.headtohead import head_to_head
from teamenv.match import MatchOptions
from teamenv.seeds import EVALUATION_SEEDS, TUNING_SEEDS

PAIRINGS = "full:chaser,full:static,full:silent,chaser:static"


def goal_difference_ci(scores: tuple[tuple[int, int], ...],
                       confidence: float = 0.95) -> tuple[float, float, float]:
    """(mean, low, high): mean goal difference per match of A over B and its bootstrap
    interval (a degenerate sample, e.g. all 0-0, gives the point itself)."""
    diff = np.array([a - b for a, b in scores], dtype=np.float64)
    mean = float(diff.mean())
    if len(diff) < 2 or np.all(diff == diff[0]):
        return mean, mean, mean
    res = bootstrap((diff,), np.mean, confidence_level=confidence, n_resamples=4000,
                    method="BCa", random_state=np.random.default_rng(0))
    return mean, float(res.confidence_interval.low), float(res.confidence_interval.high)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=40, help="matches per pairing")
    parser.add_argument("--seed-range", default="evaluation", choices=("evaluation", "tuning"),
                        help="which reserved seed range (teamenv.seeds) to draw from")
    parser.add_argument("--offset", type=int, default=0, help="seeds to skip into the range")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--field", default="mj7v7")
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--half-time", type=float, default=300.0)
    parser.add_argument("--observation", default="state", choices=("state", "vision"))
    parser.add_argument("--vision", default=None, help="vision profile (simspark or mj)")
    parser.add_argument("--channel", default="simspark")
    parser.add_argument("--pairings", default=PAIRINGS,
                        help="comma-separated a:b team pairs (default: %(default)s)")
    parser.add_argument("--json", help="write the results here")
    args = parser.parse_args()
    options = MatchOptions(field=args.field, team_size=args.team_size,
                           half_time_s=args.half_time, observation_mode=args.observation,
                           vision=args.vision, channel=args.channel)
    seed_range = EVALUATION_SEEDS if args.seed_range == "evaluation" else TUNING_SEEDS
    seeds = seed_range.take(args.seeds, args.offset)
    print(f"{args.field} {args.team_size} v {args.team_size}, 2 x {args.half_time:g} s, "
          f"observation {args.observation}"
          f"{'' if args.vision is None else ' (' + args.vision + ')'}, channel {args.channel}, "
          f"{seed_range.name} seeds {seeds[0]}..{seeds[-1]}", flush=True)
    rows = []
    for pair in args.pairings.split(","):
        a, b = pair.split(":")
        start = time.perf_counter()
        result = head_to_head(a, b, seeds, options, jobs=args.jobs)
        wall = time.perf_counter() - start
        mean, low, high = goal_difference_ci(result.scores)
        print(f"{result.summary()}  goal difference per match {mean:+.2f} "
              f"[95 % CI {low:+.2f}, {high:+.2f}]  [{wall:.0f} s]", flush=True)
        rows.append({"team_a": a, "team_b": b, "goals": result.goals, "record": result.record,
                     "scores": result.scores, "forfeits": result.forfeits, "wall_s": wall,
                     "goal_difference": {"mean": mean, "ci95": [low, high]}})
    matches = list(rows)
    for i, first in enumerate(matches):
        for second in matches[i + 1:]:
            if first["team_b"] != second["team_b"]:
                continue
            paired = tuple((a - b, c - d) for (a, b), (c, d) in
                           zip(first["scores"], second["scores"], strict=True))
            mean, low, high = goal_difference_ci(paired)
            print(f"paired against {first['team_b']}: {first['team_a']} minus "
                  f"{second['team_a']}, goal difference per match {mean:+.2f} "
                  f"[95 % CI {low:+.2f}, {high:+.2f}] over {len(paired)} seeds", flush=True)
            rows.append({"paired": [first["team_a"], second["team_a"], first["team_b"]],
                         "goal_difference": {"mean": mean, "ci95": [low, high]}})
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump({"options": vars(args), "results": rows}, fh, indent=2)


if __name__ == "__main__":
    main()
