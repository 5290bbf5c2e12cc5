"""Every play-mode transition of the referee, in hand-made scenes."""

import math

import numpy as np
import pytest

import teamenv
from teamenv.errors import ActionError
from teamenv.sim.playmode import PlayMode
from tests.teamenv.helpers import ball_xy, idle, make_env, mode, play_on, roll_ball, step_until


def test_before_kickoff_then_kickoff_left_then_play_on_when_kicker_touches():
    env = make_env()
    assert mode(env) == PlayMode.BeforeKickOff
    assert env.sim.referee.time_s == 0.0
    step_until(env, lambda e: mode(e) == PlayMode.KickOff_Left)
    assert env.sim.referee.time_s == 0.0  # time stands still before kick-off
    # Put left_2 at the ball and kick.
    env.sim.world.place_player(1, -0.25, 0.0, 0.0)
    kick = {a: {} for a in env.agents}
    kick["left_2"] = {"kick": np.array([0.5, 0.0], np.float32)}
    step_until(env, lambda e: mode(e) == PlayMode.PlayOn, actions=lambda e: kick, max_steps=100)
    assert env.sim.referee.time_s > 0


def test_goal_scores_and_conceding_team_kicks_off():
    env = make_env()
    play_on(env)
    f = env.field
    roll_ball(env, f.half_length - 0.5, 0.1, 4.0, 0.0)
    env.sim.referee.last_touch = 1  # left_2
    _, rewards, _, _, infos = env.step(idle(env))
    step_until(env, lambda e: mode(e) == PlayMode.Goal_Left, max_steps=50)
    assert env.sim.referee.score == [1, 0]
    step_until(env, lambda e: mode(e) == PlayMode.KickOff_Right,
               max_steps=int(env.rules.goal_pause_s / 0.02) + 5)
    assert np.allclose(ball_xy(env), 0.0)


def test_goal_reward_is_plus_one_for_scorers_minus_one_for_others():
    env = make_env()
    play_on(env)
    roll_ball(env, env.field.half_length - 0.1, 0.0, 3.0, 0.0)
    for _ in range(20):
        _, rewards, _, _, infos = env.step(idle(env))
        if any(rewards.values()):
            break
    assert rewards["left_1"] == 1.0 and rewards["right_1"] == -1.0
    assert infos["left_1"]["goal"] == "left"


def test_ball_over_side_line_gives_kick_in_to_other_team():
    env = make_env()
    play_on(env)
    env.sim.referee.last_touch = 0  # left touched last
    roll_ball(env, 3.0, env.field.half_width - 0.1, 0.0, 3.0)
    step_until(env, lambda e: mode(e) != PlayMode.PlayOn, max_steps=50)
    assert mode(env) == PlayMode.KickIn_Right
    assert ball_xy(env)[1] == pytest.approx(env.field.half_width)
    assert ball_xy(env)[0] == pytest.approx(3.0, abs=0.2)


def test_ball_over_goal_line_by_attacker_gives_goal_kick():
    env = make_env()
    play_on(env)
    env.sim.referee.last_touch = 0  # left attacks +x
    roll_ball(env, env.field.half_length - 0.3, 3.0, 3.0, 0.0)
    step_until(env, lambda e: mode(e) != PlayMode.PlayOn, max_steps=50)
    assert mode(env) == PlayMode.GoalKick_Right
    assert ball_xy(env)[0] > 0 and ball_xy(env)[1] == 0.0


def test_ball_over_goal_line_by_defender_gives_corner():
    env = make_env()
    play_on(env)
    env.sim.referee.last_touch = env.team_size  # right_1 defends the +x goal
    roll_ball(env, env.field.half_length - 0.3, -3.0, 3.0, 0.0)
    step_until(env, lambda e: mode(e) != PlayMode.PlayOn, max_steps=50)
    assert mode(env) == PlayMode.CornerKick_Left
    assert np.allclose(ball_xy(env), [env.field.half_length, -env.field.half_width])


