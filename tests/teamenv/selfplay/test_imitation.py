"""The imitation warm start (teamenv.selfplay.teacher_env, teamenv.selfplay.imitation): the
teacher's labels decode to exactly what the teacher does; cloning moves the network towards
the teacher on states it was not trained on; the same seed gives the same network bit for bit;
a checkpoint carries the clone over to PPO; bad options fail with one clear error."""

from __future__ import annotations

import math

import numpy as np
import pytest

from teamenv.box_layout import decode_box_actions
from teamenv.errors import ConfigError
from teamenv.selfplay.pfsp import OpponentMix
from teamenv.selfplay.teacher_env import TeacherBatchEnv, dict_to_box_action
from teamenv.selfplay.training_setup import ActionSetup, TrainingSetup, kick_gate_m

SETUP = TrainingSetup(team_size=3, episode_s=6.0)
LOW, HIGH = np.array([-0.3, -0.25, -1.0]), np.array([0.6, 0.25, 1.0])


@pytest.mark.parametrize("walk, kick", [
    ([0.6, -0.25, 0.3], [1.0, 2.5]), ([-0.15, 0.1, -1.0], None), ([0.0, 0.0, 0.0], [0.4, -3.0]),
    ([0.2, 0.05, 0.0], [0.0, 1.0])])
def test_a_dict_action_becomes_the_box_action_the_env_decodes_into_it(walk, kick):
    action = {"walk": np.array(walk)} | ({} if kick is None else {"kick": np.array(kick)})
    box = dict_to_box_action(action, LOW, HIGH)
    assert box.shape == (9,) and np.all(np.abs(box) <= 1.0)
    decoded = decode_box_actions(box[None], LOW, HIGH, 15.0, 10.0)
    np.testing.assert_allclose(decoded.walk[0], walk, atol=1e-12)
    kicks = kick is not None and kick[0] > 0
    assert decoded.kick_power[0] == (kick[0] if kicks else 0.0)
    if kicks:
        assert math.isclose(decoded.kick_direction[0], kick[1], abs_tol=1e-12)
    assert not decoded.beam_request[0]


def test_the_labels_decode_to_what_the_teacher_does_in_the_states_played():
    env = TeacherBatchEnv(TrainingSetup(team_size=3, episode_s=30.0),
                          OpponentMix.single("static", 0), "chaser", copies=1, seed=4)
    env.reset()
    kicked = walked = 0
    try:
        for _ in range(150):
            labels = env.teacher_outputs()
            host = env._env[0].team_host
            teacher = host.teams["left"].act(host.observations["left"])
            box = env.box_actions(labels)
            parser = env._env[0].parser
            decoded = decode_box_actions(box.astype(np.float64), parser.walk_low,
                                         parser.walk_high, 15.0, 10.0)
            for k, agent in enumerate(env.agents):
                np.testing.assert_allclose(decoded.walk[k], teacher[agent]["walk"], atol=1e-6)
                kick = teacher[agent].get("kick")
                if kick is not None and kick[0] > 0:
                    kicked += 1
                    assert abs(decoded.kick_power[k] - kick[0]) < 1e-6
                    assert abs(math.remainder(decoded.kick_direction[k] - kick[1],
                                              2 * math.pi)) < 1e-5
                else:
                    assert decoded.kick_power[k] == 0.0
                walked += bool(np.any(teacher[agent]["walk"] != 0))
            env.step(labels)
    finally:
        env.close()
    assert walked > 0 and kicked > 0  # both parts of the label were exercised


def test_a_bad_teacher_is_one_clear_error():
    with pytest.raises(ConfigError, match="teacher"):
        TeacherBatchEnv(SETUP, OpponentMix.single("chaser", 0), "no_such_team")
    with pytest.raises(ConfigError, match="teacher"):
        TeacherBatchEnv(SETUP, OpponentMix.single("chaser", 0), "")


# -- the learner (needs torch and Stable-Baselines3) ------------------------------------------
TINY = {"copies": 1, "n_steps": 64, "batch_size": 64, "n_epochs": 2, "dagger_rounds": 1,
        "bc_epochs": 20}


def _learner(seed=0, **options):
    pytest.importorskip("stable_baselines3", reason="needs the rl extra")
    from teamenv.selfplay.imitation import ImitationPPOLearner

    return ImitationPPOLearner(SETUP, seed=seed, teacher="chaser", **(TINY | options))


