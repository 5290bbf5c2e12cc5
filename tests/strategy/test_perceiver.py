"""One perceiver interface for both observation modes, and the full team's one decide path."""

from __future__ import annotations

import numpy as np
import pytest

import teamenv
from strategy.perception.perceiver import StatePerceiver, perceiver_for
from strategy.perception.vision_perceiver import VisionPerceiver
from strategy.perception.worldmodel import WorldModel
from strategy.positioning.roles.message import decode_role_vote
from strategy.teams.talk import RoleVoteTalk, TeamReportTalk


def _env(mode: str, left: str = "full", **kwargs):
    return teamenv.parallel_env(field="mj7v7", team_size=4, left=left, right="static",
                                observation_mode=mode, rules={"half_time_s": 30.0},
                                profile_phases=False, **kwargs)


@pytest.mark.parametrize("mode, kind, talk", [("state", StatePerceiver, RoleVoteTalk),
                                              ("vision", VisionPerceiver, TeamReportTalk)])
def test_the_full_team_gets_the_perceiver_and_talk_of_its_mode(mode, kind, talk):
    env = _env(mode)
    env.reset(seed=1)
    team = env.teams["left"]
    assert type(team.perceiver) is kind and type(team.talk) is talk
    assert all(p.talk is team.talk for p in team.players.values())
    assert isinstance(perceiver_for(team.context), kind)


def test_state_perceiver_gives_each_agent_the_belief_of_its_own_observation():
    env = _env("state")
    observations, _ = env.reset(seed=4)
    for _ in range(30):
        observations, *_ = env.step({})
    team = env.teams["left"]
    perceiver = StatePerceiver(team.context, roll=team.skills.ball_roll, resolution=None)
    mine = {a: o for a, o in observations.items() if a in team.context.agents}
    beliefs = perceiver.update(mine)
    assert list(beliefs) == list(mine)
    for k, (agent, obs) in enumerate(mine.items()):
        alone = WorldModel.from_observation(obs, k, env.field, agent, team.skills.ball_roll,
                                            None)
        assert beliefs[agent].me == k
        np.testing.assert_array_equal(beliefs[agent].position, alone.position)
        np.testing.assert_array_equal(beliefs[agent].ball, alone.ball)
        np.testing.assert_array_equal(beliefs[agent].teammates, alone.teammates)
        np.testing.assert_array_equal(beliefs[agent].opponents, alone.opponents)
    perceiver.reset(7)  # holds nothing: the same observations give the same beliefs
    again = perceiver.update(mine)
    for agent in mine:
        np.testing.assert_array_equal(again[agent].position, beliefs[agent].position)


def test_state_mode_players_say_their_own_role_vector_and_hear_the_others():
    env = _env("state")
    env.reset(seed=2)
    team = env.teams["left"]
    for _ in range(20):
        env.step({})
    for player in team.players.values():
        vote = decode_role_vote(player.last_request.say, 4, "simspark")
        assert vote is not None and vote[0] == player.me
        np.testing.assert_array_equal(vote[1], player.last_decision.own_vector)
    # what an agent heard (its teammates' texts) reaches its positioning as decoded votes
    player = next(iter(team.players.values()))
    heard = player.last_world_model.heard
    votes = team.talk.votes(player.positioning, player.last_world_model)
    assert len(votes) == len([t for t in heard if decode_role_vote(t, 4, "simspark")]) > 0


def test_a_silent_full_team_neither_hears_votes_nor_speaks_in_either_mode():
    for mode in ("state", "vision"):
        env = _env(mode, left_config={"communicate": False})
        env.reset(seed=3)
        team = env.teams["left"]
        for _ in range(12):
            env.step({})
            assert all(not p.last_request.say for p in team.players.values())
        player = next(iter(team.players.values()))
        assert team.talk.votes(player.positioning, player.last_world_model) == ()


def test_vision_talk_counts_the_vector_each_agent_last_said_as_its_own_vote():
    env = _env("vision")
    env.reset(seed=5)
    team = env.teams["left"]
    assert team.talk.said == [None] * 4
    for _ in range(16):
        env.step({})
        for player in team.players.values():
            if player.last_request.say:
                np.testing.assert_array_equal(team.talk.own_ballot(player.me),
                                              player.last_decision.own_vector)
    assert all(v is not None for v in team.talk.said)
    env.reset(seed=5)
    assert team.talk.said == [None] * 4
