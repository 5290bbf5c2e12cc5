"""Search get-up keyframes fast: CMA-ES on ``FastPlant`` over many falls, then check on LocalServer.

``league_getup_tune.py`` scores a candidate on ``LocalServer`` (~1.2 s of CPU per 5 s get-up);
this script makes each tuning fall once on ``LocalServer`` (``getup_trial.fall``), keeps the
simulation's state, and scores every candidate from those states on ``FastPlant`` (the same
MuJoCo model and motor semantics without the protocol, ~0.1 s per get-up), so a search can
see many falls per candidate and many more candidates. The motion runs as ``GetUpMotion``
runs it (the front's arm check and its start-over included). The score per fall is the
tuner's (``league_getup_tune.trial_score``'s terms: best crouch during the motion, 2 x mean
standing quality in the ``--hold-s`` after it, success bonus 2 + (5 s - time to up) / 5 s)
plus the best leg support; a candidate's score is the mean over the falls. What stands the
robot after the motion (``--after``): by default the league's walk (``NetworkWalkController``
stepping on the spot, on ``LocalServer`` from the plant's state: ~0.35 s of CPU per 2 s), as
in a match and in ``league_getup_trials.py``; ``--after pose`` holds the end pose on the fast
plant (the searches before, which could not see a robot that stood and fell on the walk).
``--variants N`` scores every fall N times with the joints' velocities nudged (a robot that
comes up on the edge of balance stands or falls by chance). Candidates are the tuner's
keyframes (``encode`` / ``decode``: duration and the ``TUNED`` groups of every keyframe after
the first ``--fixed``, and the last keyframe's duration) plus each searched keyframe's
``damping`` (the kd scale, ``getup.DAMPING``, 0.05-2 on a log scale; the last keyframe's too
with ``--end-damping``). ``--upto K`` searches only the keyframes from ``--fixed`` to K - 1
(``--fixed 4 --upto 7``: the front's kneel and push-up, the rise kept as it is).

Every ``--check-every`` generations, and at the end, the best candidate is run on LocalServer
(``getup_trial``, with the same ``--after``) on the same falls: the success count there is
printed next to the fast one.

    nice -n 10 python benchmarks/league_getup_search.py --side front --fixed 4 \\
        --seeds 1000-1011 --generations 60 --popsize 16 --seed 1 --out front.json
    nice -n 19 python benchmarks/league_getup_search.py --side front --fixed 10 \\
        --end-damping --seeds 1006,1016,1063 --variants 3 --hold-s 1.0 --out rise.json
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

from teamenv.league import effectors, getup  # noqa: E402
from teamenv.league.controller import CYCLE_S  # noqa: E402
from teamenv.league.falls import is_fallen, torso_down  # noqa: E402
from teamenv.league.getup import DAMPING, UP_HEIGHT_M, GetUpMotion  # noqa: E402
from teamenv.league.getup_plant import FastPlant, motor_arrays  # noqa: E402
from teamenv.league.getup_trial import (  # noqa: E402
    TEAM,
    UNUM,
    fall,
    fall_setup,
    getup_trial,
    trial_server,
)
from teamenv.league.t1 import T1_MOTORS, joint_sensor  # noqa: E402

#: the kd scale's range (log scale in the search vector)
DAMPING_RANGE = (0.05, 2.0)


def parse_seeds(text: str) -> list[int]:
    """``N``, ``N-M`` or several of them joined by commas."""
    seeds = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        try:
            seeds += range(int(lo), int(hi or lo) + 1)
        except ValueError:
            raise SystemExit(f"--seeds: {text!r} is not N, N-M or a list of them") from None
    return seeds


def make_falls(side: str, seeds: list[int], server,
               variants: int = 1) -> tuple[FastPlant, list]:
    """The plant of ``server`` and (perception, snapshot, the server's random state) of each
    seed's fall, made on it. The random state (``LocalServer``'s own generator) is put back at
    every hand-over to the walk, so that a fall's walk sees the same state whatever ran
    before. ``variants`` > 1: each fall that many times, all but the first with the joints'
    velocities nudged (normal, ``VARIANT_RAD_S``): a get-up that comes up on the edge of
    balance falls or stands by chance (the same fall made after another trial on the same
    server, whose ball lies a little differently, can end either way), so each fall is
    scored over a few such draws."""
    plant = FastPlant(server)
    rng = np.random.default_rng(12345)
    out = []
    for seed in seeds:
        p = fall(server, fall_setup(side, seed))
        snap = plant.snapshot()
        out.append((p, snap, server._np_state))
        for _ in range(variants - 1):
            plant.restore(snap)
            plant.data.qvel[plant._dadr] += rng.normal(0.0, VARIANT_RAD_S, len(plant._dadr))
            plant._mujoco.mj_forward(plant.model, plant.data)
            out.append((p, plant.snapshot(), server._np_state))
    return plant, out


#: the joint velocity nudge (rad/s, s.d.) of a fall's variants
VARIANT_RAD_S = 1e-3


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


class _Joints:
    """The measured joints the motion reads (``perception.joints``): the plant's ``q``."""

    def __init__(self, motors: tuple[str, ...], q: np.ndarray) -> None:
        self.joints = {joint_sensor(m): _Angle(float(a)) for m, a in zip(motors, q,
                                                                          strict=True)}


