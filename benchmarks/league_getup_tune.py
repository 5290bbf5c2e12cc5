"""Tune the T1's get-up keyframes (``teamenv.league.getup``) by CMA-ES on the server's physics.

The plant is ``LocalServer`` (rcsssmj in this process). A candidate is one side's keyframes:
for each keyframe but the last (the end pose, fixed), its duration and the angles of the
``TUNED`` joint groups (the other groups keep the start keyframes' values); plus the
duration of the last. Each candidate gets up from the falls of the tuning seeds
(``TUNING_SEEDS``, disjoint from the seeds ``league_getup_trials.py`` reports on); score per
trial (higher is better):

    best crouch during the motion + 2 x mean quality while holding the end pose
    + (up and still up 2 s later) x (2 + (5 s - time to up) / 5 s)

where quality = min(torso height / 0.62 m, 1) x max(z of the torso's up axis, 0), 1 when
standing, and crouch = min(centre of mass height / 0.45 m, 1) x exp(-max(d - 0.08 m, 0) /
0.1 m), d the horizontal distance from the centre of mass to the midpoint of the feet, both
on the ground (read from the simulation; 0 with a foot in the air): it rewards getting the weight over the feet, the step every get-up
has to make and the one a robot lying on its front or back is far from. The search is pycma's CMA-ES over the box ``BOX`` (normalised to [0, 1]); one process (``nice`` it: the machine is shared).

    nice -n 10 python benchmarks/league_getup_tune.py --side front --fixed 4 --generations 16 \
        --popsize 12 --seed 8 --out f.json          # getup.FRONT (stopped after 6 generations)
    nice -n 10 python benchmarks/league_getup_tune.py --side back --generations 20 \
        --popsize 12 --seed 5 --out b.json          # getup.BACK (stopped after 10 generations)
    python benchmarks/league_getup_tune.py --side front --check     # score getup.FRONT

``--out`` gets the best keyframes as JSON (copy them into ``FRONT`` / ``BACK`` of getup.py).
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from teamenv.league import getup
from teamenv.league.getup import END_POSE, GetUpMotion
from teamenv.league.getup_trial import TEAM, UNUM, getup_trial, trial_server

#: joint group -> (low, high) rad; durations (s) below
BOX = {
    "shoulder_pitch": (-3.0, 1.2),
    "shoulder_roll": (-1.6, 0.2),
    "elbow_pitch": (-2.2, 2.2),
    "hip_pitch": (-1.8, 1.0),
    "hip_roll": (-0.2, 1.57),
    "hip_yaw": (-1.0, 1.0),
    "knee": (0.0, 2.34),
    "ankle_pitch": (-0.87, 0.35),
}
TUNED = tuple(BOX)

_STAND = dict(END_POSE)
#: hand-made start of the front search: arms swept to the sides along the ground, turned, and
#: swept overhead (pushing them down into the ground would need more than the shoulders' 18 N m);
#: knees drawn under the hips (toes tucked); hands and knees; the torso swung up by the hips;
#: sit back onto the heels; up onto the toes; squat; stand
START_FRONT = (
    (0.25, {"shoulder_pitch": -0.3, "shoulder_roll": 0.0, "elbow_pitch": 0.0, "elbow_yaw": 0.0,
            "hip_pitch": 0.0, "hip_roll": 0.0, "knee": 0.0, "ankle_pitch": 0.0}),
    (0.2, {"shoulder_pitch": -3.0}),
    (0.3, {"shoulder_roll": -1.3}),
    (0.4, {"hip_pitch": -1.6, "knee": 2.2, "ankle_pitch": -0.87}),
    (0.4, {"shoulder_pitch": -1.7, "hip_pitch": -1.0, "knee": 1.6}),
    (0.2, {"shoulder_pitch": 0.5, "hip_pitch": 0.0, "knee": 1.6, "ankle_pitch": -0.87}),
    (0.3, {"hip_pitch": 0.0, "knee": 2.34}),
    (0.25, {"hip_pitch": -0.6, "knee": 1.9, "ankle_pitch": -0.87, "shoulder_pitch": -1.2}),
    (0.4, {"hip_pitch": -1.3, "knee": 2.2, "ankle_pitch": -0.87}),
    (1.0, _STAND),
)
#: hand-made start of the back search: legs tucked; hips thrown up (a bridge on shoulders and
#: feet, the weight over the feet); the torso raised by the hips onto the folded legs; up onto
#: the toes; squat; stand
START_BACK = (
    (0.4, {"shoulder_pitch": 0.0, "shoulder_roll": -1.3, "elbow_pitch": 0.0, "elbow_yaw": 0.0,
           "hip_pitch": -1.2, "hip_roll": 0.0, "knee": 2.34, "ankle_pitch": -0.87}),
    (0.4, {"hip_pitch": 0.8, "knee": 2.34, "ankle_pitch": -0.87}),
    (0.6, {"hip_pitch": 0.0, "knee": 2.34, "ankle_pitch": -0.87, "shoulder_pitch": -1.2}),
    (0.25, {"hip_pitch": -0.6, "knee": 1.9, "ankle_pitch": -0.87}),
    (0.4, {"hip_pitch": -1.3, "knee": 2.2, "ankle_pitch": -0.87}),
    (1.0, _STAND),
)
DURATION = (0.1, 0.9)
END_DURATION = (0.3, 1.5)
#: the falls the search sees (league_getup_trials.py reports on seeds 0-99)
TUNING_SEEDS = (1000, 1001)
HOLD_S = 2.0
#: a foot counts as on the ground with its ankle body below this (0.06 m standing flat; the
#: toes tucked under a kneeling robot hold it at ~0.1)
FOOT_DOWN_M = 0.12
STAND_HEIGHT_M = 0.62


def crouch(server) -> float:
    """How much the robot crouches over its feet (1: centre of mass >= 0.45 m, over them)."""
    data = server.sim.mj_data
    prefix = server._agents[(TEAM, UNUM)].agent_id.prefix
    com = data.subtree_com[server.sim.mj_model.body(prefix + "torso").id]
    left, right = (data.body(prefix + f"{s}_foot_link").xpos for s in ("left", "right"))
    return crouch_of(com, left, right)


def crouch_of(com, left, right) -> float:
    """``crouch`` from the centre of mass and the two foot bodies' positions (world)."""
    if max(left[2], right[2]) > FOOT_DOWN_M:  # weight over feet in the air is no crouch
        return 0.0
    d = float(np.hypot(*(com[:2] - (left[:2] + right[:2]) / 2)))
    return min(float(com[2]) / 0.45, 1.0) * math.exp(-max(d - 0.08, 0.0) / 0.1)


