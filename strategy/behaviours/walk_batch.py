"""Walk commands for a whole team in one pass.

A behaviour that walks somewhere (``go_to``) records a ``WalkGoal`` — the walker's pose, the
target, what to face, the speed and the players it believes are around it — instead of
computing the command at once. ``walk_commands`` then computes every agent's command
together: the distances and near-obstacle tests of the potential field (the part that costs)
in one numpy pass over (agents x players), the per-agent remainder in plain floats. Each
command depends only on that agent's own goal and beliefs, and equals ``walk_command`` bit
for bit (same IEEE operations in the same order; tested), so batching changes no match.

A team that writes its own behaviours can batch the same way: build ``WalkGoal``s, then call
``walk_commands`` once per cycle (or ``resolve_walks`` on the requests).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from strategy.behaviours.navigation import (
    NavigationParams,
    approach,
    walk_along,
    walk_command,
)
from strategy.geometry import wrap_angle

_THIRD_PI = math.pi / 3


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
    """``[goal.command() for goal in goals]``, computed together (goals that share their
    navigation gains; others one by one)."""
    if not goals:
        return []
    params = goals[0].params
    if any(g.params is not params for g in goals):
        return [g.command() for g in goals]
    out: list[NDArray[np.float64] | None] = [None] * len(goals)
    field = []  # (index, p0, p1, t0, t1, dist, v, heading) of goals that follow the field
    for i, g in enumerate(goals):
        command, dist, v = approach(g.position, g.heading, g.target, params, g.face, g.speed)
        if command is not None:
            out[i] = command
            continue
        field.append((i, float(g.position[0]), float(g.position[1]), float(g.target[0]),
                      float(g.target[1]), dist, v, g.heading))
    if field:
        pushes = _repulsions([goals[row[0]] for row in field], [row[5] for row in field], params)
        for row, push in zip(field, pushes, strict=True):
            out[row[0]] = _follow_field(row, push, params)
    return out  # type: ignore[return-value]


def _repulsions(goals: Sequence[WalkGoal], d_targets: Sequence[float],
                params: NavigationParams) -> list[NDArray[np.float64] | None]:
    """Per goal, the summed repulsion of its near obstacles (eq. 6, 8-9), or None if none is
    near: the distance tests for all goals in one pass, each sum over its own near rows."""
    shapes = {g.players.shape for g in goals if g.avoid is not None}
    if len(shapes) != 1:  # mixed belief sizes (never in one team): one by one
        return [_repulsion_alone(g, d, params) for g, d in zip(goals, d_targets, strict=True)]
    rows = [k for k, g in enumerate(goals) if g.avoid is not None]
    players = np.array([goals[k].players for k in rows])            # (B, M, 2)
    mask = np.array([goals[k].avoid for k in rows])                 # (B, M)
    position = np.array([goals[k].position for k in rows], dtype=np.float64)
    rel = players - position[:, None, :]
    d = np.sqrt(rel[:, :, 0] * rel[:, :, 0] + rel[:, :, 1] * rel[:, :, 1])
    limit = np.array([d_targets[k] for k in rows]) + 0.3
    near = mask & (d < params.influence_m) & (d > 1e-6) & (d < limit[:, None])
    out: list[NDArray[np.float64] | None] = [None] * len(goals)
    for b in np.flatnonzero(near.any(axis=1)).tolist():
        # the same expression on the same rows as field_vector: the same sum
        m = mask[b]
        rel_b, d_b = rel[b][m], d[b][m]
        n_b = near[b][m]
        dn = d_b[n_b]
        out[rows[b]] = ((params.k_repulse / dn**4)[:, None] * rel_b[n_b]).sum(axis=0)
    return out


def _repulsion_alone(goal: WalkGoal, d_target: float,
                     params: NavigationParams) -> NDArray[np.float64] | None:
    obs = goal.obstacles()
    if not len(obs):
        return None
    rel = obs - np.asarray(goal.position, dtype=np.float64)
    d = np.sqrt(rel[:, 0] * rel[:, 0] + rel[:, 1] * rel[:, 1])
    near = (d < params.influence_m) & (d > 1e-6) & (d < d_target + 0.3)
    if not near.any():
        return None
    dn = d[near]
    return ((params.k_repulse / dn**4)[:, None] * rel[near]).sum(axis=0)


def _follow_field(row: tuple, push: NDArray[np.float64] | None,
                  params: NavigationParams) -> NDArray[np.float64]:
    """The walk along the potential field's direction (``direction_to`` + the forward walk
    of ``walk_command``), in plain floats."""
    _, p0, p1, t0, t1, dist, v, heading = row
    tx, ty = t0 - p0, t1 - p1
    straight = math.atan2(ty, tx)
    if dist < 1e-9:
        vx = vy = 0.0
    else:
        scale = params.k_attract / dist / dist
        vx, vy = tx * scale, ty * scale
        if push is not None:
            vx, vy = vx + float(push[0]), vy + float(push[1])
    if vx != 0.0 or vy != 0.0 or vx != vx or vy != vy:  # ndarray.any(): NaN counts
        theta = math.atan2(vy, vx)
        error = wrap_angle(theta - straight)
        if abs(error) > _THIRD_PI:
            theta = straight + math.copysign(_THIRD_PI, error if error != 0 else 1.0)
    else:
        theta = straight
    return walk_along(theta, heading, v, params)
