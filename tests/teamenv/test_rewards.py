"""The ``reward=`` option: documented terms, signs, weights, and its order with ``reward_fn``."""

from __future__ import annotations

import numpy as np
import pytest

import teamenv
from teamenv.errors import ConfigError
from teamenv.rewards import reward_weights
from teamenv.sim.playmode import PlayMode
from tests.teamenv.helpers import idle
from tests.teamenv.scenario_drivers import go_and_kick, play_out


def _run(reward, seed=0, steps=None, scenario="one_v_goalie", target=(16.0, 0.0), **opts):
    """Rewards per step of an episode where left_1 goes and kicks towards ``target``."""
    env = teamenv.parallel_env(scenario=scenario, reward=reward, **opts)
    obs, _ = env.reset(seed=seed)
    trace = []
    while env.agents and (steps is None or len(trace) < steps):
        actions = idle(env)
        actions["left_1"] = go_and_kick(obs["left_1"], target)
        obs, rewards, *_ = env.step(actions)
        trace.append(rewards)
    return env, trace


def test_weights_are_validated():
    assert reward_weights(None) is None
    assert reward_weights("goal") == {"goal": 1.0}
    assert reward_weights({"ball_progress": 2, "possession": 0.5}) == {
        "ball_progress": 2.0, "possession": 0.5}
    with pytest.raises(ConfigError, match="unknown term 'shots'.*ball_progress"):
        teamenv.parallel_env(reward="shots")
    with pytest.raises(ConfigError, match=r"reward\['goal'\]: weight must be a finite number"):
        teamenv.parallel_env(reward={"goal": float("nan")})
    with pytest.raises(ConfigError, match="expected None"):
        teamenv.parallel_env(reward=3)


def _scoring_episode(reward):
    for seed in range(8):
        env = teamenv.parallel_env(scenario="one_v_goalie", reward=reward)
        totals, (_, _, infos) = play_out(env, seed, target=(env.field.half_length + 0.5, 0.0))
        if infos["left_1"]["end"] == "goal":
            return totals
    raise AssertionError("no seed scored")


def test_goal_term_is_plus_one_for_the_scorers_and_minus_one_for_the_others():
    for reward in (None, "goal"):  # None keeps the built-in goal reward
        totals = _scoring_episode(reward)
        assert totals == {"left_1": 1.0, "right_1": -1.0}
    assert _scoring_episode({}) == {"left_1": 0.0, "right_1": 0.0}
    assert _scoring_episode({"goal": 3.0}) == {"left_1": 3.0, "right_1": -3.0}


def test_ball_progress_is_the_ball_travel_towards_the_attacked_goal():
    env, trace = _run("ball_progress", steps=150)
    left = np.array([r["left_1"] for r in trace])
    right = np.array([r["right_1"] for r in trace])
    assert np.array_equal(left, -right)  # zero-sum, team-shared
    assert left.sum() > 1.0  # the attacker kicked the ball towards the goal (+x)
    env0 = teamenv.parallel_env(scenario="one_v_goalie")
    env0.reset(seed=0)
    start_x = env0.sim.world.ball_state()[0]
    if env.sim.referee.mode.name == "PlayOn":
        assert left.sum() == pytest.approx(env.sim.world.ball_state()[0] - start_x)
    # kicked backwards: negative
    _, back = _run("ball_progress", steps=300, target=(-15.0, 0.0))
    assert sum(r["left_1"] for r in back) < -1.0


def test_ball_progress_ignores_the_referees_placements():
    # A ball rolling into the right goal: the goal cycle and the ball put back on the centre
    # spot for the kick-off (a 15 m jump) add nothing; rolling in PlayOn counts.
    env = teamenv.parallel_env(team_size=1, reward="ball_progress")
    env.reset(seed=0)
    env.sim.referee.mode = PlayMode.PlayOn
    env.sim.world.place_ball(13.0, 0.7, 3.0, 0.0)  # past the keeper standing at y = 0
    _, rewards, *_ = env.step(idle(env))
    assert rewards["left_1"] > 0.0
    assert rewards == {"left_1": -rewards["right_1"], "right_1": rewards["right_1"]}
    jumps = 0
    for _ in range(400):
        before = env.state()[0]
        _, rewards, *_ = env.step(idle(env))
        moved = env.state()[0] - before
        if env.sim.referee.mode == PlayMode.PlayOn:
            assert rewards["left_1"] == pytest.approx(moved)
        else:
            assert rewards["left_1"] == 0.0
            jumps += abs(moved) > 10.0
    assert env.sim.referee.score == [1, 0]
    assert jumps == 1  # the kick-off placement happened, and paid nothing


def test_possession_goes_to_the_team_within_kick_reach():
    env = teamenv.parallel_env(scenario="one_v_one", reward="possession")
    env.reset(seed=0)
    _, rewards, *_ = env.step(idle(env))  # the attacker starts with the ball at its feet
    assert rewards == {"left_1": pytest.approx(0.02), "right_1": pytest.approx(-0.02)}
    env = teamenv.parallel_env(scenario="one_v_one", reward="possession", right="chaser",
                               caller_agents=["right_1"])
    env.reset(seed=0)
    # the defender walks onto the ball while the attacker walks away from it
    obs = None
    for _ in range(400):
        actions = {"left_1": {"walk": np.array([-1.0, 0.0, 0.0], np.float32)},
                   "right_1": {} if obs is None else go_and_kick(obs["right_1"], (0.0, 0.0))}
        obs, rewards, *_ = env.step(actions)
        if rewards["right_1"] > 0:
            break
    assert rewards == {"left_1": pytest.approx(-0.02), "right_1": pytest.approx(0.02)}


def test_weights_combine_linearly():
    _, progress = _run("ball_progress", steps=120)
    _, possession = _run("possession", steps=120)
    _, goal = _run("goal", steps=120)
    _, mixed = _run({"ball_progress": 2.0, "possession": 3.0, "goal": -1.0}, steps=120)
    for p, q, g, m in zip(progress, possession, goal, mixed, strict=True):
        for agent in m:
            assert m[agent] == pytest.approx(2.0 * p[agent] + 3.0 * q[agent] - g[agent])


def test_reward_fn_sees_the_reward_option_as_its_default():
    seen = []

    def shaped(inp):
        seen.append(dict(inp.default))
        return {a: 10.0 * inp.default[a] for a in inp.agents}

    _, plain = _run("ball_progress", steps=80)
    _, trace = _run("ball_progress", steps=80, reward_fn=shaped)
    assert seen == plain
    for a, b in zip(plain, trace, strict=True):
        assert b == {k: pytest.approx(10.0 * v) for k, v in a.items()}
