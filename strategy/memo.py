"""A bounded cache of pure computations that a team's agents share.

Agents of one team run in one process; when they believe exactly the same thing they would
compute the same formation, role assignment and team-wide facts. Caching those pure results
by the exact inputs lets the first agent do the work and the others read it; an agent that
believes something else gets a different key and computes its own.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import TypeVar

T = TypeVar("T")

MEMO_LIMIT = 64
"""Entries kept before the cache is emptied (a cycle adds a handful; old cycles never hit)."""

_MISSING = object()


def memoized(memo: dict | None, key: Hashable, compute: Callable[[], T]) -> T:
    """``compute()``, cached in ``memo`` under ``key`` (None: no caching). ``compute`` must be
    a pure function of what ``key`` identifies; callers must not modify the result."""
    if memo is None:
        return compute()
    hit = memo.get(key, _MISSING)
    if hit is _MISSING:
        hit = remember(memo, key, compute())
    return hit


def remember(memo: dict, key: Hashable, value: T) -> T:
    """Keep ``value`` in ``memo`` under ``key`` (for results computed elsewhere, e.g. several
    keys' at once); the cache is emptied first when full. Returns ``value``."""
    if len(memo) >= MEMO_LIMIT:
        memo.clear()
    memo[key] = value
    return value