class _Angle:
    __slots__ = ("angle",)

    def __init__(self, angle: float) -> None:
        self.angle = angle


def _motion_step(motion: GetUpMotion, seen: _Joints) -> tuple[dict, dict]:
    """``motion.step`` without the message: the arm check (on the joints ``seen``, the state
    the step's perception shows), the clock, this cycle's targets and gains."""
    if motion._arms_stuck(seen):
        motion._plan_from(seen, motion.arms_retry + motion.front[1:])
        motion._offset, motion.arms_retried = motion._t, True
    motion._t += CYCLE_S
    return motion.command_at(motion._t - motion._offset)


def run_fast(motion: GetUpMotion, plant: FastPlant, p, snap, walk=None,
             hold_s: float = HOLD_S, np_state=None) -> dict:
    """One get-up from a saved fall on the fast plant: the tuner's score terms.

    The motion runs as ``GetUpMotion.step`` runs it (the front's arm check included) until it
    is done; then for ``hold_s`` either the end pose is held on the fast plant (``walk``
    None) or, as a match and ``league_getup_trials.py`` do it, ``walk`` (a
    ``NetworkWalkController``, reset at the hand-over) stands the robot on ``LocalServer``
    from the plant's state (the motion's last command still pending, as the server's delay
    has it), with perceptions as the server makes them (its random state ``np_state`` if
    given). A robot that is not up when the
    motion is done holds the end pose either way (it has failed; the hold only shapes the
    score)."""
    plant.restore(snap)
    motion.start(p)
    n_hold = round(hold_s / CYCLE_S)
    crouches, supports, quality, ups = [], [], [], []
    last = [None]
    # the step after cycle k sees the state after cycle k (its perception), and the plant
    # calls the policy after the physics of the next cycle: keep the joints one cycle
    seen = [plant.joints()]

    def policy(k, pl):
        last[0] = _motion_step(motion, _Joints(pl.motors, seen[0]))
        return motor_arrays(*last[0], pl.motors)

    def watch(k, pl):
        pos, quat = pl.torso()
        left, right = pl.feet()
        crouches.append(crouch_of(pl.com(), left, right))
        supports.append(leg_support(pl))
        ups.append(not torso_down(quat, pos[2]) and pos[2] >= UP_HEIGHT_M)
        seen[0] = pl.joints()
        return motion._t >= motion.duration - 1e-9

    plant.run(policy, round(10.0 / CYCLE_S), watch)
    up = bool(ups and ups[-1])
    fell = False
    if up and walk is not None:
        fell = _walk_hold(plant, last[0], walk, quality, n_hold, np_state)
    else:
        def hold_policy(k, pl):
            pose, gains = motion.command_at(motion._t - motion._offset + (k + 1) * CYCLE_S)
            return motor_arrays(pose, gains, pl.motors)

        def hold_watch(k, pl):
            nonlocal fell
            pos, quat = pl.torso()
            up_z = 1.0 - 2.0 * (quat[1] ** 2 + quat[2] ** 2)
            quality.append(min(pos[2] / STAND_HEIGHT_M, 1.0) * max(up_z, 0.0))
            if torso_down(quat, pos[2]):
                fell = True
                return True
            return False

        # the motion's last command is the plant's pending one: apply it first
        plant.command(*motor_arrays(*last[0], plant.motors))
        plant.run(hold_policy, n_hold, hold_watch)
    t_up = math.nan
    if up:
        k = len(ups) - 1
        while k > 0 and ups[k - 1]:
            k -= 1
        t_up = k * CYCLE_S  # the cycle index of the first up cycle of the last run of ups
    success = up and not fell
    score = (max(crouches, default=0.0) + max(supports, default=0.0)
             + 2.0 * sum(quality) / n_hold)
    if success:
        score += 2.0 + (5.0 - min(t_up, 5.0)) / 5.0
    return {"score": score, "success": success, "up": up, "fell_after": fell,
            "time_to_up": t_up, "support": max(supports, default=0.0),
            "crouch": max(crouches, default=0.0)}


