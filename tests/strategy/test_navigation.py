"""Potential-field navigation (seed 001 eq. 6-10) and the walk controller."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategy.behaviours.navigation import (
    NavigationParams,
    direction_to,
    field_vector,
    walk_command,
)
from strategy.geometry import wrap_angle as wrap
from teamenv.errors import ConfigError
from tests.strategy import scenes

P = NavigationParams()
coord = st.floats(-12.0, 12.0, allow_nan=False)


def hand_vector(p, t, obstacles, params):
    """eq. 6-9 by hand: k_att/d towards the target plus k_rep/d^3 (k_rep < 0) along the unit
    vector to each obstacle within the influence radius (and not beyond the target)."""
    p, t = np.asarray(p, float), np.asarray(t, float)
    d_t = math.dist(p, t)
    v = params.k_attract / d_t * (t - p) / d_t
    for o in np.asarray(obstacles, float).reshape(-1, 2):
        d = math.dist(p, o)
        if 1e-6 < d < params.influence_m and d < d_t + 0.3:
            v = v + params.k_repulse / d**3 * (o - p) / d
    return v


@settings(max_examples=60, deadline=None)
@given(px=coord, py=coord, tx=coord, ty=coord,
       obs=st.lists(st.tuples(st.floats(-2, 2), st.floats(-2, 2)), max_size=6))
def test_field_vector_is_the_hand_computed_sum(px, py, tx, ty, obs):
    if math.hypot(tx - px, ty - py) < 0.05:
        return
    obstacles = np.array([[px + dx, py + dy] for dx, dy in obs]).reshape(-1, 2)
    got = field_vector([px, py], [tx, ty], obstacles, P)
    want = hand_vector([px, py], [tx, ty], obstacles, P)
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12)


def test_single_terms_have_the_documented_magnitudes():
    # attraction alone: |V| = k/d, pointing at the target
    v = field_vector([0, 0], [4, 0], np.zeros((0, 2)), P)
    np.testing.assert_allclose(v, [P.k_attract / 4, 0.0])
    # one obstacle at distance 0.5 straight ahead (target far): adds k_rep/0.5^3 along +x
    v2 = field_vector([0, 0], [4, 0], [[0.5, 0.0]], P)
    np.testing.assert_allclose(v2 - v, [P.k_repulse / 0.5**3, 0.0])
    assert v2[0] < v[0]  # repulsion points away from the obstacle


@settings(max_examples=60, deadline=None)
@given(px=coord, py=coord, tx=coord, ty=coord)
def test_no_obstacles_walks_straight_at_the_target(px, py, tx, ty):
    if math.hypot(tx - px, ty - py) < 0.05:
        return
    theta = direction_to([px, py], [tx, ty], np.zeros((0, 2)), P)
    assert abs(wrap(theta - math.atan2(ty - py, tx - px))) < 1e-9


@pytest.mark.parametrize("offset", [0.05, -0.05, 0.2, -0.2])
def test_obstacle_on_the_line_deflects_to_one_side(offset):
    # 1.5 m ahead, a hair off the line: the walker veers to the free side and keeps going
    theta = direction_to([0, 0], [5, 0], [[1.5, offset]], P)
    assert 0.02 < abs(theta) < math.pi / 2
    assert np.sign(theta) == -np.sign(offset)


@pytest.mark.parametrize("where", [[0.0, 1.7], [2.5, 0.0], [-3.0, 0.5]])
def test_obstacles_beyond_the_influence_radius_are_ignored(where):
    far = np.array([where])
    assert math.dist((0, 0), where) >= P.influence_m
    np.testing.assert_array_equal(field_vector([0, 0], [6, 0], far, P),
                                  field_vector([0, 0], [6, 0], np.zeros((0, 2)), P))
    assert direction_to([0, 0], [6, 0], far, P) == 0.0


def test_obstacle_beyond_the_target_is_ignored():
    # target 0.5 ahead, obstacle 1.0 ahead (within influence but past the target + 0.3)
    np.testing.assert_array_equal(field_vector([0, 0], [0.5, 0], [[1.0, 0.0]], P),
                                  field_vector([0, 0], [0.5, 0], np.zeros((0, 2)), P))


@pytest.mark.parametrize("field,value", [
    ("k_attract", 0.0), ("k_attract", -1.0), ("k_attract", math.nan),
    ("k_repulse", 0.0), ("k_repulse", 0.5), ("k_repulse", math.inf),
    ("influence_m", -1.0), ("max_speed", math.nan),
])
def test_params_reject_bad_gains_naming_the_field(field, value):
    with pytest.raises(ConfigError, match=field) as info:
        NavigationParams(**{field: value})
    assert repr(value) in str(info.value) or str(value) in str(info.value)


def test_walk_command_turns_on_the_spot_for_a_target_behind():
    cmd = walk_command([0, 0], 0.0, [-5, 0.1], np.zeros((0, 2)), P)
    assert cmd[0] == 0.0 and cmd[1] == 0.0
    assert abs(cmd[2]) > 1.0


@pytest.mark.parametrize("heading", [0.0, 1.0, -2.5])
def test_walk_command_walks_forward_for_a_target_ahead(heading):
    target = [5 * math.cos(heading), 5 * math.sin(heading)]
    cmd = walk_command([0, 0], heading, target, np.zeros((0, 2)), P)
    assert cmd[0] == pytest.approx(P.max_speed)
    assert abs(cmd[1]) < 1e-9 and abs(cmd[2]) < 1e-9


@pytest.mark.parametrize("heading", [0.0, 2.0])
def test_walk_command_stands_within_arrive(heading):
    cmd = walk_command([1, 1], heading, [1 + P.arrive_m / 2, 1], np.zeros((0, 2)), P)
    assert cmd[0] == 0.0 and cmd[1] == 0.0 and cmd[2] == 0.0
    # with a point to face: only turns towards it
    cmd = walk_command([1, 1], heading, [1.01, 1], np.zeros((0, 2)), P, face=[1, 5])
    assert cmd[0] == 0.0 and cmd[1] == 0.0
    assert np.sign(cmd[2]) == np.sign(wrap(math.pi / 2 - heading))


def unicycle(start, heading, target, obstacles, cycles=1500, params=P):
    """Integrate the clipped walk command with a kinematic unicycle; returns (reached,
    smallest distance to an obstacle centre)."""
    p, h = np.array(start, float), float(heading)
    obstacles = np.asarray(obstacles, float).reshape(-1, 2)
    closest = math.inf
    for _ in range(cycles):
        cmd = np.clip(walk_command(p, h, target, obstacles, params), scenes.LOW, scenes.HIGH)
        c, s = math.cos(h), math.sin(h)
        p = p + 0.02 * np.array([c * cmd[0] - s * cmd[1], s * cmd[0] + c * cmd[1]])
        h += 0.02 * cmd[2]
        if len(obstacles):
            closest = min(closest, float(np.min(np.hypot(*(obstacles - p).T))))
        if math.dist(p, target) < 0.15:
            return True, closest
    return False, closest


@pytest.mark.parametrize("obstacles,target", [
    ([[3.0, 0.05]], [6.0, 0.0]),
    ([[3.0, -0.3], [3.0, 0.3]], [6.0, 0.0]),
    ([[3.0, -0.6], [3.0, 0.0], [3.0, 0.6]], [5.0, 0.5]),
    ([[2.5, -0.5], [3.2, 0.1], [3.9, 0.7]], [6.0, 0.3]),
])
def test_closed_loop_walks_round_players_to_a_target_behind_them(obstacles, target):
    reached, closest = unicycle([0, 0], 0.0, np.array(target), obstacles)
    assert reached
    assert closest > 2 * scenes.BODY_RADIUS


def test_closed_loop_passes_a_wall_of_three_players():
    reached, closest = unicycle([0, 0], 0.0, np.array([6.0, 0.0]),
                                [[3.0, -0.6], [3.0, 0.0], [3.0, 0.6]])
    assert reached and closest > 2 * scenes.BODY_RADIUS


# -- one-sided side-steps (a body whose walk does not move to one side) --------------------
def test_the_side_steps_follow_the_bodys_tracking_table():
    from teamenv.capabilities import body_capabilities

    league = _league()  # the reference network: right, not left
    assert league.side_speed(league.walk_high[1]) < 0.01 < -league.side_speed(league.walk_low[1])
    params = P.for_body(league)
    assert (params.side_step_left, params.side_step_right) == (False, True)
    for symmetric in ("t1_mj", "nao_simspark"):
        assert P.for_body(body_capabilities(symmetric)) is P  # unchanged: both sides


def test_a_target_on_the_side_the_body_cannot_step_to_is_walked_to_as_a_far_one():
    no_left = NavigationParams(side_step_left=False)
    none = np.zeros((0, 2))
    left, right, ahead = [0.0, 0.3], [0.0, -0.3], [0.3, 0.1]
    # to the left: no side-step, the far walk's turn towards it (on the spot: 90 degrees)
    assert walk_command([0, 0], 0.0, left, none, P)[1] > 0.0
    cmd = walk_command([0, 0], 0.0, left, none, no_left)
    assert cmd[0] == 0.0 and cmd[1] == 0.0 and cmd[2] > 0.0
    # to the right, or nearly ahead (less than 30 degrees off the axis): side-steps as before
    for target in (right, ahead):
        assert walk_command([0, 0], 0.0, target, none, no_left).tobytes() == \
            walk_command([0, 0], 0.0, target, none, P).tobytes()


def one_sided_walk(params, start, heading, target, face, cycles=1000):
    """Integrate the command with a unicycle that walks as the league's T1 does (the
    ``t1_league`` tracking of each axis: no side-step to the left); whether it reaches."""
    body = _league()
    p, h = np.array(start, float), float(heading)
    for _ in range(cycles):
        cmd = np.clip(walk_command(p, h, target, np.zeros((0, 2)), params, face=face),
                      body.walk_low, body.walk_high)
        vx, vy = body.forward_speed(cmd[0]), body.side_speed(cmd[1])
        c, s = math.cos(h), math.sin(h)
        p = p + 0.02 * np.array([c * vx - s * vy, s * vx + c * vy])
        h += 0.02 * cmd[2]
        if math.dist(p, target) < params.arrive_m * 2:
            return True
    return False


@pytest.mark.parametrize("target", [[0.1, 0.3], [0.2, 0.3], [0.0, 0.35]])
def test_a_body_that_does_not_step_left_reaches_a_spot_on_its_left(target):
    # asking it to side-step left, it stands (20 s); walking there as a far target, it arrives
    face = [5.0, target[1]]
    assert not one_sided_walk(P, [0, 0], 0.0, target, face)
    assert one_sided_walk(P.for_body(_league()), [0, 0], 0.0, target, face)


def _league():
    from teamenv.capabilities import body_capabilities

    return body_capabilities("t1_league")
