"""Strength of the built-in teams: the full team against chaser, static and silent.

    python benchmarks/strategy_strength.py              # 10 seeded 7 v 7 matches of 2 x 60 s each
    python benchmarks/strategy_strength.py --seeds 20 --jobs 2 --json out/strength.json

Each pairing plays one match per seed with sides alternating (``teamenv.headtohead``), on the
``mj7v7`` pitch with 7 players a side, and prints the aggregate score and record.
"""

from __future__ import annotations

import argparse
import json
import time

from teamenv.headtohead import head_to_head
from teamenv.match import MatchOptions

PAIRINGS = (("full", "chaser"), ("full", "static"), ("full", "silent"), ("chaser", "static"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--field", default="mj7v7")
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--half-time", type=float, default=60.0)
    parser.add_argument("--json", help="write the results here")
    args = parser.parse_args()
    options = MatchOptions(field=args.field, team_size=args.team_size,
                           half_time_s=args.half_time)
    rows = []
    for a, b in PAIRINGS:
        start = time.perf_counter()
        result = head_to_head(a, b, args.seeds, options, jobs=args.jobs)
        wall = time.perf_counter() - start
        print(f"{result.summary()}  [{wall:.0f} s]", flush=True)
        rows.append({"team_a": a, "team_b": b, "goals": result.goals, "record": result.record,
                     "scores": result.scores, "forfeits": result.forfeits, "wall_s": wall})
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump({"options": vars(args), "results": rows}, fh, indent=2)


if __name__ == "__main__":
    main()
