"""The hand-over of a kick's approach from the robot's walk controller to the kick's walker.

The kick is a step of our LIPM walker's gait (``teamenv.league.kick``), so with another walk
controller (the league's reference network, the default) the kick's own walker takes over the
approach near the ball. That walker starts its gait from rest: taking over a robot that still
walks at the speed the team asked for fells it (in a LocalServer 1 v 1 of the chaser, 6 of 8
hand-overs at 0.5-0.7 m/s ended in a fall within 2.5 s), while a walk slowed down over half a
second stays up (``benchmarks/league_walk_transitions.py``). So near the ball the controller
first brakes towards the approach's own command, and the kick's walker takes over once the
torso has slowed down (or after ``HANDOVER_MAX_S``, so a robot that cannot slow down still
kicks).
"""

from __future__ import annotations

import math
from collections import deque

from .command_ramp import CommandRamp
from .controller import CYCLE_S
from .perception import Perception

#: the kick's walker takes over below this torso speed (m/s, over ``SPEED_WINDOW_S``): the
#: approach itself walks at most 0.3 m/s
HANDOVER_SPEED_M_S = 0.3
#: the torso sways sideways with every step; its mean speed over about one gait cycle is the walk's
SPEED_WINDOW_S = 0.5
#: how fast the braking command may change (m/s and rad/s per second)
BRAKE_M_S2 = 2.5
BRAKE_TURN_S2 = 3.0
#: hand over anyway after this long (s) of braking
HANDOVER_MAX_S = 1.5


class TorsoSpeed:
    """The torso's mean planar speed over the last ``SPEED_WINDOW_S`` (inf until known)."""

    def __init__(self) -> None:
        self._places: deque[tuple[float, float]] = deque(
            maxlen=round(SPEED_WINDOW_S / CYCLE_S) + 1)

    def reset(self) -> None:
        self._places.clear()

    def update(self, perception: Perception) -> None:
        pos = perception.positions.get("torso_pos")
        if pos is None:
            self._places.clear()
        else:
            self._places.append((float(pos[0]), float(pos[1])))

    @property
    def speed(self) -> float:
        if len(self._places) < self._places.maxlen:
            return math.inf
        (x0, y0), (x1, y1) = self._places[0], self._places[-1]
        return math.hypot(x1 - x0, y1 - y0) / ((len(self._places) - 1) * CYCLE_S)


class HandOver:
    """Braking before the kick's walker takes the approach over from the walk controller.

    ``brake(target)`` is the controller's command this cycle (from the last command it walked
    towards the approach's ``target``, at the braking rates, through a ``CommandRamp``);
    ``ready`` says when to hand over."""

    def __init__(self) -> None:
        self.torso = TorsoSpeed()
        self._ramp = CommandRamp((BRAKE_M_S2, BRAKE_M_S2, BRAKE_TURN_S2))
        self._braking_s = 0.0

    def reset(self) -> None:
        """A new walk, from rest: the next braking starts from ``walked``'s command."""
        self._ramp.reset()
        self._braking_s = 0.0

    def walked(self, command: tuple[float, float, float]) -> None:
        """The controller walked ``command`` this cycle (not braking)."""
        self._ramp.reset(command)
        self._braking_s = 0.0

    def brake(self, target: tuple[float, float, float]) -> tuple[float, float, float]:
        self._braking_s += CYCLE_S
        return self._ramp(target)

    @property
    def ready(self) -> bool:
        return self.torso.speed <= HANDOVER_SPEED_M_S or self._braking_s >= HANDOVER_MAX_S
