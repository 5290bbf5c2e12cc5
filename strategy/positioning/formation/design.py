"""Parametric formation design: the rules that generate the built-in formation files.

A ``RoleSpec`` gives one player's home position as a clamped linear function of the ball, in
*normalised* pitch units (u = x / half-length, v = y / half-width, both in [-1, 1]):

    u = clip(u0 + ku * ball_u, u_lo, u_hi)      then  u = max(u_lo, min(u, ball_u - goal_side))
    v = clip(v0 + kv * ball_v, -v_max, v_max)

``parametric_formation`` evaluates the specs at a grid of sample ball positions and returns a
Delaunay ``Formation`` (so the built-ins are ordinary formation files you can edit);
``static_formation`` makes a one-sample formation (kick-off line-ups).
``write_builtins()`` regenerates ``strategy/positioning/formation/data/*.json``; a test checks that the
shipped files match.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from strategy.positioning.formation.model import Formation, Role
from teamenv.field import FieldSpec, field_preset

GRID_U: tuple[float, ...] = (-1.0, -0.75, -0.5, -0.25, 0.0, 0.25, 0.5, 0.75, 1.0)
GRID_V: tuple[float, ...] = (-1.0, -0.5, 0.0, 0.5, 1.0)
DATA_DIR = Path(__file__).with_name("data")


@dataclass(frozen=True)
class RoleSpec:
    """One player's home-position rule, in normalised pitch units (see the module docstring)."""

    name: str
    type: str
    base: tuple[float, float]
    follow: tuple[float, float]
    u_range: tuple[float, float] = (-1.0, 1.0)
    v_max: float = 0.95
    goal_side: float | None = None

    def position(self, ball_u: float, ball_v: float) -> tuple[float, float]:
        """Home position (u, v) for a ball at (ball_u, ball_v), normalised units."""
        lo, hi = self.u_range
        u = min(max(self.base[0] + self.follow[0] * ball_u, lo), hi)
        if self.goal_side is not None:
            u = max(lo, min(u, ball_u - self.goal_side))
        v = min(max(self.base[1] + self.follow[1] * ball_v, -self.v_max), self.v_max)
        return (u, v)

    def mirror(self, name: str) -> RoleSpec:
        """The same rule on the other wing (v0 negated)."""
        return RoleSpec(name, self.type, (self.base[0], -self.base[1]), self.follow,
                        self.u_range, self.v_max, self.goal_side)


def parametric_formation(
    specs: Sequence[RoleSpec],
    *,
    field: str | FieldSpec,
    name: str,
    description: str = "",
    grid_u: Sequence[float] = GRID_U,
    grid_v: Sequence[float] = GRID_V,
    keep_away_m: float | None = None,
) -> Formation:
    """A Delaunay formation sampled from ``specs`` at the ball grid ``grid_u x grid_v``.

    Args:
        specs: one rule per player (role 0 the goalie).
        field: the pitch the formation is written for (metres come from its size).
        name: the formation's name; description: free text.
        grid_u, grid_v: sample ball positions, normalised units.
        keep_away_m: if given, home positions closer than this (metres) to a sample's ball are
            pushed out to that distance, away from the ball (opponents' set plays).
    """
    spec = field_preset(field)
    half = np.array([spec.half_length, spec.half_width])
    balls, players = [], []
    for bu in grid_u:
        for bv in grid_v:
            b = np.array([bu, bv]) * half
            p = np.array([s.position(bu, bv) for s in specs]) * half
            if keep_away_m is not None:
                p = _keep_away(p, b, keep_away_m, spec)
            balls.append(b)
            players.append(p)
    roles = [Role(s.name, s.type) for s in specs]
    return Formation(roles, np.array(balls), np.array(players), field=spec.name, name=name,
                     description=description)


