"""Tune the T1 walker for the league server, with the server's own physics as the plant.

The plant is ``teamenv.league.local_server.LocalServer``: rcsssmj's simulation in this
process, with the server's 5 ms x 4 physics steps per 20 ms cycle, its PD motors, its
perception encoder (values truncated as on the wire) and its one-cycle action delay (the
default parallel sync mode). Each candidate ``WalkParams`` walks every command of ``TRIALS``
for ``--seconds`` from the left team's beam pose, after standing 0.6 s; score per trial = the
share of the run it stayed up + (if it never fell) 1 - the tracking error (|achieved -
commanded| per axis over max(|commanded|, scale), summed, capped at 1; the ``switching``
trial, a chase-like sequence, scores survival twice). The search is CMA-ES (pycma) over the
``BOX`` below, started at ``LEAGUE_WALK``; ``--check`` scores given parameters, also on the
real ``rcssservermj`` with ``--real``.

Commands (each prints what it measured; see docs/league.md for the numbers):

    python benchmarks/league_walker_tune.py --check                  # LEAGUE_WALK, local plant
    python benchmarks/league_walker_tune.py --check --real           # ... and on the real server
    python benchmarks/league_walker_tune.py --check --params '{}'    # the native-MuJoCo defaults
    python benchmarks/league_walker_tune.py --envelope               # LEAGUE_WALK's speed limits
    python benchmarks/league_walker_tune.py --tracking               # the t1_league profile's curves
    python benchmarks/league_walker_tune.py --generations 25 --workers 2 --out tuned.json
"""

from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from locomotion.humanoid.envelope import achieved_velocity
from locomotion.humanoid.walker import WalkParams
from teamenv.league.controller import LEAGUE_WALK, WalkerController
from teamenv.league.walk_trial import walk_trial


def _switching(t: float) -> tuple[float, float, float]:
    """A chase-like sequence: run, turn on the spot, curve back, stop."""
    if t < 1.5:
        return (0.5, 0.0, 0.0)
    if t < 2.5:
        return (0.0, 0.0, 0.8)
    if t < 4.0:
        return (0.3, 0.0, -0.4)
    return (0.0, 0.0, 0.0)


#: name -> constant command (vx, vy, turn) or a schedule
TRIALS = {
    "forward 0.3": (0.3, 0.0, 0.0),
    "forward 0.5": (0.5, 0.0, 0.0),
    "backward 0.2": (-0.2, 0.0, 0.0),
    "sideways 0.15": (0.0, 0.15, 0.0),
    "turn 0.6": (0.0, 0.0, 0.6),
    "curve 0.3/0.3": (0.3, 0.0, 0.3),
    "in place": (0.0, 0.0, 0.0),
    "switching": _switching,
}
# name -> (low, high) of the search box
BOX = {
    "step_period": (0.26, 0.45),
    "double_support": (0.04, 0.14),
    "lateral": (0.09, 0.13),
    "com_height": (0.48, 0.62),
    "lift": (0.02, 0.06),
    "torso_lean": (-0.05, 0.1),
    "pd_gain_scale": (1.0, 3.5),
    "ankle_fb": (-0.1, 0.3),
    "ankle_fd": (-0.05, 0.15),
    "hip_fb": (-0.3, 0.3),
    "hip_fd": (-0.1, 0.1),
    "step_fb": (0.0, 1.5),
    "cp_pos": (0.0, 1.0),
    "step_max": (0.04, 0.1),
    "tilt_ik": (0.0, 0.4),
}
SCALE = np.array([0.1, 0.1, 0.3])
#: the trials start from these beam poses in turn (left team frame), so a candidate that only
#: works from one spot does not score
STARTS = ((-5.0, 0.0, 0.0), (-12.0, 3.0, 0.5), (-20.0, -6.0, -1.0), (-3.0, 8.0, 2.0))
SETTLE_S = 1.5  # the walker stands 0.5 s and slews its command: velocity is measured after


def trial_score(params: WalkParams, name: str, seconds: float, real: bool = False) -> dict:
    spec = TRIALS[name]
    fn = spec if callable(spec) else (lambda t, c=spec: c)
    start = STARTS[list(TRIALS).index(name) % len(STARTS)]
    r = walk_trial(WalkerController(params, envelope=None), fn, seconds, start=start,
                   real_server=real)
    share = r.upright_s / seconds
    row = {"trial": name, "fell": r.fell, "upright_s": round(r.upright_s, 2)}
    if callable(spec):
        return {**row, "score": 2.0 * share}
    achieved = achieved_velocity(r.times, r.poses, SETTLE_S)
    row["achieved"] = [round(float(v), 3) for v in achieved]
    score = share
    if not r.fell:
        err = np.abs(achieved - np.array(spec)) / np.maximum(np.abs(spec), SCALE)
        score += 1.0 - min(float(err.sum()), 1.0)
    return {**row, "score": score}


def score(params: WalkParams, seconds: float, real: bool = False) -> tuple[float, list[dict]]:
    rows = [trial_score(params, name, seconds, real) for name in TRIALS]
    return sum(r["score"] for r in rows), rows


def _fitness(args: tuple[dict, float]) -> float:
    fields, seconds = args
    return score(LEAGUE_WALK.with_(**fields), seconds)[0]


def _decode(u: np.ndarray) -> dict[str, float]:
    u = np.clip(u, 0.0, 1.0)
    return {k: float(lo + ui * (hi - lo)) for ui, (k, (lo, hi)) in zip(u, BOX.items(), strict=True)}


