"""Each side sees itself attacking +x: mirrored worlds give identical observations."""

import math

import numpy as np

from tests.teamenv.helpers import make_env


def test_rotated_world_gives_equal_observations_for_both_sides():
    env = make_env(team_size=4)
    world = env.sim.world
    rng = np.random.default_rng(5)
    n = env.team_size
    for k in range(n):
        x, y, h = rng.uniform(-10, -1), rng.uniform(-8, 8), rng.uniform(-math.pi, math.pi)
        world.place_player(k, x, y, h)
        world.place_player(n + k, -x, -y, h + math.pi)  # the right team: rotated by pi
    world.place_ball(0.0, 0.0)
    obs = env.sim.observations()
    for k in range(n):
        left, right = obs[k], obs[n + k]
        for key in ("self", "ball", "teammates", "opponents", "game", "heard"):
            a, b = np.array(left[key], float), np.array(right[key], float)
            if key in ("self", "teammates", "opponents"):  # headings: equal modulo 2 pi
                a[..., 2], b[..., 2] = np.cos(a[..., 2]) + 2 * np.sin(a[..., 2]), \
                    np.cos(b[..., 2]) + 2 * np.sin(b[..., 2])
            np.testing.assert_allclose(a, b, atol=1e-4, err_msg=key)
        assert left["play_mode"] == right["play_mode"]


def test_team_relative_play_mode():
    env = make_env(team_size=1)
    from teamenv.sim.playmode import PlayMode

    env.sim.referee.mode = PlayMode.CornerKick_Right
    obs = env.sim.observations()
    assert PlayMode(obs[0]["play_mode"]) == PlayMode.CornerKick_Right
    assert PlayMode(obs[1]["play_mode"]) == PlayMode.CornerKick_Left


def test_team_frame_helper_recovers_absolute_positions():
    from teamenv.observation import team_frame

    env = make_env(team_size=2)
    world = env.sim.world
    world.place_player(0, -3.0, 1.0, 0.7)
    world.place_player(1, -6.0, -2.0, -1.0)
    world.place_player(2, 4.0, 2.0, 2.0)
    world.place_ball(1.0, -1.0)
    view = team_frame(env.sim.observations()[0])
    np.testing.assert_allclose(view.ball, [1.0, -1.0], atol=1e-4)
    np.testing.assert_allclose(view.teammates[1], [-6.0, -2.0], atol=1e-4)
    np.testing.assert_allclose(view.opponents[0], [4.0, 2.0], atol=1e-4)
    right_view = team_frame(env.sim.observations()[2])
    np.testing.assert_allclose(right_view.ball, [-1.0, 1.0], atol=1e-4)
    np.testing.assert_allclose(right_view.position, [-4.0, -2.0], atol=1e-4)
