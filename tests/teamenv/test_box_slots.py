"""Slot names of the flat (Box) observation and action (teamenv.slots): as many as the spaces
hold, and each names the value found at its place."""

from __future__ import annotations

import math

import numpy as np
import pytest

import teamenv
from teamenv.errors import ActionError
from teamenv.landmarks import landmarks
from teamenv.slots import action_slot_names, observation_slot_names
from tests.teamenv.helpers import park_players

# The README's tables of the Dict observation, column by column: the names are checked against
# the Dict values through these, independently of how teamenv.slots lists them.
README_COLUMNS = {
    "self": ("x", "y", "heading", "vx", "vy", "omega", "fallen"),
    "ball_state": ("rel_x", "rel_y", "rel_vx", "rel_vy"),
    "player_state": ("rel_x", "rel_y", "rel_heading", "fallen", "present"),
    "sighting": ("present", "distance", "azimuth", "elevation"),
    "lines": ("present", "distance_1", "azimuth_1", "elevation_1", "distance_2", "azimuth_2",
              "elevation_2"),
    "game": ("time_s", "half", "own_score", "opponent_score"),
    "heard": ("present", "from_self", "from_teammate", "direction"),
    "vision": ("fresh", "cycles_since_update"),
    "counts": ("landmarks", "players", "lines", "ball"),
    "odometry": ("dx", "dy", "dpsi"),
    "gyro": ("dpsi",),
    "body": ("fallen", "head_pan"),
}

CONFIGS = [
    {"team_size": 3},
    {"team_size": 1, "channel": "mj"},
    {"team_size": 11},
    {"team_size": 3, "observation_mode": "vision"},
    {"team_size": 2, "observation_mode": "vision", "vision": "mj", "channel": "mj"},
]


def dict_value(env, obs: dict, name: str) -> float:
    """The value ``name`` stands for, read from a Dict observation ``obs`` of ``env``."""
    part, column = name.split(".", 1)
    vision = env.perception is not None
    if part == "play_mode":
        return float(obs["play_mode"] == teamenv.PLAY_MODES.index(column))
    head, _, label = part.partition("_")
    if head in ("teammate", "opponent"):
        table = "sighting" if vision else "player_state"
        row = obs[head + "s"][int(label) - 1]
    elif head == "landmark":
        table = "sighting"
        row = obs["landmarks"][landmarks(env.field, env.perception.landmark_kind).index(label)]
    elif head in ("line", "heard"):
        table = "lines" if head == "line" else "heard"
        row = obs[table][int(label)]
    else:
        table = {"ball": "sighting" if vision else "ball_state"}.get(part, part)
        row = obs[part]
    return float(row[README_COLUMNS[table].index(column)])


def twin_envs(**kwargs):
    """A Dict-observation env and a Box-observation env, built and reset alike."""
    envs = []
    for form in ("dict", "box"):
        env = teamenv.parallel_env(observation_format=form, rules={"half_time_s": 1e6}, **kwargs)
        env.reset(seed=3)
        envs.append(env)
    return envs


@pytest.mark.parametrize("kwargs", CONFIGS)
def test_one_name_per_slot_of_the_spaces(kwargs):
    env = teamenv.parallel_env(observation_format="box", action_format="box", **kwargs)
    for agent in env.possible_agents:
        names = observation_slot_names(env, agent)
        assert len(names) == env.observation_space(agent).shape[0]
        assert len(set(names)) == len(names)
        assert len(action_slot_names()) == env.action_space(agent).shape[0]
    assert observation_slot_names(teamenv.env(observation_format="box", **kwargs)) == names
    with pytest.raises(ActionError, match="left_12"):
        observation_slot_names(env, "left_12")


