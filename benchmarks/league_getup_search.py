"""Search get-up keyframes fast: CMA-ES on ``FastPlant`` over many falls, then check on LocalServer.

``league_getup_tune.py`` scores a candidate on ``LocalServer`` (~1.2 s of CPU per 5 s get-up);
this script makes each tuning fall once on ``LocalServer`` (``getup_trial.fall``), keeps the
simulation's state, and scores every candidate from those states on ``FastPlant`` (the same
MuJoCo model and motor semantics without the protocol, ~0.1 s per get-up), so a search can
see many falls per candidate and many more candidates. The score per fall is the tuner's
(``league_getup_tune.trial_score``'s terms: best crouch during the motion, 2 x mean standing
quality in the hold, success bonus 2 + (5 s - time to up) / 5 s); a candidate's score is the
mean over the falls. Candidates are the tuner's keyframes (``encode`` / ``decode``: duration
and the ``TUNED`` groups of every keyframe after the first ``--fixed``) plus each searched
keyframe's ``damping`` (the kd scale, ``getup.DAMPING``, 0.05-2 on a log scale).

Every ``--check-every`` generations, and at the end, the best candidate is run on LocalServer
(``getup_trial``) on the same falls: the success count there is printed next to the fast one.

    nice -n 10 python benchmarks/league_getup_search.py --side front --fixed 4 \\
        --seeds 1000-1011 --generations 60 --popsize 16 --seed 1 --out front.json
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from league_getup_tune import (  # noqa: E402
    HOLD_S,
    STAND_HEIGHT_M,
    START_BACK,
    START_FRONT,
    crouch_of,
    decode,
    encode,
    load,
)

from teamenv.league import getup  # noqa: E402
from teamenv.league.controller import CYCLE_S  # noqa: E402
from teamenv.league.falls import torso_down  # noqa: E402
from teamenv.league.getup import DAMPING, UP_HEIGHT_M, GetUpMotion  # noqa: E402
from teamenv.league.getup_plant import FastPlant, motor_arrays  # noqa: E402
from teamenv.league.getup_trial import fall, fall_setup, getup_trial, trial_server  # noqa: E402

#: the kd scale's range (log scale in the search vector)
DAMPING_RANGE = (0.05, 2.0)


def parse_seeds(text: str) -> list[int]:
    lo, _, hi = text.partition("-")
    try:
        return list(range(int(lo), int(hi or lo) + 1))
    except ValueError:
        raise SystemExit(f"--seeds: {text!r} is not N or N-M") from None


def make_falls(side: str, seeds: list[int], server) -> tuple[FastPlant, list]:
    """The plant of ``server`` and (perception, snapshot) of each seed's fall, made on it."""
    plant = FastPlant(server)
    out = []
    for seed in seeds:
        p = fall(server, fall_setup(side, seed))
        out.append((p, plant.snapshot()))
    return plant, out


def outside(point: np.ndarray, pts: np.ndarray) -> float:
    """Distance (m) from ``point`` to the convex hull of ``pts`` (0 inside; inf for none)."""
    if len(pts) == 0:
        return math.inf
    pts = np.unique(np.round(pts, 4), axis=0)
    if len(pts) >= 3:
        hull = _hull(pts)
        if len(hull) >= 3 and all(_cross(hull[i], hull[(i + 1) % len(hull)], point) >= 0
                                  for i in range(len(hull))):
            return 0.0
    else:
        hull = list(pts)
    best = math.inf
    for i in range(len(hull)):
        a, b = hull[i], hull[(i + 1) % len(hull)]
        ab = b - a
        t = 0.0 if not ab.any() else float(np.clip(np.dot(point - a, ab) / np.dot(ab, ab), 0, 1))
        best = min(best, float(np.hypot(*(point - a - t * ab))))
    return best


def _cross(o, a, b) -> float:
    return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))


def _hull(pts: np.ndarray) -> list:
    """Counter-clockwise convex hull (Andrew's monotone chain)."""
    pts = sorted(map(tuple, pts))
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and _cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and _cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return [np.array(p) for p in lower[:-1] + upper[:-1]]


def leg_support(plant: FastPlant) -> float:
    """How well the legs alone carry the robot: 1 with the centre of mass above the convex
    hull of the legs' ground contacts, ``SUPPORT_M`` away e^-1 times that, times its height
    (up to 0.35 m); the torso, head and arms off the ground count twice as much."""
    pts, other = plant.ground_contacts()
    com = plant.com()
    score = math.exp(-outside(com[:2], pts) / SUPPORT_M) * min(com[2] / 0.35, 1.0)
    return score if not other else 0.5 * score


#: the leg support's length scale (m)
SUPPORT_M = 0.05


