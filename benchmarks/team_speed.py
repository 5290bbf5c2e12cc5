"""The cost of one team's decisions alone, on a recorded match: CPU per team cycle.

Plays a seeded match (both sides the same team by default), records every observation the
left team is handed, then hands the same observations to copies of that team as it was at
kick-off and times only their ``act()`` calls (process CPU and wall time, best of
``--repeats``). The copies must answer exactly as the team did in the match (checked, action
for action): the benchmark times the same work every repeat, and a run that decides
differently fails loudly instead of timing something else.

A team's cost is most of a match (~85 % of a 7 v 7 vision match), and a whole match is noisy
on a shared machine; this times the part that decision-layer changes touch, and the same
recorded cycles each time. Compare two commits by running each tree's copy of this script
(the recorded observations are the same in both when the env did not change).

Usage:
    python benchmarks/team_speed.py                                  # full, mj7v7 vision
    python benchmarks/team_speed.py --observation state --seconds 30
    python benchmarks/team_speed.py --team chaser --json
"""

from __future__ import annotations

import argparse
import copy
import json
import time
from typing import Any

import numpy as np

from teamenv.config import RulesConfig
from teamenv.env import SoccerParallelEnv


def _copied(observations: dict[str, Any]) -> dict[str, Any]:
    # the env may reuse its arrays from cycle to cycle
    return {agent: {key: (np.array(value) if isinstance(value, np.ndarray) else
                          copy.deepcopy(value)) for key, value in obs.items()}
            for agent, obs in observations.items()}


def _same(a: dict[str, Any], b: dict[str, Any]) -> bool:
    if a.keys() != b.keys():
        return False
    for agent in a:
        x, y = a[agent], b[agent]
        if x.keys() != y.keys():
            return False
        for key in x:
            u, v = np.asarray(x[key]), np.asarray(y[key])
            if u.dtype != v.dtype or u.shape != v.shape or u.tobytes() != v.tobytes():
                return False
    return True


def record(team: str, opponent: str, field: str, team_size: int, seconds: float, seed: int,
           observation_mode: str, vision: str | None):
    """(the left team as it was after reset, [(observations, actions)] per cycle)."""
    env = SoccerParallelEnv(field=field, team_size=team_size, left=team, right=opponent,
                            rules=RulesConfig(half_time_s=seconds),
                            observation_mode=observation_mode, vision=vision)
    env.reset(seed=seed)
    left = env.teams["left"]
    initial = copy.deepcopy(left)
    cycles: list[tuple[dict, dict]] = []
    act = left.act

    def recording(observations):
        seen = _copied(observations)
        actions = act(observations)
        cycles.append((seen, _copied(actions)))
        return actions

    left.act = recording
    while not env.episode_over:
        env.step({})
    env.close()
    return initial, cycles


def replay(initial: Any, cycles: list[tuple[dict, dict]]) -> tuple[float, float]:
    """(process CPU s, wall s) of a fresh copy's ``act()`` over the recorded cycles."""
    team = copy.deepcopy(initial)
    cpu = wall = 0.0
    for observations, expected in cycles:
        c, w = time.process_time(), time.perf_counter()
        actions = team.act(observations)
        cpu += time.process_time() - c
        wall += time.perf_counter() - w
        if not _same(actions, expected):
            raise SystemExit("team_speed: the copy decided differently from the team in the "
                             "match; its timings would not be comparable")
    return cpu, wall


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--team", default="full")
    parser.add_argument("--opponent", default=None, help="right team (default: --team)")
    parser.add_argument("--field", default="mj7v7")
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--seconds", type=float, default=20.0, help="one half of this length")
    parser.add_argument("--seed", type=int, default=100_201)
    parser.add_argument("--observation", default="vision", choices=("state", "vision"))
    parser.add_argument("--vision", default="mj", help="vision profile (vision mode)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    vision = args.vision if args.observation == "vision" else None
    initial, cycles = record(args.team, args.opponent or args.team, args.field, args.team_size,
                             args.seconds, args.seed, args.observation, vision)
    runs = [replay(initial, cycles) for _ in range(args.repeats)]
    n = len(cycles)
    result = {"team": args.team, "field": args.field, "team_size": args.team_size,
              "observation_mode": args.observation, "vision": vision, "seed": args.seed,
              "cycles": n, "cpu_us_per_cycle": [1e6 * c / n for c, _ in runs],
              "wall_us_per_cycle": [1e6 * w / n for _, w in runs]}
    if args.json:
        print(json.dumps(result, indent=1))
        return
    print(f"{args.team} ({args.observation}{'' if vision is None else ', ' + vision}), "
          f"{args.field} {args.team_size} v {args.team_size}, seed {args.seed}: {n} cycles")
    print("process CPU per team cycle: " + ", ".join(f"{v:.0f}" for v in
                                                     result["cpu_us_per_cycle"])
          + f" us (best {min(result['cpu_us_per_cycle']):.0f})")
    print("wall time per team cycle:   " + ", ".join(f"{v:.0f}" for v in
                                                     result["wall_us_per_cycle"])
          + f" us (best {min(result['wall_us_per_cycle']):.0f})")


if __name__ == "__main__":
    main()
