"""Scenarios reset into their documented situations and end as documented."""

from __future__ import annotations

import math

import numpy as np
import pytest
from pettingzoo.test import api_test, parallel_api_test

import teamenv
from teamenv.errors import ConfigError
from teamenv.scenarios import (
    BALL_AT_FEET_M,
    SCENARIOS,
    Scenario,
    Spot,
    bench_pose,
    get_scenario,
    scenario_names,
)
from teamenv.sim.playmode import PlayMode
from tests.teamenv.helpers import idle
from tests.teamenv.scenario_drivers import play_out

PLACED = [name for name in scenario_names() if SCENARIOS[name].team_sizes is not None]


def test_registry_has_the_documented_scenarios():
    assert {"kickoff", "empty_goal", "one_v_goalie", "counter_3v2", "corner_kick",
            "one_v_one"} <= set(scenario_names())
    for name in scenario_names():
        assert get_scenario(name).name == name
        assert get_scenario(name).description


def test_unknown_scenario_lists_the_valid_names():
    with pytest.raises(ConfigError, match="unknown scenario 'penalty'.*empty_goal"):
        teamenv.parallel_env(scenario="penalty")


def test_team_size_too_small_for_the_scenario():
    with pytest.raises(ConfigError, match="counter_3v2.*at least 3.*got 2"):
        teamenv.parallel_env(scenario="counter_3v2", team_size=2)


def test_scenario_definition_is_checked():
    with pytest.raises(ConfigError, match="unknown condition"):
        Scenario("x", "x", None, (1, 0), (Spot(1.0),), (), None, 0, "PlayOn",
                 frozenset({"offside"}), 10.0)
    with pytest.raises(ConfigError, match="team_sizes"):
        Scenario("x", "x", None, (2, 0), (Spot(1.0),), (), None, 0, "PlayOn",
                 frozenset({"goal"}), 10.0)


@pytest.mark.parametrize("name", PLACED)
def test_resets_into_the_documented_situation(name):
    sc = SCENARIOS[name]
    env = teamenv.parallel_env(scenario=name)
    env.reset(seed=3)
    field, n = env.field, env.team_size
    assert field.name == sc.field
    assert n == max(sc.team_sizes)
    poses = env.sim.world.player_poses()
    for team, spots in ((0, sc.left), (1, sc.right)):
        for k, spot in enumerate(spots):
            x, y, h = spot.pose(field)
            got = poses[team * n + k]
            assert abs(got[0] - x) <= sc.player_jitter_m + 1e-9, (name, team, k)
            assert abs(got[1] - y) <= sc.player_jitter_m + 1e-9, (name, team, k)
            turn = (got[2] - h + math.pi) % (2 * math.pi) - math.pi
            assert abs(turn) <= sc.heading_jitter_rad + 1e-9
    ball = env.sim.world.ball_state()
    if sc.ball_with is not None:
        carrier = poses[sc.ball_with]
        assert math.hypot(*(ball[:2] - carrier[:2])) == pytest.approx(BALL_AT_FEET_M)
        assert env.sim.referee.last_touch == sc.ball_with
    else:
        assert ball[:2] == pytest.approx(sc.ball.pose(field)[:2])
    assert env.sim.referee.mode == PlayMode[sc.play_mode]
    benched = set(env.benched_agents)
    assert sorted(env.possible_agents + env.benched_agents) == sorted(env.player_names)
    assert not benched & set(env.agents)


def test_empty_goal_benches_the_keeper_outside_the_pitch():
    env = teamenv.parallel_env(scenario="empty_goal", team_size=2)
    env.reset(seed=0)
    assert env.agents == ["left_1"]
    assert env.benched_agents == ["left_2", "right_1", "right_2"]
    poses = env.sim.world.player_poses()
    for agent in env.benched_agents:
        i = env.player_names.index(agent)
        team, k = divmod(i, 2)
        assert tuple(poses[i]) == pytest.approx(bench_pose(env.field, team, k))
        assert not env.field.contains(*poses[i, :2])
    # benched players stand still even when a team drives their side
    env = teamenv.parallel_env(scenario="empty_goal", right="chaser")
    env.reset(seed=0)
    before = env.sim.world.player_poses()[1].copy()
    for _ in range(50):
        env.step(idle(env))
    assert env.sim.world.player_poses()[1] == pytest.approx(before)
    with pytest.raises(teamenv.ActionError, match="benched by the scenario"):
        env.step({"left_1": {}, "right_1": {}})


