"""The league observation adapter on recorded real server messages: one agent's perceptions ->
the env's ``vision``-mode Dict observation (``mj`` profile, ``mj`` channel, ``mj7v7``): the
same keys, shapes and dtypes as the env's observation space, sightings in the env's rows and
units (checked against the env's own vision of the same pose), play modes, odometry/gyro from
the torso pose, fall detection and heard slots."""

from __future__ import annotations

import base64
import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import teamenv
from teamenv.config import VISION_PROFILES
from teamenv.field import field_preset
from teamenv.landmarks import landmarks
from teamenv.league.adapter import observe
from teamenv.league.controller import torso_pose
from teamenv.league.errors import LeagueError
from teamenv.league.falls import is_fallen
from teamenv.league.observation import VisionObservationBuilder, play_mode_index
from teamenv.league.perception import GameState, Heard, parse_perception
from teamenv.sim.playmode import PLAY_MODES, PlayMode
from teamenv.sim.vision import VisionPerception

DATA = Path(__file__).resolve().parents[1] / "league_data"
RECORDED = [("first.txt", "Alpha", "left", 2), ("vision_players_ball.txt", "Beta", "right", 1),
            ("heard.txt", "Beta", "right", 1), ("kick_off.txt", "Alpha", "left", 2),
            ("no_vision.txt", "Alpha", "left", 2)]


def _recorded(name: str):
    return parse_perception((DATA / name).read_text().strip())


@pytest.mark.parametrize("name, team, side, unum, team_size",
                         [(*r, n) for r in RECORDED for n in (1, 2, 7) if r[3] <= n])
def test_observation_has_the_env_layout(name, team, side, unum, team_size):
    env = teamenv.parallel_env(field="mj7v7", team_size=team_size, observation_mode="vision",
                               vision="mj", channel="mj")
    space = env.observation_space("left_1")
    env_obs, _ = env.reset(seed=0)
    builder = VisionObservationBuilder(side, team_size, team)
    obs = builder.observe(unum, _recorded(name))
    assert list(obs) == list(env_obs["left_1"])          # the same keys, in the same order
    for key, sub in space.spaces.items():
        if key == "heard_text":
            assert len(obs[key]) == len(sub.spaces) == 8
        elif key != "play_mode":
            assert obs[key].shape == sub.shape and obs[key].dtype == sub.dtype == np.float32, key
    assert space.contains(obs)
    assert builder.agent(unum) == f"{side}_{unum}"


@pytest.mark.parametrize("name, team, side, unum", [r for r in RECORDED if r[0] in
                                                    ("first.txt", "vision_players_ball.txt")])
def test_sightings_sit_in_the_env_rows_and_agree_with_the_env_vision(name, team, side, unum):
    """The same pose in the env's own vision: the same landmark rows seen, distances and
    azimuths close (the server's camera is the head, the env's an upright one at 1.1 m)."""
    p = _recorded(name)
    obs = VisionObservationBuilder(side, 2, team).observe(unum, p)
    seen = observe(p, team, side)
    names = landmarks(field_preset("mj7v7"), "mj").names
    for k, lm in enumerate(names):
        row = obs["landmarks"][k]
        if lm in seen.landmarks:
            s = seen.landmarks[lm]
            assert row.tolist() == pytest.approx([1.0, s.distance, s.azimuth, s.elevation],
                                                 abs=1e-5)
        else:
            assert not row.any()
    assert obs["counts"][0] == len(seen.landmarks) and obs["counts"][3] == (seen.ball is not None)

    # the env's vision of an agent at the server's torso pose (the other agent far away)
    x, y, yaw = torso_pose(p)
    vision = VisionPerception(field_preset("mj7v7"), 1, 8, VISION_PROFILES["mj"], 0.2, 0.042)
    vision.reset(np.random.default_rng(0))
    me, other = [x, y, yaw], [60.0, 60.0, 0.0]
    poses = np.array([me, other] if side == "left" else [other, me])
    frame = vision.observe(0, poses, np.zeros(4), np.zeros(2), np.zeros((2, 3)), np.zeros(2),
                           PlayMode.PlayOn, 0.0, 1, (0, 0), (1.0, -1.0), np.zeros((2, 8, 4)),
                           [("",) * 8] * 2)
    env = vision.as_dicts(frame)[0 if side == "left" else 1]
    assert (obs["landmarks"][:, 0] == env["landmarks"][:, 0]).all()
    for k in np.flatnonzero(env["landmarks"][:, 0]):
        got, want = obs["landmarks"][k], env["landmarks"][k]
        assert abs(got[1] - want[1]) < 0.15, names[k]
        assert abs(math.remainder(got[2] - want[2], 2 * math.pi)) < math.radians(2), names[k]
    assert obs["ball"][0] == 1 and abs(obs["ball"][1] - math.hypot(x, y)) < 0.5


