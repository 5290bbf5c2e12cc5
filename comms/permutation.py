"""Lehmer-code ranking of permutations: a bijection between S_n and the integers 0..n!-1."""

import math
from collections.abc import Sequence

from comms.errors import DecodeError, EncodeError

_FACTORIALS: tuple[int, ...] = tuple(math.factorial(k) for k in range(64))


def permutation_bits(n: int) -> int:
    """Bits needed to hold the rank of a permutation of n items: ceil(log2(n!)) (11 -> 26)."""
    return (math.factorial(n) - 1).bit_length() if n > 1 else 0


def lehmer_rank(perm: Sequence[int], start: int = 0) -> int:
    """Lexicographic rank of `perm`, a permutation of start..start+n-1, in 0..n!-1.

    The rank is the Lehmer code read as a factorial-base number: digit i is how many of the
    items after position i are smaller than perm[i]. O(n^2) on a small list (n <= ~20).

    Raises:
        EncodeError: `perm` is not a permutation of start..start+n-1 (names the bad value).
    """
    n = len(perm)
    remaining = list(range(start, start + n))
    rank = 0
    facts = _FACTORIALS if n < len(_FACTORIALS) else None
    for i, x in enumerate(perm):
        try:
            k = remaining.index(x)
        except ValueError:
            raise EncodeError(
                f"not a permutation of {start}..{start + n - 1}: value {x!r} at position {i} "
                f"is out of range or repeated (got {list(perm)!r})"
            ) from None
        del remaining[k]
        if k:
            rank += k * (facts[n - 1 - i] if facts else math.factorial(n - 1 - i))
    return rank


def lehmer_unrank(rank: int, n: int, start: int = 0) -> list[int]:
    """Inverse of `lehmer_rank`: the permutation of start..start+n-1 with this rank.

    Raises:
        DecodeError: rank outside 0..n!-1.
    """
    total = _FACTORIALS[n] if n < len(_FACTORIALS) else math.factorial(n)
    if not 0 <= rank < total:
        raise DecodeError(f"permutation rank {rank!r} out of range 0..{total - 1} for n={n}")
    remaining = list(range(start, start + n))
    out = []
    for i in range(n - 1, -1, -1):
        f = _FACTORIALS[i] if i < len(_FACTORIALS) else math.factorial(i)
        k, rank = divmod(rank, f)
        out.append(remaining.pop(k))
    return out
