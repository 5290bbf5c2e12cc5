"""The ``full_options`` team (strategy.teams.full_options): with no policy it is ``full``
bit for bit; the options it is told to play are the ones played; its rule's choices are what
``full`` does; a policy file plays the option with the highest score; bad input is one clear
error naming the agent, the option or the file."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import teamenv
from strategy.decision.field_player import COVER, HOLD, OPTIONS, PLAY_BALL
from teamenv.errors import ConfigError
from teamenv.policy_team import PolicyFileError, save_mlp_policy
from teamenv.selfplay.egocentric_team import add_egocentric_slots, add_option_team

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


def _option_file(path, scores: np.ndarray, count: int = len(OPTIONS), team="full_options"):
    """A policy file whose network ignores its input and outputs ``scores`` (first Box
    entries) for every row: egocentric slots 4 + 5 (5 v 5), marked for ``team``."""
    from teamenv.egocentric import EgocentricObservation

    size = EgocentricObservation(5, 4, 4, 5).size
    w = np.zeros((size, 9), np.float32)
    b = np.zeros(9, np.float32)
    b[:len(scores)] = scores
    save_mlp_policy(path, [(w, b)], activation="identity", output_activation="identity",
                    action_repeat=5)
    add_egocentric_slots(path, 4, 5)
    if team is not None:
        add_option_team(path, team, count)
    return path


def test_a_policy_file_plays_the_team_its_scores_rank(tmp_path):
    path = _option_file(tmp_path / "tied.npz", np.array([-0.5, 0.7, 0.1]))
    env, team = _team_env(path=str(path))
    for _ in range(200):
        env.step({})
    # every player scores the same: the first field player plays the ball, the second covers
    assert team.field_maker.option_override == {0: HOLD, 1: PLAY_BALL, 2: COVER, 3: HOLD,
                                                4: HOLD}
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


def test_files_that_do_not_fit_are_refused_with_the_reason(tmp_path):
    plain = _option_file(tmp_path / "plain.npz", np.zeros(3), team=None)
    with pytest.raises(PolicyFileError, match="Box actions.*'full_options' team plays a file"):
        _team_env(path=str(plain))
    four = _option_file(tmp_path / "four.npz", np.zeros(4), count=4)
    with pytest.raises(ConfigError, match="scores 4 options; this team has 3"):
        _team_env(path=str(four))
    options = _option_file(tmp_path / "options.npz", np.zeros(3))
    for team in ("policy", "teamenv.selfplay.egocentric_team:EgocentricPolicyTeam"):
        with pytest.raises(Exception, match="scores 3 options for the 'full_options' team.*"
                                            "play it as full_options:path="):
            teamenv.parallel_env(field="mj7v7", team_size=5, left=team,
                                 left_config={"path": str(options)}).reset(seed=0)
