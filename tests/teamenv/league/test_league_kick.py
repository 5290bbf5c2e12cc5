"""The T1's kick on the league server (teamenv.league.kick): the strike on the walk's swing
leg and input checks, the ball seen from the camera, the approach that aims it; on LocalServer a kick from
standing, an aimed kick from a walking approach, the encoder playing a kick to its end and the
get-up hook; on the real server one short kick; a 1 v 1 LocalServer match with a kick."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from teamenv.league.errors import LeagueError
from teamenv.league.kick import (
    LEAGUE_KICK,
    MOTORS,
    KickMotion,
    approach_command,
    in_kick_spot,
    kick_foot,
    kick_heading,
    measured_angles,
)
from teamenv.league.perception import Perception, parse_perception
from tests.teamenv.league.recorders import RecordingController, recording_walker

pytestmark = pytest.mark.humanoid
DATA = Path(__file__).resolve().parents[1] / "league_data"


def _perception() -> Perception:
    return parse_perception((DATA / "first.txt").read_text().strip())


def test_the_kicking_foot_and_the_heading_that_aims():
    assert kick_foot((0.5, -0.1), 0.0) == "right" and kick_foot((0.5, 0.1), 0.0) == "left"
    # along a kick 90 deg to the left, a ball ahead lies on the right of the kick line
    assert kick_foot((0.5, 0.0), math.pi / 2) == "right"
    # the ball leaves the foot deflected outwards: the body faces inwards by aim_bias
    assert kick_heading(0.2, "right") == pytest.approx(0.2 + LEAGUE_KICK.aim_bias)
    assert kick_heading(0.2, "left") == pytest.approx(0.2 - LEAGUE_KICK.aim_bias)


class _Walker:
    """A stand-in for the walker's phase, as ``WalkerController.step`` hands it to a kick."""

    class p:  # noqa: N801 - mirrors LipmWalker.p
        step_period, double_support, dt = 0.32, 0.06, 0.01

    def __init__(self, swing, t_step):
        self.swing, self.t_step = swing, t_step


def test_the_strike_moves_only_the_kicking_leg_and_only_on_its_swing():
    p = _perception()
    kick = KickMotion(params=LEAGUE_KICK.with_(strike_x=5.0))  # any ball distance strikes
    kick.start(p, 0.0, 1.0, ball=(0.4, -LEAGUE_KICK.foot_y))
    assert kick.foot == "right"
    kick._perception = p
    q = np.zeros(len(MOTORS))
    assert np.array_equal(kick._strike(_Walker("Left", 0.02), list(MOTORS), q), q)
    assert kick.strike_ball_x is None                    # the other foot's swing: no strike
    # the kicking foot's swing begins: this swing is the kick (nothing moves yet)
    assert np.array_equal(kick._strike(_Walker("Right", 0.02), list(MOTORS), q), q)
    assert kick.strike_ball_x is not None
    peak = 0.26 * (LEAGUE_KICK.strike_from + LEAGUE_KICK.strike_to) / 2   # the bump's top
    mid = kick._strike(_Walker("Right", peak), list(MOTORS), q)
    moved = {MOTORS[k] for k in np.flatnonzero(mid)}
    assert moved == {"rle1"}                             # hip flexes; the knee stays >= 0
    assert mid[MOTORS.index("rle1")] == pytest.approx(-LEAGUE_KICK.strike_hip, abs=0.05)
    bent = np.zeros(len(MOTORS))
    bent[MOTORS.index("rle4")] = 1.0
    out = kick._strike(_Walker("Right", peak), list(MOTORS), bent)
    assert out[MOTORS.index("rle4")] == pytest.approx(1.0 - LEAGUE_KICK.strike_knee, abs=0.02)
    weak = KickMotion(params=LEAGUE_KICK.with_(strike_x=5.0))
    weak.start(p, 0.0, 0.0, ball=(0.4, -LEAGUE_KICK.foot_y))
    weak._perception = p
    weak._strike(_Walker("Right", 0.02), list(MOTORS), q)
    soft = weak._strike(_Walker("Right", peak), list(MOTORS), q)
    assert soft[MOTORS.index("rle1")] == pytest.approx(0.4 * mid[MOTORS.index("rle1")], rel=0.05)


