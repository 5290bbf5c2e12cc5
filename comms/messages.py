"""Typed messages the strategies need (role vector, ball, sender state, marking) and their sizes."""

import functools
import math

from comms.schema import Array, Bool, Fixed, Int, Permutation, Schema

#: What the source documents spend on an 11-player role vector (seed 000: base64 of the
#: vector, "around 110 - 120 bits").
SOURCE_ROLE_VECTOR_BITS = (110, 120)

#: Half-extent (m) covered by position fields: the SimSpark field (30 x 20 m) plus 1 m.
SIMSPARK_HALF_EXTENT = (16.0, 11.0)


@functools.lru_cache(maxsize=64)
def role_vector_schema(
    n: int = 11,
    *,
    channel: str = "simspark",
    codec: str = "auto",
    start: int = 0,
    check_bits: int = 0,
) -> Schema:
    """The role vector of `n` players: `roles[i]` = the formation position given to player i.

    One field, "roles", a permutation of start..start+n-1 sent as its Lehmer rank:
    ceil(log2(n!)) bits (26 for 11, 5 base64 characters), against the source documents'
    110-120 bits. `encode({"roles": [...]})` / `decode(text).roles` (a tuple).
    """
    return Schema(
        f"role_vector_{n}",
        [Permutation("roles", n, start=start)],
        channel=channel,
        codec=codec,
        check_bits=check_bits,
    )


#: The 11-player role vector on the simspark channel (26 bits, base64, 5 chars).
ROLE_VECTOR = role_vector_schema(11)


def position_fields(
    prefix: str,
    half_length: float = SIMSPARK_HALF_EXTENT[0],
    half_width: float = SIMSPARK_HALF_EXTENT[1],
    resolution: float = 0.1,
) -> list[Fixed]:
    """Two clipped fixed-point fields `<prefix>_x`, `<prefix>_y` (metres, team frame)."""
    return [
        Fixed(f"{prefix}_x", -half_length, half_length, resolution, clip=True),
        Fixed(f"{prefix}_y", -half_width, half_width, resolution, clip=True),
    ]


@functools.lru_cache(maxsize=64)
def team_state_schema(
    n: int = 11,
    *,
    channel: str = "simspark",
    half_length: float = SIMSPARK_HALF_EXTENT[0],
    half_width: float = SIMSPARK_HALF_EXTENT[1],
    resolution: float = 0.1,
    check_bits: int = 8,
) -> Schema:
    """One message with everything a player tells its team each time it speaks.

    Fields: roles (permutation of 0..n-1), ball_x / ball_y (m, clipped), ball_age (s since the
    sender last saw the ball, 0-3.1 in 0.1 s steps, clipped), self_x / self_y (m, clipped),
    fallen (bool); plus `check_bits` CRC bits. 11 players on the SimSpark field: 66 + 8 = 74
    bits: fits `simspark` (base64, 13 chars) and `mj` (80 bits).
    """
    return Schema(
        f"team_state_{n}",
        [
            Permutation("roles", n),
            *position_fields("ball", half_length, half_width, resolution),
            Fixed("ball_age", 0.0, 3.1, 0.1, clip=True),
            *position_fields("self", half_length, half_width, resolution),
            Bool("fallen"),
        ],
        channel=channel,
        check_bits=check_bits,
    )


TEAM_STATE = team_state_schema(11)

#: Ball seen by the sender: position (0.1 m) and age (0.1 s) - 22 bits.
BALL = Schema(
    "ball",
    [*position_fields("ball"), Fixed("ball_age", 0.0, 3.1, 0.1, clip=True)],
)

#: The sender's own pose and state: position (0.1 m), heading (5 degrees), fallen - 25 bits.
SELF_STATE = Schema(
    "self_state",
    [
        *position_fields("self"),
        Fixed("heading", -math.pi, math.pi, math.radians(5)),
        Bool("fallen"),
    ],
)


@functools.lru_cache(maxsize=64)
def marking_schema(n: int = 11, *, channel: str = "simspark") -> Schema:
    """Marking assignment: `marks[i]` = uniform number (1..n) of the opponent player i marks,
    0 for none (seed 000 section 5.4). (n+1)**n values, one field: 40 bits for 11."""
    return Schema(
        f"marking_{n}",
        [Array("marks", Int("opponent", 0, n), n)],
        channel=channel,
    )


MARKING = marking_schema(11)


@functools.lru_cache(maxsize=16)
def opponents_schema(
    n: int = 11,
    *,
    half_length: float = 15.0,
    half_width: float = 10.0,
    resolution: float = 0.5,
) -> Schema:
    """All `n` opponent positions at `resolution` metres in one message (radix packing).

    11 opponents at 0.5 m on the SimSpark field: 11 log2(61 * 41) = 124.2 -> 125 bits: fits
    only the base-92 big-integer codec (130 bits); base64 (120) and `mj` (80) are too small.
    A position is sent as cell = ix * ny + iy with ix = round((x + half_length) / resolution),
    iy = round((y + half_width) / resolution), ny = round(2 half_width / resolution) + 1.
    """
    nx = round(2 * half_length / resolution) + 1
    ny = round(2 * half_width / resolution) + 1
    cell = Int("cell", 0, nx * ny - 1)
    return Schema(f"opponents_{n}", [Array("cells", cell, n)], packing="radix")


def catalogue() -> list[dict]:
    """Sizes of the shipped message types on both channels (rows for the README table).

    Each row: name, bits, information (log2 of distinct messages), simspark codec and chars,
    fits_mj (bool).
    """
    rows = []
    for s in (
        ROLE_VECTOR,
        BALL,
        SELF_STATE,
        MARKING,
        TEAM_STATE,
        opponents_schema(),
    ):
        rows.append(
            {
                "name": s.name,
                "bits": s.bits,
                "information": round(s.information_bits, 1),
                "simspark_codec": s.codec_name,
                "simspark_chars": s.chars,
                "fits_mj": s.bits <= 80,
            }
        )
    return rows