def trial_score(motion: GetUpMotion, side: str, seed: int, server) -> tuple[float, dict]:
    crouches = []
    r = getup_trial(motion, side, seed, hold_s=HOLD_S, server=server,
                    watch=lambda s: crouches.append(crouch(s)))
    n_motion = round(r.motion_s / 0.02)
    quality = np.clip(r.heights / STAND_HEIGHT_M, 0, 1) * np.clip(r.uprights, 0, 1)
    hold = quality[n_motion:]
    # a fall in the hold ends the recording early: count the missing cycles as 0
    hold_mean = float(hold.sum()) / round(HOLD_S / 0.02)
    score = max(crouches[:n_motion], default=0.0) + 2.0 * hold_mean
    if r.success:
        score += 2.0 + (5.0 - min(r.time_to_up, 5.0)) / 5.0
    return score, {"seed": seed, "up": r.up, "fell_after": r.fell_after,
                   "time_to_up": None if math.isnan(r.time_to_up) else round(r.time_to_up, 2),
                   "score": round(score, 3)}


def score(frames, side: str, server) -> tuple[float, list[dict]]:
    motion = GetUpMotion(front=frames, back=frames, attempts=1)
    rows = [trial_score(motion, side, seed, server) for seed in TUNING_SEEDS]
    return sum(s for s, _ in rows) / len(rows), [r for _, r in rows]


