"""Falls read from a league replay: one event per fall (a robot flickering across the fall test
falls once) with the distance to the nearest robot just before."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from teamenv.league.replay import (
    FALL_LOOKBACK_CYCLES,
    RECOVER_CYCLES,
    down_times,
    fall_events,
)


def test_fall_events_latch_flicker_and_measure_the_nearest_robot():
    t, p = 200, 3
    down = np.zeros((t, p), bool)
    down[50:60] = [True, False, False]
    down[62:64, 0] = True  # up for 2 cycles only: still the same fall
    down[120:130, 2] = True
    players = np.zeros((t, p, 3))
    players[:, 1, 0] = 0.8  # robot 1 stands 0.8 m from robot 0 ...
    players[:, 2, 0] = 5.0
    players[100:, 1, 0] = 3.0  # ... then walks to 2 m from robot 2
    replay = SimpleNamespace(fallen=down, players=players)
    events = fall_events(replay)
    assert RECOVER_CYCLES > 2
    assert [(e.row, e.player) for e in events] == [(50, 0), (120, 2)]
    assert events[0].nearest_m == pytest.approx(0.8)
    assert events[1].nearest_m == pytest.approx(2.0)
    # the distance is read before the fall: a robot that moves during it does not count
    players[120 - FALL_LOOKBACK_CYCLES + 1:, 1, 0] = 5.1
    assert fall_events(replay)[1].nearest_m == pytest.approx(2.0)


def test_down_times_count_a_fall_until_the_robot_stood_and_leave_out_one_still_down():
    t = 300
    down = np.zeros((t, 2), bool)
    down[50:60, 0] = True
    down[62:64, 0] = True        # flickers up for 2 cycles: the same fall, down until 64
    down[100:140, 1] = True      # a second try, or the referee: one fall of 40 cycles
    down[280:, 0] = True         # still down when the replay ends
    times, still_down = down_times(SimpleNamespace(fallen=down), cycle_s=0.02)
    assert sorted(times.round(6).tolist()) == [0.28, 0.8]
    assert still_down == 1
