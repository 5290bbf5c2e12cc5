"""Set plays obey the referee: unit properties of ``strategy.decision.setplays`` and whole teams through
the env (``full`` against ``static``, which never takes a set play, so every one of theirs
lasts until the referee's timeout)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from strategy.decision.setplays import (
    Situation,
    keep_distance,
    set_play_taker,
    situation,
    we_kick_off_next,
)
from teamenv import PlayMode
from tests.strategy import scenes

#: Cycles a body needs to stop from the team's top speed (accel limit + one step period):
#: a player walking at the ball when the other side is awarded a set play cannot stop at once.
STOP_CYCLES = math.ceil((1.2 / scenes.PROFILE.accel[0] + scenes.PROFILE.step_period) / 0.02)

TAKER_BEHAVIOURS = {"corner_kick", "goal_kick", "kick_in_pass", "kick_in_forward",
                    "kick_off_pass", "kick_off_forward"}


# -- units --------------------------------------------------------------------------------------
@pytest.mark.parametrize("mode,want", [
    (PlayMode.BeforeKickOff, Situation.BEAM), (PlayMode.Goal_Left, Situation.BEAM),
    (PlayMode.Goal_Right, Situation.BEAM), (PlayMode.PlayOn, Situation.PLAY_ON),
    (PlayMode.GameOver, Situation.OVER), (PlayMode.KickOff_Left, Situation.OUR_KICKOFF),
    (PlayMode.KickOff_Right, Situation.THEIR_KICKOFF),
    (PlayMode.KickIn_Left, Situation.OUR_SET_PLAY),
    (PlayMode.CornerKick_Left, Situation.OUR_SET_PLAY),
    (PlayMode.GoalKick_Left, Situation.OUR_SET_PLAY),
    (PlayMode.KickIn_Right, Situation.THEIR_SET_PLAY),
    (PlayMode.CornerKick_Right, Situation.THEIR_SET_PLAY),
    (PlayMode.GoalKick_Right, Situation.THEIR_SET_PLAY),
])
def test_situation_of_every_play_mode(mode, want):
    assert situation(mode) is want


def test_who_kicks_off_next():
    assert we_kick_off_next(PlayMode.BeforeKickOff, 1, "left")
    assert not we_kick_off_next(PlayMode.BeforeKickOff, 1, "right")
    assert we_kick_off_next(PlayMode.BeforeKickOff, 2, "right")
    assert not we_kick_off_next(PlayMode.BeforeKickOff, 2, "left")
    assert we_kick_off_next(PlayMode.Goal_Right, 1, "left")  # we conceded
    assert not we_kick_off_next(PlayMode.Goal_Left, 1, "right")


def taker_scene(fallen=()):
    # goalie (index 0) near the ball, then field players at 3, 1 and 2 m
    return scenes.world((-12.0, 0.0), 0.0, (-12.5, 0.0), me=0,
                        teammates=[(-9.5, 0.0), (-13.5, 0.3), (-10.5, 0.0)],
                        fallen_mates=fallen)


def test_set_play_taker():
    wm = taker_scene()
    assert set_play_taker(wm, PlayMode.GoalKick_Left, goalie=0) == 0
    assert set_play_taker(wm, PlayMode.KickIn_Left, goalie=0) == 2  # closest field player
    assert set_play_taker(wm, PlayMode.CornerKick_Left, goalie=None) == 0
    assert set_play_taker(taker_scene(fallen=[2]), PlayMode.KickIn_Left, goalie=0) == 3
    assert set_play_taker(taker_scene(fallen=[0]), PlayMode.GoalKick_Left, goalie=0) == 2


coord = st.floats(-14.0, 14.0)


@settings(max_examples=100, deadline=None)
@given(tx=coord, ty=st.floats(-9.0, 9.0), bx=coord, by=st.floats(-9.0, 9.0),
       clearance=st.floats(0.5, 3.0), kickoff=st.booleans())
def test_keep_distance_respects_the_rules(tx, ty, bx, by, clearance, kickoff):
    ball = (0.0, 0.0) if kickoff else (bx, by)
    wm = scenes.world((0.0, 5.0), 0.0, ball)
    t = keep_distance(np.array([tx, ty]), wm, clearance, kickoff)
    assert math.dist(t, ball) >= clearance - 1e-9
    if kickoff:
        assert t[0] <= -0.4 + 1e-12
        assert math.dist(t, (0, 0)) >= wm.field.center_circle_radius
    elif math.dist((tx, ty), ball) >= clearance:
        np.testing.assert_array_equal(t, [tx, ty])


# -- through the env ------------------------------------------------------------------------------
class RefereeSpy:
    """Records, each time the referee enforces a set play's distance, where the defending
    team's players stood before it moved anybody: (mode, mode_cycles, min distance to the
    spot, max depth into the other half (m, > 0 = over the half-way line))."""

    def __init__(self, env) -> None:
        ref = env.sim.referee
        original = ref._keep_opponents_away
        self.log: list[tuple[str, int, float, float]] = []

        def spy(world, owner, kickoff):
            p = world.player_poses()
            rows = np.flatnonzero(ref.team_of != owner)
            team = 1 - owner
            d = np.hypot(p[rows, 0] - ref.set_play_spot[0], p[rows, 1] - ref.set_play_spot[1])
            depth = float(np.max(ref.attack_sign[team] * p[rows, 0]))
            self.log.append((ref.mode.name, ref.mode_cycles, float(d.min()), depth))
            return original(world, owner, kickoff)

        ref._keep_opponents_away = spy


def award(env, kind: str, team: int, at: float) -> None:
    """Let the referee award ``kind`` to world team ``team`` (0 left, 1 right) by putting the
    ball out of bounds after a touch of the other team. ``at``: x of a kick-in (world)."""
    f, ref = env.field, env.sim.referee
    n = env.team_size
    ref.mode, ref.mode_cycles = PlayMode.PlayOn, 0
    ref.last_touch = (1 - team) * n + 1
    sign = ref.attack_sign[team]  # the goal team ``team`` attacks is at x = sign * L/2
    if kind == "KickIn":
        env.sim.world.place_ball(at, f.half_width + 0.5)
    elif kind == "CornerKick":  # over the goal line the team attacks
        env.sim.world.place_ball(sign * (f.half_length + 0.5), f.half_goal_width + 1.0)
    else:  # GoalKick: over the team's own goal line
        env.sim.world.place_ball(-sign * (f.half_length + 0.5), -(f.half_goal_width + 1.0))
    env.step({})
    assert ref.mode == PlayMode.of(kind, team), ref.mode.name


@pytest.mark.parametrize("field,n", [("mj7v7", 7), ("simspark", 11)])
def test_their_set_plays_keep_the_distance(field, n):
    env, _ = scenes.make_env(field=field, team_size=n, left="full", right="static",
                             profile_phases=False)
    spy = RefereeSpy(env)
    ref = env.sim.referee
    players = env.teams["left"].players
    rule = ref.rules.set_play_distance
    for _ in range(120):
        env.step({})
    for kind in ("KickIn", "CornerKick", "GoalKick"):
        award(env, kind, team=1, at=-3.0)
        spot = np.array(ref.set_play_spot)
        # crowd the spot with three of ours walking at it
        for k in (1, 2, 3):
            angle = math.atan2(-spot[1], -spot[0]) + 0.4 * (k - 2)
            pos = spot + 0.6 * np.array([math.cos(angle), math.sin(angle)])
            env.sim.world.place_player(k, *pos, angle + math.pi)
        spy.log.clear()
        for cycle in range(250):
            before = scenes.poses(env)
            env.step({})
            assert ref.mode == PlayMode.of(kind, 1)
            # intent: from the first cycle on, nobody of ours inside the distance walks at
            # the ball
            for k, agent in enumerate(env.team_agents["left"]):
                x, y, h = before[k]
                to_ball = spot - (x, y)
                dist = float(np.hypot(*to_ball))
                if dist < rule and cycle >= 1:
                    walk = np.clip(players[agent].last_request.walk, scenes.LOW, scenes.HIGH)
                    vw = (math.cos(h) * walk[0] - math.sin(h) * walk[1],
                          math.sin(h) * walk[0] + math.cos(h) * walk[1])
                    assert float(np.dot(vw, to_ball / dist)) <= 1e-9, (
                        kind, cycle, agent, players[agent].last_request.behaviour, walk)
        late = [entry for entry in spy.log if entry[1] > STOP_CYCLES and entry[2] < rule]
        assert not late, f"{kind}: the referee had to move our players: {late[:5]}"
        # and the whole team walked out to its own clearance in the end
        assert min(e[2] for e in spy.log[-5:]) >= rule
        ref.mode = PlayMode.PlayOn
        for _ in range(30):
            env.step({})


@pytest.mark.parametrize("field,n", [("mj7v7", 7), ("simspark", 11)])
def test_their_kickoff_own_half_out_of_the_circle_and_beams(field, n):
    # left kicks off the first half; ``full`` plays right; ``static`` never takes the kick-off
    env, _ = scenes.make_env(field=field, team_size=n, left="static", right="full",
                             profile_phases=False)
    spy = RefereeSpy(env)
    ref, f = env.sim.referee, env.field
    beamed = set()
    while ref.mode == PlayMode.BeforeKickOff:
        env.step({})
        beamed.update(env.last_report.beams)
        p = scenes.poses(env)[n:]
        assert np.all(p[:, 0] > 0), "a beam left our (right) half"
    assert beamed >= set(range(n, 2 * n)), "not every player beamed"
    assert ref.mode == PlayMode.KickOff_Left
    radius = max(ref.rules.set_play_distance, f.center_circle_radius)
    for _ in range(250):
        env.step({})
        assert ref.mode == PlayMode.KickOff_Left
    entries = [e for e in spy.log if e[0] == "KickOff_Left" and e[1] >= 1]
    assert len(entries) >= 200
    assert min(e[2] for e in entries) >= radius, "inside the centre circle"
    assert max(e[3] for e in entries) <= -scenes.BODY_RADIUS, "in the other half"


@pytest.mark.parametrize("field,n", [("mj7v7", 7), ("simspark", 11)])
def test_beams_land_in_the_own_half_both_sides(field, n):
    env, _ = scenes.make_env(field=field, team_size=n, left="full", right="full",
                             profile_phases=False)
    ref = env.sim.referee
    beamed = set()
    while ref.mode == PlayMode.BeforeKickOff:
        env.step({})
        beamed.update(env.last_report.beams)
    assert beamed == set(range(2 * n))
    p = scenes.poses(env)
    assert np.all(p[:n, 0] < 0) and np.all(p[n:, 0] > 0)
    # kick-off positions of the kick-off team are on its own side, the others outside the
    # circle (nobody had to be moved by the referee, so the poses are the beams')
    assert np.all(np.hypot(p[n:, 0], p[n:, 1]) >= env.field.center_circle_radius)


def take(env, kind: str, n: int, max_cycles: int):
    """Award ``kind`` to the left (full) team and run until the mode changes. Returns
    (changed to PlayOn by our touch, takers seen per cycle, the last toucher)."""
    ref, f = env.sim.referee, env.field
    players = env.teams["left"].players
    if kind != "GoalKick":  # as in play: one of ours followed the ball out, 3 m from the spot
        spot = np.array([4.0 if kind == "KickIn" else f.half_length, f.half_width])
        inside = spot + 3.0 * np.array([-0.6, -0.8])
        env.sim.world.place_player(3, *inside, math.atan2(0.8, 0.6))
    award(env, kind, team=0, at=4.0)
    takers, dropped = [], False
    for _ in range(max_cycles):
        env.step({})
        takers.append({a for a, pl in players.items()
                       if pl.last_request.behaviour in TAKER_BEHAVIOURS})
        dropped |= any(e.kind == "drop_ball" for e in env.last_report.referee)
        if ref.mode != PlayMode.of(kind, 0):
            break
    ours = ref.last_touch is not None and ref.last_touch < n
    return (ref.mode != PlayMode.of(kind, 0) and not dropped and ours), takers, ref.last_touch


@pytest.mark.parametrize("field,n", [("mj7v7", 5), ("simspark", 11)])
def test_our_set_plays_are_taken_by_one_player_before_the_timeout(field, n):
    env, _ = scenes.make_env(field=field, team_size=n, left="full", right="static",
                             profile_phases=False)
    ref = env.sim.referee
    goalie = env.teams["left"].players["left_1"].decision.goalie
    timeout = round(ref.rules.set_play_timeout_s / 0.02)
    taken = 0
    cases = ["KickIn", "CornerKick", "GoalKick", "KickIn", "GoalKick"]
    for kind in cases:
        for _ in range(60):
            env.step({})
        ok, takers, toucher = take(env, kind, n, timeout + 5)
        taken += ok
        assert all(len(t) <= 1 for t in takers), f"{kind}: several takers {takers}"
        assert any(len(t) == 1 for t in takers), f"{kind}: nobody took it"
        if kind == "GoalKick" and ok:
            assert toucher == goalie, f"goal kick taken by player {toucher}, not the goalie"
        ref.mode = PlayMode.PlayOn
    assert taken >= len(cases) - 1, f"only {taken} of {len(cases)} set plays kicked in time"


def test_our_kickoff_is_kicked_by_us():
    env, _ = scenes.make_env(field="mj7v7", team_size=7, left="full", right="static",
                             profile_phases=False)
    ref = env.sim.referee
    events = []
    for _ in range(800):
        env.step({})
        events += env.last_report.referee
        if ref.mode == PlayMode.PlayOn:
            break
    assert ref.mode == PlayMode.PlayOn
    assert not any(e.kind == "drop_ball" for e in events)
    assert ref.last_touch is not None and ref.last_touch < 7


def test_under_the_double_touch_rule_the_taker_leaves_the_ball_to_the_others():
    """The league's rule: after our kick-off the taker may not touch the ball again before
    another player has. With the rule in force (``TeamContext.double_touch``) the taker, who
    kicked the ball 3 m ahead and is still the nearest, is nobody's ball player until a
    teammate has reached the ball; without it, it chases its own kick."""
    from strategy.decision.field_player import FieldPlayerDecisionMaker
    from strategy.positioning import PositioningDecision
    from strategy.teams.full_config import FullTeamConfig

    from .scenes import skills, world

    def decide(maker, mode, ball, mates):
        wm = world(position=(-0.3, 0.0), ball=ball, teammates=mates, field="mj7v7",
                   play_mode=mode, me=0)
        hold = PositioningDecision(np.array([-0.3, 0.0]), 0, np.zeros(3, np.intp),
                                   np.zeros(3, np.intp), np.zeros((3, 2)), "", 0.0)
        maker.plan_all([wm], [hold])
        return maker.ball_players[0]

    mates = [(-6.0, 4.0), (-6.0, -4.0)]
    for rule in (True, False):
        maker = FieldPlayerDecisionMaker(FullTeamConfig().decision_params(), skills("mj7v7"),
                                         goalie=None)
        maker.double_touch = rule
        assert decide(maker, PlayMode.KickOff_Left, (0.0, 0.0), mates) == 0   # we take it
        after = decide(maker, PlayMode.PlayOn, (3.0, 0.0), mates)            # kicked 3 m
        assert (after != 0) == rule
        # a teammate reached the ball: the taker may play it again
        reached = decide(maker, PlayMode.PlayOn, (3.0, 0.0), [(3.2, 0.0), (-6.0, -4.0)])
        assert reached == 1
        assert decide(maker, PlayMode.PlayOn, (6.0, 0.0), mates) == 0