def test_a_kick_on_its_own_walker_starts_from_the_measured_angles():
    p = _perception()
    kick = KickMotion()                                  # not sharing a walker
    kick.start(p, 0.0, 1.0, ball=(0.45, -0.11))
    msg = kick.step(p)
    sent = {m: math.radians(float(v)) for m, v in
            (part.split()[:2] for part in msg.strip("()").split(")("))}
    measured = dict(zip(MOTORS, measured_angles(p), strict=True))
    # 0.02 s into the 0.2 s blend: a tenth of the way from the measured angles
    assert max(abs(sent[m] - measured[m]) for m in MOTORS) < 0.15
    assert len(sent) == len(MOTORS)                      # every motor commanded


class _Gait:
    """A stand-in for a ``WalkerController`` whose phase ``KickMotion.ready`` reads."""

    def __init__(self, gait):
        self.gait = gait


def test_a_walking_kick_starts_when_the_kicking_foots_next_swing_will_strike():
    """In a running gait the kick starts during the other foot's step, when the kicking
    foot's swing that follows finds the ball (walking on at walk_vx) within strike_x: the
    wait for a suitable swing is walked as approach, so the strike is on the kick's first
    swing of that foot."""
    k, side = LEAGUE_KICK, -LEAGUE_KICK.foot_y           # the right foot kicks
    period = 0.32
    ball, direction = (k.strike_x + 0.02, side), -k.aim_bias
    assert in_kick_spot(ball, direction)

    def ready(gait, walking=True, b=ball):
        return KickMotion(_Gait(gait)).ready(b, direction, walking)

    assert ready(("Left", 0.02, period))                 # 0.02 m closer in 0.3 s: strikes
    assert not ready(("Right", 0.02, period))            # the kicking foot swings now
    assert not ready(("Left", 0.25, period))             # its swing is due with the ball 0.39+
    assert not ready(("Left", 0.02, period), b=(k.strike_x + 0.05, side))
    # standing (a fresh walker) or not walking the approach: in the spot is enough
    assert ready(None) and ready(("Right", 0.02, period), walking=False)
    plain = KickMotion(_Gait(("Right", 0.02, period)), LEAGUE_KICK.with_(phase_start=False))
    assert plain.ready(ball, direction)


@pytest.mark.parametrize("kwargs, match", [
    ({"power": 1.5, "ball": (0.4, 0.1)}, "power 1.5 is not in 0..1"),
    ({"power": float("nan"), "ball": (0.4, 0.1)}, "power nan"),
    ({"direction": float("inf"), "ball": (0.4, 0.1)}, "direction inf is not finite"),
    ({"foot": "middle", "ball": (0.4, 0.1)}, "foot 'middle'"),
    ({}, "needs the ball's body-frame place"),
])
def test_bad_kick_requests_are_named(kwargs, match):
    with pytest.raises(LeagueError, match=match):
        KickMotion().start(_perception(), **kwargs)
    with pytest.raises(LeagueError, match="step.*without a running kick"):
        KickMotion().step(_perception())


def test_the_approach_walks_into_the_spot_and_faces_the_kick_heading():
    sx, sy, bias = LEAGUE_KICK.spot_x, LEAGUE_KICK.foot_y, LEAGUE_KICK.aim_bias
    # lined up: the ball at the kicking foot's spot, the body facing the kick heading
    assert in_kick_spot((sx, -sy), -bias) and in_kick_spot((sx, sy), bias)
    assert not in_kick_spot((sx, -sy), 0.5)              # faces the wrong way
    assert not in_kick_spot((sx + 0.3, -sy), -bias)      # too far
    assert not in_kick_spot((sx, -sy - 0.08), -bias)     # off the foot's line
    vx, vy, turn = approach_command((2.0, 0.0), 0.0)
    assert vx > 0.15 and abs(turn) < 0.2                 # far ahead: walk at it
    assert approach_command((1.5, 1.5), 0.0)[2] > 0.3    # far left: turn left
    assert approach_command((sx, -sy), 0.6)[2] > 0.15    # kick asked to the left: turn
    vx, vy, turn = approach_command((sx + 0.1, -sy), -bias)
    assert vx > 0.05 and abs(vy) < 0.05 and abs(turn) < 0.05   # a little short: step on
    vx, vy, turn = approach_command((sx, -sy - 0.05), -bias)
    assert vy < -0.02                                    # the ball too far right: step right