@pytest.mark.parametrize("kind", ["KickIn", "CornerKick", "GoalKick"])
def test_opponents_kept_two_metres_from_ball_in_set_plays(kind):
    env = make_env(team_size=3)
    play_on(env)
    spot = (2.0, env.field.half_width)
    env.sim.referee._start_set_play(env.sim.world, kind, 0, spot, [])
    # Opponents try to walk onto the ball.
    for i in range(3):
        env.sim.world.place_player(3 + i, spot[0] + 0.3 * i, spot[1] - 0.5, math.pi)
    for _ in range(30):
        env.step({a: {"walk": np.array([0.5, 0, 0], np.float32)} if a.startswith("right")
                  else {} for a in env.agents})
        poses = env.sim.world.player_poses()
        dist = np.hypot(poses[3:, 0] - spot[0], poses[3:, 1] - spot[1])
        assert (dist >= env.rules.set_play_distance - 0.05).all()
    assert mode(env).kind == kind  # not taken: ball held at its spot
    assert np.allclose(ball_xy(env), spot)


def test_kickoff_keeps_defenders_out_of_centre_circle_and_own_half():
    env = make_env(team_size=3)
    step_until(env, lambda e: mode(e) == PlayMode.KickOff_Left)
    for _ in range(20):
        env.sim.world.place_player(3, 0.5, 0.2, math.pi)  # a right player walks in
        env.step(idle(env))
        x, y = env.sim.world.player_poses()[3, :2]
        assert math.hypot(x, y) >= env.field.center_circle_radius - 1e-6
        assert x >= 0


def test_stalled_set_play_is_dropped_after_timeout():
    env = make_env(rules={"set_play_timeout_s": 1.0})
    play_on(env)
    env.sim.referee._start_set_play(env.sim.world, "KickIn", 1, (0.0, env.field.half_width), [])
    step_until(env, lambda e: mode(e) == PlayMode.PlayOn, max_steps=60)
    assert any(ev.kind == "drop_ball" for ev in env.last_report.referee)


def test_stalled_kickoff_is_dropped_after_timeout():
    env = make_env(rules={"kickoff_timeout_s": 0.5})
    step_until(env, lambda e: mode(e) == PlayMode.PlayOn, max_steps=60)


def test_beam_allowed_before_kickoff_only_in_own_half():
    env = make_env()
    beam = {a: {} for a in env.agents}
    beam["left_1"] = {"beam": np.array([-3.0, 1.0, 0.5], np.float32), "beam_request": 1}
    env.step(beam)
    x, y, h = env.sim.world.player_poses()[0]
    assert x == pytest.approx(-3.0, abs=0.3) and y == pytest.approx(1.0, abs=0.3)
    assert h == pytest.approx(0.5, abs=0.3)
    # Right team beams in its own frame: it lands in the +x half of the world.
    beam = {a: {} for a in env.agents}
    beam["right_1"] = {"beam": np.array([-3.0, 1.0, 0.0], np.float32), "beam_request": 1}
    env.step(beam)
    x, y, _ = env.sim.world.player_poses()[env.team_size]
    assert x == pytest.approx(3.0, abs=0.3) and y == pytest.approx(-1.0, abs=0.3)
    with pytest.raises(ActionError, match="left_1.*beam"):
        env.step({**idle(env), "left_1": {"beam": np.array([2.0, 0, 0], np.float32),
                                          "beam_request": 1}})


def test_beam_refused_in_play_on():
    env = make_env()
    play_on(env)
    before = env.sim.world.player_poses()[0].copy()
    out = env.step({**idle(env), "left_1": {"beam": np.array([-1.0, 0, 0], np.float32),
                                            "beam_request": 1}})
    assert out[4]["left_1"]["beam_refused"] == "PlayOn"
    assert np.allclose(env.sim.world.player_poses()[0][:2], before[:2], atol=0.05)


def test_beam_allowed_after_goal():
    env = make_env()
    play_on(env)
    roll_ball(env, env.field.half_length - 0.1, 0.0, 3.0, 0.0)
    step_until(env, lambda e: mode(e) == PlayMode.Goal_Left, max_steps=50)
    env.step({**idle(env), "right_2": {"beam": np.array([-2.0, 0.0, 0.0], np.float32),
                                       "beam_request": 1}})
    assert env.sim.world.player_poses()[env.team_size + 1][0] == pytest.approx(2.0, abs=0.3)


def test_half_time_and_game_over():
    env = make_env(rules={"half_time_s": 2.0})
    step_until(env, lambda e: e.sim.referee.half == 2, max_steps=400)
    assert mode(env) == PlayMode.BeforeKickOff
    step_until(env, lambda e: mode(e) == PlayMode.KickOff_Right, max_steps=50)
    obs, _, terms, truncs, _ = None, None, None, None, None
    for _ in range(400):
        obs, _, terms, truncs, _ = env.step(idle(env))
        if env.episode_over:
            break
    assert mode(env) == PlayMode.GameOver
    assert all(terms.values()) and not any(truncs.values())
    assert env.agents == []
    with pytest.raises(ActionError, match="finished episode"):
        env.step({})


