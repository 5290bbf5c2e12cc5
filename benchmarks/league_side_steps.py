"""`full` with one-sided side-steps against symmetric ones, in both worlds, paired by seed.

The league's reference walking network steps right but not left (the ``t1_league`` profile's
tracking: 0.12 m/s asked to the left gives 0.006 m/s), so within ``omni_m`` of its target a
player that asks for a side-step to its left stands still. ``full``'s ``nav_side_steps="body"``
(``NavigationParams.for_body``) turns such side-steps into the far walk (turn towards the
target, walk forward); this script plays each seed twice, the left team as it is (side-steps
both ways, the default) and with ``nav_side_steps=body``, and counts the left team's kicks of
at least 1 m, goals and falls:

- ``--world league``: 7 v 7 on ``LocalServer`` (``league_falls.play``: kicks from the replay's
  ball contacts, falls from its fall events);
- ``--world teamenv``: the study's calibrated world (``t1_league``, ``mj`` vision and channel,
  the double-touch rule): kicks from the env's cycle reports, falls as fallen flags rising.

    python benchmarks/league_side_steps.py --world league --seeds 100360:100372 --seconds 40
    python benchmarks/league_side_steps.py --world teamenv --seeds 100400:100416 --seconds 60

Prints every match and the paired differences (one-sided minus symmetric) with a 95 % t
interval; ``--json`` writes the rows.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import league_falls  # noqa: E402  (the sibling script)

KICK_M = 1.0
ONE_SIDED = "nav_side_steps=body"


def league_match(left: str, right: str, seed: int, seconds: float, team_size: int) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        m = league_falls.play(left, right, seed, seconds, False, Path(folder),
                              team_size=team_size)
    return {"score": m["score"], "kicks": m["kicks"], "falls": len(m["falls"])}


def teamenv_match(left: str, right: str, seed: int, seconds: float, team_size: int) -> dict:
    import teamenv
    from teamenv.tournament.spec import parse_team_spec

    spec = parse_team_spec(left)
    env = teamenv.parallel_env(left=spec.name, left_config=spec.config_dict, right=right,
                               field="mj7v7", team_size=team_size,
                               observation_mode="vision", vision="mj", channel="mj",
                               locomotion_profile="t1_league",
                               rules={"half_time_s": seconds, "halves": 1,
                                      "double_touch": True}, profile_phases=False)
    env.reset(seed=seed)
    kicks = falls = 0
    before = env.sim.fallen().copy()
    while env.sim.referee.mode.name != "GameOver":
        env.step({})
        kicks += sum(1 for who, dist, _ in env.last_report.kicks
                     if who < team_size and dist >= KICK_M)
        now = env.sim.fallen()
        falls += int(((now > 0.5) & (before <= 0.5))[:team_size].sum())
        before = now.copy()
    score = list(env.sim.referee.score)
    env.close()
    return {"score": score, "kicks": kicks, "falls": falls}


def paired(rows: list[dict], key: str) -> tuple[float, float, float]:
    """Mean of (one-sided - symmetric) per seed, with a 95 % t interval."""
    from scipy import stats

    by_seed: dict[int, dict[bool, float]] = {}
    for row in rows:
        value = row[key] if key != "goals" else row["score"][0]
        by_seed.setdefault(row["seed"], {})[row["one_sided"]] = value
    d = np.array([v[True] - v[False] for v in by_seed.values() if len(v) == 2], dtype=float)
    if len(d) < 2:
        return float(d.mean()) if len(d) else math.nan, math.nan, math.nan
    half = stats.t.ppf(0.975, len(d) - 1) * d.std(ddof=1) / math.sqrt(len(d))
    return float(d.mean()), float(d.mean() - half), float(d.mean() + half)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--world", choices=("league", "teamenv"), default="league")
    parser.add_argument("--left", default="full")
    parser.add_argument("--right", default="static")
    parser.add_argument("--seeds", default="100360:100372", help="START:STOP (half-open)")
    parser.add_argument("--seconds", type=float, default=40.0)
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    start, stop = (int(v) for v in args.seeds.split(":"))
    play = league_match if args.world == "league" else teamenv_match
    sep = "," if ":" in args.left else ":"
    rows = []
    for seed in range(start, stop):
        for one_sided in (False, True):
            left = args.left + sep + ONE_SIDED if one_sided else args.left
            row = {"seed": seed, "one_sided": one_sided,
                   **play(left, args.right, seed, args.seconds, args.team_size)}
            rows.append(row)
            print(json.dumps(row), flush=True)
            if args.json:
                args.json.write_text(json.dumps({"args": vars(args) | {"json": str(args.json)},
                                                 "rows": rows}, indent=1) + "\n")
    for key in ("kicks", "goals", "falls"):
        mean, low, high = paired(rows, key)
        print(f"{key}: one-sided - symmetric per match {mean:+.2f} [{low:+.2f}, {high:+.2f}]")


if __name__ == "__main__":
    main()
