"""The built-in teams are graded on evaluation seeds nobody tuned on (``teamenv.seeds``).

Full-length 7 v 7 matches (mj7v7 pitch, 2 x 300 s, sides alternating; ``teamenv.headtohead``)
against the ball chaser, shorter ones against the static team. The numbers in
docs/team_strength.md (20-40 matches per pairing, with confidence intervals) come from
``python benchmarks/strategy_strength.py`` on the same range; this test asserts the direction
on the first few of those seeds: the full team outscores the chaser and the static team.
"Not worse than its silent twin" in state mode is exact, not statistical: the two play the
same match cycle for cycle (tests/strategy/test_full_team.py).
"""

from __future__ import annotations

import pytest

from teamenv.headtohead import head_to_head
from teamenv.match import MatchOptions
from teamenv.seeds import EVALUATION_SEEDS, evaluation_seeds

FULL_LENGTH = MatchOptions(field="mj7v7", team_size=7, half_time_s=300.0)
SHORT = MatchOptions(field="mj7v7", team_size=7, half_time_s=60.0)
SEEDS = evaluation_seeds(4)


@pytest.fixture(scope="module")
def results():
    return {"chaser": head_to_head("full", "chaser", SEEDS, FULL_LENGTH, jobs=2),
            "static": head_to_head("full", "static", evaluation_seeds(6), SHORT, jobs=2)}


def test_strength_is_judged_on_evaluation_seeds(results):
    for r in results.values():
        assert all(s in EVALUATION_SEEDS for s in r.seeds), r.seeds


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


def test_head_to_head_alternates_sides_and_is_deterministic():
    short = MatchOptions(field="mj7v7", team_size=3, half_time_s=5.0, halves=1)
    a = head_to_head("chaser", "static", 2, short, jobs=1)
    b = head_to_head("chaser", "static", 2, short, jobs=2)
    assert a == b
    assert a.seeds == (0, 1) and len(a.scores) == 2
