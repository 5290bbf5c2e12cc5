"""The league client's command ramp: walk requests change no faster than the body the teams
plan with (the t1_league profile's accelerations), inside the controller's envelope; it
restarts from standing after a beam, a kick request or a motion."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from locomotion import load_profile
from teamenv.league.adapter import Request, RequestEncoder
from teamenv.league.command_ramp import CommandRamp
from teamenv.league.controller import CYCLE_S, WalkEnvelope
from teamenv.league.errors import LeagueError
from teamenv.league.match import LOCOMOTION_PROFILE, LeagueMatchOptions, _ramp
from teamenv.league.perception import parse_perception

DATA = Path(__file__).resolve().parents[1] / "league_data"


def test_each_component_moves_by_at_most_its_acceleration_per_cycle():
    ramp = CommandRamp((1.0, 0.5, 2.0), cycle_s=0.02)
    out = [ramp((1.2, -0.4, -1.5)) for _ in range(100)]
    steps = np.abs(np.diff(np.array([(0.0, 0.0, 0.0)] + out), axis=0))
    assert np.all(steps <= np.array([0.02, 0.01, 0.04]) + 1e-12)
    assert out[0] == pytest.approx((0.02, -0.01, -0.04))
    assert out[-1] == (1.2, -0.4, -1.5)          # reached, and held exactly
    # full speed ahead -> turning on the spot the other way: 1.2 s to stop, 1.5 s to turn
    back = [ramp((0.0, 0.0, 1.5)) for _ in range(80)]
    assert back[29][0] == pytest.approx(0.6) and back[-1] == (0.0, 0.0, 1.5)
    assert ramp.command == (0.0, 0.0, 1.5)
    ramp.reset()
    assert ramp((0.0, 0.0, 0.0)) == (0.0, 0.0, 0.0)


def test_the_ramp_is_the_league_bodys_accelerations():
    profile = load_profile(LOCOMOTION_PROFILE)
    ramp = _ramp(LeagueMatchOptions(server="local", ramp=True))
    assert ramp.accel == tuple(float(a) for a in profile.accel)
    assert ramp.cycle_s == CYCLE_S
    assert _ramp(LeagueMatchOptions(server="local")) is None     # off by default


@pytest.mark.parametrize("accel, match", [((1.0, 0.0, 1.0), "accel must be"),
                                          ((1.0, 1.0), "accel must be"),
                                          ((1.0, float("nan"), 1.0), "accel must be")])
def test_bad_accelerations_are_named(accel, match):
    with pytest.raises(LeagueError, match=match):
        CommandRamp(accel)


def test_bad_requests_are_named():
    ramp = CommandRamp((1.0, 1.0, 1.0))
    with pytest.raises(LeagueError, match=r"not finite"):
        ramp((float("inf"), 0.0, 0.0))
    with pytest.raises(LeagueError, match=r"is \(vx, vy, turn\)"):
        ramp((1.0, 0.0))


class _Walk:
    """A controller that records the commands it is asked to walk (and has an envelope)."""

    def __init__(self, envelope=None):
        self.envelope = envelope
        self.commands, self.stands = [], 0

    def reset(self):
        pass

    def stand(self, perception):
        self.stands += 1
        return "(stand)"

    def step(self, command, perception):
        self.commands.append(tuple(command))
        return "(walk)"


def test_the_encoder_ramps_walk_requests_inside_the_envelope_and_stands_when_stopped():
    p = parse_perception((DATA / "first.txt").read_text().strip())
    walk = _Walk(WalkEnvelope(vx_forward=1.0, vx_backward=0.5, vy=0.1, turn=1.5))
    enc = RequestEncoder(walk, "agent A_1", kick=None, get_up=None,
                         ramp=CommandRamp((1.0, 0.5, 2.0)))
    for _ in range(10):
        enc.encode(Request(walk=(1.5, 0.4, 0.0)), p)   # outside the envelope: scaled onto it
    vx, vy, _ = walk.commands[-1]
    limited = walk.envelope.limit((1.5, 0.4, 0.0))      # (0.351, 0.0936, 0)
    assert vx == pytest.approx(10 * 0.02) and vy == pytest.approx(limited[1])
    # a stop request decelerates: the robot walks on slower, then stands
    said = [enc.encode(Request(), p) for _ in range(20)]
    assert said[0] == "(walk)" and said[-1] == "(stand)" and walk.stands >= 1
    assert all(abs(c[0]) <= 0.2 + 1e-12 for c in walk.commands)
    # a beam stands the robot: the next walk starts from zero again
    enc.encode(Request(walk=(1.0, 0.0, 0.0)), p)
    enc.encode(Request(beam=(-3.0, 0.0, 0.0)), p)
    enc.encode(Request(walk=(1.0, 0.0, 0.0)), p)
    assert walk.commands[-1] == pytest.approx((0.02, 0.0, 0.0))
    # without a ramp the request goes straight through
    plain = _Walk()
    RequestEncoder(plain, "agent A_1", kick=None, get_up=None).encode(
        Request(walk=(1.0, 0.0, -1.5)), p)
    assert plain.commands == [(1.0, 0.0, -1.5)]


def test_the_kick_approach_on_the_controller_is_ramped_and_the_hand_over_restarts_it():
    # the recorded perception sees the ball 1-2 m off: the approach walks on the controller
    p = parse_perception((DATA / "first.txt").read_text().strip())
    walk = _Walk()
    ramp = CommandRamp((1.0, 0.5, 2.0))
    enc = RequestEncoder(walk, "agent A_1", get_up=None, ramp=ramp)
    enc.encode(Request(kick=(1.0, 0.0)), p)
    first = walk.commands[-1]
    assert 0.0 < first[0] <= 0.02 + 1e-12 and abs(first[2]) <= 0.04 + 1e-12
    for _ in range(5):
        enc.encode(Request(kick=(1.0, 0.0)), p)
    vx = [c[0] for c in walk.commands[-6:]]
    assert all(0.0 < b - a <= 0.02 + 1e-12 for a, b in zip(vx, vx[1:], strict=False)), vx
    assert ramp.command == walk.commands[-1]
    # a beam restarts the walk from standing, so does the ramp
    enc.encode(Request(beam=(-3.0, 0.0, 0.0)), p)
    assert ramp.command == (0.0, 0.0, 0.0)