def test_players_go_to_their_uniform_rows_and_never_oneself():
    p = _recorded("vision_players_ball.txt")               # Beta 1 sees Alpha 1 and 2
    obs = VisionObservationBuilder("right", 2, "Beta").observe(1, p)
    assert obs["opponents"][:, 0].tolist() == [1.0, 1.0] and not obs["teammates"].any()
    assert obs["counts"][1] == 2
    # as if Beta were Alpha: Alpha 1 sees its teammate 2, never itself
    alpha = VisionObservationBuilder("left", 2, "Alpha").observe(1, p)
    assert alpha["teammates"][:, 0].tolist() == [0.0, 1.0] and alpha["counts"][1] == 1
    # a player numbered beyond the team size has no row
    small = VisionObservationBuilder("right", 1, "Beta").observe(1, p)
    assert small["opponents"][:, 0].tolist() == [1.0] and small["counts"][1] == 1


def test_vision_freshness_counts_cycles_since_the_last_see():
    b = VisionObservationBuilder("left", 2, "Alpha")
    seen, blind = _recorded("first.txt"), _recorded("no_vision.txt")
    assert b.observe(1, seen)["vision"].tolist() == [1.0, 0.0]
    assert b.observe(1, blind)["vision"].tolist() == [0.0, 1.0]
    second = b.observe(1, blind)
    assert second["vision"].tolist() == [0.0, 2.0] and not second["landmarks"].any()
    assert b.observe(2, blind)["vision"].tolist() == [0.0, 1.0]    # per agent


def _moved(p, dx=0.0, dy=0.0, dyaw=0.0, z=None, tilt=0.0):
    """``p`` with the torso moved by (dx, dy) world metres, turned by dyaw, tilted about x."""
    x, y, zz = p.positions["torso_pos"]
    _, _, yaw = torso_pose(p)
    yaw += dyaw
    half = yaw / 2
    qz = (math.cos(half), 0.0, 0.0, math.sin(half))
    qx = (math.cos(tilt / 2), math.sin(tilt / 2), 0.0, 0.0)
    w = qz[0] * qx[0]                                  # qz * qx (yaw, then tilt about x)
    q = (w, qz[0] * qx[1], qz[3] * qx[1], qz[3] * qx[0])
    return dataclasses.replace(p, positions={**p.positions, "torso_pos": (x + dx, y + dy,
                                                                           zz if z is None else z)},
                               orientations={**p.orientations, "torso_quat": q})


def test_odometry_and_gyro_are_the_cycles_motion_in_the_body_frame():
    p = _recorded("kick_off.txt")
    _, _, yaw = torso_pose(p)
    b = VisionObservationBuilder("left", 2, "Alpha")
    first = b.observe(1, p)
    assert not first["odometry"].any() and not first["gyro"].any()
    step = 0.01
    nxt = b.observe(1, _moved(p, step * math.cos(yaw), step * math.sin(yaw), dyaw=0.02))
    assert nxt["odometry"].tolist() == pytest.approx([step, 0.0, 0.02], abs=1e-5)
    assert nxt["gyro"][0] == pytest.approx(0.02, abs=1e-5)
    side = b.observe(1, _moved(p, -step * math.sin(yaw), step * math.cos(yaw)))  # to its left
    assert side["odometry"][1] > 0.009
    b.note_beam(1)                                     # a beam is no motion
    far = b.observe(1, _moved(p, 5.0, 3.0))
    assert not far["odometry"].any() and not far["gyro"].any()