def _held_out(n_decisions=100):
    """Teacher-played states and labels on a seed the clone never saw."""
    env = TeacherBatchEnv(SETUP, OpponentMix.single("static", 0), "chaser", copies=1, seed=99)
    xs, ys = [], []
    obs = env.reset()
    for _ in range(n_decisions):
        y = env.teacher_outputs()
        xs.append(obs)
        ys.append(y)
        obs, *_ = env.step(y)
    env.close()
    return np.concatenate(xs), np.concatenate(ys)


@pytest.fixture(scope="module")
def cloned():
    learner = _learner()
    before = learner.act(_held_out()[0])
    weights = learner.train(900, OpponentMix.single("static", 0), seed=11)
    return learner, weights, before


@pytest.mark.rl
def test_cloning_fits_the_teacher_on_held_out_states(cloned):
    learner, _, before = cloned
    x, y = _held_out()
    mask = learner.label_mask(x, kick_gate_m())
    error_before = float(np.sum(mask * (before - y) ** 2) / mask.sum())
    error_after = float(np.sum(mask * (learner.act(x) - y) ** 2) / mask.sum())
    assert error_after < 0.5 * error_before, (error_before, error_after)
    log = learner.clone_log
    assert [r["played_by"] for r in log] == ["teacher", "network"]
    assert log[1]["samples"] == 2 * log[0]["samples"] and log[0]["samples"] >= 900 // 2
    assert all(np.isfinite(r["bc_loss"]) for r in log)
    assert learner.last_episodes  # the league summarises them per opponent


@pytest.mark.rl
def test_the_same_seed_clones_the_same_network_bit_for_bit(cloned):
    _, weights, _ = cloned
    again = _learner().train(900, OpponentMix.single("static", 0), seed=11)
    for (w1, b1), (w2, b2) in zip(weights.layers, again.layers, strict=True):
        assert np.array_equal(w1, w2) and np.array_equal(b1, b2)
    assert np.array_equal(weights.obs_mean, again.obs_mean)
    other = _learner().train(900, OpponentMix.single("static", 0), seed=12)
    assert not np.array_equal(other.layers[0][0], weights.layers[0][0])


@pytest.mark.rl
def test_a_checkpoint_carries_the_clone_over_to_ppo(cloned, tmp_path):
    learner, weights, _ = cloned
    learner.save(tmp_path)
    resumed = _learner(seed=5)
    resumed.load(tmp_path)
    assert resumed.cloned and resumed.clone_log == learner.clone_log
    np.testing.assert_array_equal(resumed.weights().layers[-1][0], weights.layers[-1][0])
    after = resumed.train(192, OpponentMix.single("static", 0), seed=12)  # PPO now
    assert resumed.model.num_timesteps > 900
    assert not np.array_equal(after.layers[-1][0], weights.layers[-1][0])


def test_the_kick_labels_count_only_where_the_kick_gate_is_open():
    learner = _learner()
    gate = kick_gate_m()
    x = np.zeros((3, learner.batch.observation_size), dtype=np.float32)
    x[:, 7:9] = [[gate * 0.6, gate * 0.8], [gate + 0.01, 0.0], [3.0, -2.0]]  # ball.rel_x, rel_y
    mask = learner.label_mask(x, gate)
    assert mask.tolist() == [[1, 1, 1, 1, 1], [1, 1, 1, 0, 0], [1, 1, 1, 0, 0]]
    assert learner.label_mask(x, None).tolist() == [[1] * 5] * 3  # no gate: every entry
    reflex = TrainingSetup(team_size=3, actions=ActionSetup(walk_to_ball=True))
    from teamenv.selfplay.imitation import ImitationPPOLearner

    walker = ImitationPPOLearner(reflex, seed=0, teacher="chaser", **TINY)
    assert walker.label_mask(x, gate).tolist() == [[0, 0, 0, 1, 1], [0, 0, 0, 0, 0],
                                                   [0, 0, 0, 0, 0]]


@pytest.mark.parametrize("options, message", [
    ({"dagger_rounds": -1}, "dagger_rounds"), ({"bc_epochs": 0}, "bc_epochs"),
    ({"bc_learning_rate": 0.0}, "bc_learning_rate"), ({"teacher": "nobody"}, "teacher")])
def test_bad_learner_options_are_one_clear_error(options, message):
    pytest.importorskip("stable_baselines3", reason="needs the rl extra")
    from teamenv.selfplay.imitation import ImitationPPOLearner

    with pytest.raises(ConfigError, match=message):
        learner = ImitationPPOLearner(SETUP, seed=0, **(TINY | options))
        learner.train(30, OpponentMix.single("static", 0), seed=1)