@pytest.mark.parametrize("kwargs", CONFIGS)
def test_each_name_reads_the_value_of_the_dict_observation(kwargs):
    """Step a Dict env and a Box env of the same seed with the same actions (walking, talking):
    at every named slot the Box holds the value the name stands for in the Dict."""
    dict_env, box_env = twin_envs(**kwargs)
    rng = np.random.default_rng(0)
    low, high = dict_env.action_space("left_1")["walk"].low, dict_env.action_space(
        "left_1")["walk"].high
    say = dict_env.action_space("left_1")["say"]
    say.seed(0)
    names = observation_slot_names(box_env)
    checked = 0
    for cycle in range(8):
        actions = {a: {"walk": rng.uniform(low, high), "say": say.sample() if cycle % 2 else ""}
                   for a in dict_env.agents}
        dict_obs = dict_env.step(actions)[0]
        box_obs = box_env.step(actions)[0]
        for agent in dict_env.agents:
            expected = np.array([dict_value(dict_env, dict_obs[agent], n) for n in names],
                                np.float32)
            np.testing.assert_array_equal(box_obs[agent], expected, err_msg=f"{agent} {cycle}")
            checked += int(np.count_nonzero(expected))
    assert checked > 100  # the values compared are not all zeros


def test_state_names_mean_what_they_say():
    """Known poses in, the named slots hold them: absolute team-frame self, body-frame ball and
    teammate, both teams (the right one sees the world turned by pi)."""
    env = teamenv.parallel_env(team_size=2, observation_format="box")
    env.reset(seed=0)
    park_players(env)
    world = env.sim.world
    world.place_player(0, -2.0, -1.0, 0.0)  # left_1 faces +x
    world.place_player(1, -4.0, 3.0, 0.0)  # left_2
    world.place_player(2, 3.0, 0.5, math.pi)  # right_1 faces -x, i.e. +x of its team frame
    world.place_ball(0.0, 0.0, 0.0, 0.0)
    obs = env.step({a: {} for a in env.agents})[0]
    slot = {name: k for k, name in enumerate(observation_slot_names(env))}

    def read(agent: str, name: str) -> float:
        return float(obs[agent][slot[name]])

    assert read("left_1", "self.x") == pytest.approx(-2.0, abs=0.02)
    assert read("left_1", "self.y") == pytest.approx(-1.0, abs=0.02)
    assert read("left_1", "ball.rel_x") == pytest.approx(2.0, abs=0.02)
    assert read("left_1", "ball.rel_y") == pytest.approx(1.0, abs=0.02)
    assert read("left_1", "teammate_2.rel_x") == pytest.approx(-2.0, abs=0.02)
    assert read("left_1", "teammate_2.rel_y") == pytest.approx(4.0, abs=0.02)
    assert read("left_1", "opponent_1.present") == 1.0
    assert read("right_1", "self.x") == pytest.approx(-3.0, abs=0.02)
    assert read("right_1", "self.y") == pytest.approx(-0.5, abs=0.02)
    assert read("right_1", "self.heading") == pytest.approx(0.0, abs=0.02)
    assert read("right_1", "ball.rel_x") == pytest.approx(3.0, abs=0.02)
    assert read("right_1", "ball.rel_y") == pytest.approx(0.5, abs=0.02)
    assert read("left_1", "play_mode.BeforeKickOff") == 1.0
    assert read("left_1", "game.half") == 1.0  # the clock stands still before kick-off


def test_vision_names_mean_what_they_say():
    """left_1 faces the ball 2 m ahead and 1 m to its left: the ball's named sighting slots
    hold its 3D distance from the camera and its azimuth (+ to the left)."""
    env = teamenv.parallel_env(team_size=2, observation_format="box", observation_mode="vision")
    env.reset(seed=0)
    park_players(env)
    env.sim.world.place_player(0, -2.0, -1.0, 0.0)
    env.sim.world.place_ball(0.0, 0.0, 0.0, 0.0)
    slot = {name: k for k, name in enumerate(observation_slot_names(env))}
    for _ in range(env.perception.update_period_cycles):
        row = env.step({a: {} for a in env.agents})[0]["left_1"]
        if row[slot["vision.fresh"]] == 1.0:
            break
    else:
        raise AssertionError("no vision update")
    drop = env.perception.camera_height_m - env.physics.ball_radius
    assert row[slot["ball.present"]] == 1.0
    assert row[slot["ball.distance"]] == pytest.approx(math.sqrt(5 + drop**2), abs=0.05)
    assert row[slot["ball.azimuth"]] == pytest.approx(math.atan2(1.0, 2.0), abs=0.02)
    assert row[slot["ball.elevation"]] < 0  # the camera looks down on it
    assert row[slot["counts.ball"]] == 1.0
