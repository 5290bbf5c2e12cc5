"""What a camera can see on the pitch: landmarks, field lines, and the polar projection.

Pure geometry shared by the simulator's vision (``teamenv.sim.vision``) and by the teams that
localize from it (``strategy.perception``), so both use the same landmark table.

Everything is in the **team frame** (the team attacks +x, its own goal at x = -length/2; metres,
radians). The pitch is symmetric under a rotation by pi, so one table serves both teams: the
right team's landmark ``k`` is the left team's landmark ``k`` rotated by pi in the world.

Landmark sets (``kind``):

- ``simspark`` (the classic 3D league's restricted vision): the 4 corner flags (z = 0) and the
  4 goal posts (the top of the post, z = the crossbar height), 8 in all.
- ``mj`` (RCSSServerMJ 0.2.1's vision markers, where its ``SoccerSimulation`` puts them): the 4
  corner L-junctions, the 2 T-junctions of the halfway line, the 2 points where the halfway
  line crosses the centre circle, the 2 penalty spots (when the field has them), the 4
  goal-post tops, then (when the field has the areas) the goal area's 4 L-junctions (its front
  corners) and 4 T-junctions (on the goal lines), and the same 8 of the penalty area. The
  server places the area markers at y = +-(the area's full width), not at +-half of it where
  the painted corners are (its ``soccer_sim.py`` takes ``*_area_dim[1]`` as the half width);
  a robot localizes against what the server reports, so the table follows the server.

Polar sightings follow the league: ``distance`` is the 3D distance from the camera, the
horizontal angle (azimuth) is positive to the left of the camera's axis, the vertical angle
(elevation) is positive upwards.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

import portable_math as pm
from teamenv.errors import ConfigError
from teamenv.field import FieldSpec

LANDMARK_KINDS = ("simspark", "mj")
CENTRE_CIRCLE_SEGMENTS = 10
"""SimSpark sends the centre circle as this many straight segments."""


@dataclass(frozen=True)
class Landmarks:
    """Named points the camera reports, team frame: ``xyz[k]`` is landmark ``names[k]``."""

    names: tuple[str, ...]
    xyz: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.names)

    def index(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise KeyError(f"no landmark {name!r}; landmarks are {list(self.names)}") from None


def landmarks(field: FieldSpec, kind: str = "simspark") -> Landmarks:
    """The landmark table of ``kind`` on ``field`` (team frame; see the module docstring).

    Names say where a point is from the team's view: ``own``/``their`` end, ``left`` (+y) or
    ``right`` (-y), e.g. ``flag_own_left`` at (-length/2, +width/2, 0).
    """
    if kind not in LANDMARK_KINDS:
        raise ConfigError(f"landmarks: unknown kind {kind!r}; choose one of {list(LANDMARK_KINDS)}")
    hl, hw, hg, gz = field.half_length, field.half_width, field.half_goal_width, field.goal_height
    corners = [("own_left", -hl, hw), ("own_right", -hl, -hw),
               ("their_left", hl, hw), ("their_right", hl, -hw)]
    posts = [("post_own_left", -hl, hg, gz), ("post_own_right", -hl, -hg, gz),
             ("post_their_left", hl, hg, gz), ("post_their_right", hl, -hg, gz)]
    rows: list[tuple[str, float, float, float]] = []
    if kind == "simspark":
        rows += [(f"flag_{name}", x, y, 0.0) for name, x, y in corners]
    else:
        rows += [(f"corner_{name}", x, y, 0.0) for name, x, y in corners]
        rows += [("halfway_left", 0.0, hw, 0.0), ("halfway_right", 0.0, -hw, 0.0)]
        r = field.center_circle_radius
        rows += [("circle_left", 0.0, r, 0.0), ("circle_right", 0.0, -r, 0.0)]
        if field.penalty_spot_distance > 0:
            d = hl - field.penalty_spot_distance
            rows += [("penalty_own", -d, 0.0, 0.0), ("penalty_their", d, 0.0, 0.0)]
    rows += posts
    if kind == "mj":
        for area, depth, across in (("goal_area", field.goal_area_length, field.goal_area_width),
                                    ("penalty_area", field.penalty_length, field.penalty_width)):
            if depth > 0 and across > 0:
                x = hl - depth
                rows += [(f"{area}_corner_own_left", -x, across, 0.0),
                         (f"{area}_corner_own_right", -x, -across, 0.0),
                         (f"{area}_corner_their_left", x, across, 0.0),
                         (f"{area}_corner_their_right", x, -across, 0.0),
                         (f"{area}_line_own_left", -hl, across, 0.0),
                         (f"{area}_line_own_right", -hl, -across, 0.0),
                         (f"{area}_line_their_left", hl, across, 0.0),
                         (f"{area}_line_their_right", hl, -across, 0.0)]
    xyz = np.array([row[1:] for row in rows], dtype=np.float64)
    xyz.flags.writeable = False
    return Landmarks(tuple(row[0] for row in rows), xyz)


def _mj_marks_left() -> dict[str, str]:
    """RCSSServerMJ's vision marker name -> our ``mj`` landmark name, for the left team (whose
    team frame is the world frame). Marker names: kind ``l`` L-junction, ``t`` T-junction,
    ``x`` X-junction, ``p`` penalty spot, ``g`` goal post; then the end (``l``/``r``: x < 0 /
    x > 0, ``c``: the halfway line) and ``u``/``l`` (y > 0 / y < 0); then the feature (``f``
    field, ``c`` circle, ``p`` post, ``ga`` goal area, ``pa`` penalty area)."""
    ends = {"l": "own", "r": "their"}
    sides = {"u": "left", "l": "right"}
    marks = {"t_cuf": "halfway_left", "t_clf": "halfway_right",
             "x_cuc": "circle_left", "x_clc": "circle_right",
             "p_lpm": "penalty_own", "p_rpm": "penalty_their"}
    for end, own in ends.items():
        for ud, side in sides.items():
            marks[f"l_{end}{ud}f"] = f"corner_{own}_{side}"
            marks[f"g_{end}{ud}p"] = f"post_{own}_{side}"
            for tag, area in (("ga", "goal_area"), ("pa", "penalty_area")):
                marks[f"l_{end}{ud}{tag}"] = f"{area}_corner_{own}_{side}"
                marks[f"t_{end}{ud}{tag}"] = f"{area}_line_{own}_{side}"
    return marks


def _turned(mark: str) -> str:
    """The marker at the world point turned by pi (left <-> right end, upper <-> lower)."""
    kind, where = mark.split("_", 1)
    end = {"l": "r", "r": "l", "c": "c"}[where[0]]
    if where[1] in "ul":
        return f"{kind}_{end}{'l' if where[1] == 'u' else 'u'}{where[2:]}"
    return f"{kind}_{end}{where[1:]}"  # the penalty spots: p_<end>pm


#: RCSSServerMJ's vision marker -> our ``mj`` landmark name, for the left and the right team
#: (the right team's landmark k is the left's turned by pi in the world). Markers a field does
#: not have are simply never reported.
MJ_MARKS_LEFT: dict[str, str] = _mj_marks_left()
MJ_MARKS_RIGHT: dict[str, str] = {_turned(m): name for m, name in MJ_MARKS_LEFT.items()}


def field_lines(field: FieldSpec) -> NDArray[np.float64]:
    """(L, 4) the pitch's painted lines as straight segments ``x1, y1, x2, y2`` (team frame).

    The touch and goal lines, the halfway line, both penalty boxes (three sides each) and the
    centre circle as ``CENTRE_CIRCLE_SEGMENTS`` chords, as SimSpark sends them.
    """
    hl, hw = field.half_length, field.half_width
    pl, pw = field.penalty_length, field.penalty_width / 2.0
    segs = [
        (-hl, hw, hl, hw), (-hl, -hw, hl, -hw),          # touch lines
        (-hl, -hw, -hl, hw), (hl, -hw, hl, hw),          # goal lines
        (0.0, -hw, 0.0, hw),                             # halfway line
    ]
    for end in (-1.0, 1.0):                              # penalty boxes
        x0, x1 = end * hl, end * (hl - pl)
        segs += [(x0, pw, x1, pw), (x0, -pw, x1, -pw), (x1, -pw, x1, pw)]
    angles = np.linspace(0.0, 2.0 * np.pi, CENTRE_CIRCLE_SEGMENTS + 1)
    r = field.center_circle_radius
    ring = np.column_stack((r * np.cos(angles), r * np.sin(angles)))
    segs += [(*ring[k], *ring[k + 1]) for k in range(CENTRE_CIRCLE_SEGMENTS)]
    out = np.array(segs, dtype=np.float64)
    out.flags.writeable = False
    return out


def to_polar(points: NDArray[np.floating], x: float, y: float, heading: float,
             camera_height: float) -> NDArray[np.float64]:
    """(M, 3) ``distance, azimuth, elevation`` of team-frame ``points`` (M, 3: x, y, z) seen from
    a camera at ``camera_height`` above (x, y), looking along ``heading`` (level)."""
    p = np.asarray(points, dtype=np.float64)
    dx, dy, dz = p[:, 0] - x, p[:, 1] - y, p[:, 2] - camera_height
    c, s = np.cos(heading), np.sin(heading)
    fwd, left = c * dx + s * dy, -s * dx + c * dy
    ground = np.hypot(fwd, left)
    out = np.empty((len(p), 3))
    out[:, 0] = np.sqrt(ground * ground + dz * dz)
    out[:, 1] = pm.arctan2(left, fwd)
    out[:, 2] = pm.arctan2(dz, ground)
    return out


def from_polar(polar: NDArray[np.floating], camera_height: float) -> NDArray[np.float64]:
    """(M, 3) body-frame points ``forward, left, z`` (z above the ground) of polar sightings
    (M, 3: distance, azimuth, elevation) from a camera at ``camera_height``; the inverse of
    ``to_polar`` for a camera at the origin looking along +x."""
    pol = np.asarray(polar, dtype=np.float64)
    d, az, el = pol[:, 0], pol[:, 1], pol[:, 2]
    ground = d * np.cos(el)
    out = np.empty((len(pol), 3))
    out[:, 0] = ground * np.cos(az)
    out[:, 1] = ground * np.sin(az)
    out[:, 2] = camera_height + d * np.sin(el)
    return out
