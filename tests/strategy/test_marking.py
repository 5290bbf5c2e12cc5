"""Marking (seed 000 §5.4) in hand-built scenes on the simspark pitch (our goal centre (-15, 0))."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from strategy.positioning.marking import (
    MarkingError,
    MarkingParams,
    apply_marking,
    dangerous_opponents,
    marking_positions,
)
from strategy.positioning.roles import assign_roles

PRM = MarkingParams(shoot_range_m=9.0, min_ball_distance_m=2.0, max_behind_ball_m=3.0,
                    mark_distance_m=1.5, max_markers=None)


def test_each_condition_in_one_scene():
    ball = [-5.0, 0.0]
    opponents = np.array([
        [-5.5, 0.5],   # 0: the closest opponent to the ball -> not marked
        [-10.0, 3.0],  # 1: 5.8 m from goal, 5.8 m from ball, in front of it -> marked
        [0.0, 0.0],    # 2: 15 m from our goal: cannot shoot -> not marked
        [-9.0, -6.0],  # 3: 8.5 m from goal, 7.2 m from ball -> marked
        [-6.0, 1.2],   # 4: 1.6 m from the ball: too close -> not marked
        [-11.0, 0.0],  # 5: would qualify but is not in our world model -> not marked
    ])
    present = [True, True, True, True, True, False]
    marked = dangerous_opponents(ball, opponents, "simspark", PRM, present)
    assert marked.tolist() == [1, 3]  # sorted by distance to our goal: 5.83 m, 8.49 m


def test_too_far_behind_the_ball_is_not_marked():
    ball = [-12.0, 5.0]
    opponents = np.array([
        [-12.5, 5.0],  # closest to the ball
        [-8.0, -2.0],  # shooting range (7.3 m) but 4 m behind the ball -> not marked
        [-9.5, -2.0],  # 2.5 m behind the ball: within 3 m -> marked
    ])
    assert dangerous_opponents(ball, opponents, "simspark", PRM).tolist() == [2]
    relaxed = MarkingParams(max_behind_ball_m=5.0, max_markers=None)
    assert dangerous_opponents(ball, opponents, "simspark", relaxed).tolist() == [2, 1]


def test_closest_to_ball_is_never_marked_even_if_dangerous():
    ball = [-11.0, 0.0]
    opponents = np.array([[-13.5, 0.0], [-12.0, 4.0]])  # 0 is 2.5 m from the ball, closest
    assert dangerous_opponents(ball, opponents, "simspark", PRM).tolist() == [1]


def test_marking_position_is_on_the_line_to_our_goal_centre():
    marks = marking_positions([[-10.0, 3.0], [-14.0, 0.5]], "simspark", 1.5)
    goal = np.array([-15.0, 0.0])
    d0 = goal - np.array([-10.0, 3.0])
    np.testing.assert_allclose(marks[0], [-10.0, 3.0] + 1.5 * d0 / np.hypot(*d0))
    assert np.hypot(*(marks[0] - [-10.0, 3.0])) == pytest.approx(1.5)
    # an opponent 1.1 m from the goal centre: the marker stands on the goal centre
    np.testing.assert_allclose(marks[1], goal)


def test_nearest_formation_positions_are_replaced_and_goalie_protected():
    home = np.array([
        [-14.0, 0.0],  # 0 goalie: nearest to everything near our goal, but protected
        [-9.0, 4.0],   # 1
        [-9.0, -4.0],  # 2
        [-3.0, 0.0],   # 3
        [2.0, 5.0],    # 4
    ])
    ball = [-5.0, 0.0]
    opponents = np.array([[-5.5, 0.5], [-10.0, 3.0], [-9.0, -6.0], [10.0, 0.0]])
    result = apply_marking(home, ball, opponents, "simspark", PRM)
    assert result.marked.tolist() == [1, 3 - 1]  # opponents 1 and 2
    # the marker of opponent 1 replaces position 1, the one of opponent 2 position 2
    assert result.replaced.tolist() == [1, 2]
    np.testing.assert_allclose(result.positions[1], result.marking_positions[0])
    np.testing.assert_allclose(result.positions[2], result.marking_positions[1])
    np.testing.assert_allclose(result.positions[[0, 3, 4]], home[[0, 3, 4]])
    # then role assignment runs on the result
    players = home + 0.3
    a = assign_roles(players, result.positions)
    assert sorted(a.position_of.tolist()) == list(range(5))


def test_replaced_positions_minimise_the_sum_of_distances():
    """Checked against brute force over every choice of replaced positions."""
    home = np.array([[-14.0, 0.0], [1.9, 0.0], [-1.5, 0.0], [10.0, 9.0]])
    opponents = np.array([[5.0, 9.0], [-13.0, 5.0], [-11.0, -6.0]])
    prm = MarkingParams(shoot_range_m=30.0, min_ball_distance_m=0.0, max_behind_ball_m=30.0,
                        max_markers=None)
    result = apply_marking(home, [6.0, 9.0], opponents, "simspark", prm)
    marks = result.marking_positions
    def cost(cols):
        return sum(float(np.hypot(*(marks[k] - home[c]))) for k, c in enumerate(cols))

    best = min(cost(cols) for cols in itertools.permutations([1, 2, 3], len(marks)))
    assert len(marks) == 2
    assert cost(result.replaced.tolist()) == pytest.approx(best)


def test_max_markers_keeps_the_most_dangerous():
    ball = [0.0, 0.0]
    opponents = np.array([[0.5, 0.0], [-7.0, 2.0], [-10.0, 1.0], [-12.0, -2.0], [-8.0, -3.0]])
    prm = MarkingParams(max_markers=2)
    home = np.array([[-14.0, 0.0], [-9.0, 4.0], [-9.0, -4.0], [-3.0, 0.0], [2.0, 5.0]])
    result = apply_marking(home, ball, opponents, "simspark", prm)
    assert result.marked.tolist() == [3, 2]  # the two closest to our goal centre


def test_no_danger_no_change_and_fields_scale():
    home = np.array([[-14.0, 0.0], [-9.0, 4.0]])
    result = apply_marking(home, [10.0, 0.0], [[11.0, 0.0], [12.0, 3.0]], "simspark")
    assert result.marked.size == 0
    np.testing.assert_allclose(result.positions, home)
    fifa = MarkingParams.for_field("fifa")
    assert fifa.shoot_range_m == pytest.approx(9.0 * 3.5)
    assert fifa.mark_distance_m == 1.5
    assert MarkingParams.for_field("simspark", max_markers=1).max_markers == 1
    with pytest.raises(MarkingError, match="unknown parameter"):
        MarkingParams.for_field("fifa", range=3)


def test_bad_input():
    with pytest.raises(MarkingError, match="shoot_range_m"):
        MarkingParams(shoot_range_m=-1.0)
    with pytest.raises(MarkingError, match="ball must be"):
        dangerous_opponents([np.nan, 0.0], [[0.0, 0.0]], "simspark")
    with pytest.raises(MarkingError, match=r"opponents\[1\] = \(nan, 0\.0\) is not finite"):
        dangerous_opponents([0.0, 0.0], [[0.0, 0.0], [np.nan, 0.0]], "simspark")
    # an absent opponent may carry junk
    assert dangerous_opponents([0.0, 0.0], [[-10.0, 0.0], [np.nan, 0.0], [-1, 0]], "simspark",
                               PRM, present=[True, False, True]).tolist() == [0]
    with pytest.raises(MarkingError, match="protected position 9"):
        apply_marking(np.zeros((3, 2)), [0.0, 0.0], [[-10.0, 0.0], [0.0, 1.0]], "simspark",
                      PRM, protected=(9,))
