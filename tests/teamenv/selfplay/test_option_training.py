"""Training a network that chooses an option team's options (TrainingSetup.option_team):
the rule's own play is ``full``'s and its labels are its choices; the network's outputs
become the options the team plays (highest score, ties to the lower index); a snapshot plays
through the option team as the training env chose; setups that cannot work fail clearly.
Torch-free."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import teamenv
from strategy.decision.field_player import COVER, HOLD, OPTIONS, PLAY_BALL
from strategy.teams.full_options import SWITCH_MARGIN
from teamenv.errors import ConfigError
from teamenv.selfplay.batch_env import OPTION_LABEL, TeamBatchEnv
from teamenv.selfplay.learner import PolicyWeights
from teamenv.selfplay.option_policy_team import OPTION_POLICY_SPEC_NAME
from teamenv.selfplay.pfsp import OpponentMix
from teamenv.selfplay.snapshots import SnapshotPool
from teamenv.selfplay.teacher_env import TeacherBatchEnv
from teamenv.selfplay.training_setup import ActionSetup, TrainingSetup, option_actions

SETUP = TrainingSetup(field="mj7v7", team_size=5, episode_s=8.0, teammate_slots=4,
                      opponent_slots=5, actions=option_actions(len(OPTIONS)),
                      option_team="full_options", ball_race=True, game_state=False)


def test_the_rules_demonstration_is_full_and_its_labels_are_its_choices():
    env = TeamBatchEnv(SETUP, OpponentMix.single("chaser", 0), copies=2, seed=3)
    env.reset()
    chosen = []
    try:
        for _ in range(80):
            env.step(None)
            labels = env.option_labels()
            assert set(np.unique(labels)) <= {OPTION_LABEL, -OPTION_LABEL}
            assert ((labels == OPTION_LABEL).sum(axis=1) == 1).all()
            chosen.append(labels.argmax(axis=1))
            for copy in range(2):
                team = env._teams[copy]["chaser"]
                assert team.field_maker.option_override is None  # the rule plays
    finally:
        env.close()
    chosen = np.array(chosen[40:])          # open play
    field = chosen.reshape(len(chosen), 2, 5)[:, :, 1:]
    assert ((field == PLAY_BALL).sum(axis=2) == 1).all()   # one ball player per copy


def test_the_network_outputs_are_the_options_played():
    """Each decision: the upright field player with the highest play_ball output plays the
    ball, the one of the others with the highest cover output covers (either keeps its
    option unless beaten by SWITCH_MARGIN), the rest hold."""
    env = TeamBatchEnv(SETUP, OpponentMix.single("static", 0), copies=1, seed=5)
    env.reset()
    rng = np.random.default_rng(0)
    held: dict[int, int] = {}
    try:
        for _ in range(30):
            outputs = rng.uniform(-1.5, 1.5, (5, 3)).astype(np.float32)
            upright = env._raw[:, 6] < 0.5
            env.step(outputs)
            scores = np.clip(outputs, -1.0, 1.0)
            free = list(np.flatnonzero(upright[1:]) + 1)    # field players (left_1 keeps goal)
            expected = np.full(5, HOLD)
            for option in (PLAY_BALL, COVER):
                pick = free[int(np.argmax(scores[free, option]))]
                kept = held.get(option)
                if kept in free and scores[kept, option] >= scores[pick, option] - SWITCH_MARGIN:
                    pick = kept
                expected[pick] = option
                held[option] = pick
                free.remove(pick)
            np.testing.assert_array_equal(env.played_options(), expected)
            team = env._teams[0]["static"]
            assert team.field_maker.option_override == dict(enumerate(expected.tolist()))
    finally:
        env.close()


def test_the_teacher_env_is_the_option_teams_rule():
    env = TeacherBatchEnv(SETUP, OpponentMix.single("static", 0), "full_options", seed=1)
    env.reset()
    with pytest.raises(ConfigError, match="labels are its rule's choices"):
        env.teacher_outputs()
    env.step(None)
    assert env.option_labels().shape == (5, 3)
    env.close()


def test_a_snapshot_plays_the_options_the_training_env_would_choose(tmp_path):
    """A network with a fixed output written as a snapshot: its team spec is the option
    policy team's, and with every score tied the first field player plays the ball, the
    second covers."""
    env = TeamBatchEnv(SETUP, OpponentMix.single("static", 0), seed=0)
    size = env.observation_size
    env.close()
    weights = PolicyWeights.of([(np.zeros((size, 3)), np.array([-0.2, 0.4, 0.1]))],
                               activation="identity")
    pool = SnapshotPool(tmp_path, SETUP)
    pool.write(0, weights)
    spec = pool.spec(0)
    assert spec.name == OPTION_POLICY_SPEC_NAME
    assert spec.config_dict == {"path": str(pool.path(0))}
    game = teamenv.parallel_env(field="mj7v7", team_size=5, left=spec.name,
                                left_config=spec.config_dict, right="static")
    game.reset(seed=2)
    for _ in range(10):
        game.step({})
    team = game.unwrapped.team_host.teams["left"].team
    assert team.field_maker.option_override == {0: HOLD, 1: PLAY_BALL, 2: COVER, 3: HOLD,
                                                4: HOLD}
    game.close()


@pytest.mark.parametrize("change, match", [
    ({"actions": ActionSetup()}, "the network scores options; use actions=option_actions"),
    ({"observation": "box", "ball_race": False, "game_state": True},
     "reads egocentric observations"),
    ({"observation": "box", "ball_race": False}, "game_state=false leaves columns out"),
    ({"observation": "box", "game_state": True}, "ball_race columns are part of egocentric"),
    ({"option_team": 3}, "option_team must be a team spec string"),
    ({"ball_race": 1}, "ball_race must be true or false"),
    ({"game_state": "no"}, "game_state must be true or false"),
])
def test_setups_that_cannot_choose_options_fail_clearly(change, match):
    with pytest.raises(ConfigError, match=match):
        dataclasses.replace(SETUP, **change)


def test_a_team_that_takes_no_options_is_one_clear_error():
    setup = dataclasses.replace(SETUP, option_team="chaser")
    env = TeamBatchEnv(setup, OpponentMix.single("static", 0), seed=0)
    with pytest.raises(ConfigError, match="'chaser' does not take options"):
        env.reset()
    env.close()
