"""The T1's kick on the league server (teamenv.league.kick): the motion's keyframes and input
checks, the ball seen from the camera, the approach that aims it; on LocalServer a kick from
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
    _keyframes,
    _mirror,
    approach_command,
    in_kick_spot,
    measured_angles,
)
from teamenv.league.perception import JointState, Perception, parse_perception

pytestmark = pytest.mark.humanoid
DATA = Path(__file__).parent / "league_data"


def _perception() -> Perception:
    return parse_perception((DATA / "first.txt").read_text().strip())


def test_the_left_kick_is_the_right_kick_mirrored():
    right = _keyframes(LEAGUE_KICK, 1.0, 0.0)
    for _, q in right:
        assert np.allclose(_mirror(_mirror(q)), q)
    strike = dict(zip(MOTORS, right[2][1], strict=True))
    left = dict(zip(MOTORS, _mirror(right[2][1]), strict=True))
    assert left["lle1"] == strike["rle1"] and left["rle1"] == strike["lle1"]   # pitch kept
    assert left["lle2"] == -strike["rle2"]                                     # roll flipped
    # the right kick's shift moves the pelvis left: both hip rolls negative
    assert strike["lle2"] < 0 and strike["rle2"] < 0


def test_a_kick_starts_from_the_measured_angles_and_ends():
    p = _perception()
    angles = measured_angles(p)
    bent = Perception(**{**p.__dict__, "joints": {
        **p.joints, "q_rlj4": JointState(1.0, 0.0)}})      # a walk left the right knee bent
    kick = KickMotion()
    kick.start(bent, 0.0, 1.0, foot="right")
    assert kick.targets()[MOTORS.index("rle4")] == pytest.approx(1.0)
    assert np.allclose(np.delete(kick.targets(), MOTORS.index("rle4")),
                       np.delete(angles, MOTORS.index("rle4")))
    steps = 0
    while not kick.done:
        msg = kick.step(bent)
        steps += 1
    assert steps == math.ceil(LEAGUE_KICK.duration_s / 0.02 - 1e-9)
    assert msg.count("(") == len(MOTORS)                 # every motor commanded
    with pytest.raises(LeagueError, match="step.*without a running kick"):
        kick.step(bent)


@pytest.mark.parametrize("kwargs, match", [
    ({"power": 1.5}, "power 1.5 is not in 0..1"),
    ({"power": float("nan")}, "power nan"),
    ({"direction": float("inf")}, "direction inf is not finite"),
    ({"foot": "middle"}, "foot 'middle'"),
])
def test_bad_kick_requests_are_named(kwargs, match):
    with pytest.raises(LeagueError, match=match):
        KickMotion().start(_perception(), **kwargs)


def test_the_approach_walks_into_the_spot_and_faces_the_direction():
    sx, sy = LEAGUE_KICK.spot_x, LEAGUE_KICK.spot_y
    assert in_kick_spot((sx, -sy), 0.0) and in_kick_spot((sx, sy), 0.0)
    assert not in_kick_spot((sx, -sy), 0.5)              # faces the wrong way
    assert not in_kick_spot((sx + 0.3, -sy), 0.0)        # too far
    vx, vy, turn = approach_command((2.0, 0.0), 0.0)
    assert vx > 0.2 and abs(turn) < 0.2                  # far ahead: walk at it
    assert approach_command((1.5, 1.5), 0.0)[2] > 0.3    # far left: turn left
    vx, vy, turn = approach_command((sx, -sy), 0.6)      # at the spot, kick asked to the left
    assert turn > 0.3
    vx, vy, turn = approach_command((sx + 0.1, -sy), 0.0)
    assert vx > 0.05 and abs(vy) < 0.05                  # a little short: step forward


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
    from teamenv.league.controller import WalkerController
    from teamenv.league.kick_trial import BALL, LOOK_DOWN, spot_start
    from teamenv.league.local_server import LocalServer

    class Counting(WalkerController):
        steps = resets = 0

        def step(self, command, perception):
            self.steps += 1
            return super().step(command, perception)

        def reset(self):
            self.resets += 1
            super().reset()

    server = LocalServer()
    key = ("K", 1)
    walker = Counting()
    enc = RequestEncoder(walker, "agent K_1", get_up=None)
    p = server.join(*key)
    p = server.cycle({key: enc.encode(Request(beam=spot_start(LEAGUE_KICK, "right")), p)})[key]
    server.kick_off("Left")
    p = server.cycle({key: walker.stand(p)})[key]
    server.place_ball(*BALL)
    for _ in range(20):     # stand looking down at the ball (it lies below a level camera)
        enc.ball.update(p)
        p = server.cycle({key: walker.stand(p) + effectors.motor("he2", LOOK_DOWN, 0, 20, 0.5)})[key]
    p = server.cycle({key: enc.encode(Request(kick=(1.0, 0.0)), p)})[key]
    assert enc.kicking
    steps, cycles = walker.steps, 1
    while enc.kicking:      # walk requests while the kick runs are ignored
        p = server.cycle({key: enc.encode(Request(walk=(0.3, 0.0, 0.0)), p)})[key]
        cycles += 1
    assert walker.steps == steps and cycles == math.ceil(LEAGUE_KICK.duration_s / 0.02 - 1e-9)
    assert walker.resets >= 1                            # the walk starts afresh
    enc.encode(Request(walk=(0.3, 0.0, 0.0)), p)
    assert walker.steps == steps + 1
    assert np.hypot(*np.subtract(server.ball_position()[:2], BALL)) > 0.3


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
    from teamenv.league.kick_trial import LOOK_DOWN, spot_start
    from teamenv.league.observation import is_fallen
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
            request = Request(kick=(1.0, 0.0)) if not kicked else Request()
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
    play_league_match("tests.teamenv.kick_teams:NearChaserTeam", "static",
                      LeagueMatchOptions(team_size=1, game_s=12.0, server="local"), seed=5,
                      replay_path=path)
    replay = load_replay(path)
    ball = replay.ball[:, :2]
    # the ball starts at the centre spot; a kick takes it >= 3 m from there
    assert float(np.max(np.hypot(*ball.T))) >= 3.0
    assert len(replay.kick_cycle) >= 1
