"""benchmarks/fidelity_ranking.py on synthetic tournaments with known rankings."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from tests.benchmark_scripts import load_benchmark

fr = load_benchmark("fidelity_ranking")


def _round_robin(strength: dict[str, float], rounds: int, rng: np.random.Generator, noise=0.0):
    """Matches where the stronger team wins (ties when equal), flipped with prob. ``noise``."""
    teams = sorted(strength)
    out = []
    for _ in range(rounds):
        for i, a in enumerate(teams):
            for b in teams[i + 1:]:
                d = np.sign(strength[a] - strength[b])
                if rng.random() < noise:
                    d = -d
                la, rb = (1, 0) if d > 0 else (0, 1) if d < 0 else (0, 0)
                out.append(SimpleNamespace(left_team=a, right_team=b, left_official=la,
                                           right_official=rb))
    return out


STRENGTH = {"full": 4.0, "full_b": 3.0, "chaser": 2.0, "static": 1.0}


def test_points_per_match():
    recs = _round_robin({"a": 2, "b": 1, "c": 1}, 1, np.random.default_rng(0))
    assert fr.points_per_match(recs) == {"a": 3.0, "b": 0.5, "c": 0.5}


def test_identical_and_reversed_rankings():
    assert fr.rank_agreement({"a": 3, "b": 2, "c": 1}, {"a": 9, "b": 5, "c": 0}) == (1.0, 1.0)
    rho, tau = fr.rank_agreement({"a": 3, "b": 2, "c": 1}, {"a": 0, "b": 5, "c": 9})
    assert rho == pytest.approx(-1.0) and tau == pytest.approx(-1.0)
    assert all(math.isnan(x) for x in fr.rank_agreement({"a": 1, "b": 1}, {"a": 1, "b": 2}))


def test_bootstrap_agreement_same_world_is_high_and_reversed_is_low():
    rng = np.random.default_rng(1)
    a = _round_robin(STRENGTH, 6, rng, noise=0.1)
    b = _round_robin(STRENGTH, 6, rng, noise=0.1)
    rev = _round_robin({t: -s for t, s in STRENGTH.items()}, 6, rng, noise=0.1)
    same = fr.bootstrap_agreement(a, b, 150, np.random.default_rng(2))
    flipped = fr.bootstrap_agreement(a, rev, 150, np.random.default_rng(2))
    assert same.rho > 0.8 and same.rho_ci[0] <= same.rho <= same.rho_ci[1] and same.rho_ci[1] <= 1
    assert flipped.rho < -0.8 and flipped.tau_ci[1] < 0
    assert same.teams == 4 and same.usable > 120


def test_bootstrap_is_seeded_and_checks_input():
    rng = np.random.default_rng(3)
    a, b = _round_robin(STRENGTH, 3, rng, 0.2), _round_robin(STRENGTH, 3, rng, 0.2)
    one = fr.bootstrap_agreement(a, b, 100, np.random.default_rng(7))
    two = fr.bootstrap_agreement(a, b, 100, np.random.default_rng(7))
    assert one == two
    with pytest.raises(ValueError, match="n_boot"):
        fr.bootstrap_agreement(a, b, 0, np.random.default_rng(0))
    with pytest.raises(ValueError, match="at least one match"):
        fr.bootstrap_agreement([], b, 10, np.random.default_rng(0))


def test_goal_difference_ranks_what_points_cannot_split():
    recs = [SimpleNamespace(left_team="a", right_team="b", left_official=3, right_official=0),
            SimpleNamespace(left_team="b", right_team="c", left_official=1, right_official=0),
            SimpleNamespace(left_team="a", right_team="c", left_official=1, right_official=0)]
    assert fr.goal_diff_per_match(recs) == {"a": 2.0, "b": -1.0, "c": -1.0}
    with pytest.raises(ValueError, match="metric must be one of"):
        fr.bootstrap_agreement(recs, recs, 10, np.random.default_rng(0), metric="elo")
    agreement = fr.bootstrap_agreement(recs, recs, 50, np.random.default_rng(0),
                                       metric="goal_diff")
    assert agreement.rho == pytest.approx(1.0)


def test_world_stats_are_per_match_totals():
    def team(goals, kicks, attacking, middle, possession):
        return {"goals": goals, "kicks": kicks, "shots": 0, "xg": 0.1, "possession_pct": possession,
                "ball_progress_m": 1.0, "falls": 2, "distance_walked_m": 10.0,
                "third_pct": {"attacking": attacking, "middle": middle,
                              "defensive": 100 - attacking - middle}}
    stats = {1: {"left": team(1, 4, 30, 40, 60), "right": team(0, 2, 10, 40, 40)},
             2: {"left": team(0, 0, 0, 100, 50), "right": team(0, 2, 0, 100, 50)}}
    w = fr.world_stats(stats)
    assert w["matches"] == 2 and w["goals"] == 0.5 and w["kicks"] == 4.0
    assert w["falls"] == 4.0 and w["possession_pct"] == 50.0
    assert w["attacking_third_pct"] == 20.0 and w["middle_third_pct"] == 70.0
    assert fr.world_stats({}) == {}


def test_rankings_on_a_statistic_use_the_matches_that_have_it():
    recs = [SimpleNamespace(id=1, left_team="a", right_team="b", left_official=0, right_official=0),
            SimpleNamespace(id=2, left_team="b", right_team="a", left_official=0, right_official=0),
            SimpleNamespace(id=3, left_team="a", right_team="b", left_official=0, right_official=0)]
    stats = {1: {"left": {"xg": 0.5}, "right": {"xg": 0.1}},
             2: {"left": {"xg": 0.2}, "right": {"xg": 0.4}}}     # match 3 has none
    rows = fr.stat_records(recs, stats, "xg")
    assert len(rows) == 2
    assert fr.goal_diff_per_match(rows) == pytest.approx({"a": 0.3, "b": -0.3})