def _walk_hold(plant: FastPlant, last: tuple, walk, quality: list, n_hold: int,
               np_state=None) -> bool:
    """``n_hold`` cycles on ``LocalServer`` (the plant's server, in the plant's state) with ``walk``
    standing the robot, the motion's last command ``last`` (targets, gains) pending; appends
    each cycle's standing quality to ``quality``; returns whether the robot fell."""
    server = plant.server
    if np_state is not None:
        server._np_state = np_state
    key = (TEAM, UNUM)
    agent = server._agents[key]
    pose, gains = last
    text = effectors.message(*(effectors.motor(m, pose[m], 0.0, *gains[m]) for m in T1_MOTORS))
    server._pending = {key: server._parser.parse_action(text.encode("ascii"),
                                                        agent.agent_id.prefix)}
    p = server._generate([key])[key]
    walk.reset()
    for _ in range(n_hold):
        p = server.cycle({key: walk.stand(p)})[key]
        _, x, y, _ = p.orientations["torso_quat"]
        quality.append(min(p.positions["torso_pos"][2] / STAND_HEIGHT_M, 1.0)
                       * max(1.0 - 2.0 * (x * x + y * y), 0.0))
        if is_fallen(p):
            return True
    return False


def with_damping(frames: list, u_damp: np.ndarray, fixed: int, end: bool = False) -> list:
    """``frames`` with the searched keyframes' damping from ``u_damp`` (the last keyframe's
    too with ``end``, else 1)."""
    out = list(frames[:fixed])
    lo, hi = DAMPING_RANGE

    def scale(u: float) -> float:
        return round(float(lo * (hi / lo) ** float(np.clip(u, 0, 1))), 4)

    for (dt, frame), u in zip(frames[fixed:-1], u_damp[:len(frames) - 1 - fixed], strict=True):
        out.append((dt, {**frame, DAMPING: scale(u)}))
    last_dt, last = frames[-1]
    out.append((last_dt, {**last, DAMPING: scale(u_damp[-1]) if end else 1.0}))
    return out


def damping_u(frames: list, fixed: int, end: bool = False) -> np.ndarray:
    lo, hi = DAMPING_RANGE
    searched = frames[fixed:] if end else frames[fixed:-1]
    return np.array([math.log(f.get(DAMPING, 1.0) / lo) / math.log(hi / lo)
                     for _, f in searched])


def motion_of(frames, side: str) -> GetUpMotion:
    """The motion of a candidate, one run (the front with the arm check's retry, as
    ``GetUpMotion`` runs ``getup.FRONT``)."""
    retry = getup.FRONT_ARMS_RETRY if side == "front" else None
    return GetUpMotion(front=frames, back=frames, attempts=1, arms_retry=retry)


def evaluate(frames, side, plant, falls, walk=None,
             hold_s: float = HOLD_S) -> tuple[float, int, list]:
    motion = motion_of(frames, side)
    rows = [run_fast(motion, plant, p, snap, walk, hold_s, rng) for p, snap, rng in falls]
    return (float(np.mean([r["score"] for r in rows])), sum(r["success"] for r in rows), rows)


