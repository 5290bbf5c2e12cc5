"""The ``full_options`` team (strategy.teams.full_options): left to its rule it is ``full``
bit for bit; the options it is told to play are the ones played; its rule's choices are what
``full`` does; scores become one ball player and one cover; bad input is one clear error
naming the agent and the option. (Policy files that score its options:
tests/teamenv/selfplay/test_option_policy_team.py.)"""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import teamenv
from strategy.decision.field_player import COVER, HOLD, PLAY_BALL
from teamenv.errors import ConfigError

AGENTS = [f"left_{k}" for k in range(1, 6)]


def _play(left: str, cycles: int, seed: int = 5, **config) -> str:
    """A hash of every state of a 5 v 5 mj7v7 match of ``left`` against chaser."""
    env = teamenv.parallel_env(field="mj7v7", team_size=5, left=left, right="chaser",
                               left_config=config)
    env.reset(seed=seed)
    digest = hashlib.sha256()
    for _ in range(cycles):
        env.step({})
        digest.update(np.ascontiguousarray(env.unwrapped.state()).tobytes())
    env.close()
    return digest.hexdigest()


def test_without_a_policy_it_plays_exactly_as_full():
    assert _play("full_options", 600) == _play("full", 600)


def _team_env(**config):
    env = teamenv.parallel_env(field="mj7v7", team_size=5, left="full_options",
                               right="chaser", left_config=config)
    env.reset(seed=11)
    return env, env.unwrapped.team_host.teams["left"]


def test_the_rule_chooses_one_ball_player_and_one_cover_in_open_play():
    env, team = _team_env()
    seen = []
    for _ in range(400):
        env.step({})
        seen.append(team.rule_options(AGENTS))
    env.close()
    seen = np.array(seen[100:])  # in open play: kick-off over
    field = seen[:, 1:]          # the goalie (left_1) never has an open-play option
    assert (seen[:, 0] == HOLD).all()
    assert ((field == PLAY_BALL).sum(axis=1) == 1).all()
    assert ((field == COVER).sum(axis=1) == 1).all()


@pytest.mark.parametrize("chosen", [PLAY_BALL, COVER, HOLD])
def test_the_chosen_options_are_played(chosen):
    """Every field player told to play one option plays it (its behaviour), where the rule
    gives each option to some of them only; the override names the options as given."""
    env, team = _team_env()
    behaviours = []
    for cycle in range(300):
        team.choose(dict.fromkeys(AGENTS[1:], chosen))
        assert team.field_maker.option_override == dict.fromkeys(range(1, 5), chosen)
        env.step({})
        if cycle >= 150:  # open play
            behaviours.append([team.players[a].last_request.behaviour for a in AGENTS[1:]])
    env.close()
    played = set(np.ravel(behaviours))
    if chosen == PLAY_BALL:
        assert played <= {"intercept", "kick_at_goal", "shoot", "pass", "clear", "dribble"}
    else:
        assert played == {"cover" if chosen == COVER else "hold_position"}


@pytest.mark.parametrize("options, match", [
    ({"left_9": PLAY_BALL}, "no agent 'left_9'"),
    ({"left_2": 3}, "left_2: option must be an int in 0..2"),
    ({"left_2": True}, "left_2: option must be an int"),
    ({"left_2": "cover"}, "left_2: option must be an int"),
])
def test_a_bad_choice_is_one_clear_error(options, match):
    env, team = _team_env()
    with pytest.raises(ConfigError, match=match):
        team.choose(options)
    env.close()


def test_scores_make_one_ball_player_and_one_cover_among_the_upright_field_players():
    env, team = _team_env()
    rows = np.zeros((5, 9))
    scores = np.array([[0.9, 0.9, 0.0],    # the goalie: never chosen
                       [0.1, 0.8, 0.0],
                       [0.8, 0.2, 0.0],
                       [0.95, 0.1, 0.0],   # down: never chosen
                       [0.3, 0.9, 0.0]])
    rows[3, 6] = 1.0
    assert team.options_from_scores(AGENTS, rows, scores) == {
        "left_1": HOLD, "left_2": HOLD, "left_3": PLAY_BALL, "left_4": HOLD, "left_5": COVER}
    # the ball player keeps the ball against a score higher by less than SWITCH_MARGIN
    scores[1, PLAY_BALL] = scores[2, PLAY_BALL] + 0.2
    assert team.options_from_scores(AGENTS, rows, scores)["left_3"] == PLAY_BALL
    scores[1, PLAY_BALL] = scores[2, PLAY_BALL] + 0.3
    assert team.options_from_scores(AGENTS, rows, scores)["left_2"] == PLAY_BALL
    rows[1:, 6] = 1.0  # everyone down but the goalie: nobody
    assert set(team.options_from_scores(AGENTS, rows, scores).values()) == {HOLD}
    env.close()