# -- on the server's physics -----------------------------------------------------------------
def _local():
    pytest.importorskip("rcsssmj")
    pytest.importorskip("mujoco")


def test_the_ball_seen_by_the_camera_is_where_the_ball_is():
    _local()
    from teamenv.league import effectors
    from teamenv.league.controller import WalkerController
    from teamenv.league.kick import BallTracker, to_body
    from teamenv.league.local_server import LocalServer

    server = LocalServer()
    key = ("K", 1)
    walker = WalkerController()
    p = server.join(*key)
    p = server.cycle({key: effectors.message(effectors.beam(-7.0, 0.5, 0.3),
                                             walker.stand(p))})[key]
    server.kick_off("Left")
    p = server.cycle({key: walker.stand(p)})[key]
    server.place_ball(-6.0, 0.0)
    tracker = BallTracker()
    errors = []
    for _ in range(60):
        seen = tracker.update(p)
        if tracker.age_s == 0.0:
            errors.append(np.hypot(*np.subtract(seen, to_body(p, server.ball_position()[:2]))))
        p = server.cycle({key: walker.step((0.3, 0.0, 0.0), p)})[key]
    assert len(errors) >= 25                             # vision every second cycle
    assert max(errors) < 0.03                            # m, while walking


def test_a_kick_from_standing_sends_the_ball_3m_ahead_and_stays_up():
    _local()
    from teamenv.league.kick_trial import kick_trial, spot_start

    r = kick_trial(spot_start(LEAGUE_KICK, "right"), approach=False, settle_s=4.0)
    assert r.kicked and r.foot == "right"
    assert r.travel >= 3.0
    assert abs(math.degrees(r.error)) < 25.0
    assert r.upright and not r.fell_during


def test_a_kick_started_close_behind_the_ball_waits_for_its_strike():
    """0.35 m straight behind the ball (where a kick-off taker stands) the kick's walker needs
    more than one kicking-foot swing to bring the ball into line; a kick that gave up after
    1.5 s only nudged the ball (0 m here), and a retouch at a kick-off is a foul. (Since the
    approach walks until the kicking foot's swing is due, that wait is mostly in the approach
    and the kick strikes within 1.5 s; before, it took longer.)"""
    _local()
    from teamenv.league.kick_trial import BALL, kick_trial
    from teamenv.league.network_walk import NetworkWalkController

    r = kick_trial((BALL[0] - 0.35, BALL[1], 0.0), 0.0, walker=NetworkWalkController(),
                   settle_s=3.0)
    assert r.kicked and r.strike_ball_x is not None
    assert r.kick_s <= 1.5
    assert r.travel >= 2.0
    assert r.upright and not r.fell_during


def test_a_kick_from_a_walking_approach_strikes_on_its_first_swing():
    """The approach walks into the spot at the kick's pace and starts the kick one step
    before the kicking foot's swing that strikes: the kick lasts one step and the 0.4 s
    after the strike (started on reaching the spot it waited up to three swings: 1.5-2.3 s
    in a quarter of the held-out trials)."""
    _local()
    from teamenv.league.kick_trial import BALL, kick_trial

    # the start of trial seed 1023 (a tuning seed), rounded: the kick there took 1.64 s before
    r = kick_trial((BALL[0] - 0.83, BALL[1] - 1.26, 1.85), 0.39, settle_s=3.0)
    assert r.kicked and r.strike_ball_x is not None and r.strike_ball_x <= LEAGUE_KICK.strike_x
    assert r.kick_s <= 0.8
    assert r.travel >= 2.0
    assert r.upright and not r.fell_during


def test_a_kick_asked_left_goes_left_of_one_asked_right():
    _local()
    from teamenv.league.kick_trial import BALL, kick_trial

    start = (BALL[0] - 0.9, BALL[1] + 0.1, 0.0)          # 0.9 m behind the ball, facing it
    left = kick_trial(start, math.radians(30.0), settle_s=3.0)
    right = kick_trial(start, math.radians(-30.0), settle_s=3.0)
    assert left.kicked and right.kicked
    assert left.travel > 1.0 and right.travel > 1.0
    assert left.direction > right.direction + math.radians(30.0)


