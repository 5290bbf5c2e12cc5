"""Behaviours of the full team in hand-built scenes: world models built from arrays, and
closed loops through a real env (one caller-driven agent per side, the other standing)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

import strategy.behaviours.ball as ball_mod
from strategy.behaviours.ball import (
    approach_ball,
    choose_pass,
    clear_ball,
    in_kick_reach,
    kick_to,
    quick_kick,
    shoot,
    shot_target,
)
from strategy.behaviours.control import ControlRequest
from strategy.behaviours.goalie import goalie_target
from strategy.behaviours.motion import beam_to, detour, face_ball, hold_position, keep_clear
from strategy.geometry import wrap_angle as wrap
from strategy.perception.worldmodel import WorldModel
from teamenv import PlayMode
from tests.strategy import scenes

SK = scenes.skills()
F = SK.field
xs = st.floats(-F.half_length + 0.3, F.half_length - 0.3)
ys = st.floats(-F.half_width + 0.3, F.half_width - 0.3)
angles = st.floats(-math.pi, math.pi)


# -- closed loops through the env -------------------------------------------------------------
def solo_env():
    env, _ = scenes.make_env(team_size=1)
    return env


def drive(env, behaviour, cycles, stop=None):
    """Step the env with ``behaviour(wm) -> ControlRequest`` for left_1 (right_1 idle);
    returns the last world model and request. ``stop(wm, request)`` ends the loop early."""
    obs, *_ = env.step(scenes.idle_actions(env))
    wm = request = None
    for _ in range(cycles):
        wm = WorldModel.from_observation(obs["left_1"], 0, F)
        request = behaviour(wm)
        if stop is not None and stop(wm, request):
            break
        obs, *_ = env.step({"left_1": request.to_action(scenes.LOW, scenes.HIGH),
                            "right_1": {}})
    return wm, request


START = [(-3.0, -2.0, 1.5), (4.0, 1.0, math.pi), (2.5, 0.1, 0.0), (0.0, 3.0, -2.0)]


@pytest.fixture(scope="module")
def env():
    return solo_env()


@pytest.mark.parametrize("start", START)
def test_approach_ball_lines_up_behind_the_ball_facing_the_aim(env, start):
    env.reset(seed=0)
    ball, aim = np.array([2.0, 0.0]), np.array([14.0, 3.0])
    scenes.place(env, {0: start, 1: (10.0, 8.0, math.pi)}, ball=ball, mode=PlayMode.PlayOn)
    state = {"ready": False}

    def behaviour(wm):
        request, state["ready"] = approach_ball(wm, aim, SK)
        return request

    wm, _ = drive(env, behaviour, 700, stop=lambda wm, req: state["ready"])
    assert state["ready"], "never lined up"
    u = (aim - wm.ball) / np.linalg.norm(aim - wm.ball)
    assert np.linalg.norm(wm.ball - ball) < 0.05  # did not push the ball on the way
    assert float((wm.ball - wm.position) @ u) > 0.1  # behind the ball on the aim line
    assert wm.ball_distance() <= SK.kick_reach
    assert abs(wrap(math.atan2(u[1], u[0]) - wm.heading)) < SK.kick_max_angle
    assert in_kick_reach(wm, SK)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_kick_to_kicks_the_ball_towards_the_target(env, seed):
    rng = np.random.default_rng(seed)
    env.reset(seed=seed)
    ball = np.array([rng.uniform(-4, 4), rng.uniform(-3, 3)])
    target = np.array([rng.uniform(6, 13), rng.uniform(-6, 6)])
    start = START[seed]
    scenes.place(env, {0: start, 1: (10.0, 8.0, math.pi)}, ball=ball, mode=PlayMode.PlayOn)
    kicked = []
    drive(env, lambda wm: kick_to(wm, target, SK), 900,
          stop=lambda wm, req: kicked.append(bool(env.last_report.kicks)) or kicked[-1])
    assert any(kicked), "kick_to never kicked"
    for _ in range(150):  # let it roll
        env.step({"left_1": {}, "right_1": {}})
    moved = scenes.ball_xy(env) - ball
    assert np.linalg.norm(moved) > 1.0
    error = wrap(math.atan2(moved[1], moved[0]) - math.atan2(*(target - ball)[::-1]))
    assert abs(error) < math.radians(30)  # the kick's spread is ~10 degrees (64.5 %)


def test_hold_position_stands_at_its_target_facing_the_ball(env):
    env.reset(seed=0)
    target = np.array([-3.0, 2.0])
    scenes.place(env, {0: (1.0, -1.0, 0.0), 1: (10.0, 8.0, math.pi)}, ball=(2.0, 4.0),
                 mode=PlayMode.PlayOn)
    wm, request = drive(env, lambda wm: hold_position(wm, target, SK), 600)
    assert wm.distance(target) < 0.25
    bearing = math.atan2(wm.ball[1] - wm.position[1], wm.ball[0] - wm.position[0])
    assert abs(wrap(bearing - wm.heading)) < 0.3
    assert np.hypot(*request.walk[:2]) < 0.45  # standing (at most creeping in)


def test_face_ball_turns_towards_the_ball(env):
    env.reset(seed=0)
    scenes.place(env, {0: (0.0, 0.0, 0.0), 1: (10.0, 8.0, math.pi)}, ball=(-2.0, -1.0),
                 mode=PlayMode.PlayOn)
    wm, _ = drive(env, lambda wm: face_ball(wm, SK), 200)
    bearing = math.atan2(wm.ball[1] - wm.position[1], wm.ball[0] - wm.position[0])
    assert abs(wrap(bearing - wm.heading)) < 0.1
    assert np.linalg.norm(wm.position) < 0.3  # turned on the spot


@settings(max_examples=50, deadline=None)
@given(px=xs, py=ys, h=angles, bx=xs, by=ys)
def test_face_ball_turns_the_short_way(px, py, h, bx, by):
    assume(math.hypot(bx - px, by - py) > 0.1)
    wm = scenes.world((px, py), h, (bx, by))
    req = face_ball(wm, SK)
    error = wrap(math.atan2(by - py, bx - px) - h)
    assume(abs(error) > 1e-3)
    assert req.walk[0] == 0 and req.walk[1] == 0
    assert np.sign(req.walk[2]) == np.sign(error)


def test_beam_to_produces_a_beam_action_and_lands_there():
    req = beam_to((-5.0, 2.0, 0.5))
    action = req.to_action(scenes.LOW, scenes.HIGH)
    assert action["beam_request"] == 1
    np.testing.assert_allclose(action["beam"], [-5.0, 2.0, 0.5])
    assert "kick" not in action and not np.any(action["walk"])
    env, _ = scenes.make_env(team_size=1)  # BeforeKickOff: beaming allowed
    env.step({"left_1": action, "right_1": {}})
    pose = scenes.poses(env)[0]
    assert math.dist(pose[:2], (-5.0, 2.0)) < 0.3
    assert abs(wrap(pose[2] - 0.5)) < 0.3


def test_to_action_clips_the_walk_and_omits_what_was_not_asked():
    req = ControlRequest(walk=np.array([9.0, -9.0, 9.0]), kick=(2.0, 0.3))
    action = req.to_action(scenes.LOW, scenes.HIGH)
    np.testing.assert_allclose(action["walk"], [scenes.HIGH[0], scenes.LOW[1], scenes.HIGH[2]])
    np.testing.assert_allclose(action["kick"], [1.0, 0.3])
    assert "beam" not in action and "say" not in action


# -- shooting, passing, clearing -------------------------------------------------------------
@pytest.mark.parametrize("goalie_y", [0.5, -0.5, 0.8, -0.8])
def test_shot_target_picks_the_open_side_of_the_goal(goalie_y):
    wm = scenes.world((9.0, 0.3), 0.0, (9.5, 0.3), opponents=[(F.half_length - 0.4, goalie_y)])
    target = shot_target(wm)
    assert target[0] == F.half_length
    assert abs(target[1]) < F.half_goal_width
    assert np.sign(target[1]) == -np.sign(goalie_y)


def test_shot_target_without_opponents_is_the_goal_centre():
    wm = scenes.world((9.0, 2.0), 0.0, (9.5, 2.0))
    np.testing.assert_allclose(shot_target(wm), [F.half_length, 0.0])


def test_shoot_kicks_at_the_open_side_when_lined_up(monkeypatch):
    seen = {}
    real = ball_mod.kick_to

    def spy(wm, target, skills, power=None, behaviour="kick_to"):
        seen["target"], seen["power"] = np.asarray(target), power
        return real(wm, target, skills, power, behaviour)

    monkeypatch.setattr(ball_mod, "kick_to", spy)
    wm = scenes.world((10.0, 0.0), 0.0, (10.25, 0.0), opponents=[(F.half_length - 0.4, 0.6)])
    req = shoot(wm, SK)
    assert seen["target"][1] < 0 and seen["power"] == 1.0
    assert req.kick is not None and req.kick[0] == 1.0
    assert req.kick[1] < 0  # body frame: to the right, the open side


# me = index 1 (index 0 is the goalie, excluded by default), receiver index 2
PASS = dict(min_gain_m=3.0, max_distance_m=9.0, lane_m=1.0, free_m=1.5)


def pass_scene(receiver, opponents=(), others=()):
    return scenes.world((-0.3, 0.0), 0.0, (0.0, 0.0), me=1,
                        teammates=[(-14.0, 0.0), receiver, *others], opponents=opponents)


def test_choose_pass_picks_the_free_teammate_ahead():
    assert choose_pass(pass_scene((5.0, 1.0)), **PASS) == 2
    # two ahead, the first is marked: the free one
    wm = pass_scene((5.0, 1.0), opponents=[(5.5, 1.2)], others=[(5.0, -3.0)])
    assert choose_pass(wm, **PASS) == 3


@pytest.mark.parametrize("case", ["lane_blocked", "receiver_marked", "nobody_ahead",
                                  "too_far", "receiver_fallen"])
def test_choose_pass_returns_none(case):
    if case == "lane_blocked":
        wm = pass_scene((5.0, 1.0), opponents=[(2.5, 0.6)])
    elif case == "receiver_marked":
        wm = pass_scene((5.0, 1.0), opponents=[(5.0, 2.0)])
    elif case == "nobody_ahead":
        wm = pass_scene((-4.0, 1.0), others=[(0.5, 5.0)])
    elif case == "too_far":
        wm = pass_scene((12.0, 0.0))
    else:
        wm = scenes.world((-0.3, 0.0), 0.0, (0.0, 0.0), me=1,
                          teammates=[(-14.0, 0.0), (5.0, 1.0)], fallen_mates=[2])
    assert choose_pass(wm, **PASS) is None


@settings(max_examples=60, deadline=None)
@given(bx=xs, by=ys)
def test_clear_ball_target_is_away_from_our_goal(bx, by):
    seen = {}

    def spy(wm, target, skills, power=None, behaviour="kick_to"):
        seen["target"] = np.asarray(target)
        return ControlRequest(behaviour=behaviour)

    real = ball_mod.kick_to
    ball_mod.kick_to = spy
    try:
        clear_ball(scenes.world((bx - 0.3, by), 0.0, (bx, by)), SK)
    finally:
        ball_mod.kick_to = real
    target, ball = seen["target"], np.array([bx, by])
    own_goal = np.array([-F.half_length, 0.0])
    assert target[0] > ball[0]
    assert np.linalg.norm(target - own_goal) > np.linalg.norm(ball - own_goal)
    assert abs(target[1]) < F.half_width


@settings(max_examples=80, deadline=None)
@given(bx=st.floats(-F.half_length, F.half_length), by=ys,
       line=st.floats(0.2, 1.5))
def test_goalie_target_on_the_ball_goal_line_within_the_posts(bx, by, line):
    wm = scenes.world((-F.half_length + 0.5, 0.0), 0.0, (bx, by))
    t = goalie_target(wm, line)
    goal = np.array([-F.half_length, 0.0])
    assert t[0] == pytest.approx(goal[0] + line)
    assert abs(t[1]) <= F.half_goal_width - 0.2 + 1e-12
    d, g = np.array([bx, by]) - goal, t - goal
    if abs(t[1]) < F.half_goal_width - 0.2 - 1e-9 and d[0] > line:
        # unclipped: on the segment from the goal centre to the ball
        assert abs(d[0] * g[1] - d[1] * g[0]) < 1e-6 * max(1.0, np.linalg.norm(d))
        assert 0 <= g @ d <= d @ d
    elif abs(by) > 1e-9:
        assert np.sign(t[1]) == np.sign(by)  # clipped to the post on the ball's side


# -- keeping clear of a circle -----------------------------------------------------------------
@settings(max_examples=80, deadline=None)
@given(tx=xs, ty=ys, cx=xs, cy=ys, r=st.floats(0.5, 3.0))
def test_keep_clear_moves_a_target_out_of_the_circle(tx, ty, cx, cy, r):
    out = keep_clear((tx, ty), (cx, cy), r)
    assert math.dist(out, (cx, cy)) >= r - 1e-9
    if math.dist((tx, ty), (cx, cy)) >= r:
        np.testing.assert_array_equal(out, [tx, ty])
    elif math.dist((tx, ty), (cx, cy)) > 1e-6:  # moved radially
        v, w = np.subtract((tx, ty), (cx, cy)), out - np.array([cx, cy])
        assert abs(v[0] * w[1] - v[1] * w[0]) < 1e-6 and v @ w > 0


def walk_round(p, t, r, cycles=2000):
    """Walk 5 cm a cycle towards ``detour``'s waypoint round the circle (origin, ``r``),
    re-planned every cycle; returns (arrived, closest approach to the centre)."""
    c = np.zeros(2)
    p, t = np.asarray(p, float), np.asarray(t, float)
    closest = math.inf
    for _ in range(cycles):
        if np.linalg.norm(t - p) < 0.06:
            return True, closest
        w = detour(p, t, c, r)
        assert np.linalg.norm(w - c) >= r - 1e-9  # the waypoint itself is outside
        step = w - p
        p = p + step / np.linalg.norm(step) * min(0.05, float(np.linalg.norm(step)))
        closest = min(closest, float(np.linalg.norm(p - c)))
    return False, closest


@settings(max_examples=60, deadline=None)
@given(px=xs, py=ys, tx=xs, ty=ys, r=st.floats(1.0, 3.0))
def test_detour_waypoints_lie_outside_and_the_walk_arrives(px, py, tx, ty, r):
    p, t = np.array([px, py]), np.array([tx, ty])
    assume(np.linalg.norm(p) > r + 0.05 and np.linalg.norm(t) > r + 0.05)
    arrived, _ = walk_round(p, t, r)
    assert arrived


@settings(max_examples=60, deadline=None)
@example(px=0.0, py=-2.7, tx=0.0, ty=2.7, r=2.6)
@example(px=0.3, py=-3.0, tx=0.0, ty=3.0, r=2.6)
@given(px=xs, py=ys, tx=xs, ty=ys, r=st.floats(1.0, 3.0))
def test_detour_keeps_the_walk_outside_the_circle(px, py, tx, ty, r):
    p, t = np.array([px, py]), np.array([tx, ty])
    assume(np.linalg.norm(p) > r + 0.05 and np.linalg.norm(t) > r + 0.05)
    arrived, closest = walk_round(p, t, r)
    assert arrived and closest > r - 0.06


def test_detour_is_the_target_when_the_path_is_clear():
    np.testing.assert_array_equal(detour((-5, 3), (5, 3), (0, 0), 2.0), [5, 3])


# -- quick kicks ---------------------------------------------------------------------------------
@settings(max_examples=120, deadline=None)
@given(bx=xs, by=ys, h=angles, d=st.floats(0.0, 0.3), side=angles,
       opps=st.lists(st.tuples(xs, ys), max_size=5))
def test_quick_kick_never_kicks_backwards(bx, by, h, d, side, opps):
    pos = (bx - d * math.cos(h + side * 0.3), by - d * math.sin(h + side * 0.3))
    wm = scenes.world(pos, h, (bx, by), opponents=opps)
    req = quick_kick(wm, SK)
    if req is None:
        return
    assert req.kick is not None and req.kick[0] > 0
    world_angle = h + req.kick[1]
    end = np.array([bx, by]) + 7.0 * np.array([math.cos(world_angle), math.sin(world_angle)])
    assert end[0] >= bx - 1.0 - 1e-6  # not backwards towards our goal line
    assert end[0] >= -F.half_length + 1.0 - 1e-6
    assert abs(req.kick[1]) <= SK.kick_max_angle + 1e-9


@pytest.mark.parametrize("pos,heading", [((0.0, 0.0), 0.0), ((1.3, 0.0), 0.0),
                                         ((0.6, 0.0), math.pi / 2)])
def test_quick_kick_is_none_out_of_reach(pos, heading):
    wm = scenes.world(pos, heading, (1.0, 0.0) if pos != (0.6, 0.0) else (0.9, 0.0))
    # (0, 0) -> 1 m away; (1.3, 0) facing away -> behind; (0.6, 0) facing +y -> to the side
    assert quick_kick(wm, SK) is None


def test_quick_kick_facing_our_goal_does_not_kick_at_it():
    wm = scenes.world((-8.0, 0.0), math.pi, (-8.25, 0.0))
    req = quick_kick(wm, SK)
    if req is not None:
        assert math.cos(math.pi + req.kick[1]) > -1.0 / 7.0 - 1e-9


# -- dribbling -----------------------------------------------------------------------------------
def test_dribble_walks_through_the_ball_towards_the_target():
    wm = scenes.world((0.0, 0.0), 0.0, (0.25, 0.0))
    req = ball_mod.dribble(wm, np.array([10.0, 0.0]), SK)
    assert req.kick is None and req.walk[0] > 0.3 and abs(req.walk[2]) < 0.2


@pytest.mark.parametrize("blocker_y", [0.2, -0.2])
def test_dribble_aim_goes_round_an_opponent_in_the_way(blocker_y):
    wm = scenes.world((0.0, 0.0), 0.0, (0.25, 0.0), opponents=[(1.2, blocker_y)])
    aim = ball_mod.dribble_aim(wm, np.array([10.0, 0.0]))
    assert np.sign(aim[1]) == -np.sign(blocker_y)  # the free side
    free = scenes.world((0.0, 0.0), 0.0, (0.25, 0.0), opponents=[(6.0, 5.0)])
    np.testing.assert_array_equal(ball_mod.dribble_aim(free, np.array([10.0, 0.0])), [10, 0])
