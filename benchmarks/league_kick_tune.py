"""Tune the T1's kick (a kick step of the walker, ``teamenv.league.kick``) for the league
server, with the server's own physics as the plant.

The plant is ``LocalServer`` (rcsssmj in this process). Each candidate ``KickParams`` kicks
from standing at the kick spot (``teamenv.league.kick_trial.kick_trial`` with
``approach=False``): each foot with the ball on the spot and 2 cm off it. Score per kick =
the ball's travel along the asked direction (capped at ``CAP`` m) - 0.1 m per degree of
direction error, - 8 if the robot went down during or within ``--settle`` s after the kick
(a fall costs less the later it comes: up to 4 of the 8 back for a robot still up 1 s after
the motion), - 10 per second the motion lasts beyond ``MAX_KICK_S`` + ``STANDING_START_S``
(from standing the walker stands 0.5 s and steps once before the kicking foot can swing;
the duration target itself is measured from a walking approach by
``benchmarks/league_kick_trials.py``). The search is CMA-ES (pycma) over ``BOX``, started at
``LEAGUE_KICK``, in one process (the machine is shared: run it under ``nice``).

    nice -n 10 python benchmarks/league_kick_tune.py --check           # LEAGUE_KICK's score
    nice -n 10 python benchmarks/league_kick_tune.py --check --params '{"strike_hip": 0.6}'
    nice -n 10 python benchmarks/league_kick_tune.py --generations 6 --out kick.json
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from teamenv.league.kick import LEAGUE_KICK, KickParams
from teamenv.league.kick_trial import kick_trial, spot_start

#: the kick's target duration (s) and the travel that counts at most (m)
MAX_KICK_S = 1.5
STANDING_START_S = 0.8
CAP = 12.0
#: (foot, dx, dy): the tuning kicks (ball offset from the spot, m)
KICKS = (("right", 0.0, 0.0), ("right", 0.02, -0.02), ("left", 0.0, 0.0), ("left", -0.02, 0.02))
BOX = {
    "spot_x": (0.42, 0.62),
    "foot_y": (0.08, 0.14),
    "strike_x": (0.34, 0.5),
    "walk_vx": (0.1, 0.3),
    "strike_hip": (0.2, 0.8),
    "strike_knee": (0.0, 0.6),
    "strike_from": (0.0, 0.3),
    "strike_to": (0.6, 1.0),
    "follow_s": (0.3, 0.8),
}


def kick_score(params: KickParams, settle_s: float) -> tuple[float, list[dict]]:
    rows = []
    total = 0.0
    for foot, dx, dy in KICKS:
        side = 1.0 if foot == "right" else -1.0
        r = kick_trial(spot_start(params, foot, dx, side * dy), params=params, approach=False,
                       settle_s=settle_s)
        along = r.travel * math.cos(r.error)
        s = min(along, CAP) - 0.1 * abs(math.degrees(r.error)) * min(1.0, r.travel)
        if r.fell_during or not r.upright:   # the longer it stayed up, the less it costs
            s -= 8.0 - 4.0 * min(1.0, r.upright_s / (r.kick_s + 1.0))
        s -= 10.0 * max(0.0, r.kick_s - MAX_KICK_S - STANDING_START_S)
        total += s
        rows.append({"foot": foot, "travel": round(r.travel, 2),
                     "error_deg": round(math.degrees(r.error), 1), "fell": r.fell_during,
                     "score": round(s, 2)})
    return total, rows


def _decode(u: np.ndarray) -> dict[str, float]:
    u = np.clip(u, 0.0, 1.0)
    return {k: float(lo + ui * (hi - lo)) for ui, (k, (lo, hi)) in zip(u, BOX.items(), strict=True)}


def search(generations: int, settle_s: float, seed: int, out: str | None) -> None:
    import cma

    start = np.array([(getattr(LEAGUE_KICK, k) - lo) / (hi - lo) for k, (lo, hi) in BOX.items()])
    es = cma.CMAEvolutionStrategy(np.clip(start, 0, 1).tolist(), 0.15,
                                  {"bounds": [0.0, 1.0], "seed": seed + 1, "verbose": -9})
    best, rows = kick_score(LEAGUE_KICK, settle_s)
    best_fields: dict[str, float] = {}
    print(f"start (LEAGUE_KICK) {best:.2f} {rows}", flush=True)
    for g in range(generations):
        t0 = time.perf_counter()
        xs = es.ask()
        fields = [_decode(np.asarray(x)) for x in xs]
        scored = [kick_score(LEAGUE_KICK.with_(**f), settle_s) for f in fields]
        scores = [s for s, _ in scored]
        es.tell(xs, [-s for s in scores])
        i = int(np.argmax(scores))
        if scores[i] > best:
            best, best_fields = scores[i], fields[i]
            if out:
                with open(out, "w", encoding="utf-8") as fh:
                    json.dump({"score": best, "rows": scored[i][1],
                               "params": LEAGUE_KICK.with_(**best_fields).as_dict()}, fh, indent=1)
        print(f"gen {g:2d}: best of gen {scores[i]:.2f} {scored[i][1]}, best {best:.2f} "
              f"({time.perf_counter() - t0:.0f} s)", flush=True)
    print(json.dumps({k: round(v, 4) for k, v in best_fields.items()}))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="score the parameters, no search")
    ap.add_argument("--params", default=None, help="JSON of KickParams fields (--check)")
    ap.add_argument("--generations", type=int, default=8)
    ap.add_argument("--settle", type=float, default=2.5, help="seconds watched after a kick")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=None, help="write the best parameters (JSON) here")
    args = ap.parse_args()
    if args.check:
        params = LEAGUE_KICK.with_(**json.loads(args.params or "{}"))
        total, rows = kick_score(params, args.settle)
        print(f"score {total:.2f}")
        for r in rows:
            print(f"  {r}")
        return
    search(args.generations, args.settle, args.seed, args.out)


if __name__ == "__main__":
    main()
