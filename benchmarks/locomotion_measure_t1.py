"""Measure the T1's push/fall thresholds and fall duration in brax (cross-checked in MuJoCo) and write the profile."""

from __future__ import annotations

import argparse
import json
import shlex
import sys
import time

import numpy as np

from locomotion.humanoid.measure import (
    DIRECTIONS,
    analyse_push_grid,
    base_profile,
    bisect_threshold_mujoco,
    fall_duration_from_grid,
    measure_push_grid,
    measurements_to_profile,
    write_measured_profile,
)
from locomotion.humanoid.t1 import load_t1


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--engine", choices=("brax", "mujoco"), default="brax")
    ap.add_argument("--speeds", default="0.25:1.0:0.05", help="start:stop:step (m/s, inclusive)")
    ap.add_argument("--sim-s", type=float, default=2.0)
    ap.add_argument("--out", default=None, help="profile JSON to write (default: print only)")
    ap.add_argument("--base", default="t1_mj")
    ap.add_argument(
        "--crosscheck", action="store_true", help="bisect each threshold in native MuJoCo"
    )
    args = ap.parse_args()
    a, b, c = (float(x) for x in args.speeds.split(":"))
    speeds = np.round(np.arange(a, b + 1e-9, c), 4)
    command = "python " + " ".join(shlex.quote(x) for x in sys.argv)
    t1 = load_t1()
    t0 = time.perf_counter()
    grid = measure_push_grid(args.engine, speeds, sim_s=args.sim_s, t1=t1)
    wall = time.perf_counter() - t0
    analysis = analyse_push_grid(grid)
    fall = fall_duration_from_grid(grid, analysis)
    print(
        f"{args.engine}: {len(speeds) * len(DIRECTIONS)} pushes x {args.sim_s} s in {wall:.0f} s wall"
    )
    for d, r in analysis.items():
        print(
            f"  {d:9s} threshold {r['threshold']} m/s  bracket {r['bracket']}  monotonic {r['monotonic']}"
        )
    print(f"  fall duration (median, push 1.5x threshold): {fall} s")
    raw = dict(grid)
    if args.crosscheck:
        cc = {d: bisect_threshold_mujoco(d, t1=t1, sim_s=args.sim_s) for d in DIRECTIONS}
        raw["mujoco_bisection"] = cc
        for d, r in cc.items():
            br = analysis[d]["bracket"]
            inside = (
                br[0] is not None
                and br[1] is not None
                and br[0] - 0.025 <= r["threshold"] <= br[1] + 0.025
            )
            print(
                f"  mujoco {d:9s} threshold {r['threshold']:.3f} m/s (bisection) -> "
                f"{'agrees with' if inside else 'DIFFERS from'} {args.engine} bracket {br}"
            )
    prof = measurements_to_profile(
        base_profile(args.base), analysis, args.engine, command, fall_duration=fall, raw=raw
    )
    if args.out:
        write_measured_profile(prof, args.out)
        print(f"wrote {args.out}")
    else:
        print(json.dumps(prof["measurements"], indent=1)[:2000])


if __name__ == "__main__":
    main()
