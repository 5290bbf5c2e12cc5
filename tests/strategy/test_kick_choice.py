"""The ball-roll prediction, interception and the kick evaluator (best_kick) in hand-built
scenes, and the roll model against the env's own ball."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategy.behaviours.kick_choice import best_kick, goal_probability
from strategy.geometry import BallRoll
from teamenv.config import PhysicsConfig
from teamenv.sim.world import roll_distance

from . import scenes
from .scenes import world

ROLL = BallRoll(PhysicsConfig().ball_linear_drag, PhysicsConfig().ball_rolling_decel)


@pytest.mark.parametrize("speed", [0.5, 2.0, 5.0, 9.0, 12.0])
def test_rest_point_matches_the_env_ball_within_one_percent(speed):
    # roll_distance steps the env's per-cycle drag; the closed form is its continuous limit
    expected = roll_distance(speed, PhysicsConfig())
    got = float(ROLL.travel(speed, ROLL.stop_time(speed)))
    assert got == pytest.approx(expected, rel=0.01, abs=0.02)


@settings(max_examples=60, deadline=None)
@given(speed=st.floats(0.1, 12.0), t1=st.floats(0.0, 10.0), t2=st.floats(0.0, 10.0))
def test_travel_never_goes_back_and_stops_at_rest(speed, t1, t2):
    lo, hi = sorted((t1, t2))
    assert float(ROLL.travel(speed, lo)) <= float(ROLL.travel(speed, hi)) + 1e-12
    stop = ROLL.stop_time(speed)
    assert float(ROLL.travel(speed, stop + 5.0)) == pytest.approx(float(ROLL.travel(speed, stop)))


def test_drag_free_models_stop_or_cap():
    assert BallRoll(0.0, 0.5).stop_time(2.0) == pytest.approx(4.0)
    assert BallRoll(0.0, 0.5).rest_point(np.zeros(2), np.array([2.0, 0.0]))[0] == \
        pytest.approx(4.0)
    assert BallRoll(0.0, 0.0).stop_time(1.0) == 20.0


def test_intercept_meets_a_ball_rolling_towards_the_player_before_it_passes():
    wm = world(position=(5.0, 0.0), ball=(0.0, 0.0), ball_velocity=(4.0, 0.0))
    when, where = wm.intercepts(np.array([[5.0, 0.0], [-5.0, 0.0]]), 1.2)
    assert where[0, 0] < 5.0 and when[0] < 1.5  # meets it on the way
    assert where[1, 0] == pytest.approx(wm.ball_rest()[0])  # the one behind waits for it
    assert when[1] > when[0]


def test_best_kick_passes_to_the_free_teammate_not_into_the_opponents():
    # free teammate up the left wing, opponents crowding the straight line to goal
    wm = world(position=(-0.3, 0.0), ball=(0.0, 0.0), teammates=[(6.0, 6.0)],
               opponents=[(7.0, 0.0), (7.5, -1.0), (6.5, 1.0)], field="mj7v7")
    choice = best_kick(wm, scenes.BODY, 1.2, 2.0, 0.15, 25.0)
    assert choice.margin_s > 1.0
    assert choice.target[1] > 2.0  # towards the free wing, not at the crowd
    assert not choice.shot


def test_best_kick_shoots_from_close_range_in_front_of_an_open_goal():
    wm = world(position=(20.0, 0.0), ball=(20.3, 0.0), teammates=[(10.0, 5.0)],
               opponents=[(0.0, 0.0)], field="mj7v7")
    choice = best_kick(wm, scenes.BODY, 1.2, 2.0, 0.15, 25.0)
    assert choice.shot and choice.target[0] > wm.field.half_length


def test_goal_probability_falls_with_distance_and_angle():
    near = world(ball=(22.0, 0.0), field="mj7v7")
    far = world(ball=(12.0, 0.0), field="mj7v7")
    wide = world(ball=(22.0, 12.0), field="mj7v7")
    goal = near.opponent_goal + np.array([1.0, 0.0])
    p_near = goal_probability(near, goal, 1.0, scenes.BODY)
    assert p_near > goal_probability(far, goal, 1.0, scenes.BODY) > 0.0
    assert p_near > goal_probability(wide, goal, 1.0, scenes.BODY)
    assert 0.0 <= p_near <= 1.0
    behind = world(ball=(28.0, 0.0), field="mj7v7")
    assert goal_probability(behind, goal, 1.0, scenes.BODY) == 0.0


def test_best_kick_never_aims_off_the_pitch():
    for y in (-15.0, 15.0):
        wm = world(position=(0.0, y - 0.3 * math.copysign(1, y)), ball=(0.0, y),
                   opponents=[(2.0, y)], field="mj7v7")
        choice = best_kick(wm, scenes.BODY, 1.2, 2.0, 0.15, 25.0)
        assert abs(choice.target[1]) <= wm.field.half_width - 0.5


def test_the_full_team_predicts_with_the_env_drag_it_is_told():
    # a stickier pitch: the team's roll model is the env's, not a default
    import teamenv

    env = teamenv.parallel_env(field="mj7v7", team_size=3, left="full",
                               physics={"ball_linear_drag": 0.9, "ball_rolling_decel": 0.6})
    env.reset(seed=0)
    roll = env.teams["left"].skills.ball_roll
    assert (roll.linear_drag, roll.rolling_decel) == (0.9, 0.6)
    expected = roll_distance(5.0, PhysicsConfig(ball_linear_drag=0.9, ball_rolling_decel=0.6))
    assert float(roll.travel(5.0, roll.stop_time(5.0))) == pytest.approx(expected, rel=0.02)


def _decider():
    from strategy.decision.field_player import FieldPlayerDecisionMaker
    from strategy.teams.full_config import FullTeamConfig

    from .scenes import skills

    return FieldPlayerDecisionMaker(FullTeamConfig().decision_params(), skills("mj7v7"), goalie=None)


def test_ball_player_runs_to_meet_a_rolling_ball_not_to_where_it_is():
    # ball rolling up the pitch past us on our left: go forward-left to meet it
    wm = world(position=(0.0, 0.0), heading=0.0, ball=(-3.0, 2.0), ball_velocity=(5.0, 0.0),
               field="mj7v7")
    request = _decider().play_ball(wm)
    assert request.behaviour == "intercept"
    assert request.walk[0] > 0.0  # walks forward, towards where the ball will be
    assert request.walk[2] > 0.0  # turning left, to the ball's line


def test_ball_player_kicks_when_a_teammate_wins_the_race_and_dribbles_when_none_does():
    decider = _decider()
    # in reach, a free teammate ahead on the wing, opponents in the way to goal: a pass
    passing = world(position=(-0.25, 0.0), ball=(0.0, 0.0), teammates=[(6.0, 6.0)],
                    opponents=[(7.0, 0.0), (7.5, -1.0), (6.5, 1.0)], field="mj7v7")
    kick = decider.play_ball(passing)
    assert kick.kick is not None and kick.kick[0] > 0 and kick.behaviour == "pass"
    # in reach near their corner, our only teammate far behind, their defenders on the goal
    # line and in the box: no kick wins the race, no shot has a chance: push the ball on
    alone = world(position=(21.75, 14.0), ball=(22.0, 14.0), teammates=[(-20.0, 10.0)],
                  opponents=[(26.0, 2.0), (26.0, -1.0), (24.0, 6.0), (24.0, 12.0), (27.0, 0.0)],
                  field="mj7v7")
    push = decider.play_ball(alone)
    assert push.kick is None and push.behaviour == "dribble", push
    # from the centre circle with nobody near, a long kick at the goal (not called a shot)
    open_field = world(position=(-0.25, 0.0), ball=(0.0, 0.0), teammates=[(-20.0, 10.0)],
                       opponents=[(0.0, 12.0), (0.0, -12.0)], field="mj7v7")
    long = decider.play_ball(open_field)
    assert long.kick is not None and long.behaviour == "kick_at_goal"


def test_formation_positions_are_pulled_towards_the_ball_rest_point():
    decider = _decider()
    wm = world(ball=(10.0, 0.0), ball_velocity=(0.0, 0.0), field="mj7v7")
    pulled = decider.pulled(wm, np.array([0.0, 0.0]))
    assert pulled == pytest.approx([10.0 * decider.config.ball_pull, 0.0])
