"""The hand-over of a kick's approach (teamenv.league.handover): the torso's speed over a gait
cycle, the braking command's rates and when the kick's walker may take over."""

from __future__ import annotations

import math

import pytest

from teamenv.league.controller import CYCLE_S
from teamenv.league.handover import (
    BRAKE_M_S2,
    BRAKE_TURN_S2,
    HANDOVER_MAX_S,
    HANDOVER_SPEED_M_S,
    SPEED_WINDOW_S,
    HandOver,
    TorsoSpeed,
)


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