def test_corner_kick_keeps_defenders_away_and_mirrors_for_the_right_team():
    env = teamenv.parallel_env(scenario="corner_kick")
    obs, _ = env.reset(seed=0)
    f = env.field
    ball = env.sim.world.ball_state()
    assert ball[:2] == pytest.approx((f.half_length, f.half_width))
    poses = env.sim.world.player_poses()
    right = poses[env.team_size:]
    assert np.hypot(right[:, 0] - ball[0], right[:, 1] - ball[1]).min() >= 2.0
    # each team sees its own set play as _Left
    assert obs["left_2"]["play_mode"] == PlayMode.CornerKick_Left
    assert obs["right_2"]["play_mode"] == PlayMode.CornerKick_Right


def test_placement_is_deterministic_per_seed_with_jitter():
    def start(seed):
        env = teamenv.parallel_env(scenario="counter_3v2")
        env.reset(seed=seed)
        return env.state()

    assert np.array_equal(start(5), start(5))
    assert not np.array_equal(start(5), start(6))


def test_kickoff_scenario_is_the_normal_match():
    plain = teamenv.parallel_env(team_size=2, right="chaser")
    scen = teamenv.parallel_env(team_size=2, right="chaser", scenario="kickoff")
    assert plain.field == scen.field
    plain.reset(seed=4)
    scen.reset(seed=4)
    for _ in range(60):
        plain.step(idle(plain))
        scen.step(idle(scen))
        assert np.array_equal(plain.state(), scen.state())


def test_kickoff_scenario_ends_at_game_over():
    env = teamenv.parallel_env(team_size=1, scenario="kickoff", left="static", right="static",
                               rules={"half_time_s": 0.5, "halves": 1})
    env.reset(seed=0)
    while not env.episode_over:
        env.step({})
    assert env.end_reason == "game_over"


def test_empty_goal_ends_on_a_goal_or_ball_out():
    reasons = []
    for seed in range(8):
        env = teamenv.parallel_env(scenario="empty_goal")
        totals, (terms, truncs, infos) = play_out(env, seed, target=(env.field.half_length + 0.5,
                                                                      0.0))
        reason = infos["left_1"]["end"]
        reasons.append(reason)
        assert reason in ("goal", "ball_out")
        assert terms["left_1"] and not truncs["left_1"]
        if reason == "goal":
            assert infos["left_1"]["goal"] == "left"
            assert env.sim.referee.score == [1, 0]
            break
    assert "goal" in reasons, reasons


def test_ball_kicked_over_the_touchline_ends_with_ball_out():
    env = teamenv.parallel_env(scenario="empty_goal")
    _, (terms, _, infos) = play_out(env, 0, target=(7.0, 30.0))
    assert infos["left_1"]["end"] == "ball_out"
    assert env.sim.referee.mode.kind == "KickIn"
    assert terms["left_1"]


def test_one_v_one_ends_when_the_defender_wins_the_ball():
    env = teamenv.parallel_env(scenario="one_v_one", right="chaser")
    env.reset(seed=2)
    while env.agents:
        _, _, terms, truncs, infos = env.step(idle(env))
    assert infos["left_1"]["end"] == "defender_possession"
    assert terms["left_1"] and not truncs["left_1"]
    assert env.sim.referee.last_touch == env.team_size  # right_1


def test_time_limit_truncates():
    env = teamenv.parallel_env(scenario="empty_goal")
    env.reset(seed=0)
    steps = 0
    while env.agents:
        _, _, terms, truncs, infos = env.step(idle(env))
        steps += 1
    assert steps == round(SCENARIOS["empty_goal"].max_duration_s / env.physics.cycle_s)
    assert truncs["left_1"] and not terms["left_1"]
    assert infos["left_1"]["end"] == "time_limit"


def test_max_cycles_before_the_scenario_ends_is_reported():
    env = teamenv.parallel_env(scenario="empty_goal", max_cycles=5)
    env.reset(seed=0)
    for _ in range(5):
        _, _, _, truncs, infos = env.step(idle(env))
    assert truncs["left_1"] and infos["left_1"]["end"] == "max_cycles"


@pytest.mark.parametrize("opts", [
    dict(scenario="one_v_one"),
    dict(scenario="counter_3v2", right="chaser", observation_format="box",
         action_format="box"),
    dict(scenario="empty_goal", team_size=2),
    dict(scenario="corner_kick", left="chaser", caller_agents=["left_2"]),
], ids=lambda o: "-".join(f"{k}={v}" for k, v in o.items()))
def test_pettingzoo_api_on_scenarios(opts):
    parallel_api_test(teamenv.parallel_env(max_cycles=120, **opts), num_cycles=150)
    api_test(teamenv.env(max_cycles=40, **opts), num_cycles=50)
