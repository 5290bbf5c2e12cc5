"""Our LIPM walker and the league's reference walking network on the same LocalServer trials.

Each trial beams one T1 to a start pose drawn from its seed (left team's half, any heading),
lets it stand 1 s with the controller's ``stand``, then walks one command for ``--seconds``
(6 s); achieved velocity = the mean body-frame velocity after the first 1.5 s of walking
(``locomotion.humanoid.envelope.achieved_velocity``); fall = the project's fall test
(``teamenv.league.falls.is_fallen``: torso tilted past 60 degrees or below 0.4 m).

Modes (each prints a table; the numbers are in docs/league.md):

    python benchmarks/league_walk_compare.py --compare            # both controllers, eval seeds
    python benchmarks/league_walk_compare.py --turn               # turn commands above 1 rad/s
    python benchmarks/league_walk_compare.py --envelope           # the network's limits (tuning seeds)
    python benchmarks/league_walk_compare.py --stand              # network at zero vs a held pose
    python benchmarks/league_walk_compare.py --curves --trials 8 --controllers network

``--compare``, ``--turn`` and ``--curves`` run each controller as a league match does (its envelope scales
the command), on seeds 1000+, 1500+ and 3000+ (never used to choose anything); ``--envelope`` runs the network
without its envelope on seeds 0+ and is what ``NETWORK_ENVELOPE`` was chosen from.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from locomotion.humanoid.envelope import achieved_velocity
from teamenv.league.controller import CYCLE_S, WalkerController
from teamenv.league.network_walk import (
    ACTION_SCALE,
    KD,
    KP,
    NETWORK_ENVELOPE,
    NETWORK_MOTORS,
    NOMINAL_POSE,
    TRAINING_SIGN,
    NetworkWalkController,
)
from teamenv.league.walk_trial import walk_trial

STAND_S = 1.0
SETTLE_S = 1.5
TUNING_SEED, EVALUATION_SEED = 0, 1000

CONTROLLERS = {
    "walker": WalkerController,
    "network": NetworkWalkController,
}


def _switching(t: float) -> tuple[float, float, float]:
    """A chase-like sequence: run, turn on the spot, curve back, stop."""
    if t < 1.5:
        return (1.0, 0.0, 0.0)
    if t < 2.5:
        return (0.0, 0.0, 1.0)
    if t < 4.0:
        return (0.6, 0.0, -0.6)
    return (0.0, 0.0, 0.0)


#: the comparison's commands (a match asks for up to its profile's speeds; the envelope scales)
COMPARE = {
    "forward 1.5": (1.5, 0.0, 0.0),
    "forward 0.5": (0.5, 0.0, 0.0),
    "backward 0.5": (-0.5, 0.0, 0.0),
    "sideways 0.3": (0.0, 0.3, 0.0),
    "turn 1.5": (0.0, 0.0, 1.5),
    "turn -1.0": (0.0, 0.0, -1.0),
    "curve 0.6/0.6": (0.6, 0.0, 0.6),
    "curve 0.6/-0.6": (0.6, 0.0, -0.6),
    "curve 1.0/0.8": (1.0, 0.0, 0.8),
    "in place": (0.0, 0.0, 0.0),
    "switching": _switching,
}
TURNS = {f"turn {w}": (0.0, 0.0, w) for w in (1.0, 1.2, 1.5, -1.5, 2.0)}
#: curves: forward speed x turn rate
CURVES = {f"curve {vx}/{w}": (vx, 0.0, w) for vx in (0.3, 0.6, 0.9)
          for w in (0.3, -0.3, 0.6, -0.6, 1.0, -1.0)}
#: per axis, commands of growing size for the network without its envelope
ENVELOPE_AXES = {
    "forward": [(v, 0.0, 0.0) for v in (1.0, 1.2, 1.4, 1.6, 1.8)],
    "backward": [(-v, 0.0, 0.0) for v in (0.5, 0.7, 1.0)],
    "sideways": [(0.0, s * v, 0.0) for v in (0.12, 0.15, 0.2, 0.3) for s in (1, -1)],
    "turn": [(0.0, 0.0, w) for w in (1.5, 2.0, 2.5)],
    # commands far outside in these directions, limited onto NETWORK_ENVELOPE's boundary
    "boundary": [NETWORK_ENVELOPE.limit((10.0 * a, 10.0 * b, 10.0 * c)) for a, b, c in (
        (1, 0, 1), (1, 0, -1), (1, 1, 0), (1, -1, 0), (-1, 0, 1), (0, 1, 1), (1, -1, 1))],
}


def start_pose(seed: int) -> tuple[float, float, float]:
    """A beam pose in the left team's half, away from the centre circle and the goal."""
    rng = np.random.default_rng(seed)
    return (float(rng.uniform(-20.0, -8.0)), float(rng.uniform(-12.0, 12.0)),
            float(rng.uniform(-math.pi, math.pi)))


