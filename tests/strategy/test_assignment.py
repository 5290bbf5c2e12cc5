"""Role assignment: MMD+MSD² equals brute force over all permutations; greedy is never better."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategy.positioning.roles import (
    RoleAssignmentError,
    assign_roles,
    assign_roles_all,
    solve_greedy,
    solve_mmd_msd2,
)
from strategy.positioning.roles import assignment as assignment_module

_PERMS = {n: np.array(list(itertools.permutations(range(n)))) for n in range(1, 9)}


def brute_force(dist: np.ndarray) -> tuple[float, float]:
    """(longest walk, sum of squares) of the lexicographic optimum, by enumeration."""
    n = dist.shape[0]
    walks = dist[np.arange(n), _PERMS[n]]  # (n!, n)
    longest = walks.max(axis=1)
    best = longest.min()
    return float(best), float((walks[longest == best] ** 2).sum(axis=1).min())


def check_optimal(dist: np.ndarray) -> None:
    rows, cols = solve_mmd_msd2(dist)
    assert sorted(rows.tolist()) == list(range(dist.shape[0]))
    assert sorted(cols.tolist()) == list(range(dist.shape[1]))
    walks = dist[rows, cols]
    best_max, best_sq = brute_force(dist)
    assert walks.max() == best_max  # exactly: both are entries of dist
    assert (walks**2).sum() == pytest.approx(best_sq, rel=1e-12, abs=1e-12)
    g_rows, g_cols = solve_greedy(dist)
    assert dist[g_rows, g_cols].max() >= walks.max()


@pytest.mark.parametrize("n", range(1, 9))
def test_equals_brute_force_on_random_instances(n):
    rng = np.random.default_rng(100 + n)
    for trial in range(40 if n < 8 else 12):
        players = rng.uniform([-15, -10], [15, 10], (n, 2))
        positions = rng.uniform([-15, -10], [15, 10], (n, 2))
        dist = np.hypot(*(players[:, None, :] - positions[None, :, :]).transpose(2, 0, 1))
        if trial % 4 == 0:
            dist = np.round(dist)  # many ties
        check_optimal(dist)


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 7).flatmap(
    lambda n: st.lists(st.lists(st.integers(0, 6), min_size=n, max_size=n), min_size=n,
                       max_size=n)))
def test_equals_brute_force_on_integer_matrices_with_ties(rows):
    check_optimal(np.array(rows, dtype=np.float64))


def test_binary_search_fallback_is_exact(monkeypatch):
    monkeypatch.setattr(assignment_module, "_TIGHTEN_ROUNDS", 0)
    rng = np.random.default_rng(7)
    for n in range(1, 8):
        for _ in range(30):
            check_optimal(rng.uniform(0, 10, (n, n)))
            check_optimal(np.round(rng.uniform(0, 5, (n, n))))


def test_rectangular_problems_leave_the_far_positions_out():
    dist = np.array([[1.0, 9.0, 5.0], [9.0, 1.0, 5.0]])
    rows, cols = solve_mmd_msd2(dist)
    assert cols.tolist() == [0, 1]
    with pytest.raises(RoleAssignmentError):
        solve_mmd_msd2(dist.T)


def test_longest_walk_never_worse_than_greedy_and_sum_is_second():
    # greedy takes the closest pair (A -> P, 0.9 m) and leaves B a 3 m walk to Q
    players = np.array([[0.0, 0.0], [2.0, 0.0]])
    positions = np.array([[0.9, 0.0], [-1.0, 0.0]])
    best = assign_roles(players, positions, goalie=None)
    greedy = assign_roles(players, positions, goalie=None, method="greedy")
    assert best.position_of.tolist() == [1, 0]
    assert best.max_distance == pytest.approx(1.1)
    assert greedy.position_of.tolist() == [0, 1]
    assert greedy.max_distance == pytest.approx(3.0)
    # equal longest walk: the smaller sum of squares wins
    players = np.array([[0.0, 0.0], [0.0, 1.0], [10.0, 0.0]])
    positions = np.array([[0.0, 1.0], [0.0, 0.0], [10.0, 5.0]])
    a = assign_roles(players, positions, goalie=None)
    assert a.position_of.tolist() == [1, 0, 2]
    assert a.max_distance == pytest.approx(5.0) and a.sum_squared == pytest.approx(25.0)  # not 27


def test_goalie_is_fixed():
    players = np.array([[5.0, 0.0], [-14.0, 0.0], [0.0, 3.0]])
    positions = np.array([[-14.0, 0.0], [5.0, 0.0], [0.0, 3.0]])
    # the goalie walks 19 m to its goal; the others minimise their own longest walk
    fixed = assign_roles(players, positions)
    assert fixed.position_of.tolist() == [0, 2, 1]
    assert fixed.max_distance == pytest.approx(19.0)
    free = assign_roles(players, positions, goalie=None)
    assert free.position_of.tolist() == [1, 0, 2]
    other = assign_roles(players, positions, goalie=2, goalie_position=1)
    assert other.position_of[2] == 1


def test_fallen_players_pay_a_penalty():
    # upright: player 1 walks 2 m to (0, 3), player 2 1 m to (0, 0); longest walk 2 m.
    # player 1 fallen (+5 m): it would then be the bottleneck (7 m), so it takes the nearest
    # position (6 m) and player 2 walks 4 m instead.
    players = np.array([[-14.0, 0.0], [0.0, 1.0], [0.0, -1.0]])
    positions = np.array([[-14.0, 0.0], [0.0, 0.0], [0.0, 3.0]])
    up = assign_roles(players, positions)
    assert up.position_of.tolist() == [0, 2, 1]
    assert up.max_distance == pytest.approx(2.0)
    fallen = assign_roles(players, positions, fallen=[False, True, False], fallen_penalty_m=5.0)
    assert fallen.position_of.tolist() == [0, 1, 2]
    assert fallen.max_distance == pytest.approx(6.0)


def test_missing_players_get_the_leftover_positions():
    players = np.array([[-14.0, 0.0], [np.nan, np.nan], [5.0, 5.0], [5.0, -5.0]])
    positions = np.array([[-14.0, 0.0], [5.0, -5.0], [5.0, 5.0], [-3.0, 0.0]])
    a = assign_roles(players, positions, available=[True, False, True, True])
    assert a.position_of.tolist() == [0, 3, 2, 1]
    assert sorted(a.position_of.tolist()) == [0, 1, 2, 3]
    assert a.max_distance == pytest.approx(0.0)
    nobody = assign_roles(players, positions, available=[False] * 4, goalie=None)
    assert sorted(nobody.position_of.tolist()) == [0, 1, 2, 3]
    assert nobody.max_distance == 0.0


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 11), st.integers(0, 2**31), st.booleans())
def test_result_is_always_a_permutation(n, seed, goalie):
    rng = np.random.default_rng(seed)
    players = rng.uniform(-15, 15, (n, 2))
    positions = rng.uniform(-15, 15, (n, 2))
    available = rng.random(n) < 0.8
    fallen = rng.random(n) < 0.2
    a = assign_roles(players, positions, available=available, fallen=fallen,
                     goalie=0 if goalie else None)
    assert sorted(a.position_of.tolist()) == list(range(n))
    if goalie:
        assert a.position_of[0] == 0


def test_bad_input_names_the_field():
    ok = np.zeros((3, 2))
    with pytest.raises(RoleAssignmentError, match="positions has 2 rows, expected 3"):
        assign_roles(ok, np.zeros((2, 2)))
    with pytest.raises(RoleAssignmentError, match=r"players must have shape \(N, 2\)"):
        assign_roles(np.zeros(3), ok)
    bad = ok.copy()
    bad[1, 0] = np.inf
    with pytest.raises(RoleAssignmentError, match=r"players\[1\] = \(inf, 0\.0\) is not finite"):
        assign_roles(bad, ok)
    with pytest.raises(RoleAssignmentError, match="positions must be finite"):
        assign_roles(ok, bad)
    with pytest.raises(RoleAssignmentError, match="available must have shape"):
        assign_roles(ok, ok, available=[True])
    with pytest.raises(RoleAssignmentError, match="goalie=5"):
        assign_roles(ok, ok, goalie=5)
    with pytest.raises(RoleAssignmentError, match="method must be"):
        assign_roles(ok, ok, method="auction")
    with pytest.raises(RoleAssignmentError, match="fallen_penalty_m"):
        assign_roles(ok, ok, fallen_penalty_m=-1.0)


@pytest.mark.parametrize("goalie", [0, None])
def test_problems_solved_together_get_the_bits_each_gets_alone(goalie):
    # A team's agents in vision mode, each with its own belief: unavailable players (NaN
    # positions), fallen ones, scales from centimetres to a pitch
    rng = np.random.default_rng(5)
    a, n = 40, 7
    players = rng.uniform(-15, 15, (a, n, 2)) * rng.uniform(0.01, 1.0, (a, 1, 1))
    positions = rng.uniform(-15, 15, (a, n, 2))
    available = rng.random((a, n)) < 0.85
    players[~available] = np.nan
    fallen = rng.random((a, n)) < 0.2
    together = assign_roles_all(players, positions, available=available,
                                                  fallen=fallen, goalie=goalie)
    for k, got in enumerate(together):
        alone = assign_roles(players[k], positions[k], available=available[k],
                             fallen=fallen[k], goalie=goalie)
        assert got.position_of.tolist() == alone.position_of.tolist()
        assert (got.max_distance, got.sum_squared) == (alone.max_distance, alone.sum_squared)
    # and the distances are scipy's cdist, bit for bit
    from scipy.spatial.distance import cdist
    d = assignment_module._distances(np.nan_to_num(players), positions)
    assert all(np.array_equal(d[k], cdist(np.nan_to_num(players[k]), positions[k]))
               for k in range(a))


def test_stacked_input_is_checked():
    with pytest.raises(RoleAssignmentError, match=r"players must have shape \(A, N, 2\)"):
        assign_roles_all(np.zeros((3, 2)), np.zeros((3, 2)))
    with pytest.raises(RoleAssignmentError, match=r"positions has shape \(1, 2, 2\)"):
        assign_roles_all(np.zeros((1, 3, 2)), np.zeros((1, 2, 2)))
    with pytest.raises(RoleAssignmentError, match=r"fallen must have shape \(1, 3\)"):
        assign_roles_all(np.zeros((1, 3, 2)), np.zeros((1, 3, 2)),
                                           fallen=np.zeros(3, bool))
