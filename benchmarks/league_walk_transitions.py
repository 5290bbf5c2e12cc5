"""Does the league's walking network fall when the walk request changes abruptly?

    python benchmarks/league_walk_transitions.py                 # every schedule, 5 start poses
    python benchmarks/league_walk_transitions.py stop-abrupt stop-0.6s --json out.json

One T1 on ``LocalServer`` (``teamenv.league.walk_trial``) walks a command schedule with the
reference walking network (``NetworkWalkController``): 2 s forward at 1.2 m/s, then a change —
an abrupt stop, a stop spread over 0.6-2.4 s, turning on the spot at once or after slowing
down, turning on the spot with the direction flipped every 0.3 s — from five start poses;
prints, per schedule, how many of the runs fell and when (seconds since walking began).
The steady walks and forward-speed swings (``STEADY_AND_SWINGS``, run with ``--seconds 20``)
ask what in the teams' requests fells a robot walking alone::

    python benchmarks/league_walk_transitions.py --seconds 20 steady-forward-1.2 \
        swing-1.2-0.4-1s swing-1.2-0.4-1s-ramp-1 swing-1.2-0.4-1s-lowpass-0.5
These are the requests a team makes in a match when its target or the ball passes behind a
robot running at full speed; ``teamenv.league.command_ramp`` spreads them out.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from league_walk_playback import LowPass  # noqa: E402  (the sibling script)

Command = tuple[float, float, float]
RUN_S, FAST = 2.0, 1.2
STARTS = ((-5.0, 0.0, 0.0), (-4.0, 1.0, 0.7), (-6.0, -1.0, -0.7), (-5.0, 2.0, 1.5),
          (-3.0, -2.0, 3.0))


def _after_run(then: Callable[[float], Command], slow_s: float = 0.0) -> Callable[[float],
                                                                                   Command]:
    """2 s at full speed, slowing down linearly over ``slow_s``, then ``then(t)``."""

    def schedule(t: float) -> Command:
        if t < RUN_S:
            return (FAST, 0.0, 0.0)
        if t < RUN_S + slow_s:
            return (FAST * (1.0 - (t - RUN_S) / slow_s), 0.0, 0.0)
        return then(t)

    return schedule


def _flip(rate: float) -> Callable[[float], Command]:
    return lambda t: (0.0, 0.0, rate if int(t / 0.3) % 2 == 0 else -rate)


def _swing(high: float, low: float, period_s: float) -> Callable[[float], Command]:
    """Forward at ``high`` and ``low`` m/s by turns, ``period_s`` each."""
    return lambda t: (high if int(t / period_s) % 2 == 0 else low, 0.0, 0.0)


def _filtered(schedule: Callable[[float], Command], kind: str, value: float
              ) -> Callable[[float], Command]:
    """``schedule``'s forward speed through a rate limit (``kind`` "ramp": ``CommandRamp`` at
    ``value`` m/s^2) or a first-order low-pass filter ("lowpass": time constant ``value`` s,
    ``league_walk_playback.LowPass``); restarts at t = 0."""
    from teamenv.league.command_ramp import CommandRamp

    state: list = [None]

    def filtered(t: float) -> Command:
        if t == 0.0:
            state[0] = CommandRamp((value, value, value)) if kind == "ramp" else LowPass(value)
        want = (schedule(t)[0], 0.0, 0.0)
        if kind == "ramp":
            return state[0](want)
        return (state[0](want[0]), 0.0, 0.0)

    return filtered


def _limited(command: Command) -> Callable[[float], Command]:
    """A steady ``command`` scaled into the network's envelope, as matches walk it."""
    from teamenv.league.network_walk import NETWORK_ENVELOPE

    limited = NETWORK_ENVELOPE.limit(command)
    return lambda t: limited


