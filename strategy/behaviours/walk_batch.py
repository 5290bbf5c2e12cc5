"""Walk commands for a whole team in one pass.

A behaviour that walks somewhere (``go_to``) records a ``WalkGoal`` — the walker's pose, the
target, what to face, the speed and the players it believes are around it — instead of
computing the command at once. ``walk_commands`` then computes every agent's command
together in one compiled loop (``walk_kernel``). Each command depends only on that agent's
own goal and beliefs, and equals ``walk_command`` bit for bit (same IEEE operations in the
same order; tested), so batching changes no match.

A team that writes its own behaviours can batch the same way: build ``WalkGoal``s, then call
``walk_commands`` once per cycle (or ``resolve_walks`` on the requests).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from strategy.behaviours.navigation import SIDE_STEP_SHARE, NavigationParams, walk_command


@dataclass(frozen=True)
class WalkGoal:
    """Where one agent walks this cycle, and what it believes is around it.

    Attributes:
        position: (2,) the walker, team frame, metres.
        heading: its heading, radians.
        target: (2,) where it walks to.
        players: (M, 2) every player row of its belief (teammates then opponents).
        avoid: (M,) bool, the rows to walk around (None: walk straight, no obstacles).
        face: (2,) the point to face near the target, or None.
        speed: top speed, m/s (None: the navigation default).
        params: the navigation gains.
    """

    position: NDArray[np.float64]
    heading: float
    target: NDArray[np.float64]
    players: NDArray[np.float64]
    avoid: NDArray[np.bool_] | None
    face: NDArray[np.float64] | None = None
    speed: float | None = None
    params: NavigationParams = NavigationParams()

    def obstacles(self) -> NDArray[np.float64]:
        if self.avoid is None:
            return np.zeros((0, 2))
        return self.players[self.avoid]

    def command(self) -> NDArray[np.float64]:
        """This goal's walk command alone (``walk_command``)."""
        return walk_command(self.position, self.heading, self.target, self.obstacles(),
                            self.params, face=self.face, speed=self.speed)


def walk_commands(goals: Sequence[WalkGoal]) -> list[NDArray[np.float64]]:
    """``[goal.command() for goal in goals]``, computed together in one compiled loop
    (``walk_kernel``; goals with other navigation gains or belief sizes than the first's in
    loops of their own)."""
    if not goals:
        return []
    first = goals[0]
    shape = first.players.shape
    if all(g.params is first.params and g.players.shape == shape for g in goals):
        return list(_commands(goals, first.params))
    return [_commands([g], g.params)[0] for g in goals]


def _commands(goals: Sequence[WalkGoal], params: NavigationParams) -> NDArray[np.float64]:
    """(B, 3) the walk commands of ``goals`` (one navigation gain set, one belief size)."""
    b = len(goals)
    faces = [g.face for g in goals]
    speeds = [g.speed for g in goals]
    avoids = [g.avoid for g in goals]
    players = goals[0].players
    out = np.empty((b, 3))
    _kernel().walk_commands(
        np.array([g.position for g in goals], dtype=np.float64),
        np.array([g.heading for g in goals], dtype=np.float64),
        np.array([g.target for g in goals], dtype=np.float64),
        np.array([_NO_POINT if f is None else f for f in faces], dtype=np.float64),
        np.array([f is not None for f in faces]),
        np.array([0.0 if v is None else v for v in speeds], dtype=np.float64),
        np.array([v is not None for v in speeds]),
        np.array([g.players for g in goals], dtype=np.float64).reshape(b, -1, 2),
        np.array([np.zeros(len(players), dtype=bool) if a is None else a for a in avoids],
                 dtype=bool).reshape(b, -1),
        np.array([a is not None for a in avoids]), _packed(params), out)
    return out


_NO_POINT = np.zeros(2)
_PACKED: dict[NavigationParams, NDArray[np.float64]] = {}


def _packed(params: NavigationParams) -> NDArray[np.float64]:
    """The gains as ``walk_kernel`` reads them (its ``params`` indices), held per gain set."""
    packed = _PACKED.get(params)
    if packed is None:
        packed = _PACKED[params] = np.array((
            params.k_attract, params.k_repulse, params.influence_m, params.max_speed,
            params.slow_down_m, params.arrive_m, params.turn_gain, params.turn_in_place_rad,
            params.omni_m, params.min_speed, REPULSION_EXPONENT, float(params.side_step_left),
            float(params.side_step_right), SIDE_STEP_SHARE))
        if len(_PACKED) > 64:  # a tuning run's many gain sets: keep the newest
            del _PACKED[next(iter(_PACKED))]
    return packed


REPULSION_EXPONENT = 4.0
"""``field_vector``'s ``d**4`` (k/d^3 along the unit vector), passed to the kernel as data:
with a constant exponent the compiler may replace the C library's ``pow`` by multiplies,
which round differently."""


@functools.cache
def _kernel():
    """The compiled loop, imported on the first walk command (numba takes a few tenths of a
    second to import)."""
    from strategy.behaviours import walk_kernel

    return walk_kernel


def prepare_kernel() -> None:
    """Compile (or load from numba's cache) the loop now, before a match's first cycle runs
    under its stall watchdog."""
    goal = WalkGoal(np.zeros(2), 0.0, np.ones(2) * 3.0, np.zeros((2, 2)),
                    np.array((False, True)), np.ones(2), 1.0)
    walk_commands([goal])
