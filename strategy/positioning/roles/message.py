"""The role-vote message: a speaker's uniform number and its role vector, in one say text.

Agents are not told who spoke (the env hides speaker ids), but voting keeps the latest vector
per teammate, so the message carries its sender. Schema (``comms.schema``): ``sender``
(0..n-1, the speaker's player index) and ``roles`` (a permutation of 0..n-1 sent as its Lehmer
rank, as ``comms.messages.role_vector_schema`` does), plus 8 CRC check bits so a corrupt or
foreign text is rejected with probability 255/256. For 11 players: 4 + 26 + 8 = 38 bits,
7 characters on ``simspark`` (base64), 8 on ``mj``.
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import ArrayLike, NDArray

from comms.errors import DecodeError
from comms.schema import Int, Permutation, Schema

ROLE_VOTE_CHECK_BITS = 8


@functools.lru_cache(maxsize=32)
def role_vote_schema(n: int = 11, channel: str = "simspark") -> Schema:
    """The ``comms`` schema of an n-player role vote on ``channel`` ("simspark" or "mj")."""
    return Schema(
        f"role_vote_{n}",
        [Int("sender", 0, n - 1), Permutation("roles", n)],
        channel=channel,
        check_bits=ROLE_VOTE_CHECK_BITS,
    )


def encode_role_vote(sender: int, vector: ArrayLike, n: int = 11,
                     channel: str = "simspark") -> str:
    """The say text of ``sender``'s role ``vector`` (a permutation of 0..n-1).

    Raises ``comms.EncodeError`` if the sender or the vector does not fit the schema.
    """
    roles = tuple(np.asarray(vector).reshape(-1).tolist())
    return _encode(int(sender), roles, n, channel)


@functools.lru_cache(maxsize=4096)
def _encode(sender: int, roles: tuple[int, ...], n: int, channel: str) -> str:
    return role_vote_schema(n, channel).encode(sender=sender, roles=roles)


def decode_role_vote(text: str, n: int = 11,
                     channel: str = "simspark") -> tuple[int, NDArray[np.intp]] | None:
    """``(sender, vector)`` from a heard text, or None if it is not a valid n-player role vote.

    The vector is a read-only array (results are cached per text).
    """
    if not isinstance(text, str):
        return None
    return _decode(text, n, channel)


@functools.lru_cache(maxsize=4096)
def _decode(text: str, n: int, channel: str) -> tuple[int, NDArray[np.intp]] | None:
    try:
        rec = role_vote_schema(n, channel).decode(text)
    except DecodeError:
        return None
    vec = np.asarray(rec.roles, dtype=np.intp)
    vec.flags.writeable = False
    return rec.sender, vec
