"""Voting: a permutation always; the max-vote, lexicographically smallest one; the team converges."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategy.positioning.roles import (
    RoleVoter,
    VotingError,
    is_permutation,
    tally_votes,
    vote_matrix,
)
from strategy.positioning.roles.message import decode_role_vote, encode_role_vote, role_vote_schema
from strategy.positioning.roles.voting import _tally, _tally_slow


def brute_force(vectors: np.ndarray) -> list[int]:
    n = vectors.shape[1]
    votes = vote_matrix(vectors, n)
    best, best_perm = -1, None
    for perm in itertools.permutations(range(n)):  # lexicographic order
        score = int(votes[np.arange(n), list(perm)].sum())
        if score > best:
            best, best_perm = score, list(perm)
    return best_perm


@settings(max_examples=150, deadline=None)
@given(st.integers(1, 6).flatmap(lambda n: st.lists(st.permutations(list(range(n))),
                                                    min_size=1, max_size=8)))
def test_tally_is_the_max_vote_lexicographically_smallest_permutation(vectors):
    arr = np.array(vectors)
    result = tally_votes(arr)
    assert is_permutation(result, arr.shape[1])
    assert result.tolist() == brute_force(arr)
    assert _tally_slow(vote_matrix(arr, arr.shape[1])).tolist() == result.tolist()


def test_per_player_modes_win_when_they_form_a_permutation():
    a = [0, 1, 2, 3]
    b = [0, 2, 1, 3]
    assert tally_votes([a, a, b]).tolist() == a
    assert tally_votes([b, a, b]).tolist() == b
    # unanimous, any order of speakers
    assert tally_votes([b] * 5).tolist() == b


def test_modes_that_collide_are_repaired():
    # player 1 and player 2 both most often voted to position 1: repaired into a permutation
    vectors = [[0, 1, 2, 3], [0, 2, 1, 3], [0, 1, 3, 2], [0, 3, 1, 2], [0, 2, 1, 3]]
    result = tally_votes(vectors)
    assert is_permutation(result, 4)
    assert result.tolist() == brute_force(np.array(vectors))


def test_ties_break_to_the_lexicographically_smallest():
    a, b = [0, 2, 1], [0, 1, 2]
    assert tally_votes([a, b]).tolist() == [0, 1, 2]
    assert tally_votes([b, a]).tolist() == [0, 1, 2]  # speaker order does not matter
    assert tally_votes([[1, 0], [0, 1]]).tolist() == [0, 1]


def test_slow_path_for_large_teams_agrees():
    rng = np.random.default_rng(3)
    for n in (4, 9, 12):
        vecs = np.array([rng.permutation(n) for _ in range(5)])
        votes = vote_matrix(vecs, n)
        assert _tally_slow(votes).tolist() == _tally(votes).tolist()
    big = np.array([rng.permutation(14) for _ in range(3)])
    assert is_permutation(tally_votes(big), 14)


def test_bad_vectors_are_rejected():
    with pytest.raises(VotingError, match=r"vectors\[1\] = \[0, 0, 2\] is not a permutation"):
        tally_votes([[0, 1, 2], [0, 0, 2]])
    with pytest.raises(VotingError, match="shape"):
        tally_votes(np.zeros((0, 3), dtype=int))
    voter = RoleVoter(3, me=0)
    with pytest.raises(VotingError, match="speaker=5"):
        voter.hear(5, [0, 1, 2], 0)
    with pytest.raises(VotingError, match="not a permutation"):
        voter.hear(1, [0, 1, 1], 0)
    with pytest.raises(VotingError, match="own vector"):
        voter.vote([2, 2, 2], 0)
    with pytest.raises(VotingError, match="me=3"):
        RoleVoter(3, me=3)
    assert not is_permutation([0.0, 1.0], 2)
    assert not is_permutation([0, 1], 3)


def test_age_limit_and_own_echo():
    voter = RoleVoter(3, me=0, max_age_cycles=10)
    other = [0, 2, 1]
    voter.hear(1, other, cycle=0)
    voter.hear(2, other, cycle=0)
    assert voter.vote([0, 1, 2], cycle=5).tolist() == other  # 2 fresh votes beat our 1
    assert voter.fresh_speakers(10).tolist() == [1, 2]
    assert voter.vote([0, 1, 2], cycle=11).tolist() == [0, 1, 2]  # theirs are too old now
    voter.hear(0, other, cycle=12)  # our own echo is ignored: our vote is always our latest
    assert voter.vote([0, 1, 2], cycle=12).tolist() == [0, 1, 2]
    voter.reset()
    assert voter.fresh_speakers(12).tolist() == []


def simulate(own_vectors: list[list[int]], cycles: int, loss: float, seed: int,
             max_age: int = 60) -> list[list[list[int]]]:
    """Agents say their own vector every cycle; each hears one random teammate's per cycle
    (as the simspark channel allows) unless lost. Returns every agent's result per cycle."""
    rng = np.random.default_rng(seed)
    n = len(own_vectors)
    voters = [RoleVoter(n, i, max_age) for i in range(n)]
    history = []
    said = [encode_role_vote(i, v, n) for i, v in enumerate(own_vectors)]
    for c in range(cycles):
        results = []
        for i, voter in enumerate(voters):
            speaker = int(rng.integers(n - 1))
            speaker += speaker >= i
            if rng.random() >= loss:
                sender, vec = decode_role_vote(said[speaker], n)
                voter.hear(sender, vec, c)
            results.append(voter.vote(own_vectors[i], c).tolist())
        history.append(results)
    return history


