"""``benchmarks/team_speed.py`` times a team on recorded cycles; its copies must decide as the
team did in the match, or it refuses to time them."""

from __future__ import annotations

import numpy as np
import pytest

from tests.benchmark_scripts import load_benchmark


def test_replayed_team_decides_as_in_the_match_and_a_difference_stops_the_run():
    team_speed = load_benchmark("team_speed")
    initial, cycles = team_speed.record("full", "chaser", "simspark", 3, 1.0, 7, "state", None)
    assert len(cycles) > 50
    cpu, wall = team_speed.replay(initial, cycles)
    assert cpu > 0.0 and wall > 0.0
    team_speed.replay(initial, cycles)  # a second copy of the kick-off team: the same again
    observations, actions = cycles[-1]
    agent = next(iter(actions))
    walk = np.array(actions[agent]["walk"])
    walk[0] = np.nextafter(walk[0], walk.dtype.type(np.inf))  # one ulp off, in its own dtype
    changed = {**actions, agent: {**actions[agent], "walk": walk}}
    with pytest.raises(SystemExit, match="decided differently"):
        team_speed.replay(initial, cycles[:-1] + [(observations, changed)])