def check_local(frames, side, seeds, after: str = "network") -> tuple[int, list]:
    from teamenv.league.network_walk import NetworkWalkController

    server = trial_server()
    rs = [getup_trial(motion_of(frames, side), side, seed, hold_s=HOLD_S, server=server,
                      after=NetworkWalkController() if after == "network" else None)
          for seed in seeds]
    return sum(r.success for r in rs), [None if math.isnan(r.time_to_up) else
                                        round(r.time_to_up, 2) for r in rs]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--side", choices=("front", "back"), required=True)
    ap.add_argument("--seeds", default="1000-1011",
                    help="tuning falls, N-M (or N-M,K-L,...)")
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
    ap.add_argument("--after", choices=("network", "pose"), default="network",
                    help="what stands the robot in the 2 s after the motion in the score: the "
                         "league's walk, as in a match and the trials (default), or the end "
                         "pose held on the fast plant (the searches before)")
    ap.add_argument("--hold-s", type=float, default=HOLD_S,
                    help="seconds after the motion in the score (default 2, as the trials; "
                         "shorter is cheaper with the walk)")
    ap.add_argument("--variants", type=int, default=1,
                    help="score each fall this many times, nudged (make_falls; default 1)")
    ap.add_argument("--end-damping", action="store_true",
                    help="search the last keyframe's damping too (default: 1, the walker's kd)")
    ap.add_argument("--upto", type=int, default=None,
                    help="search only the keyframes before this index (from --fixed on; the "
                         "later ones, the last included, kept as they are); default: all")
    args = ap.parse_args()
    import cma

    from teamenv.league.network_walk import NetworkWalkController

    walk = NetworkWalkController() if args.after == "network" else None

    seeds = parse_seeds(args.seeds)
    if args.keyframes:
        template = load(args.keyframes)
    elif args.start == "hand":
        template = list(START_FRONT if args.side == "front" else START_BACK)
    else:
        template = list(getup.FRONT if args.side == "front" else getup.BACK)
    if args.upto is not None and (not args.fixed < args.upto < len(template) - 1
                                  or args.end_damping):
        raise SystemExit("--upto: between --fixed and the last keyframe, no --end-damping")
    server = trial_server()
    plant, falls = make_falls(args.side, seeds, server, args.variants)
    best, n_ok, _ = evaluate(template, args.side, plant, falls, walk, args.hold_s)
    best_frames = template
    print(f"start: {best:.3f}, {n_ok}/{len(falls)} up (fast)", flush=True)
    if args.upto is not None:
        # the searched part as a template of its own: its keyframes, then the next as its last
        # (whose duration is left out of the search vector)
        part = list(template[:args.upto + 1])
        x0 = np.concatenate([encode(part, args.fixed)[:-1], damping_u(part, args.fixed)])
        n_key = args.upto - args.fixed
    else:
        x0 = np.concatenate([encode(template, args.fixed),
                             damping_u(template, args.fixed, args.end_damping)])
        n_key = len(template) - 1 - args.fixed + (1 if args.end_damping else 0)
    es = cma.CMAEvolutionStrategy(np.clip(x0, 0, 1).tolist(), args.sigma,
                                  {"bounds": [0.0, 1.0], "seed": args.seed + 1, "verbose": -9,
                                   "popsize": args.popsize})

    def build(x):
        x = np.asarray(x)
        if args.upto is not None:
            frames = decode(np.append(x[:-n_key], 0.0), part, args.fixed)
            frames = with_damping(frames, np.append(x[-n_key:], 0.0), args.fixed)
            return frames[:-1] + list(template[args.upto:])
        frames = decode(x[:-n_key], template, args.fixed)
        return with_damping(frames, x[-n_key:], args.fixed, args.end_damping)

    for g in range(args.generations):
        t0 = time.perf_counter()
        xs = es.ask()
        cands = [build(x) for x in xs]
        results = [evaluate(c, args.side, plant, falls, walk, args.hold_s) for c in cands]
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
            ok, times = check_local(best_frames, args.side, seeds, args.after)
            print(f"  LocalServer: {ok}/{len(seeds)} up, times {times}", flush=True)
    print(json.dumps(best_frames))
    ok, times = check_local(best_frames, args.side, seeds, args.after)
    print(f"LocalServer: {ok}/{len(seeds)} up, times {times}")


if __name__ == "__main__":
    main()
