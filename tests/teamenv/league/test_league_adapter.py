"""League adapter: server perceptions -> team-frame sightings in our landmark names, requests
-> effectors (say through the mj channel profile, beam, kick = walk through the ball); and on
the real server one agent walks towards a point and gets closer."""

from __future__ import annotations

import base64
import math
from pathlib import Path

import numpy as np
import pytest

from teamenv.field import field_preset
from teamenv.landmarks import landmarks, to_polar
from teamenv.league.adapter import LEFT_MARKS, RIGHT_MARKS, Request, RequestEncoder, observe
from teamenv.league.controller import torso_pose
from teamenv.league.errors import LeagueError
from teamenv.league.perception import parse_perception

DATA = Path(__file__).resolve().parents[1] / "league_data"


def _recorded(name: str):
    return parse_perception((DATA / name).read_text().strip())


@pytest.mark.parametrize("name, team, side", [("vision_players_ball.txt", "Beta", "right"),
                                              ("first.txt", "Alpha", "left")])
def test_sightings_are_our_landmarks_in_the_team_frame(name, team, side):
    p = _recorded(name)
    obs = observe(p, team, side)
    table = landmarks(field_preset("mj7v7"), "mj")
    assert obs.landmarks and set(obs.landmarks) <= set(table.names)
    x, y, yaw = torso_pose(p)
    if side == "right":                      # the right team's frame is the world turned by pi
        x, y, yaw = -x, -y, yaw + math.pi
    for lm, seen in obs.landmarks.items():
        want = to_polar(table.xyz[[table.index(lm)]], x, y, yaw, 1.2)[0]
        # the camera sits on the head (which may be turned a little): a few degrees
        d_az = math.remainder(seen.azimuth - want[1], 2 * math.pi)
        assert abs(d_az) < math.radians(6), (lm, math.degrees(seen.azimuth), math.degrees(want[1]))
        assert abs(seen.distance - want[0]) < 0.1 * want[0] + 0.3
    assert obs.dropped_marks == sum(1 for m in p.vision.objects if m != "B") - len(obs.landmarks)


def test_mark_tables_are_the_same_points_turned():
    assert set(LEFT_MARKS.values()) == set(RIGHT_MARKS.values())
    assert RIGHT_MARKS["l_rlf"] == "corner_own_left" and RIGHT_MARKS["g_lup"] == "post_their_right"


def test_heard_messages_come_back_as_mj_channel_text():
    obs = observe(_recorded("heard.txt"), "Beta", "right")
    assert obs.heard_text == [(math.radians(174.0), base64.b64encode(b"hello").decode())]
    assert obs.ball is None or obs.ball.distance > 0


class _Recorder:
    def __init__(self):
        self.commands, self.resets = [], 0

    def reset(self):
        self.resets += 1

    def stand(self, perception):
        self.reset()
        return "(stand)"

    def step(self, command, perception):
        self.commands.append(tuple(command))
        return "(he1 0 0 0 0 0)"


def test_requests_to_effectors():
    ctl = _Recorder()
    enc = RequestEncoder(ctl, "agent Alpha_1", stand_when_idle=False)
    p = _recorded("first.txt")
    text = base64.b64encode(b"0123456789").decode()
    assert enc.encode(Request(say=text), p) == "(he1 0 0 0 0 0)(SPK say 100 MDEyMzQ1Njc4OQ==)"
    # a beam comes with the standing targets (every motor commanded), which reset the walk
    assert enc.encode(Request(beam=(-3.0, 1.0, 0.0)), p) == "(beam -3 1 0)(stand)"
    assert ctl.resets == 1
    enc.encode(Request(walk=(0.2, 0.0, 0.1)), p)
    enc.encode(Request(walk=(0.0, 0.0, 0.0), kick=(1.0, 0.0)), p)
    # the ball is in view, 1-2 m off: a kick request walks towards the kick spot
    assert ctl.commands[-2] == (0.2, 0.0, 0.1) and ctl.commands[-1][0] > 0.1
    through = RequestEncoder(ctl, "agent Alpha_1", kick=None)   # kicks as walks through
    through.encode(Request(kick=(1.0, 0.0)), p)
    assert ctl.commands[-1] == (0.4, 0.0, 0.0)
    with pytest.raises(LeagueError, match="agent Alpha_1: say 'hello' breaks the mj channel"):
        enc.encode(Request(say="hello"), p)
    assert enc.encode(Request(), p) == "(he1 0 0 0 0 0)"  # walks on the spot
    idle = RequestEncoder(ctl, "agent Alpha_1")
    before = len(ctl.commands)
    assert idle.encode(Request(), p) == "(stand)" and ctl.resets == 2     # stands, no walker
    assert idle.encode(Request(kick=(1.0, 0.0)), p) == "(he1 0 0 0 0 0)"  # a kick walks
    assert idle.encode(Request(walk=(0.1, 0.0, 0.0)), p) == "(he1 0 0 0 0 0)"
    assert len(ctl.commands) == before + 2
    with pytest.raises(LeagueError, match="needs the 'mj' channel"):
        RequestEncoder(ctl, "agent Alpha_1", channel="simspark")


@pytest.mark.humanoid
def test_one_agent_walks_towards_a_point_on_the_real_server():
    pytest.importorskip("rcsssmj")
    pytest.importorskip("mujoco")
    from teamenv.league.controller import WalkerController
    from teamenv.league.falls import is_fallen
    from teamenv.league.server import LeagueServer
    from teamenv.league.team_client import TeamClient

    target = np.array([0.0, 0.0])
    enc = RequestEncoder(WalkerController(), "agent Alpha_1")
    with LeagueServer() as server, TeamClient("127.0.0.1", server.agent_port, "Alpha", (1,),
                                              check_alive=server.check_alive) as team:
        team.join()
        team.act({1: enc.encode(Request(beam=(-5.0, 0.0, 0.0)), team.perceive()[1])})
        dist, down = [], []
        for k in range(200):        # 4 s of game time: 0.5 s standing, then walking
            p = team.perceive()[1]
            if k == 0:              # after the beam: the server beams only before kick-off
                server.monitor.kick_off("Left")
            x, y, yaw = torso_pose(p)
            dist.append(float(np.hypot(*(target - (x, y)))))
            down.append(is_fallen(p))
            to = math.atan2(target[1] - y, target[0] - x) - yaw
            team.act({1: enc.encode(Request(walk=(0.4, 0.0, 0.5 * math.remainder(to, 2 * math.pi))), p)})
    assert dist[2] == pytest.approx(5.0, abs=0.2)        # beamed
    assert not any(down)                                 # the league walk stays up
    assert dist[-1] < dist[2] - 0.7                      # ~1 m in 3.5 s of walking
