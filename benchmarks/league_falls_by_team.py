"""Falls per robot-minute of each team in a directory of league replays (who falls, and where).

    python benchmarks/league_falls_by_team.py REPLAY_DIR [--near-m 1.0]

Reads every ``*.npz`` league replay in ``REPLAY_DIR`` (as ``teamenv league-tournament
--replay-dir`` or the fidelity study write them), counts each robot's falls with
``teamenv.league.replay.fall_events`` (latched falls, the nearest other robot 5 cycles
before) and prints, per team spec: falls, robot-minutes played, falls per robot-minute and the
share of falls with another robot within ``--near-m``; then the totals and falls per match.
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from teamenv.league.replay import fall_events


def falls_by_team(replay_dir: Path, near_m: float = 1.0) -> tuple[dict[str, dict], int]:
    """{team spec: {"falls", "robot_minutes", "near"}} over the replays, and their count."""
    table: dict[str, dict] = defaultdict(lambda: {"falls": 0, "robot_minutes": 0.0, "near": 0})
    paths = sorted(Path(replay_dir).glob("*.npz"))
    for path in paths:
        with np.load(path) as data:
            meta = json.loads(bytes(data["metadata"]).decode())
            replay = SimpleNamespace(fallen=data["fallen"], players=data["players"])
            n = int(meta["team_size"])
            minutes = len(data["fallen"]) * float(meta["cycle_s"]) / 60.0
        sides = (meta["left"], meta["right"])
        for side in sides:
            table[side]["robot_minutes"] += n * minutes
        for event in fall_events(replay):
            row = table[sides[0] if event.player < n else sides[1]]
            row["falls"] += 1
            row["near"] += event.nearest_m < near_m
    return dict(table), len(paths)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("replay_dir", type=Path)
    ap.add_argument("--near-m", type=float, default=1.0)
    args = ap.parse_args()
    table, matches = falls_by_team(args.replay_dir, args.near_m)
    if not matches:
        raise SystemExit(f"{args.replay_dir}: no *.npz replay there")
    rows = sorted(table.items(), key=lambda kv: -kv[1]["falls"] / kv[1]["robot_minutes"])
    for team, row in rows:
        rate = row["falls"] / row["robot_minutes"]
        near = row["near"] / row["falls"] if row["falls"] else 0.0
        print(f"{team[:40]:40s} {row['falls']:5d} falls  {row['robot_minutes']:7.1f} robot-min  "
              f"{rate:5.2f} per robot-minute  {near:4.0%} near another robot")
    falls = sum(row["falls"] for row in table.values())
    minutes = sum(row["robot_minutes"] for row in table.values())
    print(f"all: {falls} falls in {matches} matches, {falls / minutes:.3f} per robot-minute, "
          f"{falls / matches:.1f} per match")


if __name__ == "__main__":
    main()
