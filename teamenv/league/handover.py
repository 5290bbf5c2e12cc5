"""The hand-over of a kick's approach from the robot's walk controller to the kick's walker.

The kick is a step of our LIPM walker's gait (``teamenv.league.kick``), so with another walk
controller (the league's reference network, the default) the kick's own walker takes over the
approach near the ball. That walker starts its gait standing on both feet, from rest. Taking
over a robot that still walks at the speed the team asked for fells it (in a LocalServer 1 v 1
of the chaser, 6 of 8 hand-overs at 0.5-0.7 m/s ended in a fall within 2.5 s), and so does
taking over the network's gait itself, even at the approach's 0.2-0.3 m/s: in kick trials 36 of
100 robots fell 0.6-2.8 s after such a hand-over, most while the walker stood or took its first
steps with the network's momentum. So near the ball the controller first brakes towards the
approach's own command, and the kick's walker takes over once the torso is slow (or after
``HANDOVER_MAX_S``). With ``stop`` (``KickParams.handover_stop``, measured, not the default:
docs/league.md, *A hand-over that stops first*) it brakes to the zero command and steps on the
spot for ``HANDOVER_STOP_S``, and the kick's walker takes over once the torso is slow and
both feet are down (or after ``HANDOVER_STOP_MAX_S``) and stands ``HANDOVER_STAND_S``.
"""

from __future__ import annotations

import math
from collections import deque

from .command_ramp import CommandRamp
from .controller import CYCLE_S
from .feet import feet_down
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
#: with ``stop``: the controller brakes and steps on the spot at least this long (s) before
#: handing over: the network's stepping settles (0.6 s fell as often as no stop on tuning seeds)
HANDOVER_STOP_S = 1.0
#: with ``stop``: hand over anyway after this long (s) of braking
HANDOVER_STOP_MAX_S = 2.5
#: with ``stop``: once begun (braking, or the kick's walker walking), the hand-over goes on while the ball is
#: within the hand-over's radius + this (m): the robot stepping on the spot drifts, and with the
#: ball at the radius the stop began again and again (13 of 50 tuning trials ran out of time)
HANDOVER_KEEP_M = 0.3
#: with ``stop``: the kick's walker, taking over, stands this long (s) before its first step (a fresh walker
#: stands 0.5 s; after the stop the robot is already at rest on both feet)
HANDOVER_STAND_S = 0.3


def near(distance: float, radius: float, begun: bool) -> bool:
    """Whether the hand-over goes on with the ball ``distance`` m away: within ``radius``, or
    within ``HANDOVER_KEEP_M`` more once it has ``begun``."""
    return distance <= radius + (HANDOVER_KEEP_M if begun else 0.0)


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
    """Braking the walk controller before the kick's walker takes the approach over.

    ``update(perception)`` every cycle; ``brake(target)`` is the controller's command this
    cycle (from the last command it walked towards the approach's ``target``, or with ``stop``
    towards standing still, at the braking rates, through a ``CommandRamp``); ``ready`` says
    when to hand over."""

    def __init__(self, stop: bool = False) -> None:
        self.stop = stop
        self.torso = TorsoSpeed()
        self._ramp = CommandRamp((BRAKE_M_S2, BRAKE_M_S2, BRAKE_TURN_S2))
        self._braking_s = 0.0
        self._perception: Perception | None = None

    def reset(self) -> None:
        """A new walk, from rest: the next braking starts from ``walked``'s command."""
        self._ramp.reset()
        self._braking_s = 0.0

    def update(self, perception: Perception) -> None:
        """This cycle's measurements (the torso's place; the feet when asked ``ready``)."""
        self.torso.update(perception)
        self._perception = perception

    def walked(self, command: tuple[float, float, float]) -> None:
        """The controller walked ``command`` this cycle (not braking)."""
        self._ramp.reset(command)
        self._braking_s = 0.0

    @property
    def braking(self) -> bool:
        return self._braking_s > 0.0

    def brake(self, target: tuple[float, float, float]) -> tuple[float, float, float]:
        self._braking_s += CYCLE_S
        return self._ramp((0.0, 0.0, 0.0) if self.stop else target)

    def near(self, distance: float, radius: float, begun: bool) -> bool:
        """Whether the hand-over goes on with the ball ``distance`` m away (``near``; only
        with ``stop`` does a ``begun`` one keep going a little further out)."""
        return near(distance, radius, begun and self.stop)

    @property
    def stand_s(self) -> float | None:
        """How long the kick's walker stands when it takes over (None: the walker's own)."""
        return HANDOVER_STAND_S if self.stop else None

    @property
    def ready(self) -> bool:
        if not self.stop:
            return self.torso.speed <= HANDOVER_SPEED_M_S or self._braking_s >= HANDOVER_MAX_S
        if self._braking_s >= HANDOVER_STOP_MAX_S:
            return True
        return (self._braking_s >= HANDOVER_STOP_S - 1e-9
                and self.torso.speed <= HANDOVER_SPEED_M_S
                and self._perception is not None and feet_down(self._perception))
