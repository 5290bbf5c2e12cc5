"""The built-in teams are graded: 10 seeded 7 v 7 matches of 2 simulated minutes per pairing
(mj7v7 pitch, sides alternating; ``teamenv.headtohead``).

Issue 5's test (numbers in the README, from ``python benchmarks/strategy_strength.py``): the
full team outscores the static team and the ball-chasing team on aggregate, and the
communicating team is not worse than the silent one.
"""

from __future__ import annotations

import pytest

from teamenv.headtohead import head_to_head
from teamenv.match import MatchOptions

OPTIONS = MatchOptions(field="mj7v7", team_size=7, half_time_s=60.0)
SEEDS = 10


@pytest.fixture(scope="module")
def results():
    return {b: head_to_head("full", b, SEEDS, OPTIONS, jobs=2)
            for b in ("static", "chaser", "silent")}


def test_full_team_outscores_the_static_team(results):
    r = results["static"]
    assert not r.forfeits, r.forfeits
    assert r.goals[0] > r.goals[1], r.summary()
    assert r.record[0] > r.record[2], r.summary()


def test_full_team_outscores_the_ball_chasing_team(results):
    r = results["chaser"]
    assert not r.forfeits, r.forfeits
    assert r.goals[0] > r.goals[1], r.summary()
    assert r.record[0] > r.record[2], r.summary()


def test_communicating_team_is_not_worse_than_the_silent_one(results):
    r = results["silent"]
    assert not r.forfeits, r.forfeits
    assert r.goals[0] >= r.goals[1], r.summary()


def test_head_to_head_alternates_sides_and_is_deterministic():
    short = MatchOptions(field="mj7v7", team_size=3, half_time_s=5.0, halves=1)
    a = head_to_head("chaser", "static", 2, short, jobs=1)
    b = head_to_head("chaser", "static", 2, short, jobs=2)
    assert a == b
    assert a.seeds == (0, 1) and len(a.scores) == 2