def encode(frames, fixed: int = 0) -> np.ndarray:
    """Keyframes -> the normalised search vector (the first ``fixed`` are not searched)."""
    u = []
    for dt, frame in frames[fixed:-1]:
        u.append((dt - DURATION[0]) / (DURATION[1] - DURATION[0]))
        for g in TUNED:
            lo, hi = BOX[g]
            u.append((frame.get(g, END_POSE[g]) - lo) / (hi - lo))
    u.append((frames[-1][0] - END_DURATION[0]) / (END_DURATION[1] - END_DURATION[0]))
    return np.clip(np.asarray(u), 0.0, 1.0)


def decode(u: np.ndarray, template, fixed: int = 0) -> list:
    """The search vector -> keyframes (groups not tuned, and the first ``fixed`` keyframes,
    as in ``template``)."""
    u = np.clip(u, 0.0, 1.0)
    frames, k = list(template[:fixed]), 0
    for _, frame in template[fixed:-1]:
        dt = DURATION[0] + u[k] * (DURATION[1] - DURATION[0])
        k += 1
        new = dict(frame)
        for g in TUNED:
            lo, hi = BOX[g]
            new[g] = round(float(lo + u[k] * (hi - lo)), 4)
            k += 1
        frames.append((round(float(dt), 4), new))
    frames.append((round(float(END_DURATION[0] + u[k] * (END_DURATION[1] - END_DURATION[0])),
                         4), dict(template[-1][1])))
    return frames


def load(path: str) -> list:
    with open(path, encoding="utf-8") as fh:
        return [(dt, f) for dt, f in json.load(fh)["keyframes"]]


def search(side: str, generations: int, popsize: int, seed: int, out: str | None,
           start: str | None, fixed: int) -> None:
    import cma

    template = load(start) if start else list(START_FRONT if side == "front" else START_BACK)
    server = trial_server()
    best, rows = score(template, side, server)
    best_frames = template
    print(f"start: {best:.3f} {rows}", flush=True)
    es = cma.CMAEvolutionStrategy(encode(template, fixed).tolist(), 0.15,
                                  {"bounds": [0.0, 1.0], "seed": seed + 1, "verbose": -9,
                                   "popsize": popsize})
    for g in range(generations):
        t0 = time.perf_counter()
        xs = es.ask()
        cands = [decode(np.asarray(x), template, fixed) for x in xs]
        scores = [score(c, side, server)[0] for c in cands]
        es.tell(xs, [-s for s in scores])
        i = int(np.argmax(scores))
        if scores[i] > best:
            best, best_frames = scores[i], cands[i]
            if out:
                with open(out, "w", encoding="utf-8") as fh:
                    json.dump({"side": side, "score": best, "keyframes": best_frames}, fh,
                              indent=1)
        print(f"gen {g:2d}: best of gen {scores[i]:.3f}, best {best:.3f} "
              f"({time.perf_counter() - t0:.0f} s)", flush=True)
    print(json.dumps(best_frames))
    print(score(best_frames, side, server)[1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--side", choices=("front", "back"), required=True)
    ap.add_argument("--check", action="store_true", help="score the module's keyframes")
    ap.add_argument("--keyframes", default=None,
                    help="start from / --check these (a JSON file as --out writes)")
    ap.add_argument("--fixed", type=int, default=0,
                    help="keep the first N keyframes as they are (search the rest)")
    ap.add_argument("--generations", type=int, default=30)
    ap.add_argument("--popsize", type=int, default=12)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=None, help="write the best keyframes (JSON) here")
    args = ap.parse_args()
    if args.check:
        frames = list(getup.FRONT if args.side == "front" else getup.BACK)
        if args.keyframes:
            frames = load(args.keyframes)
        total, rows = score(frames, args.side, trial_server())
        print(f"{args.side}: score {total:.3f}")
        for r in rows:
            print(" ", r)
        return
    search(args.side, args.generations, args.popsize, args.seed, args.out, args.keyframes,
           args.fixed)


if __name__ == "__main__":
    main()