def static_formation(
    roles: Sequence[tuple[str, str]],
    positions_uv: Sequence[tuple[float, float]],
    *,
    field: str | FieldSpec,
    name: str,
    description: str = "",
) -> Formation:
    """A one-sample (static) formation; ``positions_uv`` in normalised units, ball at the centre."""
    spec = field_preset(field)
    half = np.array([spec.half_length, spec.half_width])
    pos = np.asarray(positions_uv, dtype=np.float64) * half
    return Formation([Role(n, t) for n, t in roles], np.zeros((1, 2)), pos[None],
                     field=spec.name, name=name, description=description)


def _keep_away(p: NDArray[np.float64], ball: NDArray[np.float64], r: float,
               spec: FieldSpec) -> NDArray[np.float64]:
    out = p.copy()
    goal = np.array([-spec.half_length, 0.0])
    for i in range(len(out)):
        d = out[i] - ball
        dist = float(np.hypot(*d))
        if dist < r:
            if dist < 1e-9:
                d = goal - ball
                dist = float(np.hypot(*d)) or 1.0
            out[i] = ball + d / dist * r
    lim = np.array([spec.half_length, spec.half_width])
    return np.clip(out, -lim, lim)


# ------------------------------------------------------------------------- the built-ins
def _pair(left: RoleSpec, right_name: str) -> list[RoleSpec]:
    return [left, left.mirror(right_name)]


def _eleven_defend() -> list[RoleSpec]:
    return [
        RoleSpec("Goalie", "G", (-0.93, 0.0), (0.02, 0.08), (-0.95, -0.85), 0.09),
        *_pair(RoleSpec("LeftCenterBack", "DF", (-0.62, 0.18), (0.45, 0.25), (-0.88, 0.05),
                        0.5, goal_side=0.1), "RightCenterBack"),
        *_pair(RoleSpec("LeftSideBack", "DF", (-0.55, 0.62), (0.45, 0.3), (-0.85, 0.15),
                        0.9, goal_side=0.05), "RightSideBack"),
        *_pair(RoleSpec("LeftDefensiveHalf", "MF", (-0.3, 0.2), (0.5, 0.35), (-0.75, 0.45),
                        0.6), "RightDefensiveHalf"),
        *_pair(RoleSpec("LeftSideHalf", "MF", (-0.22, 0.62), (0.5, 0.35), (-0.7, 0.6), 0.92),
               "RightSideHalf"),
        *_pair(RoleSpec("LeftForward", "FW", (0.0, 0.15), (0.5, 0.3), (-0.4, 0.8), 0.7),
               "RightForward"),
    ]


def _eleven_attack() -> list[RoleSpec]:
    return [
        RoleSpec("Goalie", "G", (-0.9, 0.0), (0.03, 0.08), (-0.95, -0.8), 0.09),
        *_pair(RoleSpec("LeftCenterBack", "DF", (-0.45, 0.2), (0.5, 0.2), (-0.85, 0.35), 0.5,
                        goal_side=0.05), "RightCenterBack"),
        *_pair(RoleSpec("LeftSideBack", "DF", (-0.3, 0.65), (0.5, 0.25), (-0.8, 0.6), 0.92),
               "RightSideBack"),
        RoleSpec("DefensiveHalf", "MF", (-0.15, 0.0), (0.55, 0.35), (-0.7, 0.6), 0.6),
        *_pair(RoleSpec("LeftCentralHalf", "MF", (0.05, 0.35), (0.55, 0.35), (-0.6, 0.8), 0.8),
               "RightCentralHalf"),
        *_pair(RoleSpec("LeftWing", "FW", (0.3, 0.7), (0.5, 0.2), (-0.4, 0.93), 0.92),
               "RightWing"),
        RoleSpec("CenterForward", "FW", (0.4, 0.0), (0.5, 0.4), (-0.3, 0.93), 0.6),
    ]


