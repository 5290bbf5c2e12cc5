"""LocalServer's perceptions without the text round trip: rcsssmj's perception objects turned
straight into our ``Perception``, exactly as their wire text parses.

On the real server each agent's perceptions are encoded as S-expression text
(``DefaultPerceptionEncoder``: ``to_sexp`` of every perception object) and we parse that text
back (``teamenv.league.perception.parse_perception``). In ``LocalServer`` both ends run in
this process, so the text is a detour: about a quarter of a 7 v 7's CPU went into writing and
reading it. ``perception_from_objects`` reads the objects instead and gives the *same*
``Perception``, bit for bit, in the same dict orders:

* the server rounds before it encodes (``trunc2``/``trunc3`` in ``generate_perceptions``), and
  encodes a number with ``str`` (an f-string), which for a Python or NumPy float64 is the
  shortest text that reads back as the same double; so ``float(value)`` is what the parser
  gets from the text. Any other number type (float32, a bool ...) goes through the f-string's
  ``format(value, "")`` and back here, as on the wire;
* degrees become radians with the parser's own expressions (``math.radians``, ``* _RAD``);
* every perceptor keeps its place and its dict keys.

Whatever the parser would refuse or read differently (a non-finite number, a name with a
space or a parenthesis, an unknown perception class, an empty message) is not handled here:
``perception_from_objects`` then returns None and the caller parses the text, which raises
the parser's own error. ``tests/teamenv/league/test_league_local_perception.py`` compares the
two paths on recorded cycles, bit for bit.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from .perception import GameState, Heard, JointState, Perception, PlayerSighting, Polar, Vision

_RAD = math.pi / 180.0           # as the parser's fast HJ path
_radians = math.radians
_isfinite = math.isfinite
#: number types whose f-string text reads back (``float``) as exactly ``float(value)``
_ROUND_TRIP = {float, np.float64, int, np.int64}
_ATOM = re.compile(r"[^\s()]+")
#: the names the parser reads differently inside ``(See ...)`` and ``(P ...)``
_SEE_RESERVED = {"P"}
_PLAYER_RESERVED = {"team", "id"}


class _Unhandled(Exception):
    """The text would not parse as these objects read (or not at all): parse the text."""


def _num(value: Any) -> float:
    """The float the parser reads from ``f"{value}"``; finite, as the parser demands."""
    if type(value) in _ROUND_TRIP:
        x = float(value)
    else:
        try:
            x = float(format(value, ""))
        except ValueError:
            raise _Unhandled from None
    if not _isfinite(x):
        raise _Unhandled
    return x


def _name(value: Any) -> str:
    """A name the parser reads back as itself (one atom)."""
    if type(value) is not str:
        raise _Unhandled
    if value not in _ATOMS:
        if not _ATOM.fullmatch(value):
            raise _Unhandled
        _ATOMS.add(value)
    return value


#: the names ``_name`` has checked (a few hundred: sensors, marks, parts, teams, play modes)
_ATOMS: set[str] = set()


def _floats(values: Any) -> list[float]:
    """Every element as ``_num`` reads it (a float64 array at once)."""
    if type(values) is np.ndarray and values.dtype == np.float64 and values.ndim == 1:
        out = values.tolist()
        if not all(map(_isfinite, out)):
            raise _Unhandled
        return out
    return [_num(v) for v in values]


def _polar(d: Any) -> Polar:
    """``(<name> (pol d az el))`` of an ObjectDetection."""
    r, a, e = d.distance, d.azimuth, d.inclination
    if type(r) is type(a) is type(e) is np.float64:      # the server's case, at once
        r, a, e = float(r), float(a), float(e)
        if _isfinite(r) and _isfinite(a) and _isfinite(e):
            return Polar(r, _radians(a), _radians(e))
        raise _Unhandled
    return Polar(_num(r), _radians(_num(a)), _radians(_num(e)))


# -- one function per rcsssmj perception class, as the parser's function of its perceptor ---
def _time(p: Perception, o: Any) -> None:          # (time (now T))
    if o.name != "now":
        raise _Unhandled
    p.time = _num(o.time)


def _game_state(p: Perception, o: Any) -> None:    # (GS (t ..)(pm ..)(tl ..)(tr ..)(sl ..)(sr ..))
    p.game = GameState(
        time=_num(o.play_time), play_mode=_name(o.play_mode),
        team_left=None if o.team_left is None else _name(o.team_left),
        team_right=None if o.team_right is None else _name(o.team_right),
        score_left=int(_num(o.score_left)), score_right=int(_num(o.score_right)))


def _pos(p: Perception, o: Any) -> None:
    p.positions[_name(o.name)] = (_num(o.x), _num(o.y), _num(o.z))


def _quat(p: Perception, o: Any) -> None:
    p.orientations[_name(o.name)] = (_num(o.qw), _num(o.qx), _num(o.qy), _num(o.qz))


def _gyro(p: Perception, o: Any) -> None:
    p.gyros[_name(o.name)] = (_radians(_num(o.rx)), _radians(_num(o.ry)), _radians(_num(o.rz)))


def _acc(p: Perception, o: Any) -> None:
    p.accelerometers[_name(o.name)] = (_num(o.ax), _num(o.ay), _num(o.az))


def _touch(p: Perception, o: Any) -> None:         # (TCH n NAME val A)
    p.touches[_name(o.name)] = _num(o.active) != 0


def _joints(p: Perception, o: Any) -> None:        # (HJ (n NAME)(ax A)(vx V)) per joint
    names = [_name(n) for n in o.joint_names]
    joints = p.joints
    for name, a, v in zip(names, _floats(o.joint_axs), _floats(o.joint_vxs), strict=False):
        joints[name] = JointState(a * _RAD, v * _RAD)


def _see(p: Perception, o: Any, object_cls: type, agent_cls: type) -> None:
    vision = Vision()
    for d in o.obj_detections:
        kind = type(d)
        if kind is object_cls:                      # (<name> (pol d az el))
            name = _name(d.name)
            if name in _SEE_RESERVED:
                raise _Unhandled
            vision.objects[name] = _polar(d)
        elif kind is agent_cls:                     # (P (team T)(id N)(<part> (pol ..))..)
            if d.name != "P":
                raise _Unhandled
            parts: dict[str, Polar] = {}
            for part in d.body_detections:
                if type(part) is not object_cls:
                    raise _Unhandled
                name = _name(part.name)
                if name in _PLAYER_RESERVED:
                    raise _Unhandled
                parts[name] = _polar(part)
            vision.players.append(PlayerSighting(_name(d.team_name), int(_num(d.player_no)),
                                                 parts))
        else:
            raise _Unhandled
    p.vision = vision


def _mic(p: Perception, o: Any) -> None:           # (MIC NAME (az base64) ...)
    _name(o.name)
    heard: list[Heard] = [] if p.heard is None else p.heard
    for azimuth, message in zip(o.azimuths, o.messages, strict=False):
        if not message:                             # b64 of nothing: an empty atom
            raise _Unhandled
        heard.append(Heard(_radians(_num(azimuth)), bytes(message)))
    p.heard = heard


_HANDLERS: dict[type, Callable[[Perception, Any], None]] | None = None


def _handlers() -> dict[type, Callable[[Perception, Any], None]]:
    """rcsssmj's perception classes -> their readers (rcsssmj imported on first use)."""
    global _HANDLERS
    if _HANDLERS is None:
        from rcsssmj.games.soccer.sim.soccer_perceptions import GameStatePerception
        from rcsssmj.sim import perceptions as rp

        def see(p: Perception, o: Any) -> None:
            _see(p, o, rp.ObjectDetection, rp.AgentDetection)

        _HANDLERS = {
            rp.TimePerception: _time, GameStatePerception: _game_state,
            rp.PositionPerception: _pos, rp.OrientationPerception: _quat,
            rp.GyroPerception: _gyro, rp.AccelerometerPerception: _acc,
            rp.TouchPerception: _touch, rp.JointStatePerception: _joints,
            rp.VisionPerception: see, rp.MicrophonePerception: _mic,
        }
    return _HANDLERS


def perception_from_objects(perceptions: Sequence[Any]) -> Perception | None:
    """The ``Perception`` that ``parse_perception`` reads from these objects' wire text, or
    None where the text must be parsed (see the module's doc)."""
    if not perceptions:
        return None                                 # the text would be "(syn)"
    handlers = _handlers()
    p = Perception()
    try:
        for o in perceptions:
            handler = handlers.get(type(o))
            if handler is None:
                return None
            handler(p, o)
    except _Unhandled:
        return None
    return p


def perception_text(perceptions: Sequence[Any], encoder: Any) -> str:
    """The wire text of these objects (the server's encoder; ``(syn)`` for none)."""
    return bytes(encoder.encode(perceptions) or b"(syn)").decode("ascii")


__all__ = ["perception_from_objects", "perception_text"]
