"""Get-up trials on the league server's physics: how often and how fast the T1 stands up.

For each side (the robot tipped onto its front, then onto its back) and each seed of the
evaluation range (default 0-99; ``league_getup_tune.py`` tuned on seeds 1000-1002), a fresh
``LocalServer`` (rcsssmj in this process) drops the robot as ``getup_trial.fall_setup`` draws
it (a random heading, tilt, roll, tip rate, arm and leg posture, joint stiffness and fall
time), then ``GetUpMotion`` (the keyframes of ``teamenv/league/getup.py``) gets it up, and it
holds the end pose for 2 s. Printed per side: success (up when the motion is done and not
down again within 2 s after), the time from the start of the motion to up (mean, 95th
percentile, max over the successes), falls within 2 s after being up, how often the motion
chose the side the robot actually lay on, and how far it got (the median over trials of the
highest torso and of the most upright torso during the motion and the hold). ``--json`` writes every trial.

    python benchmarks/league_getup_trials.py                    # 100 + 100 trials
    python benchmarks/league_getup_trials.py --seeds 0-19 --side back
    python benchmarks/league_getup_trials.py --side front --json f.json &    # in parallel
    python benchmarks/league_getup_trials.py --side back --json b.json
    python benchmarks/league_getup_trials.py --merge f.json b.json --json all.json
    python benchmarks/league_getup_trials.py --side front --front-keyframes cand.json
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from teamenv.league.getup import FRONT_ARMS_RETRY, GetUpMotion
from teamenv.league.getup_trial import getup_trial
from teamenv.league.network_walk import NetworkWalkController

#: the get-up targets (success share, seconds to up)
TARGET_SUCCESS = 0.95
TARGET_TIME_S = 5.0


def seed_range(text: str) -> list[int]:
    lo, _, hi = text.partition("-")
    try:
        return list(range(int(lo), int(hi or lo) + 1))
    except ValueError:
        raise SystemExit(f"--seeds: {text!r} is not N or N-M") from None


def run(side: str, seeds: list[int], after: str = "network",
        front: list | None = None) -> list[dict]:
    """One trial per seed, each on a fresh ``LocalServer``; ``front``: the front keyframes
    (with the arm check's retry, ``getup.FRONT_ARMS_RETRY``; default ``getup.FRONT``)."""
    rows = []
    for seed in seeds:
        walk = NetworkWalkController() if after == "network" else None
        motion = (GetUpMotion(attempts=1) if front is None else
                  GetUpMotion(front=front, attempts=1, arms_retry=FRONT_ARMS_RETRY))
        r = getup_trial(motion, side, seed, hold_s=2.0, after=walk)
        rows.append({"side": side, "seed": seed, "lay_on_front": r.lying_on_front,
                     "chose": r.side_detected, "up": r.up, "fell_after": r.fell_after,
                     "success": r.success, "after": after,
                     "time_to_up": None if math.isnan(r.time_to_up) else round(r.time_to_up, 3),
                     "motion_s": round(r.motion_s, 3),
                     "highest_torso_m": round(float(r.heights.max()), 3),
                     "most_upright": round(float(r.uprights.max()), 3)})
    return rows


def summary(side: str, rows: list[dict]) -> str:
    n = len(rows)
    ok = [r for r in rows if r["success"]]
    times = np.array([r["time_to_up"] for r in ok if r["time_to_up"] is not None])
    ups = [r for r in rows if r["up"]]
    fell = sum(r["fell_after"] for r in ups)
    right = sum(r["chose"] == ("front" if r["lay_on_front"] else "back") for r in rows)
    share = len(ok) / n if n else math.nan
    met = share >= TARGET_SUCCESS and (len(times) == 0 or times.max() <= TARGET_TIME_S)
    t = (f"time to up mean {times.mean():.2f} s, p95 {np.percentile(times, 95):.2f} s, "
         f"max {times.max():.2f} s" if len(times) else "never up")
    high = np.array([r["highest_torso_m"] for r in rows])
    upright = np.array([r["most_upright"] for r in rows])
    return (f"{side}: success {len(ok)}/{n} = {100 * share:.1f} %; {t}; fell again within 2 s "
            f"after up: {fell}/{len(ups)}; chose the side it lay on: {right}/{n}; highest torso "
            f"(median) {np.median(high):.2f} m, most upright (median z of its up axis) "
            f"{np.median(upright):+.2f}; targets "
            f"(>= {100 * TARGET_SUCCESS:.0f} %, <= {TARGET_TIME_S:.0f} s) "
            f"{'met' if met else 'NOT met'}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", default="0-99", help="evaluation seeds, N-M (default 0-99)")
    ap.add_argument("--side", choices=("front", "back", "both"), default="both")
    ap.add_argument("--after", choices=("network", "pose"), default="network",
                    help="what stands the robot in the 2 s after the motion: the league's "
                         "walk, as in a match (default), or the motion's end pose")
    ap.add_argument("--json", default=None, help="write every trial here")
    ap.add_argument("--front-keyframes", default=None,
                    help="the front's keyframes from this JSON file (as "
                         "league_getup_search.py --out writes) instead of getup.FRONT")
    ap.add_argument("--merge", nargs="+", default=None,
                    help="summarise these --json files (e.g. one per side, run in parallel) "
                         "and write them together to --json")
    args = ap.parse_args()
    if args.merge:
        every = [r for path in args.merge for r in json.load(open(path, encoding="utf-8"))]
        for side in ("front", "back"):
            rows = [r for r in every if r["side"] == side]
            if rows:
                print(summary(side, rows))
        if args.json:
            with open(args.json, "w", encoding="utf-8") as fh:
                json.dump(every, fh, indent=1)
        return
    seeds = seed_range(args.seeds)
    sides = ("front", "back") if args.side == "both" else (args.side,)
    front = None
    if args.front_keyframes:
        with open(args.front_keyframes, encoding="utf-8") as fh:
            front = [(dt, f) for dt, f in json.load(fh)["keyframes"]]
    every = []
    for side in sides:
        t0 = time.perf_counter()
        rows = run(side, seeds, args.after, front)
        every += rows
        print(summary(side, rows), f"({time.perf_counter() - t0:.0f} s wall)", flush=True)
        failed = [r["seed"] for r in rows if not r["success"]]
        if failed:
            print(f"  failed seeds: {failed}")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(every, fh, indent=1)


if __name__ == "__main__":
    main()