def _seven_defend() -> list[RoleSpec]:
    return [
        RoleSpec("Goalie", "G", (-0.92, 0.0), (0.02, 0.08), (-0.95, -0.85), 0.09),
        *_pair(RoleSpec("LeftBack", "DF", (-0.6, 0.3), (0.45, 0.3), (-0.88, 0.1), 0.7,
                        goal_side=0.08), "RightBack"),
        RoleSpec("CentralHalf", "MF", (-0.3, 0.0), (0.5, 0.4), (-0.75, 0.45), 0.6),
        *_pair(RoleSpec("LeftHalf", "MF", (-0.25, 0.55), (0.5, 0.35), (-0.7, 0.6), 0.9),
               "RightHalf"),
        RoleSpec("Forward", "FW", (0.05, 0.0), (0.5, 0.4), (-0.4, 0.8), 0.6),
    ]


def _seven_attack() -> list[RoleSpec]:
    return [
        RoleSpec("Goalie", "G", (-0.9, 0.0), (0.03, 0.08), (-0.95, -0.8), 0.09),
        *_pair(RoleSpec("LeftBack", "DF", (-0.35, 0.35), (0.5, 0.25), (-0.85, 0.4), 0.75,
                        goal_side=0.05), "RightBack"),
        RoleSpec("CentralHalf", "MF", (-0.05, 0.0), (0.55, 0.4), (-0.65, 0.7), 0.6),
        *_pair(RoleSpec("LeftHalf", "MF", (0.05, 0.6), (0.5, 0.25), (-0.5, 0.9), 0.92),
               "RightHalf"),
        RoleSpec("Forward", "FW", (0.4, 0.0), (0.5, 0.4), (-0.3, 0.93), 0.6),
    ]


def _widen(specs: list[RoleSpec], du: float, v_scale: float) -> list[RoleSpec]:
    """Own set plays: everyone ``du`` further up, spread ``v_scale`` times wider."""
    out = []
    for s in specs:
        if s.type == "G":
            out.append(s)
            continue
        lo, hi = s.u_range
        out.append(RoleSpec(s.name, s.type, (s.base[0] + du, s.base[1] * v_scale), s.follow,
                            (lo, min(hi + du, 0.95)), min(s.v_max * v_scale, 0.95), s.goal_side))
    return out


_ELEVEN_ROLES = [(s.name, s.type) for s in _eleven_defend()]
_SEVEN_ROLES = [(s.name, s.type) for s in _seven_defend()]

# Kick-off line-ups (own half, u <= 0; outside the centre circle except our kicker).
_ELEVEN_KICKOFF_OURS = [(-0.93, 0.0), (-0.6, 0.18), (-0.6, -0.18), (-0.5, 0.6), (-0.5, -0.6),
                        (-0.32, 0.22), (-0.32, -0.22), (-0.2, 0.62), (-0.2, -0.62),
                        (-0.02, 0.0), (-0.08, -0.3)]
_ELEVEN_KICKOFF_THEIRS = [(-0.93, 0.0), (-0.62, 0.18), (-0.62, -0.18), (-0.55, 0.6),
                          (-0.55, -0.6), (-0.38, 0.22), (-0.38, -0.22), (-0.3, 0.62),
                          (-0.3, -0.62), (-0.2, 0.25), (-0.2, -0.25)]
_SEVEN_KICKOFF_OURS = [(-0.92, 0.0), (-0.55, 0.3), (-0.55, -0.3), (-0.3, 0.0), (-0.2, 0.55),
                       (-0.2, -0.55), (-0.02, 0.0)]
_SEVEN_KICKOFF_THEIRS = [(-0.92, 0.0), (-0.6, 0.3), (-0.6, -0.3), (-0.38, 0.0), (-0.3, 0.55),
                         (-0.3, -0.55), (-0.2, 0.0)]

SETPLAY_KEEP_AWAY_M = 2.0
"""Opponents keep this far (metres) from the ball in the other side's set plays (simspark)."""


