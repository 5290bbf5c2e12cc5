"""Effector messages an agent sends the league server (rcsssmj 0.2.1).

=====================================  ===================================================
``(init T1 <team> <unum>)``            first message of a connection: robot model, team, number
``(beam x y theta)``                   place the robot (m, m, degrees); only before kick-off and
                                       after a goal, own half (the server mirrors x)
``(<motor> q dq kp kd tau)``           joint PD target: degrees, degrees/s, gains, torque (N m);
                                       torque = kp (q - q_now) + kd (dq - dq_now) + tau
``(SPK say <volume 0-100> <base64>)``  a message of at most 10 bytes (longer ones are not heard)
``(syn)``                              "done this cycle" in sync mode (no action)
=====================================  ===================================================

Angles are radians in our API and degrees on the wire; every function checks its input and
raises EffectorError naming the field and value.
"""

from __future__ import annotations

import base64
import math
import re
from collections.abc import Sequence
from typing import Any

import numpy as np

from teamenv.errors import ActionError, value_repr

#: the payload bytes the server delivers (longer messages are dropped by the hearing model)
SAY_MAX_BYTES = 10
ROBOT_MODELS = ("T1", "K1")
SYN = "(syn)"
_NAME = re.compile(r"[A-Za-z0-9_\-.]+")


class EffectorError(ActionError):
    """An effector request is malformed (bad name, non-finite number, too long a message)."""


def _name(value: str, what: str) -> str:
    if not isinstance(value, str) or not _NAME.fullmatch(value):
        raise EffectorError(f"{what}: {value_repr(value)} is not a name of letters, digits, _-.")
    return value


def _fmt(value: float, what: str) -> str:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise EffectorError(f"{what}: {value_repr(value)} is not a number") from None
    if not math.isfinite(x):
        raise EffectorError(f"{what}: {value_repr(value)} is not finite")
    return format(x, ".6g")


def init(team: str, unum: int, model: str = "T1") -> str:
    """``(init <model> <team> <unum>)``; uniform numbers 1-99 (the server takes them mod 100)."""
    if model not in ROBOT_MODELS:
        raise EffectorError(f"init: model {value_repr(model)} is not one of {ROBOT_MODELS}")
    if isinstance(unum, bool) or not isinstance(unum, int) or not 1 <= unum <= 99:
        raise EffectorError(f"init: uniform number {value_repr(unum)} is not an int in 1..99")
    return f"(init {model} {_name(team, 'init team')} {unum})"


def beam(x: float, y: float, theta: float) -> str:
    """``(beam x y theta)``: x, y in metres (own half, team frame), theta in radians."""
    return (f"(beam {_fmt(x, 'beam x')} {_fmt(y, 'beam y')} "
            f"{_fmt(math.degrees(_check(theta, 'beam theta')), 'beam theta')})")


def _check(value: float, what: str) -> float:
    """``value`` as a finite float (not rounded: degrees are formatted after conversion)."""
    _fmt(value, what)
    return float(value)


def motor(name: str, q: float, dq: float = 0.0, kp: float = 0.0, kd: float = 0.0,
          tau: float = 0.0) -> str:
    """One motor's PD command: target angle ``q`` (rad), velocity ``dq`` (rad/s), gains, torque."""
    what = f"motor {name!r}"
    _name(name, "motor name")
    qd = math.degrees(_check(q, f"{what} q"))
    dqd = math.degrees(_check(dq, f"{what} dq"))
    return (f"({name} {_fmt(qd, what)} {_fmt(dqd, what)} {_fmt(kp, f'{what} kp')} "
            f"{_fmt(kd, f'{what} kd')} {_fmt(tau, f'{what} tau')})")


def motors(names: Sequence[str], q: Any, dq: Any = 0.0, kp: Any = 0.0, kd: Any = 0.0,
           tau: Any = 0.0) -> str:
    """``message(*(motor(names[k], q[k], dq[k], kp[k], kd[k], tau[k]) for k ...))`` for a
    whole robot at once, the same text (each number formatted once, a number given for every
    motor once, instead of ``motor``'s checks and re-formatting per field): ``q`` ... ``tau``
    are sequences as long as ``names`` or one number for every motor. A bad name or a
    non-finite number raises ``motor``'s error."""
    names = list(names)
    n = len(names)
    for column in (q, dq, kp, kd, tau):
        if np.ndim(column) != 0 and len(column) != n:
            raise EffectorError(f"motors: {len(column)} values of a field for {n} motors")
    texts = []
    try:
        for k, column in enumerate((q, dq, kp, kd, tau)):
            angle = k < 2        # q and dq: radians, sent in degrees
            if np.ndim(column) == 0:
                x = float(column)                     # the same float() as motor's checks
                x = math.degrees(x) if angle else x
                if not math.isfinite(x):
                    raise ValueError
                texts.append([format(x, ".6g")] * n)
                continue
            values = column.tolist() if isinstance(column, np.ndarray) else list(column)
            xs = [math.degrees(float(v)) for v in values] if angle else \
                [float(v) for v in values]
            if not all(map(math.isfinite, xs)):
                raise ValueError
            texts.append([format(x, ".6g") for x in xs])
        if not all(isinstance(m, str) and (m in _GOOD_NAMES or _NAME.fullmatch(m))
                   for m in names):
            raise ValueError
    except (TypeError, ValueError, OverflowError):
        # motor's own checks name the motor, field and value
        return message(*(motor(m, *(c if np.ndim(c) == 0 else c[k]
                                    for c in (q, dq, kp, kd, tau)))
                         for k, m in enumerate(names)))
    _GOOD_NAMES.update(names)
    return "".join([f"({m} {a} {b} {c} {d} {e})"
                    for m, a, b, c, d, e in zip(names, *texts, strict=True)]) or SYN


#: motor names ``motors`` has checked already (a name is checked once per process)
_GOOD_NAMES: set[str] = set()


def say(payload: bytes, volume: float = 100.0) -> str:
    """``(SPK say <volume> <base64>)`` for a payload of at most SAY_MAX_BYTES bytes."""
    if not isinstance(payload, (bytes, bytearray)):
        raise EffectorError(f"say: payload must be bytes, not {type(payload).__name__}")
    if not 1 <= len(payload) <= SAY_MAX_BYTES:
        raise EffectorError(f"say: payload of {len(payload)} bytes; the server delivers "
                            f"1..{SAY_MAX_BYTES}: {bytes(payload)!r}")
    v = _check(volume, "say volume")
    if not 0 <= v <= 100:
        raise EffectorError(f"say: volume {value_repr(volume)} is not in 0..100")
    return f"(SPK say {_fmt(v, 'say volume')} {base64.b64encode(bytes(payload)).decode('ascii')})"


def message(*effectors: str) -> str:
    """One cycle's message: the effectors joined, ``(syn)`` when there are none."""
    return "".join(effectors) if effectors else SYN
