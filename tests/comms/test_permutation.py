"""Tests of Lehmer ranking: a bijection, exhaustively for small n and on samples of S_11."""

import itertools
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from comms.errors import DecodeError, EncodeError
from comms.permutation import lehmer_rank, lehmer_unrank, permutation_bits


@pytest.mark.parametrize("n", range(0, 8))
def test_exhaustive_bijection_small_n(n):
    # itertools.permutations yields lexicographic order: rank must be the position
    for k, perm in enumerate(itertools.permutations(range(n))):
        assert lehmer_rank(perm) == k
        assert lehmer_unrank(k, n) == list(perm)


@settings(max_examples=300, deadline=None)
@given(st.permutations(range(11)))
def test_s11_rank_unrank(perm):
    r = lehmer_rank(perm)
    assert 0 <= r < math.factorial(11)
    assert lehmer_unrank(r, 11) == list(perm)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, math.factorial(11) - 1))
def test_s11_unrank_rank(r):
    perm = lehmer_unrank(r, 11)
    assert sorted(perm) == list(range(11))
    assert lehmer_rank(perm) == r


def test_s11_bounds_and_start():
    assert lehmer_rank(range(11)) == 0
    assert lehmer_rank(range(10, -1, -1)) == math.factorial(11) - 1
    assert lehmer_unrank(0, 11, start=1) == list(range(1, 12))
    assert lehmer_rank(list(range(1, 12))[::-1], start=1) == math.factorial(11) - 1


def test_bits():
    assert permutation_bits(11) == 26
    assert [permutation_bits(n) for n in (1, 2, 3, 4, 5)] == [0, 1, 3, 5, 7]


@pytest.mark.parametrize("bad", [[0, 0, 1], [0, 1, 3], [0, 1, -1], [0, 1, 2.5]])
def test_not_a_permutation(bad):
    with pytest.raises(EncodeError, match="not a permutation"):
        lehmer_rank(bad)


@pytest.mark.parametrize("r", [-1, math.factorial(5)])
def test_rank_out_of_range(r):
    with pytest.raises(DecodeError, match="out of range"):
        lehmer_unrank(r, 5)
