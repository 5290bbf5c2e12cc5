"""Every perceptor the league server sends, parsed from its S-expression into dataclasses.

rcsssmj 0.2.1 sends one message per agent and cycle, a sequence of top-level expressions:

=====================================================  ==========================================
``(time (now 12.34))``                                 simulation time (s)
``(GS (t 0.0)(pm BeforeKickOff)(tl A)(tr B)(sl 0)(sr 0))``  game time, play mode, teams, score
``(pos (n torso_pos) (p x y z))``                      a body site's world position (m)
``(quat (n torso_quat) (q w x y z))``                  its world orientation
``(GYR (n torso_gyro) (rt x y z))``                    angular velocity (deg/s on the wire)
``(ACC (n torso_acc) (a x y z))``                      acceleration (m/s^2)
``(TCH n <name> val 0|1)``                             touch sensor (not on the T1)
``(HJ (n q_hj1)(ax deg)(vx deg/s))``                   one joint (one expression per joint)
``(JS (names ..)(axs ..)(vxs ..))``                    the joints in one expression (alternative)
``(See (<mark> (pol d az el)) ... (B (pol ..))         vision, every 2nd cycle, +-60 deg, no noise
(P (team T)(id 3)(head (pol ..))(lfoot ..)(rfoot ..)))``
``(MIC hear (<az deg> <base64>) ...)``                 heard messages (not one's own)
=====================================================  ==========================================

Angles are degrees on the wire and **radians** in the dataclasses (the protocol edge converts).
An unknown perceptor raises UnknownPerceptorError (``strict=True``, the default) or is kept in
``Perception.unknown``; a malformed one raises ProtocolError naming the perceptor and value.
"""

from __future__ import annotations

import base64
import binascii
import math
from dataclasses import dataclass, field

from .errors import ProtocolError, UnknownPerceptorError
from .sexp import SExp, parse_all

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class GameState:
    """``GS``: game time (s), play mode (league name), team names (None until joined), score."""

    time: float
    play_mode: str
    team_left: str | None
    team_right: str | None
    score_left: int
    score_right: int


@dataclass(frozen=True)
class Polar:
    """A camera sighting: distance (m), azimuth (rad, + to the left), elevation (rad, + up)."""

    distance: float
    azimuth: float
    elevation: float


@dataclass(frozen=True)
class PlayerSighting:
    """A seen player: team name, uniform number, and its seen parts (``head``, ``lfoot``...)."""

    team: str
    unum: int
    parts: dict[str, Polar]


@dataclass(frozen=True)
class Heard:
    """A heard message: direction to the speaker (rad, + to the left) and the decoded bytes."""

    azimuth: float
    payload: bytes


@dataclass(frozen=True)
class JointState:
    """One joint: angle (rad) and angular velocity (rad/s)."""

    angle: float
    velocity: float


@dataclass
class Vision:
    """``See``: fixed marks and the ball by name (``B``), and the seen players."""

    objects: dict[str, Polar] = field(default_factory=dict)
    players: list[PlayerSighting] = field(default_factory=list)

    @property
    def ball(self) -> Polar | None:
        return self.objects.get("B")


@dataclass
class Perception:
    """One agent's message of one cycle (fields absent from the message stay None / empty)."""

    time: float | None = None
    game: GameState | None = None
    positions: dict[str, Vec3] = field(default_factory=dict)
    orientations: dict[str, tuple[float, float, float, float]] = field(default_factory=dict)
    gyros: dict[str, Vec3] = field(default_factory=dict)
    accelerometers: dict[str, Vec3] = field(default_factory=dict)
    touches: dict[str, bool] = field(default_factory=dict)
    joints: dict[str, JointState] = field(default_factory=dict)
    vision: Vision | None = None
    heard: list[Heard] | None = None
    unknown: list[SExp] = field(default_factory=list)


