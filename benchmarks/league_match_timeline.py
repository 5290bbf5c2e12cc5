"""What a league match spends its time on, second by second, from its replay.

    python benchmarks/league_match_timeline.py --left full --right static --seed 100331 \
        --seconds 120

Plays one match on ``LocalServer`` (7 v 7 unless ``--team-size``, the league's default walk)
through ``league_falls.play`` (which records every robot's encoder state: ``walk``,
``approach``, ``kick``, ``get_up``, ``stand``, ``beam``) and prints, every ``--every`` seconds,
the play mode (our index, ``teamenv.sim.playmode.PlayMode``), the ball's place and velocity,
the left robot nearest the ball with its distance, whether it is down and its encoder state;
then the replay's ball contacts (cycle, player index, how far the ball went) and the seconds
spent in each play mode. This is how the double-touch fouls after kick-offs and the ball
player's endless approaches in docs/league.md were found.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import league_falls  # noqa: E402  (the sibling script)


def timeline(match: dict, replay, every_s: float) -> list[str]:
    from teamenv.league.controller import CYCLE_S
    from teamenv.sim.playmode import PlayMode

    n = match["team_size"]
    agents = list(match["commands"])[:n]
    rows = []
    step = max(1, round(every_s / CYCLE_S))
    for t in range(0, len(replay.ball), step):
        ball = replay.ball[t]
        d = np.hypot(*(replay.players[t, :n, :2] - ball[:2]).T)
        k = int(d.argmin())
        log = match["commands"][agents[k]]
        state = log[min(t + 1, len(log) - 1)][0]
        down = bool(replay.fallen[t, k]) if replay.fallen is not None else False
        rows.append(f"{replay.time_s[t]:6.1f} s  {PlayMode(int(replay.play_mode[t])).name:15s}"
                    f" ball {ball[0]:6.2f} {ball[1]:6.2f} v {ball[2]:5.2f} {ball[3]:5.2f}"
                    f"  nearest L{k + 1} {d[k]:5.2f} m{' down' if down else ''} {state}")
    return rows


def main(argv: list[str] | None = None) -> None:
    from teamenv.league.controller import CYCLE_S
    from teamenv.replay import load_replay
    from teamenv.sim.playmode import PlayMode

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--left", default="full")
    parser.add_argument("--right", default="static")
    parser.add_argument("--seed", type=int, default=100331)
    parser.add_argument("--seconds", type=float, default=120.0)
    parser.add_argument("--team-size", type=int, default=7)
    parser.add_argument("--every", type=float, default=1.0, help="seconds between rows")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        match = league_falls.play(args.left, args.right, args.seed, args.seconds, False,
                                  Path(tmp), args.team_size)
        replay = load_replay(next(Path(tmp).glob("*.npz")))
    print(f"{args.left} v {args.right}, seed {args.seed}: score {match['score']}, "
          f"{match['kicks']} kicks >= {league_falls.KICK_M} m, {len(match['falls'])} falls, "
          f"{match['cpu_s']} CPU s")
    print("\n".join(timeline(match, replay, args.every)))
    if replay.kick_cycle is not None:
        print("ball contacts (cycle, player, m):", [
            (int(c), int(p), round(float(m), 2))
            for c, p, m in zip(replay.kick_cycle, replay.kick_player, replay.kick_distance,
                               strict=True)])
    modes = Counter(int(m) for m in replay.play_mode)   # one replay row per cycle
    print("seconds per play mode:", {PlayMode(m).name: round(c * CYCLE_S, 1)
                                     for m, c in modes.most_common()})


if __name__ == "__main__":
    main()
