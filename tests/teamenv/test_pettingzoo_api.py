"""PettingZoo's own conformance tests (parallel, AEC, seeds) over a matrix of env options."""

import pytest
from pettingzoo.test import api_test, parallel_api_test, parallel_seed_test, seed_test

import teamenv

OPTION_MATRIX = [
    dict(team_size=3),
    dict(team_size=1, field="mj7v7"),
    dict(team_size=2, field="fifa", channel="mj"),
    dict(team_size=3, action_format="box", observation_format="box"),
    dict(team_size=2, action_format="box"),
    dict(team_size=2, observation_format="box", channel="mj"),
    dict(team_size=3, right="chaser"),
    dict(team_size=2, left="static", observation_format="box"),
    dict(team_size=11),
    *[dict(team_size=2, observation_mode="vision", **opts) for opts in (
        dict(),
        dict(observation_format="box"),
        dict(vision="mj", field="mj7v7"),
        dict(vision="mj", observation_format="box", channel="mj", perception={"occlusion": True}),
        dict(right="tests.teamenv.vision_teams:BallTurner", observation_format="box"),
    )],
]
VISION = [opts for opts in OPTION_MATRIX if opts.get("observation_mode") == "vision"]


def _ids(opts):
    return "-".join(f"{k}={v}" for k, v in opts.items())


@pytest.mark.parametrize("opts", OPTION_MATRIX, ids=_ids)
def test_parallel_api(opts):
    parallel_api_test(teamenv.parallel_env(max_cycles=150, **opts), num_cycles=200)


@pytest.mark.parametrize("opts", OPTION_MATRIX, ids=_ids)
def test_aec_api(opts):
    api_test(teamenv.env(max_cycles=60, **opts), num_cycles=80)


@pytest.mark.parametrize("opts", OPTION_MATRIX[:4], ids=_ids)
def test_seed_tests(opts):
    parallel_seed_test(lambda: teamenv.parallel_env(max_cycles=100, **opts))
    seed_test(lambda: teamenv.env(max_cycles=60, **opts), num_cycles=60)


@pytest.mark.parametrize("opts", VISION[:3], ids=_ids)
def test_seed_tests_vision(opts):
    parallel_seed_test(lambda: teamenv.parallel_env(max_cycles=100, **opts))


def test_spaces_are_cached_objects():
    env = teamenv.parallel_env(team_size=2)
    for agent in env.possible_agents:
        assert env.observation_space(agent) is env.observation_space(agent)
        assert env.action_space(agent) is env.action_space(agent)


def test_team_driven_side_is_not_an_agent():
    env = teamenv.parallel_env(team_size=3, right="static")
    env.reset(seed=0)
    assert env.agents == ["left_1", "left_2", "left_3"]
    assert all(not a.startswith("right") for a in env.possible_agents)


def test_state_matches_state_space():
    env = teamenv.parallel_env(team_size=4)
    env.reset(seed=0)
    assert env.state_space.contains(env.state())
