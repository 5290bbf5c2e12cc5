"""Walk commands that change no faster than the body can: the league client's command ramp.

A team asks for a new walk every cycle, and its requests jump: from full speed ahead to
turning on the spot, from turning one way to the other, as the target or the ball moves
behind the robot. In a 40 s 7 v 7 on ``LocalServer`` (full v chaser, seed 100201, no ramp)
several of the 10 falls came within a second of such a jump with nobody within 1 m, while in
the env the same team's bodies change velocity no faster than the locomotion profile's
accelerations (``accel_vx``, ``accel_vy``, ``accel_turn``: ``locomotion.bodies``).

``CommandRamp`` gives the league robots the same limits: each cycle every component of the
command moves towards the request by at most the profile's acceleration times the cycle. It
reads the accelerations from the locomotion profile the teams plan with (``from_profile``), so
both worlds take them from one place.

Measured, it does **not** reduce falls (``benchmarks/league_falls.py``; docs/league.md,
"Falls"), so league matches run without it unless asked (``LeagueMatchOptions.ramp``,
``teamenv league-match --ramp``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from .controller import CYCLE_S
from .errors import LeagueError

Command = tuple[float, float, float]


class CommandRamp:
    """Limits a walk command's change per cycle to ``accel`` (m/s^2, m/s^2, rad/s^2) times
    ``cycle_s``; ``command`` is the last command given out (the robot's walk now)."""

    def __init__(self, accel: Sequence[float], cycle_s: float = CYCLE_S) -> None:
        values = tuple(float(a) for a in accel)
        if len(values) != 3 or not all(math.isfinite(a) and a > 0 for a in values):
            raise LeagueError(f"CommandRamp: accel must be 3 finite values > 0 (vx m/s^2, "
                              f"vy m/s^2, turn rad/s^2), got {tuple(accel)!r}")
        if not (math.isfinite(cycle_s) and cycle_s > 0):
            raise LeagueError(f"CommandRamp: cycle_s must be finite and > 0, got {cycle_s!r}")
        self.accel = values
        self.cycle_s = float(cycle_s)
        self._step = tuple(a * self.cycle_s for a in values)
        self.command: Command = (0.0, 0.0, 0.0)

    @classmethod
    def from_profile(cls, profile, cycle_s: float = CYCLE_S) -> CommandRamp:
        """The ramp of a locomotion profile's body (``locomotion.profile.Profile.accel``)."""
        return cls(tuple(float(a) for a in profile.accel), cycle_s)

    def reset(self, command: Command = (0.0, 0.0, 0.0)) -> None:
        """The robot now walks ``command`` (standing after a beam, a kick or a get-up)."""
        self.command = tuple(float(c) for c in command)

    def __call__(self, request: Sequence[float]) -> Command:
        """This cycle's command on the way to ``request`` (vx, vy, turn)."""
        if len(request) != 3:
            raise LeagueError(f"CommandRamp: a walk request is (vx, vy, turn), got {tuple(request)!r}")
        out = []
        for now, want, step in zip(self.command, request, self._step, strict=True):
            want = float(want)
            if not math.isfinite(want):
                raise LeagueError(f"CommandRamp: walk request {tuple(request)!r} is not finite")
            out.append(now + min(max(want - now, -step), step))
        self.command = (out[0], out[1], out[2])
        return self.command