def test_the_encoder_plays_a_kick_to_its_end_then_walks_again():
    _local()
    from teamenv.league import effectors
    from teamenv.league.adapter import Request, RequestEncoder
    from teamenv.league.kick_trial import BALL, LOOK_DOWN, spot_start
    from teamenv.league.local_server import LocalServer

    server = LocalServer()
    key = ("K", 1)
    walker = recording_walker()
    enc = RequestEncoder(walker, "agent K_1", get_up=None)
    assert enc.kick.shares_walker                        # the kick is a step of this gait
    p = server.join(*key)
    p = server.cycle({key: enc.encode(Request(beam=spot_start(LEAGUE_KICK, "right")), p)})[key]
    server.kick_off("Left")
    p = server.cycle({key: walker.stand(p)})[key]
    server.place_ball(*BALL)
    for _ in range(20):     # stand looking down at the ball (it lies below a level camera)
        enc.ball.update(p)
        p = server.cycle({key: walker.stand(p) + effectors.motor("he2", LOOK_DOWN, 0, 20, 0.5)})[key]
    # lined up for a kick along -aim_bias (the right foot's ball leaves ~aim_bias outwards)
    p = server.cycle({key: enc.encode(Request(kick=(1.0, -LEAGUE_KICK.aim_bias)), p)})[key]
    assert enc.kicking
    while enc.kicking:      # the walk requests meanwhile are ignored
        before = len(walker.commands)
        p = server.cycle({key: enc.encode(Request(walk=(0.4, 0.0, 0.0)), p)})[key]
        assert len(walker.commands) == before + 1 and walker.commands[-1][0] < 0.3
        assert len(walker.commands) < 200
    assert enc.kick.struck
    enc.encode(Request(walk=(0.4, 0.0, 0.0)), p)
    assert walker.commands[-1] == (0.4, 0.0, 0.0)        # walking again, the same gait
    # 0.4 s after the strike began the ball is on its way (it rolls on for metres)
    assert np.hypot(*np.subtract(server.ball_position()[:2], BALL)) > 0.5


def test_a_robot_that_is_down_plays_the_get_up_motion_first():
    from teamenv.league.adapter import Request, RequestEncoder

    class Motion:
        def __init__(self):
            self.started, self.steps, self.done = 0, 0, True

        def start(self, perception):
            self.started += 1
            self.done = False

        def step(self, perception):
            self.steps += 1
            self.done = self.steps >= 3
            return "(getup)"

    class Walk:
        def reset(self):
            pass

        def stand(self, perception):
            return "(stand)"

        def step(self, command, perception):
            return "(walk)"

    p = _perception()
    lying = Perception(**{**p.__dict__, "orientations": {"torso_quat": (0.7071, 0.0, 0.7071, 0.0)},
                          "positions": {"torso_pos": (0.0, 0.0, 0.12)}})
    motion = Motion()
    enc = RequestEncoder(Walk(), "agent K_1", get_up=motion)
    assert [enc.encode(Request(walk=(0.3, 0, 0)), lying) for _ in range(3)] == ["(getup)"] * 3
    assert motion.started == 1
    assert enc.encode(Request(walk=(0.3, 0, 0)), p) == "(walk)"
    assert RequestEncoder(Walk(), "agent K_1", get_up=None).encode(
        Request(walk=(0.3, 0, 0)), lying) == "(walk)"


