"""Walk the commands teams asked for in league matches again, on a lone robot, through
different command limiters: which falls are the walk's own, and which limiter avoids them?

    python benchmarks/league_falls.py --seeds 420:424 --seconds 40 --ramp off \\
        --commands commands.json                       # record what the teams asked for
    python benchmarks/league_walk_playback.py commands.json                 # every limiter
    python benchmarks/league_walk_playback.py commands.json --limiters envelope ramp \\
        --json playback.json

A fall in a 7 v 7 has two candidate causes, the crowd (contact) and the commands themselves
(the reference network falls when a run at full speed is cut short, see
``league_walk_transitions.py``). Here every stretch of at least ``--min-seconds`` in which a
robot walked the team's command (the encoder's ``walk`` state in ``league_falls.py
--commands``) is walked again by one robot alone on ``LocalServer`` with the league's walk
(``NetworkWalkController``), so only the commands can fell it. Each limiter turns the
requests into what the network walks:

- ``envelope``: the network's envelope only (``NETWORK_ENVELOPE.limit``: the command scaled
  into the ellipsoid; what matches do now);
- ``ramp``: then ``CommandRamp`` at the ``t1_league`` profile's accelerations (the env's
  bodies' limits; ``LeagueMatchOptions(ramp=True)``);
- ``brake``: then ``CommandRamp`` at the kick hand-over's braking rates
  (``teamenv.league.handover``: 2.5 m/s^2 forward and sideways, 3 rad/s^2);
- ``clamp``: each component clamped to its own limit instead of the ellipsoid's common scale
  (a sideways part no longer slows the forward walk);
- ``clamp+brake``: both;
- ``sideV``: the sideways request capped at V m/s before the envelope (0.06, 0: the network
  barely steps sideways below 0.1 m/s; a large sideways request no longer scales the forward
  walk and the turn down, and the robot no longer walks at the envelope's sideways edge);
- ``forwardV``: the forward request capped at V m/s (0.9: a forward speed swinging between
  1.2 and 0.4 m/s fells the network, between 0.8 and 0 it does not), ``forwardV+sideW`` both;
- ``lowpassT``: the envelope, then the forward speed through a first-order low-pass filter of
  time constant T s (0.5, 1): a forward speed that swings by ~0.8 m/s every second or two
  fells the network even when each swing is ramped, see docs/league.md "Falls".

Prints, per limiter, the stretches walked, the falls and falls per minute of walking, and
the stretches that fell under one limiter but not another (paired: the same commands).
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import re
import time
from collections.abc import Callable
from pathlib import Path

Command = tuple[float, float, float]
LIMITERS = ("envelope", "ramp", "brake", "clamp", "clamp+brake", "lowpass0.5", "lowpass1",
            "side0.06", "side0", "forward0.9", "forward0.9+side0.06")


def stretches(path: Path, min_s: float, cycle_s: float) -> list[dict]:
    """Every run of ``walk`` cycles of at least ``min_s`` in a ``--commands`` file."""
    out = []
    for match in json.loads(Path(path).read_text())["matches"]:
        for agent, rows in match["commands"].items():
            start = None
            for i, row in enumerate([*rows, ["end", 0.0, 0.0, 0.0]]):
                if row[0] == "walk":
                    start = i if start is None else start
                    continue
                if start is not None and (i - start) * cycle_s >= min_s:
                    out.append({"seed": match["seed"], "agent": agent, "first": start,
                                "commands": [tuple(r[1:]) for r in rows[start:i]]})
                start = None
    return out


class LowPass:
    """A first-order low-pass filter of time constant ``tau_s``, one value per cycle, from 0."""

    def __init__(self, tau_s: float) -> None:
        from teamenv.league.controller import CYCLE_S

        self.gain = min(1.0, CYCLE_S / tau_s)
        self.value = 0.0

    def __call__(self, target: float) -> float:
        self.value += (target - self.value) * self.gain
        return self.value


def limiter(name: str) -> Callable[[Command], Command]:
    """A fresh limiter (it keeps state: the ramps)."""
    from locomotion import load_profile
    from teamenv.league.command_ramp import CommandRamp
    from teamenv.league.handover import BRAKE_M_S2, BRAKE_TURN_S2
    from teamenv.league.match import LOCOMOTION_PROFILE
    from teamenv.league.network_walk import NETWORK_ENVELOPE

    env = NETWORK_ENVELOPE

    def clamp(c: Command) -> Command:
        vx = min(max(c[0], -env.vx_backward), env.vx_forward)
        return (vx, min(max(c[1], -env.vy), env.vy), min(max(c[2], -env.turn), env.turn))

    shape = clamp if name.startswith("clamp") else env.limit
    if name.startswith(("side", "forward")):
        caps = {axis: float(value) for axis, value in
                (re.fullmatch(r"([a-z]+)([0-9.]+)", part).groups() for part in name.split("+"))}
        side, forward = caps.get("side", math.inf), caps.get("forward", math.inf)
        return lambda c: env.limit((min(c[0], forward), min(max(c[1], -side), side), c[2]))
    if name.startswith("lowpass"):
        forward = LowPass(float(name[len("lowpass"):]))

        def lowpass(c: Command) -> Command:
            c = env.limit(c)
            return (forward(c[0]), c[1], c[2])

        return lowpass
    ramp = None
    if name == "ramp":
        ramp = CommandRamp.from_profile(load_profile(LOCOMOTION_PROFILE))
    elif name.endswith("brake"):
        ramp = CommandRamp((BRAKE_M_S2, BRAKE_M_S2, BRAKE_TURN_S2))
    if ramp is None:
        return shape
    return lambda c: ramp(shape(c))


def play(stretch: dict, name: str, cycle_s: float) -> dict:
    from teamenv.field import field_preset
    from teamenv.league.match import FIELD
    from teamenv.league.network_walk import NetworkWalkController
    from teamenv.league.walk_trial import walk_trial

    commands = stretch["commands"]
    limit = limiter(name)
    # the network envelope stays on inside the controller: the limiter's output is inside it
    controller = NetworkWalkController(envelope=None)
    trial = walk_trial(controller, lambda t: limit(commands[min(round(t / cycle_s),
                                                                 len(commands) - 1)]),
                       seconds=len(commands) * cycle_s)
    # walked open loop, a long stretch can leave the pitch (into a goal, over the boundary):
    # such a fall is the playback's, not the walk's
    field = field_preset(FIELD)
    x, y = (abs(float(v)) for v in trial.poses[-1, :2])
    off = x > field.length / 2 or y > field.width / 2
    return {"fell": bool(trial.fell) and not off, "off_field": bool(off),
            "walked_s": round(float(trial.upright_s), 2)}


def main(argv: list[str] | None = None) -> None:
    from teamenv.league.controller import CYCLE_S

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("commands", nargs="+", type=Path, help="league_falls.py --commands files")
    parser.add_argument("--limiters", nargs="+", choices=LIMITERS, default=list(LIMITERS))
    parser.add_argument("--min-seconds", type=float, default=3.0)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    runs = [s for path in args.commands for s in stretches(path, args.min_seconds, CYCLE_S)]
    print(f"{len(runs)} stretches of >= {args.min_seconds:g} s, "
          f"{sum(len(r['commands']) for r in runs) * CYCLE_S / 60:.1f} min of walking", flush=True)
    results: dict[str, list[dict]] = {}
    for name in args.limiters:
        t0 = time.perf_counter()
        results[name] = [play(r, name, CYCLE_S) for r in runs]
        falls = sum(r["fell"] for r in results[name])
        off = sum(r["off_field"] for r in results[name])
        minutes = sum(r["walked_s"] for r in results[name]) / 60
        print(f"{name:12s} falls {falls:3d} of {len(runs)} stretches ({off} left the pitch), "
              f"{falls / max(minutes, 1e-9):.2f} per minute walked "
              f"({time.perf_counter() - t0:.0f} s)", flush=True)
    from scipy.stats import binomtest

    for a, b in itertools.combinations(sorted(results), 2):
        pairs = list(zip(results[a], results[b], strict=True))
        only_a = sum(x["fell"] and not y["fell"] for x, y in pairs)
        only_b = sum(y["fell"] and not x["fell"] for x, y in pairs)
        n = only_a + only_b
        p = binomtest(only_a, n).pvalue if n else 1.0    # the sign test
        print(f"  {a} only {only_a}, {b} only {only_b} (sign test p = {p:.3f})")
    if args.json:
        args.json.write_text(json.dumps({"stretches": [
            {k: v for k, v in r.items() if k != "commands"} for r in runs],
            "results": results}, indent=1) + "\n")


if __name__ == "__main__":
    main()