def test_team_converges_despite_disagreeing_world_models_and_lost_messages():
    rng = np.random.default_rng(11)
    n = 11
    truth = [0, *rng.permutation(np.arange(1, n)).tolist()]
    own = []
    for i in range(n):
        v = list(truth)
        if i % 3 == 1:  # a third of the team believes something else (two roles swapped)
            a, b = rng.choice(np.arange(1, n), 2, replace=False)
            v[a], v[b] = v[b], v[a]
        own.append(v)
    history = simulate(own, cycles=150, loss=0.4, seed=5)
    for results in history:
        for r in results:
            assert sorted(r) == list(range(n))
    final = history[-1]
    assert all(r == truth for r in final)  # every agent adopted the majority's assignment
    first_agree = next(c for c, res in enumerate(history) if all(r == truth for r in res))
    assert first_agree < 120


def test_a_tie_resolves_to_the_same_assignment_everywhere():
    a, b = [0, 1, 2, 3], [0, 1, 3, 2]
    history = simulate([a, b, a, b], cycles=80, loss=0.3, seed=2)
    final = history[-1]
    assert all(r == final[0] for r in final)
    assert final[0] == a  # lexicographically smallest of the tied


# ----------------------------------------------------------------------------- message
def test_role_vote_message_round_trip_and_budget():
    s = role_vote_schema(11, "simspark")
    assert s.bits == 4 + 26 + 8 and s.chars <= 20
    assert role_vote_schema(11, "mj").bits <= 80
    vec = [0, 3, 1, 2, 4, 5, 6, 10, 8, 9, 7]
    text = encode_role_vote(7, vec)
    sender, out = decode_role_vote(text)
    assert sender == 7 and out.tolist() == vec
    assert decode_role_vote("not a vote!") is None
    assert decode_role_vote(text, n=7) is None  # another team size's schema rejects it
    assert decode_role_vote(123) is None  # type: ignore[arg-type]


def test_since_own_change_drops_vectors_heard_before_the_own_vector_changed():
    voter = RoleVoter(3, me=0, max_age_cycles=60)
    old, new = [0, 2, 1], [0, 1, 2]
    assert voter.vote(old, cycle=0, since_own_change=True).tolist() == old
    voter.hear(1, old, cycle=1)
    voter.hear(2, old, cycle=2)
    # our vector changes at cycle 3: the two vectors heard before are stale, ours decides
    assert voter.vote(new, cycle=3, since_own_change=True).tolist() == new
    # without the rule the two stale vectors outvote ours
    plain = RoleVoter(3, me=0, max_age_cycles=60)
    plain.vote(old, cycle=0)
    plain.hear(1, old, cycle=1)
    plain.hear(2, old, cycle=2)
    assert plain.vote(new, cycle=3).tolist() == old
    # vectors heard after the change count again: two fresh teammates outvote us
    voter.hear(1, [1, 0, 2], cycle=4)
    voter.hear(2, [1, 0, 2], cycle=5)
    assert voter.vote(new, cycle=5, since_own_change=True).tolist() == [1, 0, 2]
    # an unchanged own vector keeps them counting; a reset forgets the change
    assert voter.vote(new, cycle=6, since_own_change=True).tolist() == [1, 0, 2]
    voter.reset()
    assert voter.vote(new, cycle=0, since_own_change=True).tolist() == new
