"""The hand-over of a kick's approach (teamenv.league.handover): the torso's speed over a gait
cycle, the braking command's rates and when the kick's walker may take over (slow; with
``stop``: stopped, slow and on both feet); the feet's heights from the measured joints
(teamenv.league.feet)."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

from teamenv.league.controller import CYCLE_S
from teamenv.league.feet import FOOT_DOWN_Z, feet_down, feet_heights
from teamenv.league.handover import (
    BRAKE_M_S2,
    BRAKE_TURN_S2,
    HANDOVER_MAX_S,
    HANDOVER_SPEED_M_S,
    HANDOVER_STOP_MAX_S,
    HANDOVER_STOP_S,
    SPEED_WINDOW_S,
    HandOver,
    TorsoSpeed,
)
from teamenv.league.perception import Perception, parse_perception

DATA = Path(__file__).resolve().parents[1] / "league_data"


class _At:
    def __init__(self, x, y):
        self.positions = {"torso_pos": (x, y, 0.6)}


def test_the_torso_speed_is_the_mean_over_a_gait_cycle_not_the_sway():
    speed = TorsoSpeed()
    n = round(SPEED_WINDOW_S / CYCLE_S)
    for k in range(n):
        speed.update(_At(0.4 * k * CYCLE_S, 0.0))
        assert speed.speed == math.inf                   # not known before a whole window
    for k in range(n, 3 * n):   # 0.4 m/s forward with a 5 cm sideways sway at ~1.6 Hz
        speed.update(_At(0.4 * k * CYCLE_S, 0.05 * math.sin(2 * math.pi * 1.6 * k * CYCLE_S)))
    assert speed.speed == pytest.approx(0.4, abs=0.1)
    speed.update(type("NoPose", (), {"positions": {}})())
    assert speed.speed == math.inf                        # a lost pose starts the window again


def test_braking_changes_the_command_at_the_braking_rates_towards_the_target():
    h = HandOver()
    h.walked((1.2, 0.0, 1.0))
    first = h.brake((0.2, 0.1, -0.5))
    assert first == pytest.approx((1.2 - BRAKE_M_S2 * CYCLE_S, BRAKE_M_S2 * CYCLE_S,
                                   1.0 - BRAKE_TURN_S2 * CYCLE_S))
    for _ in range(100):
        last = h.brake((0.2, 0.1, -0.5))
    assert last == pytest.approx((0.2, 0.1, -0.5))
    h.reset()
    assert h.brake((0.2, 0.0, 0.0))[0] == pytest.approx(BRAKE_M_S2 * CYCLE_S)   # from rest


def test_the_kicks_walker_takes_over_when_slow_or_after_the_longest_braking():
    h = HandOver()
    assert not h.ready                                    # speed unknown, not braked yet
    for k in range(40):
        h.torso.update(_At(1.0 * k * CYCLE_S, 0.0))       # walking 1 m/s
    assert not h.ready
    cycles = 0
    while not h.ready:
        h.brake((0.0, 0.0, 0.0))
        cycles += 1
    assert cycles == round(HANDOVER_MAX_S / CYCLE_S)
    h.walked((1.0, 0.0, 0.0))                             # walking again: braking restarts
    assert not h.ready
    for k in range(40):
        h.torso.update(_At(40 * CYCLE_S + 0.5 * HANDOVER_SPEED_M_S * k * CYCLE_S, 0.0))
    assert h.ready
    assert h.near(1.1, 1.0, begun=True) is False and h.stand_s is None   # no stop: as before


def test_with_stop_braking_stops_the_walk_at_the_braking_rates():
    h = HandOver(stop=True)
    h.walked((1.2, 0.1, 1.0))
    first = h.brake((0.2, 0.1, -0.5))                     # the approach's command is not walked
    assert first == pytest.approx((1.2 - BRAKE_M_S2 * CYCLE_S, 0.1 - BRAKE_M_S2 * CYCLE_S,
                                   1.0 - BRAKE_TURN_S2 * CYCLE_S))
    for _ in range(100):
        last = h.brake((0.2, 0.1, -0.5))
    assert last == pytest.approx((0.0, 0.0, 0.0))      # stepping on the spot
    # once begun, it goes on a little beyond the radius (a robot on the spot drifts)
    assert h.near(1.1, 1.0, begun=True) and not h.near(1.1, 1.0, begun=False)
    assert not h.near(1.4, 1.0, begun=True)


def _standing(x: float = -3.0, knee: float = 0.0) -> Perception:
    """A recorded standing T1 (both feet down) moved to ``x``; ``knee`` bends the left knee
    by that much (rad), which lifts the left foot."""
    p = parse_perception((DATA / "first.txt").read_text().strip())
    joints = dict(p.joints)
    joints["q_llj4"] = dataclasses.replace(joints["q_llj4"], angle=joints["q_llj4"].angle + knee)
    return dataclasses.replace(p, joints=joints,
                               positions={**p.positions, "torso_pos": (x, *p.positions["torso_pos"][1:])})


def test_the_feet_are_down_when_both_are_on_the_ground():
    left, right = feet_heights(_standing())
    assert left == pytest.approx(right, abs=1e-9) and 0.02 < left <= FOOT_DOWN_Z
    left, right = feet_heights(_standing(knee=0.6))
    assert left > FOOT_DOWN_Z + 0.03 and right <= FOOT_DOWN_Z
    assert feet_down(_standing()) and not feet_down(_standing(knee=0.6))


def test_with_stop_the_kicks_walker_takes_over_once_stopped_slow_and_on_both_feet():
    h = HandOver(stop=True)
    assert not h.ready                                    # speed unknown, not braked yet
    for _ in range(40):
        h.update(_standing())                             # standing still, feet down
    assert not h.ready                                    # slow, but not stopped yet
    cycles = 0
    while not h.ready:
        h.brake((0.3, 0.0, 0.0))
        cycles += 1
    assert cycles == round(HANDOVER_STOP_S / CYCLE_S)     # the whole stop, not sooner
    h.walked((0.3, 0.0, 0.0))                             # walking again: the stop restarts
    assert not h.ready
    # stopped and slow, but a foot in the air: it waits for the foot, at most
    # HANDOVER_STOP_MAX_S
    for _ in range(round(HANDOVER_STOP_S / CYCLE_S) + 5):
        h.update(_standing(knee=0.6))
        h.brake((0.3, 0.0, 0.0))
    assert not h.ready
    h.update(_standing())                                 # the foot is down
    assert h.ready
    h.walked((0.3, 0.0, 0.0))
    for _ in range(round(HANDOVER_STOP_MAX_S / CYCLE_S) - 1):
        h.update(_standing(knee=0.6))
        h.brake((0.3, 0.0, 0.0))
        assert not h.ready
    h.brake((0.3, 0.0, 0.0))
    assert h.ready                                        # hands over anyway


def test_with_stop_a_fast_torso_is_not_handed_over_before_the_longest_braking():
    h = HandOver(stop=True)
    cycles = 0
    for k in range(40):
        h.update(_standing(x=-3.0 + 1.0 * k * CYCLE_S))   # 1 m/s
    while not h.ready:
        cycles += 1
        h.update(_standing(x=-3.0 + 1.0 * (40 + cycles) * CYCLE_S))
        h.brake((0.3, 0.0, 0.0))
    assert cycles == round(HANDOVER_STOP_MAX_S / CYCLE_S)
    assert HANDOVER_SPEED_M_S < 1.0


def test_the_kicks_walker_after_a_hand_over_stands_shorter_before_its_first_step():
    from teamenv.league.controller import WalkerController
    from teamenv.league.handover import HANDOVER_STAND_S

    def first_step(walker: WalkerController) -> int:
        p = _standing()
        for cycle in range(1, 60):
            walker.step((0.0, 0.0, 0.0), p)
            if walker.gait is not None:
                return cycle
        raise AssertionError("no step")

    # (the walker's clock runs in 10 ms steps: the first step begins within a cycle)
    assert first_step(WalkerController()) == pytest.approx(0.5 / CYCLE_S, abs=1)
    assert HandOver(stop=True).stand_s == HANDOVER_STAND_S
    assert first_step(WalkerController(stand_s=HANDOVER_STAND_S)) == \
        pytest.approx(HANDOVER_STAND_S / CYCLE_S, abs=1)