def _builders() -> dict[str, Callable[[], Formation]]:
    def dyn(size: str, kind: str, specs: Callable[[], list[RoleSpec]], field: str, desc: str,
            keep: float | None = None) -> Callable[[], Formation]:
        return lambda: parametric_formation(specs(), field=field, name=f"{size}-{kind}",
                                            description=desc, keep_away_m=keep)

    def static(size: str, kind: str, roles: list[tuple[str, str]],
               pos: list[tuple[float, float]], field: str, desc: str) -> Callable[[], Formation]:
        return lambda: static_formation(roles, pos, field=field, name=f"{size}-{kind}",
                                        description=desc)

    return {
        "11v11-attack": dyn("11v11", "attack", _eleven_attack, "simspark",
                            "11 v 11, 4-3-3 when we have the ball"),
        "11v11-defend": dyn("11v11", "defend", _eleven_defend, "simspark",
                            "11 v 11, compact 4-4-2 when the opponents have the ball"),
        "11v11-setplay-ours": dyn("11v11", "setplay-ours", lambda: _widen(_eleven_attack(), 0.05,
                                  1.1), "simspark", "11 v 11, our kick-ins, corners, goal and "
                                  "free kicks: 4-3-3 pushed up and spread"),
        "11v11-setplay-theirs": dyn("11v11", "setplay-theirs", _eleven_defend, "simspark",
                                    "11 v 11, their set plays: 4-4-2, 2 m from the ball",
                                    SETPLAY_KEEP_AWAY_M),
        "11v11-kickoff-ours": static("11v11", "kickoff-ours", _ELEVEN_ROLES,
                                     _ELEVEN_KICKOFF_OURS, "simspark",
                                     "11 v 11, our kick-off (beam line-up, own half)"),
        "11v11-kickoff-theirs": static("11v11", "kickoff-theirs", _ELEVEN_ROLES,
                                       _ELEVEN_KICKOFF_THEIRS, "simspark",
                                       "11 v 11, their kick-off (own half, outside the circle)"),
        "7v7-attack": dyn("7v7", "attack", _seven_attack, "mj7v7",
                          "7 v 7, 2-3-1 when we have the ball"),
        "7v7-defend": dyn("7v7", "defend", _seven_defend, "mj7v7",
                          "7 v 7, compact 2-3-1 when the opponents have the ball"),
        "7v7-setplay-ours": dyn("7v7", "setplay-ours", lambda: _widen(_seven_attack(), 0.05, 1.1),
                                "mj7v7", "7 v 7, our set plays: 2-3-1 pushed up and spread"),
        "7v7-setplay-theirs": dyn("7v7", "setplay-theirs", _seven_defend, "mj7v7",
                                  "7 v 7, their set plays: 2-3-1, 2 m from the ball",
                                  SETPLAY_KEEP_AWAY_M),
        "7v7-kickoff-ours": static("7v7", "kickoff-ours", _SEVEN_ROLES, _SEVEN_KICKOFF_OURS,
                                   "mj7v7", "7 v 7, our kick-off (beam line-up, own half)"),
        "7v7-kickoff-theirs": static("7v7", "kickoff-theirs", _SEVEN_ROLES,
                                     _SEVEN_KICKOFF_THEIRS, "mj7v7",
                                     "7 v 7, their kick-off (own half, outside the circle)"),
    }


def build_builtins() -> dict[str, Formation]:
    """Every built-in formation, built from the rules in this module (name -> Formation)."""
    return {name: make() for name, make in _builders().items()}


def write_builtins(directory: str | Path = DATA_DIR) -> list[Path]:
    """Regenerate the built-in formation files (``<name>.json``) in ``directory``."""
    from strategy.positioning.formation.fileformat import write_formation

    out = []
    for name, formation in build_builtins().items():
        path = Path(directory) / f"{name}.json"
        write_formation(formation, path)
        out.append(path)
    return out