@pytest.mark.slow
def test_a_kick_on_the_real_server():
    _local()
    from teamenv.league import effectors
    from teamenv.league.adapter import Request, RequestEncoder
    from teamenv.league.controller import WalkerController, torso_pose
    from teamenv.league.falls import is_fallen
    from teamenv.league.kick_trial import LOOK_DOWN, spot_start
    from teamenv.league.server import LeagueServer
    from teamenv.league.team_client import TeamClient

    walker = WalkerController()
    enc = RequestEncoder(walker, "agent Alpha_1", get_up=None)
    beam = spot_start(LEAGUE_KICK, "right", ball=(0.0, 0.0))   # the kick-off ball
    with LeagueServer() as server, TeamClient("127.0.0.1", server.agent_port, "Alpha", (1,),
                                              check_alive=server.check_alive) as team:
        team.join()
        team.act({1: enc.encode(Request(beam=beam), team.perceive()[1])})
        for k in range(40):          # stand 0.8 s looking down at the ball
            p = team.perceive()[1]
            if k == 0:
                server.monitor.kick_off("Left")
            enc.ball.update(p)
            team.act({1: walker.stand(p) + effectors.motor("he2", LOOK_DOWN, 0, 20, 0.5)})
        start = enc.ball.world[:2].copy()
        kicked = down = False
        for _ in range(250):         # the kick, then 3.5 s standing (the ball in view again)
            p = team.perceive()[1]
            kicked |= enc.kicking
            down |= is_fallen(p)
            # lined up for a kick along -aim_bias: it starts at once
            request = Request(kick=(1.0, -LEAGUE_KICK.aim_bias)) if not kicked else Request()
            team.act({1: enc.encode(request, p)})
        x, y, _ = torso_pose(p)
    assert kicked
    travel = enc.ball.world[:2] - start
    assert enc.ball.age_s < 0.1                          # seen at the end
    assert travel[0] > 2.0                               # forward, as the robot faced
    assert not down


@pytest.mark.slow
def test_a_1v1_league_match_on_the_local_server_has_a_kick_of_3m(tmp_path):
    _local()
    from teamenv.league.match import LeagueMatchOptions, play_league_match
    from teamenv.replay import load_replay

    path = tmp_path / "m.npz"
    # long enough for the approach (braking, the walk to the spot) and the ball's roll
    play_league_match("tests.teamenv.kick_teams:NearChaserTeam", "static",
                      LeagueMatchOptions(team_size=1, game_s=18.0, server="local"), seed=5,
                      replay_path=path)
    replay = load_replay(path)
    ball = replay.ball[:, :2]
    # the ball starts at the centre spot; a kick takes it >= 3 m from there
    assert float(np.max(np.hypot(*ball.T))) >= 3.0
    assert len(replay.kick_cycle) >= 1


def test_with_another_walk_the_kicks_walker_takes_over_near_the_ball():
    from teamenv.league.adapter import Request, RequestEncoder
    from teamenv.league.controller import torso_pose

    class Other:   # e.g. the reference network
        def __init__(self):
            self.steps = self.resets = 0

        def reset(self):
            self.resets += 1

        def stand(self, perception):
            return "(stand)"

        def step(self, command, perception):
            self.steps += 1
            return "(other)"

    p = Perception(**{**_perception().__dict__, "vision": None})   # no sighting this cycle
    x, y, yaw = torso_pose(p)
    other = Other()
    enc = RequestEncoder(other, "agent K_1", get_up=None)
    assert enc.kick.shares_walker and enc.kick.walker is not other

    def ball_ahead(d):
        enc.ball.world = np.array([x + d * math.cos(yaw), y + d * math.sin(yaw), 0.11])
        enc.ball.age_s = 0.0

    for _ in range(30):     # standing still (the hand-over waits for a slow torso)
        enc.encode(Request(walk=(0.3, 0.0, 0.0)), p)
    other.steps = 0
    ball_ahead(3.0)
    assert enc.encode(Request(kick=(1.0, 0.0)), p) == "(other)"      # far: the team's walk
    ball_ahead(0.7)
    msg = enc.encode(Request(kick=(1.0, 0.0)), p)                    # near: our walker
    assert msg.count("(") == len(MOTORS) and other.steps == 1
    enc.encode(Request(walk=(0.3, 0.0, 0.0)), p)   # the kick request holds (ball within 1 m)
    assert other.steps == 1
    ball_ahead(3.0)
    assert enc.encode(Request(walk=(0.3, 0.0, 0.0)), p) == "(other)"   # back, afresh
    assert other.resets == 1


