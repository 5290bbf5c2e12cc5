"""The shared cache of pure computations: one computation per key, bounded size."""

from __future__ import annotations

from strategy.memo import MEMO_LIMIT, memoized


def test_memoized_computes_once_per_key_and_not_at_all_without_a_memo():
    calls = []
    memo: dict = {}
    for key in ("a", "a", "b", "a"):
        memoized(memo, key, lambda key=key: calls.append(key) or key.upper())
    assert calls == ["a", "b"]
    assert memoized(None, "a", lambda: "fresh") == "fresh"


def test_memoized_stays_bounded():
    memo: dict = {}
    for k in range(3 * MEMO_LIMIT):
        assert memoized(memo, k, lambda k=k: k * k) == k * k
        assert len(memo) <= MEMO_LIMIT