def test_fallen_from_the_torso_attitude_or_height():
    p = _recorded("kick_off.txt")
    assert not is_fallen(p)
    assert is_fallen(_moved(p, tilt=math.radians(80)))
    assert not is_fallen(_moved(p, tilt=math.radians(20)))
    assert not is_fallen(_moved(p, tilt=math.radians(50)))       # leaning, recovers
    assert is_fallen(_moved(p, z=0.2))
    obs = VisionObservationBuilder("left", 2, "Alpha").observe(1, _moved(p, tilt=1.4))
    assert obs["body"][0] == 1.0
    head = p.joints["q_hj1"].angle
    assert obs["body"][1] == pytest.approx(head, abs=1e-6)


@pytest.mark.parametrize("mode, side, ours", [
    ("BeforeKickOff", "left", "BeforeKickOff"), ("KickOff_Left", "right", "KickOff_Right"),
    ("KickOff_Right", "right", "KickOff_Left"), ("PlayOn", "right", "PlayOn"),
    ("KickIn_Left", "left", "KickIn_Left"), ("corner_kick_right", "left", "CornerKick_Right"),
    ("goal_kick_left", "right", "GoalKick_Right"), ("Goal_Left", "right", "Goal_Right"),
    ("GameOver", "right", "GameOver"), ("free_kick_right", "right", "KickIn_Left"),
    ("penalty_kick_left", "left", "KickIn_Left"), ("offside_right", "left", "KickIn_Right"),
])
def test_play_modes_map_to_ours_team_relative(mode, side, ours):
    assert PLAY_MODES[play_mode_index(mode, side)] == ours


def test_every_server_play_mode_maps_and_unknown_ones_are_an_error():
    rcsssmj = pytest.importorskip("rcsssmj.games.soccer.play_mode")
    for mode in rcsssmj.PlayMode:
        play_mode_index(mode.value, "left")
    with pytest.raises(LeagueError, match="play mode 'Halftime' from the server is unknown"):
        play_mode_index("Halftime", "left")


def test_game_and_play_mode_from_gs():
    p = _recorded("kick_off.txt")
    p = dataclasses.replace(p, game=GameState(12.5, "PlayOn", "Alpha", "Beta", 2, 1))
    left = VisionObservationBuilder("left", 2, "Alpha").observe(1, p)
    right = VisionObservationBuilder("right", 2, "Beta").observe(1, p)
    assert left["game"].tolist() == [12.5, 1.0, 2.0, 1.0]
    assert right["game"].tolist() == [12.5, 1.0, 1.0, 2.0]
    assert left["play_mode"] == PLAY_MODES.index("PlayOn")


def test_heard_messages_fill_the_env_slots_teammates_first():
    p = _recorded("heard.txt")
    hello = base64.b64encode(b"hello").decode()
    b = VisionObservationBuilder("right", 2, "Beta")
    opp = b.observe(1, p)                    # nobody of Beta said it: an opponent's message
    assert opp["heard_text"][0] == hello and opp["heard_text"][1:] == ("",) * 7
    assert opp["heard"][0].tolist() == pytest.approx([1.0, 0.0, 0.0, math.radians(174.0)])
    mate = b.observe(1, p, teammate_texts=[hello])
    assert mate["heard"][0, 2] == 1.0
    # ten messages: teammates' first, at most 8 slots
    many = [Heard(math.radians(k), base64.b64decode(base64.b64encode(bytes([k])))) for k in range(10)]
    texts = [base64.b64encode(bytes([k])).decode() for k in range(10)]
    obs = b.observe(1, dataclasses.replace(p, heard=many), teammate_texts=texts[7:])
    assert obs["heard_text"] == tuple(texts[7:] + texts[:5])
    assert obs["heard"][:, 2].tolist() == [1.0] * 3 + [0.0] * 5
    assert obs["heard"][:, 1].sum() == 0                     # never from oneself
    said = b.observe_team({1: p, 2: p}, said={1: [hello], 2: ["", "x"]})
    assert said["right_1"]["heard"][0, 2] == 0.0 and said["right_2"]["heard"][0, 2] == 1.0


def test_bad_input_is_named():
    p = _recorded("first.txt")
    with pytest.raises(LeagueError, match="uniform number 3 is not in 1..2"):
        VisionObservationBuilder("left", 2, "Alpha").observe(3, p)
    with pytest.raises(LeagueError, match="side must be"):
        VisionObservationBuilder("up", 2, "Alpha")
    with pytest.raises(LeagueError, match="agent Alpha_1: perception without time/GS"):
        VisionObservationBuilder("left", 2, "Alpha").observe(1, dataclasses.replace(p, game=None))