def test_change_sides_at_half_time_flips_attack_direction():
    env = make_env(rules={"half_time_s": 1.0, "change_sides_at_half_time": True})
    step_until(env, lambda e: e.sim.referee.half == 2, max_steps=200)
    assert env.sim.referee.attack_sign == [-1.0, 1.0]
    # Left team now stands in the +x half, and still sees itself attacking +x.
    assert (env.sim.world.player_poses()[: env.team_size, 0] > 0).all()
    obs = env.sim.observations()
    assert obs[0]["self"][0] < 0


def test_max_cycles_truncates():
    env = make_env(max_cycles=10)
    for _ in range(10):
        _, _, terms, truncs, _ = env.step(idle(env))
    assert all(truncs.values()) and not any(terms.values())
    assert teamenv.PLAY_MODES[0] == "BeforeKickOff"



def _kick_off_taken_by_left_2(env):
    """KickOff_Left taken by left_2 (a touch of its own kick): PlayOn, left_2 the taker."""
    step_until(env, lambda e: mode(e) == PlayMode.KickOff_Left)
    env.sim.world.place_player(1, -0.25, 0.0, 0.0)
    kick = {a: {} for a in env.agents}
    kick["left_2"] = {"kick": np.array([0.3, 0.0], np.float32)}
    step_until(env, lambda e: mode(e) == PlayMode.PlayOn, actions=lambda e: kick, max_steps=100)


def _wait(env, seconds: float) -> None:
    for _ in range(round(seconds / 0.02)):
        env.step(idle(env))


@pytest.mark.parametrize("rule", [True, False])
def test_the_kick_off_takers_second_touch_is_a_double_touch_foul(rule):
    """The league's rule (rcsssmj): the taker touching the ball again more than 1 s after its
    first touch, before anyone else, gives the other side a free kick (our kick-in) where the
    ball lies; without the rule play goes on."""
    env = make_env(rules={"double_touch": rule})
    _kick_off_taken_by_left_2(env)
    ref = env.sim.referee
    assert (ref.no_second_touch is not None) == rule
    _wait(env, 1.2)
    events = ref.update(env.sim.world, [1])             # left_2 touches it again
    if rule:
        assert [e.kind for e in events][:1] == ["double_touch"] and events[0].player == 1
        assert mode(env) == PlayMode.KickIn_Right
        assert ref.set_play_spot == pytest.approx(tuple(ball_xy(env)))
    else:
        assert mode(env) == PlayMode.PlayOn


def test_a_second_touch_within_1s_or_after_another_players_is_no_foul():
    env = make_env(rules={"double_touch": True})
    _kick_off_taken_by_left_2(env)
    ref = env.sim.referee
    ref.update(env.sim.world, [1])                       # the same kick, within 1 s
    assert mode(env) == PlayMode.PlayOn and ref.no_second_touch is not None
    ref.update(env.sim.world, [0])                       # left_1 touched it: left_2 is free
    assert ref.no_second_touch is None
    _wait(env, 1.2)
    ref.update(env.sim.world, [1])
    assert mode(env) == PlayMode.PlayOn


def test_the_double_touch_rule_spares_a_team_of_one():
    env = make_env(team_size=1, rules={"double_touch": True})
    step_until(env, lambda e: mode(e) == PlayMode.KickOff_Left)
    env.sim.world.place_player(0, -0.25, 0.0, 0.0)
    kick = {a: {} for a in env.agents}
    kick["left_1"] = {"kick": np.array([0.3, 0.0], np.float32)}
    step_until(env, lambda e: mode(e) == PlayMode.PlayOn, actions=lambda e: kick, max_steps=100)
    assert env.sim.referee.no_second_touch is None


def test_match_options_carry_the_double_touch_rule_to_the_env_and_its_teams():
    from teamenv.match import MatchOptions

    on = MatchOptions(field="mj7v7", team_size=3, double_touch=True)
    env = teamenv.parallel_env(**on.env_kwargs(), left="full", right="static")
    env.reset(seed=0)
    assert env.sim.referee.rules.double_touch
    assert env.team_host.teams["left"].context.double_touch
    # stored options of matches without the rule keep their keys
    assert "double_touch" not in MatchOptions().to_dict()
    assert on.to_dict()["double_touch"] is True
