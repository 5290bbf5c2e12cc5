"""The team message of vision mode: what one agent knows that its teammates lack, in one say.

Under partial observability a teammate cannot see where I am, may not see the ball, and
computes its own role vector from its own belief. One message carries all three (source
documents 000 §3, 002 §2.3):

- ``sender``: the speaker's player index (the env does not say who spoke);
- ``roles``: its role vector (Lehmer rank of the permutation, as ``role_vote`` does);
- ``x``, ``y``, ``heading``, ``fallen``: its own pose, from its localization;
- ``ball_known``, ``ball_x``, ``ball_y``, ``ball_age``: its ball belief and how old it is
  (cycles, saturating), so a listener can prefer fresher reports;
- CRC check bits, so a corrupt or foreign text is rejected.

The schema is declared per (team size, pitch, channel); ``comms`` checks the budget at
declaration. The position resolution and the check bits are the finest that fit the channel
(simspark: 20 characters; mj: 10 bytes), chosen from ``RESOLUTIONS_M`` and ``CHECK_BITS``.
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from comms.errors import BudgetError, DecodeError
from comms.schema import Bool, Fixed, Int, Permutation, Schema
from teamenv.field import FieldSpec

RESOLUTIONS_M = (0.05, 0.1, 0.2, 0.25, 0.5)
CHECK_BITS = (8, 6, 4)
HEADING_STEPS = 64
BALL_AGE_MAX_CYCLES = 255
MARGIN_M = 1.0
"""Positions are sent within the pitch grown by this (players and the ball leave it)."""


class TeamReport(NamedTuple):
    """A decoded team message (metres, radians, cycles; team frame)."""

    sender: int
    roles: NDArray[np.intp]
    position: NDArray[np.float64]
    heading: float
    fallen: bool
    ball: NDArray[np.float64] | None
    ball_age_cycles: int


@functools.lru_cache(maxsize=32)
def team_message_schema(n: int, field: FieldSpec, channel: str = "simspark") -> Schema:
    """The finest team-message schema for ``n`` players on ``field`` that fits ``channel``."""
    hl, hw = field.half_length + MARGIN_M, field.half_width + MARGIN_M
    last: BudgetError | None = None
    for check in CHECK_BITS:
        for res in RESOLUTIONS_M:
            fields = [
                Int("sender", 0, n - 1), Permutation("roles", n),
                Fixed("x", -hl, hl, res, clip=True), Fixed("y", -hw, hw, res, clip=True),
                Int("heading", 0, HEADING_STEPS - 1), Bool("fallen"), Bool("ball_known"),
                Fixed("ball_x", -hl, hl, res, clip=True), Fixed("ball_y", -hw, hw, res, clip=True),
                Int("ball_age", 0, BALL_AGE_MAX_CYCLES),
            ]
            try:
                return Schema(f"team_report_{n}", fields, channel=channel, packing="radix",
                              check_bits=check)
            except BudgetError as exc:
                last = exc
    raise BudgetError(f"team message for {n} players on {field.name!r} does not fit the "
                      f"{channel!r} channel at any resolution in {RESOLUTIONS_M}: {last}")


def encode_team_report(schema: Schema, sender: int, roles: NDArray[np.intp],
                       position: NDArray[np.float64], heading: float, fallen: bool,
                       ball: NDArray[np.float64] | None, ball_age_cycles: int) -> str:
    """The say text of one report (values outside the pitch are clipped to its margin)."""
    step = 2.0 * math.pi / HEADING_STEPS
    h = int(round((heading % (2.0 * math.pi)) / step)) % HEADING_STEPS
    known = ball is not None
    bx, by = (float(ball[0]), float(ball[1])) if known else (0.0, 0.0)
    return schema.encode(
        sender=int(sender), roles=tuple(int(v) for v in roles), x=float(position[0]),
        y=float(position[1]), heading=h, fallen=bool(fallen), ball_known=known,
        ball_x=bx, ball_y=by, ball_age=int(min(max(ball_age_cycles, 0), BALL_AGE_MAX_CYCLES)))


def decode_team_report(schema: Schema, text: str) -> TeamReport | None:
    """The report in a heard text, or None if the text is not a valid team message."""
    if not isinstance(text, str) or not text:
        return None
    try:
        rec = schema.decode(text)
    except DecodeError:
        return None
    heading = rec.heading * 2.0 * math.pi / HEADING_STEPS
    if heading >= math.pi:
        heading -= 2.0 * math.pi
    ball = np.array((rec.ball_x, rec.ball_y)) if rec.ball_known else None
    return TeamReport(rec.sender, np.asarray(rec.roles, dtype=np.intp),
                      np.array((rec.x, rec.y)), heading, bool(rec.fallen), ball, rec.ball_age)