def run_fast(motion: GetUpMotion, plant: FastPlant, p, snap) -> dict:
    """One get-up from a saved fall on the fast plant: the tuner's score terms."""
    plant.restore(snap)
    motion.start(p)
    n_motion = math.ceil(motion.duration / CYCLE_S - 1e-9)
    n_hold = round(HOLD_S / CYCLE_S)
    crouches, supports, quality, ups = [], [], [], []
    fell = [False]

    def policy(k, pl):
        pose, gains = motion.command_at((k + 1) * CYCLE_S)
        return motor_arrays(pose, gains, pl.motors)

    def watch(k, pl):
        pos, quat = pl.torso()
        up_z = 1.0 - 2.0 * (quat[1] ** 2 + quat[2] ** 2)
        up = not torso_down(quat, pos[2]) and pos[2] >= UP_HEIGHT_M
        if k < n_motion:
            left, right = pl.feet()
            crouches.append(crouch_of(pl.com(), left, right))
            supports.append(leg_support(pl))
            ups.append(up)
        else:
            quality.append(min(pos[2] / STAND_HEIGHT_M, 1.0) * max(up_z, 0.0))
            if torso_down(quat, pos[2]):
                fell[0] = True
                return True
        return False

    plant.run(policy, n_motion + n_hold, watch)
    up = bool(ups and ups[-1])
    t_up = math.nan
    if up:
        k = len(ups) - 1
        while k > 0 and ups[k - 1]:
            k -= 1
        t_up = k * CYCLE_S  # the cycle index of the first up cycle of the last run of ups
    success = up and not fell[0]
    score = (max(crouches, default=0.0) + max(supports, default=0.0)
             + 2.0 * sum(quality) / n_hold)
    if success:
        score += 2.0 + (5.0 - min(t_up, 5.0)) / 5.0
    return {"score": score, "success": success, "time_to_up": t_up,
            "support": max(supports, default=0.0), "crouch": max(crouches, default=0.0)}


def with_damping(frames: list, u_damp: np.ndarray, fixed: int) -> list:
    out = list(frames[:fixed])
    lo, hi = DAMPING_RANGE
    for (dt, frame), u in zip(frames[fixed:-1], u_damp, strict=True):
        frame = dict(frame)
        frame[DAMPING] = round(float(lo * (hi / lo) ** float(np.clip(u, 0, 1))), 4)
        out.append((dt, frame))
    last_dt, last = frames[-1]
    out.append((last_dt, {**last, DAMPING: 1.0}))
    return out


def damping_u(frames: list, fixed: int) -> np.ndarray:
    lo, hi = DAMPING_RANGE
    return np.array([math.log(f.get(DAMPING, 1.0) / lo) / math.log(hi / lo)
                     for _, f in frames[fixed:-1]])


def evaluate(frames, side, plant, falls) -> tuple[float, int, list]:
    motion = GetUpMotion(front=frames, back=frames, attempts=1)
    rows = [run_fast(motion, plant, p, snap) for p, snap in falls]
    return (float(np.mean([r["score"] for r in rows])), sum(r["success"] for r in rows), rows)


def check_local(frames, side, seeds) -> tuple[int, list]:
    motion = GetUpMotion(front=frames, back=frames, attempts=1)
    server = trial_server()
    rs = [getup_trial(motion, side, seed, hold_s=HOLD_S, server=server) for seed in seeds]
    return sum(r.success for r in rs), [None if math.isnan(r.time_to_up) else
                                        round(r.time_to_up, 2) for r in rs]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--side", choices=("front", "back"), required=True)
    ap.add_argument("--seeds", default="1000-1011", help="tuning falls, N-M")
    ap.add_argument("--keyframes", default=None, help="start from these (JSON as --out writes)")
    ap.add_argument("--start", choices=("module", "hand"), default="module",
                    help="start from getup.FRONT/BACK (module) or the tuner's START_* (hand)")
    ap.add_argument("--fixed", type=int, default=0)
    ap.add_argument("--generations", type=int, default=60)
    ap.add_argument("--popsize", type=int, default=16)
    ap.add_argument("--sigma", type=float, default=0.15)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--check-every", type=int, default=10)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    import cma

    seeds = parse_seeds(args.seeds)
    if args.keyframes:
        template = load(args.keyframes)
    elif args.start == "hand":
        template = list(START_FRONT if args.side == "front" else START_BACK)
    else:
        template = list(getup.FRONT if args.side == "front" else getup.BACK)
    server = trial_server()
    plant, falls = make_falls(args.side, seeds, server)
    best, n_ok, _ = evaluate(template, args.side, plant, falls)
    best_frames = template
    print(f"start: {best:.3f}, {n_ok}/{len(falls)} up (fast)", flush=True)
    x0 = np.concatenate([encode(template, args.fixed), damping_u(template, args.fixed)])
    n_key = len(template) - 1 - args.fixed
    es = cma.CMAEvolutionStrategy(np.clip(x0, 0, 1).tolist(), args.sigma,
                                  {"bounds": [0.0, 1.0], "seed": args.seed + 1, "verbose": -9,
                                   "popsize": args.popsize})

    def build(x):
        x = np.asarray(x)
        frames = decode(x[:-n_key], template, args.fixed)
        return with_damping(frames, x[-n_key:], args.fixed)

    for g in range(args.generations):
        t0 = time.perf_counter()
        xs = es.ask()
        cands = [build(x) for x in xs]
        results = [evaluate(c, args.side, plant, falls) for c in cands]
        es.tell(xs, [-r[0] for r in results])
        i = int(np.argmax([r[0] for r in results]))
        if results[i][0] > best:
            best, best_frames, n_ok = results[i][0], cands[i], results[i][1]
            if args.out:
                with open(args.out, "w", encoding="utf-8") as fh:
                    json.dump({"side": args.side, "score": best, "seeds": seeds,
                               "keyframes": best_frames}, fh, indent=1)
        print(f"gen {g:3d}: gen best {results[i][0]:.3f} ({results[i][1]} up), best {best:.3f} "
              f"({n_ok}/{len(falls)} up) {time.perf_counter() - t0:.1f} s", flush=True)
        if args.check_every and (g + 1) % args.check_every == 0:
            ok, times = check_local(best_frames, args.side, seeds)
            print(f"  LocalServer: {ok}/{len(seeds)} up, times {times}", flush=True)
    print(json.dumps(best_frames))
    ok, times = check_local(best_frames, args.side, seeds)
    print(f"LocalServer: {ok}/{len(seeds)} up, times {times}")


if __name__ == "__main__":
    main()