#: steady walks and swings of the forward speed (run with --seconds 20): what in the teams'
#: requests fells a robot walking alone (benchmarks/league_walk_playback.py)
STEADY_AND_SWINGS: dict[str, Callable[[float], Command]] = {
    "steady-forward-1.2": lambda t: (1.2, 0.0, 0.0),
    "steady-turn-1.0": lambda t: (0.0, 0.0, 1.0),
    "steady-fast-curve": _limited((1.2, 0.0, 1.5)),
    "steady-back-sideways": _limited((-0.5, 0.1, 0.0)),
    "steady-spin-walking": _limited((0.5, 0.0, 1.8)),
    "turn-swing-1.0-0.4s": lambda t: (1.2, 0.0, 1.0 if int(t / 0.4) % 2 else -1.0),
    "swing-1.2-0.4-1s": _swing(1.2, 0.4, 1.0),
    "swing-1.2-0.4-2s": _swing(1.2, 0.4, 2.0),
    "swing-1.2-0.8-1s": _swing(1.2, 0.8, 1.0),
    "swing-0.8-0.0-1s": _swing(0.8, 0.0, 1.0),
    "swing-0.9-0.2-1s": _swing(0.9, 0.2, 1.0),
    "swing-1.0-0.3-1s": _swing(1.0, 0.3, 1.0),
    "swing-1.2-0.4-1s-ramp-1": _filtered(_swing(1.2, 0.4, 1.0), "ramp", 1.0),
    "swing-1.2-0.4-1s-ramp-2": _filtered(_swing(1.2, 0.4, 1.0), "ramp", 2.0),
    "swing-1.2-0.4-1s-lowpass-0.5": _filtered(_swing(1.2, 0.4, 1.0), "lowpass", 0.5),
}

SCHEDULES: dict[str, Callable[[float], Command]] = {
    "stop-abrupt": _after_run(lambda t: (0.0, 0.0, 0.0)),
    "stop-0.6s": _after_run(lambda t: (0.0, 0.0, 0.0), 0.6),
    "stop-1.2s": _after_run(lambda t: (0.0, 0.0, 0.0), 1.2),
    "stop-2.4s": _after_run(lambda t: (0.0, 0.0, 0.0), 2.4),
    "turn-1.5-abrupt": _after_run(lambda t: (0.0, 0.0, -1.5)),
    "turn-1.0-abrupt": _after_run(lambda t: (0.0, 0.0, -1.0)),
    "turn-0.7-abrupt": _after_run(lambda t: (0.0, 0.0, -0.7)),
    "turn-1.5-after-1.2s": _after_run(lambda t: (0.0, 0.0, -1.5), 1.2),
    "flip-1.5-standing": _flip(1.5),
    "flip-1.5-abrupt": _after_run(_flip(1.5)),
    **STEADY_AND_SWINGS,
}


def run(names: list[str], seconds: float = 6.0) -> dict[str, list[float | None]]:
    from teamenv.league.network_walk import NetworkWalkController
    from teamenv.league.walk_trial import walk_trial

    out = {}
    for name in names:
        falls = []
        for start in STARTS:
            trial = walk_trial(NetworkWalkController(), SCHEDULES[name], seconds=seconds,
                               start=start)
            falls.append(round(trial.upright_s, 2) if trial.fell else None)
        out[name] = falls
        print(f"{name:20s} falls {sum(f is not None for f in falls)}/{len(falls)}  at {falls}",
              flush=True)
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("schedules", nargs="*", help=f"default all: {', '.join(SCHEDULES)}")
    parser.add_argument("--seconds", type=float, default=6.0)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    unknown = [n for n in args.schedules if n not in SCHEDULES]
    if unknown:
        parser.error(f"unknown schedule(s) {unknown}; known: {', '.join(SCHEDULES)}")
    result = run(args.schedules or list(SCHEDULES), args.seconds)
    if args.json:
        args.json.write_text(json.dumps({"starts": STARTS, "falls_at_s": result}, indent=1) + "\n")


if __name__ == "__main__":
    main()
