"""Random search of the T1 walker's parameters in native MuJoCo (survival + velocity tracking).

Each candidate walks a fixed set of commands for ``--seconds``; score per command = share of
the run survived + (if it stood) 1 - the tracking error (|achieved - commanded| per axis over
max(|commanded|, scale), summed); the best parameters are printed as a WalkParams(...) call.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from locomotion.humanoid.envelope import measure_command
from locomotion.humanoid.t1 import load_t1
from locomotion.humanoid.walker import WalkParams

COMMANDS = (
    (0.3, 0.0, 0.0),
    (0.5, 0.0, 0.0),
    (0.7, 0.0, 0.0),
    (-0.3, 0.0, 0.0),
    (0.0, 0.15, 0.0),
    (0.0, 0.0, 0.8),
    (0.4, 0.0, 0.4),
)
# name -> (low, high) of the search box
BOX = {
    "step_period": (0.28, 0.45),
    "double_support": (0.04, 0.12),
    "lateral": (0.095, 0.12),
    "com_height": (0.5, 0.62),
    "lift": (0.02, 0.06),
    "torso_lean": (-0.05, 0.1),
    "pd_gain_scale": (2.0, 5.0),
    "ankle_fb": (-0.1, 0.3),
    "ankle_fd": (-0.05, 0.15),
    "hip_fb": (-0.3, 0.3),
    "hip_fd": (-0.1, 0.1),
    "step_fb": (0.3, 1.5),
    "cp_pos": (0.0, 1.0),
    "step_max": (0.04, 0.1),
    "tilt_ik": (0.0, 0.4),
}
SCALE = np.array([0.1, 0.1, 0.3])


def score(t1, params: WalkParams, seconds: float) -> tuple[float, list]:
    total, rows = 0.0, []
    for c in COMMANDS:
        r = measure_command(t1, c, seconds, params)
        s = r["time"] / seconds
        if not r["fell"]:
            err = np.abs(np.array(r["achieved"]) - c) / np.maximum(np.abs(c), SCALE)
            s += 1.0 - min(float(err.sum()), 1.0)
        total += s
        rows.append((c, r["fell"], r["time"], r["achieved"]))
    return total, rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--n", type=int, default=40, help="candidates")
    ap.add_argument("--seconds", type=float, default=8.0)
    ap.add_argument("--sigma", type=float, default=0.15, help="step as a share of the box")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--start", default=None, help="JSON of WalkParams fields to start from")
    ap.add_argument("--out", default=None, help="write the best parameters (JSON) here")
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    t1 = load_t1()
    best_p = WalkParams().with_(**json.loads(args.start)) if args.start else WalkParams()
    t0 = time.perf_counter()
    best, rows = score(t1, best_p, args.seconds)
    print(f"start {best:.3f} ({time.perf_counter() - t0:.0f} s)", flush=True)
    for i in range(args.n):
        cur = best_p.as_dict()
        kw = {}
        for k in rng.choice(list(BOX), size=int(rng.integers(2, 6)), replace=False):
            lo, hi = BOX[k]
            kw[k] = float(np.clip(cur[k] + rng.normal() * args.sigma * (hi - lo), lo, hi))
        cand = best_p.with_(**kw)
        s, r = score(t1, cand, args.seconds)
        mark = ""
        if s > best:
            best, best_p, rows, mark = s, cand, r, " *"
            if args.out:
                with open(args.out, "w", encoding="utf-8") as fh:
                    json.dump({"score": best, "params": best_p.as_dict()}, fh, indent=1)
        print(
            f"{i:3d} {s:.3f} best {best:.3f}{mark} {json.dumps({k: round(v, 4) for k, v in kw.items()})}",
            flush=True,
        )
    print("best", best)
    for row in rows:
        print("  ", row)
    print(json.dumps({k: round(v, 4) for k, v in best_p.as_dict().items()}))


if __name__ == "__main__":
    main()
