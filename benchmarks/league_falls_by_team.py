"""Falls per robot-minute of each team in a directory of league replays (who falls, and where).

    python benchmarks/league_falls_by_team.py REPLAY_DIR [--near-m 1.0]

Loads every ``*.npz`` league replay in ``REPLAY_DIR`` (as ``teamenv league-tournament
--replay-dir`` or the fidelity study write them) and counts each team's falls as the fall fit
and the calibration count them (``league_fall_fit.fall_rates``: latched falls during play,
alone or with another robot within ``--near-m`` just before, per robot-minute of play). Prints,
per team spec: falls, robot-minutes of play, falls per robot-minute and the share near another
robot; then the totals and falls per match.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from league_fall_fit import NEAR_M, fall_rates  # noqa: E402  (the sibling script)


def falls_by_team(replays: Sequence[Any], near_m: float = NEAR_M) -> dict[str, dict]:
    """{team spec: {"falls", "near", "robot_minutes"}} over ``replays``, each side counted
    by ``fall_rates``."""
    table: dict[str, dict] = {}
    for replay in replays:
        for side, team in enumerate((replay.metadata["left"], replay.metadata["right"])):
            rates = fall_rates([replay], near_m, side=side)
            row = table.setdefault(str(team), {"falls": 0, "near": 0, "robot_minutes": 0.0})
            row["falls"] += rates["falls_alone"] + rates["falls_near"]
            row["near"] += rates["falls_near"]
            row["robot_minutes"] += rates["robot_minutes"]
    return table


def main() -> None:
    from teamenv.replay import load_replay

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("replay_dir", type=Path)
    ap.add_argument("--near-m", type=float, default=NEAR_M)
    args = ap.parse_args()
    replays = [load_replay(path) for path in sorted(args.replay_dir.glob("*.npz"))]
    if not replays:
        raise SystemExit(f"{args.replay_dir}: no *.npz replay there")
    table = falls_by_team(replays, args.near_m)
    rows = sorted(table.items(), key=lambda kv: -kv[1]["falls"] / kv[1]["robot_minutes"])
    for team, row in rows:
        rate = row["falls"] / row["robot_minutes"]
        near = row["near"] / row["falls"] if row["falls"] else 0.0
        print(f"{team[:40]:40s} {row['falls']:5d} falls  {row['robot_minutes']:7.1f} robot-min  "
              f"{rate:5.2f} per robot-minute  {near:4.0%} near another robot")
    falls = sum(row["falls"] for row in table.values())
    minutes = sum(row["robot_minutes"] for row in table.values())
    print(f"all: {falls} falls in {len(replays)} matches, {falls / minutes:.3f} per "
          f"robot-minute, {falls / len(replays):.1f} per match")


if __name__ == "__main__":
    main()