def search(generations: int, workers: int, seconds: float, seed: int, out: str | None) -> None:
    import cma

    start = np.array([(getattr(LEAGUE_WALK, k) - lo) / (hi - lo) for k, (lo, hi) in BOX.items()])
    es = cma.CMAEvolutionStrategy(np.clip(start, 0, 1).tolist(), 0.15,
                                  {"bounds": [0.0, 1.0], "seed": seed + 1, "verbose": -9})
    best, best_fields = score(LEAGUE_WALK, seconds)[0], {}
    print(f"start (LEAGUE_WALK) {best:.3f} of {2 * len(TRIALS)}", flush=True)
    with ProcessPoolExecutor(workers) as pool:
        for g in range(generations):
            t0 = time.perf_counter()
            xs = es.ask()
            fields = [_decode(np.asarray(x)) for x in xs]
            scores = list(pool.map(_fitness, [(f, seconds) for f in fields]))
            es.tell(xs, [-s for s in scores])
            i = int(np.argmax(scores))
            if scores[i] > best:
                best, best_fields = scores[i], fields[i]
                if out:
                    with open(out, "w", encoding="utf-8") as fh:
                        json.dump({"score": best, "params": LEAGUE_WALK.with_(**best_fields)
                                   .as_dict()}, fh, indent=1)
            print(f"gen {g:2d}: best of gen {scores[i]:.3f}, best {best:.3f} "
                  f"({time.perf_counter() - t0:.0f} s)", flush=True)
    print(json.dumps({k: round(v, 4) for k, v in best_fields.items()}))


#: per axis, commands of growing size (the envelope is the largest that stays up)
ENVELOPE_AXES = {
    "vx forward": [(v, 0.0, 0.0) for v in (0.4, 0.5, 0.6, 0.7, 0.8, 1.0)],
    "vx backward": [(-v, 0.0, 0.0) for v in (0.2, 0.3, 0.4, 0.5)],
    "vy": [(0.0, v, 0.0) for v in (0.1, 0.15, 0.2, 0.3)],
    "turn": [(0.0, 0.0, w) for w in (0.6, 0.8, 1.0, 1.3)],
}


def envelope(params: WalkParams, seconds: float) -> None:
    """Per axis, each command for ``seconds``: up or fell, and the achieved velocity."""
    for axis, commands in ENVELOPE_AXES.items():
        for c in commands:
            r = walk_trial(WalkerController(params, envelope=None), lambda t, c=c: c, seconds)
            v = achieved_velocity(r.times, r.poses, SETTLE_S)
            state = f"FELL at {r.upright_s:.1f} s" if r.fell else "up"
            print(f"  {axis:<12} {c}: {state:<14} achieved "
                  f"{[round(float(x), 3) for x in v]}", flush=True)


#: commands for the tracking curves of the ``t1_league`` profile (through WalkerController with
#: LEAGUE_ENVELOPE, as a league match walks)
TRACKING = {
    "vx": [(v, 0.0, 0.0) for v in (-1.0, -0.3, -0.15, 0.15, 0.3, 0.45, 1.0, 1.5)],
    "vy": [(0.0, v, 0.0) for v in (-0.4, -0.15, 0.1, 0.15, 0.4)],
    "turn": [(0.0, 0.0, w) for w in (-1.5, -1.0, -0.5, 0.5, 1.0, 1.5)],
}


def tracking(params: WalkParams, seconds: float) -> None:
    """Commanded -> achieved per axis (8 s runs, from the second STARTS pose), as JSON."""
    out = {}
    for axis, commands in TRACKING.items():
        k = ("vx", "vy", "turn").index(axis)
        points = []
        for c in commands:
            r = walk_trial(WalkerController(params), lambda t, c=c: c, seconds, start=STARTS[1])
            v = achieved_velocity(r.times, r.poses, SETTLE_S)
            points.append([c[k], None if r.fell else round(float(v[k]), 3)])
        out[axis] = points
        print(f"  {axis}: {points}", flush=True)
    print(json.dumps(out))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="score parameters, no search")
    ap.add_argument("--params", default=None,
                    help="JSON of WalkParams fields (--check; default LEAGUE_WALK; '{}': the "
                         "native-MuJoCo defaults)")
    ap.add_argument("--real", action="store_true", help="--check on the real rcssservermj too")
    ap.add_argument("--envelope", action="store_true",
                    help="the speed limits of the parameters (8 s per command)")
    ap.add_argument("--tracking", action="store_true",
                    help="commanded -> achieved through LEAGUE_ENVELOPE (8 s per command)")
    ap.add_argument("--generations", type=int, default=20)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seconds", type=float, default=5.0, help="walking time per trial")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=None, help="write the best parameters (JSON) here")
    args = ap.parse_args()
    if not (args.check or args.envelope or args.tracking):
        search(args.generations, args.workers, args.seconds, args.seed, args.out)
        return
    params = LEAGUE_WALK if args.params is None else WalkParams().with_(**json.loads(args.params))
    if args.envelope:
        envelope(params, 8.0)
        return
    if args.tracking:
        tracking(params, 8.0)
        return
    for real in (False, True) if args.real else (False,):
        t0 = time.perf_counter()
        total, rows = score(params, args.seconds, real)
        where = "real rcssservermj" if real else "LocalServer"
        print(f"{where}: score {total:.2f} of {2 * len(TRIALS)} "
              f"({time.perf_counter() - t0:.0f} s wall)")
        for r in rows:
            extra = f" achieved {r['achieved']}" if "achieved" in r else ""
            print(f"  {r['trial']:<14} up {r['upright_s']:4.1f} s"
                  f"{' FELL' if r['fell'] else ''}{extra}")


if __name__ == "__main__":
    main()