# -- helpers ---------------------------------------------------------------------------------
def _num(value: SExp, what: str) -> float:
    if not isinstance(value, str):
        raise ProtocolError(f"{what}: expected a number, got the list {value!r}")
    try:
        x = float(value)
    except ValueError:
        raise ProtocolError(f"{what}: expected a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ProtocolError(f"{what}: value {value!r} is not finite")
    return x


def _atom(value: SExp, what: str) -> str:
    if not isinstance(value, str):
        raise ProtocolError(f"{what}: expected a name, got the list {value!r}")
    return value


def _tagged(expr: SExp, tag: str, n: int, what: str) -> list[SExp]:
    """The ``n`` values of ``(tag v1 .. vn)``."""
    if not isinstance(expr, list) or len(expr) != n + 1 or expr[0] != tag:
        raise ProtocolError(f"{what}: expected ({tag} + {n} values), got {expr!r}")
    return expr[1:]


def _named(expr: list[SExp], value_tag: str, n: int) -> tuple[str, list[float]]:
    """``(KIND (n NAME) (value_tag v1 .. vn))`` -> (NAME, values)."""
    kind = expr[0]
    if len(expr) != 3:
        raise ProtocolError(f"perceptor {kind}: expected (n NAME) ({value_tag} ...), got {expr!r}")
    (name,) = _tagged(expr[1], "n", 1, f"perceptor {kind}")
    name = _atom(name, f"perceptor {kind}")
    vals = [_num(v, f"perceptor {kind} {name}") for v in _tagged(expr[2], value_tag, n,
                                                                  f"perceptor {kind} {name}")]
    return name, vals


def _polar(expr: SExp, what: str) -> Polar:
    d, az, el = (_num(v, what) for v in _tagged(expr, "pol", 3, what))
    return Polar(d, math.radians(az), math.radians(el))


_RAD = math.pi / 180.0
_isfinite = math.isfinite


# -- perceptors ------------------------------------------------------------------------------
def _time(p: Perception, e: list[SExp]) -> None:
    if len(e) != 2:
        raise ProtocolError(f"perceptor time: expected (time (now T)), got {e!r}")
    (t,) = _tagged(e[1], "now", 1, "perceptor time")
    p.time = _num(t, "perceptor time")


_GS_TAGS = {"t", "pm", "tl", "tr", "sl", "sr"}


def _game_state(p: Perception, e: list[SExp]) -> None:
    values: dict[str, str] = {}
    for item in e[1:]:
        if not isinstance(item, list) or len(item) != 2 or item[0] not in _GS_TAGS:
            raise ProtocolError(f"perceptor GS: unexpected item {item!r}")
        values[_atom(item[0], "perceptor GS")] = _atom(item[1], f"perceptor GS {item[0]}")
    for need in ("t", "pm", "sl", "sr"):
        if need not in values:
            raise ProtocolError(f"perceptor GS: missing ({need} ...) in {e!r}")
    p.game = GameState(
        time=_num(values["t"], "perceptor GS t"), play_mode=values["pm"],
        team_left=values.get("tl"), team_right=values.get("tr"),
        score_left=int(_num(values["sl"], "perceptor GS sl")),
        score_right=int(_num(values["sr"], "perceptor GS sr")))


def _pos(p: Perception, e: list[SExp]) -> None:
    name, v = _named(e, "p", 3)
    p.positions[name] = (v[0], v[1], v[2])


def _quat(p: Perception, e: list[SExp]) -> None:
    name, v = _named(e, "q", 4)
    p.orientations[name] = (v[0], v[1], v[2], v[3])


def _gyro(p: Perception, e: list[SExp]) -> None:
    name, v = _named(e, "rt", 3)
    p.gyros[name] = (math.radians(v[0]), math.radians(v[1]), math.radians(v[2]))


def _acc(p: Perception, e: list[SExp]) -> None:
    name, v = _named(e, "a", 3)
    p.accelerometers[name] = (v[0], v[1], v[2])


def _touch(p: Perception, e: list[SExp]) -> None:
    if len(e) != 5 or e[1] != "n" or e[3] != "val":
        raise ProtocolError(f"perceptor TCH: expected (TCH n NAME val 0|1), got {e!r}")
    name = _atom(e[2], "perceptor TCH")
    p.touches[name] = _num(e[4], f"perceptor TCH {name}") != 0


def _hinge_joint(p: Perception, e: list[SExp]) -> None:
    # the common, well-formed case at once (23 joints a message); anything else goes through
    # the checks below, which name what is wrong
    if len(e) == 4:
        n, ax, vx = e[1], e[2], e[3]
        if (type(n) is list and len(n) == 2 and n[0] == "n" and type(n[1]) is str
                and type(ax) is list and len(ax) == 2 and ax[0] == "ax" and type(ax[1]) is str
                and type(vx) is list and len(vx) == 2 and vx[0] == "vx" and type(vx[1]) is str):
            try:
                a, v = float(ax[1]), float(vx[1])
            except ValueError:
                pass
            else:
                if _isfinite(a) and _isfinite(v):
                    p.joints[n[1]] = JointState(a * _RAD, v * _RAD)
                    return
    if len(e) != 4:
        raise ProtocolError(f"perceptor HJ: expected (n NAME)(ax A)(vx V), got {e!r}")
    (name,) = _tagged(e[1], "n", 1, "perceptor HJ")
    name = _atom(name, "perceptor HJ")
    (ax,) = _tagged(e[2], "ax", 1, f"perceptor HJ {name}")
    (vx,) = _tagged(e[3], "vx", 1, f"perceptor HJ {name}")
    p.joints[name] = JointState(math.radians(_num(ax, f"perceptor HJ {name} ax")),
                                math.radians(_num(vx, f"perceptor HJ {name} vx")))


def _joint_states(p: Perception, e: list[SExp]) -> None:
    if len(e) != 4 or not all(isinstance(x, list) and x for x in e[1:]):
        raise ProtocolError(f"perceptor JS: expected (names ..)(axs ..)(vxs ..), got {e!r}")
    names, axs, vxs = (x[1:] for x in e[1:])  # type: ignore[index]
    if [x[0] for x in e[1:]] != ["names", "axs", "vxs"] or not len(names) == len(axs) == len(vxs):  # type: ignore[index]
        raise ProtocolError(f"perceptor JS: names/axs/vxs differ in length or order: {e!r}")
    for name, ax, vx in zip(names, axs, vxs, strict=True):
        name = _atom(name, "perceptor JS")
        p.joints[name] = JointState(math.radians(_num(ax, f"perceptor JS {name}")),
                                    math.radians(_num(vx, f"perceptor JS {name}")))


def _see(p: Perception, e: list[SExp]) -> None:
    vision = Vision()
    for item in e[1:]:
        if not isinstance(item, list) or not item or not isinstance(item[0], str):
            raise ProtocolError(f"perceptor See: unexpected item {item!r}")
        if item[0] == "P":
            team = unum = None
            parts: dict[str, Polar] = {}
            for sub in item[1:]:
                if not isinstance(sub, list) or len(sub) != 2 or not isinstance(sub[0], str):
                    raise ProtocolError(f"perceptor See P: unexpected item {sub!r}")
                if sub[0] == "team":
                    team = _atom(sub[1], "perceptor See P team")
                elif sub[0] == "id":
                    unum = int(_num(sub[1], "perceptor See P id"))
                else:
                    parts[sub[0]] = _polar(sub[1], f"perceptor See P {sub[0]}")
            if team is None or unum is None:
                raise ProtocolError(f"perceptor See: player without (team ..)(id ..): {item!r}")
            vision.players.append(PlayerSighting(team, unum, parts))
        else:
            if len(item) != 2:
                raise ProtocolError(f"perceptor See: expected ({item[0]} (pol d az el)), got {item!r}")
            vision.objects[item[0]] = _polar(item[1], f"perceptor See {item[0]}")
    p.vision = vision


def _mic(p: Perception, e: list[SExp]) -> None:
    heard: list[Heard] = [] if p.heard is None else p.heard
    for item in e[2:]:
        if not isinstance(item, list) or len(item) != 2:
            raise ProtocolError(f"perceptor MIC: expected (azimuth base64), got {item!r}")
        az = _num(item[0], "perceptor MIC azimuth")
        text = _atom(item[1], "perceptor MIC message")
        try:
            payload = base64.b64decode(text, validate=True)
        except binascii.Error:
            raise ProtocolError(f"perceptor MIC: message {text!r} is not base64") from None
        heard.append(Heard(math.radians(az), payload))
    p.heard = heard


PERCEPTORS = {
    "time": _time, "GS": _game_state, "pos": _pos, "quat": _quat, "GYR": _gyro, "ACC": _acc,
    "TCH": _touch, "HJ": _hinge_joint, "JS": _joint_states, "See": _see, "MIC": _mic,
}
"""Perceptor kind -> the function that adds it to a Perception."""


def parse_perception(text: str, strict: bool = True, who: str = "agent") -> Perception:
    """Parse one server message; ``who`` names the agent in errors."""
    p = Perception()
    try:
        exprs = parse_all(text)
    except ProtocolError as exc:
        raise ProtocolError(f"{who}: {exc}") from None
    for expr in exprs:
        if not isinstance(expr, list) or not expr or not isinstance(expr[0], str):
            raise ProtocolError(f"{who}: top-level item {expr!r} is not a (perceptor ...)")
        handler = PERCEPTORS.get(expr[0])
        if handler is None:
            if strict:
                raise UnknownPerceptorError(
                    f"{who}: unknown perceptor {expr[0]!r} in {str(expr)[:120]}; "
                    f"known: {sorted(PERCEPTORS)}")
            p.unknown.append(expr)
            continue
        try:
            handler(p, expr)
        except ProtocolError as exc:
            raise ProtocolError(f"{who}: {exc}") from None
    return p