def test_a_walking_robot_brakes_on_its_walk_before_the_kicks_walker_takes_over():
    from teamenv.league.adapter import Request, RequestEncoder
    from teamenv.league.controller import CYCLE_S, torso_pose
    from teamenv.league.handover import HANDOVER_MAX_S, HANDOVER_SPEED_M_S

    base = Perception(**{**_perception().__dict__, "vision": None})
    x, y, yaw = torso_pose(base)
    other = RecordingController("(other)")   # the reference network, recording its commands
    enc = RequestEncoder(other, "agent K_1", get_up=None)
    place = [x, y]

    def walked(speed):      # the torso moved ``speed`` along its heading this cycle
        place[0] += speed * CYCLE_S * math.cos(yaw)
        place[1] += speed * CYCLE_S * math.sin(yaw)
        z = base.positions["torso_pos"][2]
        return Perception(**{**base.__dict__,
                             "positions": {**base.positions, "torso_pos": (*place, z)}})

    def ball_ahead(d):
        enc.ball.world = np.array([place[0] + d * math.cos(yaw), place[1] + d * math.sin(yaw),
                                   0.11])
        enc.ball.age_s = 0.0

    for _ in range(40):     # the team walks it at 1 m/s
        enc.encode(Request(walk=(1.0, 0.0, 0.0)), walked(1.0))
    ball_ahead(0.7)
    msg = enc.encode(Request(kick=(1.0, 0.0)), walked(1.0))
    assert msg == "(other)"                               # still the team's walk: braking
    assert 0.9 < other.commands[-1][0] < 1.0              # from 1 m/s, at the braking rate
    # the torso keeps its speed: the walk brakes until HANDOVER_MAX_S, then hands over
    cycles = 1
    while enc.encode(Request(kick=(1.0, 0.0)), walked(1.0)) == "(other)":
        ball_ahead(0.7)
        cycles += 1
        assert cycles < 200
    assert cycles == pytest.approx(HANDOVER_MAX_S / CYCLE_S, abs=1)
    assert other.commands[-1][0] <= 0.3                   # braked to the approach's speed
    # a torso that slows down is handed over as soon as it is slow
    enc = RequestEncoder(other, "agent K_1", get_up=None)
    for _ in range(40):
        enc.encode(Request(walk=(1.0, 0.0, 0.0)), walked(1.0))
    ball_ahead(0.7)
    cycles = 0
    while enc.encode(Request(kick=(1.0, 0.0)), walked(0.5 * HANDOVER_SPEED_M_S)) == "(other)":
        ball_ahead(0.7)
        cycles += 1
    assert 0 < cycles < HANDOVER_MAX_S / CYCLE_S - 10


def test_an_approach_that_lost_sight_of_the_ball_steps_back_until_it_sees_it():
    from teamenv.league.adapter import (
        KICK_SIGHTING_MAX_AGE_S,
        SIGHT_AGAIN_COMMAND,
        Request,
        RequestEncoder,
    )
    from teamenv.league.controller import torso_pose

    p = Perception(**{**_perception().__dict__, "vision": None})   # no sighting this cycle
    x, y, yaw = torso_pose(p)
    walker = recording_walker()
    enc = RequestEncoder(walker, "agent K_1", get_up=None)
    # the ball at the kick spot, right foot, last seen just now: the approach walks to the spot
    ahead, beside = LEAGUE_KICK.spot_x + 0.05, -LEAGUE_KICK.foot_y
    enc.ball.world = np.array([x + ahead * math.cos(yaw) - beside * math.sin(yaw),
                               y + ahead * math.sin(yaw) + beside * math.cos(yaw), 0.11])
    enc.ball.age_s = 0.0
    enc.encode(Request(kick=(1.0, 0.0)), p)
    assert walker.commands[-1] != SIGHT_AGAIN_COMMAND and not enc.kicking
    # the ball lies below the camera's view there: once the sighting is too old to start a
    # kick, the robot steps back (the team still asking to kick) instead of waiting for ever
    enc.ball.age_s = KICK_SIGHTING_MAX_AGE_S + 0.1
    enc.encode(Request(kick=(1.0, 0.0)), p)
    assert walker.commands[-1] == SIGHT_AGAIN_COMMAND and SIGHT_AGAIN_COMMAND[0] < 0
    assert not enc.kicking
