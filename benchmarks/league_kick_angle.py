"""How far off the body's heading the league T1 can kick without first walking round the ball.

    python benchmarks/league_kick_angle.py --out benchmarks/results/league_kick_angle.json

For each offset (rad) between the robot's heading and the kick's direction, kick trials
(``teamenv.league.kick_trial.kick_trial`` on ``LocalServer``, the league's default walk, the
reference network, walking the approach) from ``STARTS``: standing 0.35-0.6 m behind the ball
(where a team that asks to kick once the ball is within ``kick_reach`` has its robot), facing
+x, the kick aimed ``offset`` to the left and to the right. A trial counts when the strike
began and the robot is up at the end. Printed per offset: trials counted / trials, mean
approach time and ball travel, falls. ``kick_max_angle`` is the largest offset (of the
sweep, from 0 up, every smaller one passing as well) at which at least ``PASS_SHARE`` of the
trials count; ``calibrate_t1_league.py --kick-angle FILE`` writes it into ``t1_league``.
The approach has to walk round the ball for a kick off the heading, with the ball below the
camera's view for most of the way, and more often than not fails beyond ~1 rad.
"""

from __future__ import annotations

import argparse
import json
import time

from teamenv.league.kick_trial import BALL, kick_trial

#: (metres behind the ball, metres to its left) of the robot's start, facing +x
STARTS = ((0.45, 0.1), (0.45, -0.1), (0.6, 0.0), (0.35, 0.2), (0.5, 0.2), (0.5, -0.2))
OFFSETS = (0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0)
#: an offset passes when at least this share of its trials struck with the robot up after
PASS_SHARE = 0.85


def sweep(offsets=OFFSETS, starts=STARTS) -> list[dict]:
    from teamenv.league.network_walk import NetworkWalkController

    rows = []
    for offset in offsets:
        for behind, left in starts:
            for sign in (1.0, -1.0):
                r = kick_trial((BALL[0] - behind, BALL[1] + left, 0.0), sign * offset,
                               walker=NetworkWalkController(), settle_s=3.0, approach_s=8.0)
                rows.append({"offset": offset, "behind": behind, "left": left, "sign": sign,
                             "kicked": r.kicked, "struck": r.strike_ball_x is not None,
                             "upright": r.upright, "travel": round(r.travel, 3),
                             "approach_s": round(r.approach_s, 2)})
    return rows


def summary(rows: list[dict]) -> dict:
    per = {}
    for offset in sorted({r["offset"] for r in rows}):
        rs = [r for r in rows if r["offset"] == offset]
        counted = sum(r["struck"] and r["upright"] for r in rs)
        per[offset] = {"trials": len(rs), "counted": counted,
                       "approach_s_mean": round(sum(r["approach_s"] for r in rs) / len(rs), 2),
                       "travel_mean_m": round(sum(r["travel"] for r in rs) / len(rs), 2),
                       "falls": sum(not r["upright"] for r in rs)}
    limit = 0.0
    for offset, s in per.items():
        if s["counted"] < PASS_SHARE * s["trials"]:
            break
        limit = offset
    return {"per_offset": {str(k): v for k, v in per.items()}, "kick_max_angle": limit,
            "pass_share": PASS_SHARE}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None, help="write the rows and the summary (JSON) here")
    args = ap.parse_args(argv)
    start = time.monotonic()
    rows = sweep()
    result = summary(rows)
    for offset, s in result["per_offset"].items():
        print(f"offset {float(offset):.2f} rad: {s['counted']}/{s['trials']} struck and up, "
              f"approach {s['approach_s_mean']:.2f} s, travel {s['travel_mean_m']:.2f} m, "
              f"falls {s['falls']}")
    print(f"kick_max_angle: {result['kick_max_angle']} rad "
          f"({time.monotonic() - start:.0f} s wall)")
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            json.dump({"command": "python benchmarks/league_kick_angle.py --out FILE",
                       "summary": result, "rows": rows}, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