def run(controller, spec, seed: int, seconds: float) -> dict:
    fn = spec if callable(spec) else (lambda t, c=spec: c)
    r = walk_trial(controller, fn, seconds, stand_s=STAND_S, start=start_pose(seed))
    v = achieved_velocity(r.times, r.poses, SETTLE_S) if not r.fell else np.full(3, np.nan)
    return {"fell": r.fell, "upright_s": r.upright_s, "v": v}


def table(specs: dict, controllers: dict, trials: int, seed0: int, seconds: float) -> None:
    print(f"{'trial':<15}{'controller':<10}{'falls':>7}   achieved vx, vy, turn (mean +- sd "
          "of the trials that stayed up)")
    for name, spec in specs.items():
        for cname, make in controllers.items():
            t0 = time.perf_counter()
            rows = [run(make(), spec, seed0 + k, seconds) for k in range(trials)]
            falls = sum(r["fell"] for r in rows)
            vs = np.array([r["v"] for r in rows if not r["fell"]]).reshape(-1, 3)
            ach = ("-" if not len(vs) else ", ".join(
                f"{m:+.2f}+-{s:.2f}" for m, s in zip(vs.mean(0), vs.std(0), strict=True)))
            print(f"{name:<15}{cname:<10}{falls:>3}/{trials:<3}   {ach}"
                  f"   ({time.perf_counter() - t0:.0f} s)", flush=True)


def envelope(trials: int, seconds: float) -> None:
    for axis, commands in ENVELOPE_AXES.items():
        for c in commands:
            rows = [run(NetworkWalkController(envelope=None), c, TUNING_SEED + k, seconds)
                    for k in range(trials)]
            falls = sum(r["fell"] for r in rows)
            vs = np.array([r["v"] for r in rows if not r["fell"]]).reshape(-1, 3)
            ach = "-" if not len(vs) else np.round(vs.mean(0), 2).tolist()
            print(f"  {axis:<9}{str(tuple(round(x, 3) for x in c)):<22} falls {falls}/{trials}  achieved {ach}", flush=True)


class HeldPose:
    """The network's nominal pose held with the network's gains (the alternative stand)."""

    def reset(self) -> None:
        pass

    def stand(self, perception) -> str:
        from teamenv.league import effectors

        q = NOMINAL_POSE * TRAINING_SIGN
        return effectors.message(*(effectors.motor(m, float(q[k]), 0.0, KP, KD)
                                   for k, m in enumerate(NETWORK_MOTORS)))

    step = lambda self, command, perception: self.stand(perception)  # noqa: E731


def stand(trials: int, seconds: float) -> None:
    assert ACTION_SCALE  # the held pose is the network's zero action
    for name, make in (("network, zero goal", NetworkWalkController), ("held nominal pose", HeldPose)):
        rows = [walk_trial(make(), lambda t: (0.0, 0.0, 0.0), seconds, stand_s=STAND_S,
                           start=start_pose(EVALUATION_SEED + k)) for k in range(trials)]
        drift = [float(np.hypot(*(r.poses[-1, :2] - r.poses[0, :2]))) for r in rows if not r.fell]
        print(f"  {name:<20} falls {sum(r.fell for r in rows)}/{trials}, first fall at "
              f"{min((r.upright_s for r in rows if r.fell), default=float('nan')):.1f} s, drift "
              f"{np.mean(drift) if drift else float('nan'):.2f} m in {seconds:.0f} s", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--compare", action="store_true")
    ap.add_argument("--turn", action="store_true")
    ap.add_argument("--envelope", action="store_true")
    ap.add_argument("--stand", action="store_true")
    ap.add_argument("--curves", action="store_true")
    ap.add_argument("--trials", type=int, default=5, help="start poses (seeds) per command")
    ap.add_argument("--seconds", type=float, default=6.0, help="walking time per trial")
    ap.add_argument("--controllers", default="walker,network")
    args = ap.parse_args()
    controllers = {k: CONTROLLERS[k] for k in args.controllers.split(",")}
    print(f"{args.trials} trials per command, {args.seconds:g} s walking, cycle {CYCLE_S} s")
    if args.compare:
        table(COMPARE, controllers, args.trials, EVALUATION_SEED, args.seconds)
    if args.turn:
        table(TURNS, controllers, args.trials, EVALUATION_SEED + 500, args.seconds)
    if args.curves:
        table(CURVES, controllers, args.trials, EVALUATION_SEED + 2000, args.seconds)
    if args.envelope:
        envelope(args.trials, args.seconds)
    if args.stand:
        stand(args.trials, 10.0)


if __name__ == "__main__":
    main()
