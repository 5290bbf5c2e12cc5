"""Rating maths (Elo, Bradley–Terry, bootstrap) and the league table on hand-made results."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from teamenv.tournament.ratings import (
    ELO_MEAN,
    ELO_SCALE,
    Game,
    bootstrap_intervals,
    bradley_terry,
    compute_ratings,
    elo,
)
from teamenv.tournament.table import goal_difference_matrix, league_table, write_csv, write_json


@dataclass(frozen=True)
class Rec:
    left_team: str
    right_team: str
    left_official: int
    right_official: int
    forfeit_side: str | None = None
    forfeit_reason: str | None = None


def test_elo_by_hand():
    r = elo([Game("a", "b", 1.0)], ["a", "b"], k=20)
    assert r.tolist() == [1510.0, 1490.0]
    r = elo([Game("a", "b", 1.0), Game("a", "b", 0.0)], ["a", "b"], k=20)
    expected_b = 1.0 / (1.0 + 10 ** ((1510 - 1490) / 400))
    assert r[1] == pytest.approx(1490 + 20 * (1 - expected_b))
    assert r.sum() == pytest.approx(3000.0)  # Elo is zero-sum
    assert elo([Game("a", "b", 0.5)], ["a", "b"]).tolist() == [1500.0, 1500.0]


def test_bradley_terry_mle_by_hand():
    # a beats b 3 times out of 4: P = 3/4, so s_a - s_b = ln 3 logits.
    games = [Game("a", "b", 1.0)] * 2 + [Game("b", "a", 0.0), Game("b", "a", 1.0)]
    r = bradley_terry(games, ["a", "b"], prior_sigma=None)
    assert r[0] - r[1] == pytest.approx(math.log(3) * ELO_SCALE, abs=1e-3)
    assert r.mean() == pytest.approx(ELO_MEAN)


def test_bradley_terry_draws_are_half_wins_and_prior_keeps_unbeaten_finite():
    even = bradley_terry([Game("a", "b", 0.5)] * 4, ["a", "b"], prior_sigma=None)
    assert even[0] == pytest.approx(even[1], abs=1e-6)
    unbeaten = bradley_terry([Game("a", "b", 1.0)] * 10, ["a", "b"], prior_sigma=2.0)
    assert np.all(np.isfinite(unbeaten)) and unbeaten[0] > unbeaten[1]


def test_bradley_terry_orders_a_transitive_league():
    games = ([Game("a", "b", 1.0)] * 3 + [Game("a", "b", 0.0)] + [Game("b", "c", 1.0)] * 3 +
             [Game("b", "c", 0.0)] + [Game("a", "c", 1.0)] * 3 + [Game("a", "c", 0.5)])
    r = bradley_terry(games, ["a", "b", "c"], prior_sigma=None)
    assert r[0] > r[1] > r[2]


def test_weights_equal_repeated_games():
    games = [Game("a", "b", 1.0), Game("b", "c", 0.5), Game("c", "a", 0.0)]
    weighted = bradley_terry(games, list("abc"), weights=np.array([3, 1, 2]))
    repeated = bradley_terry([games[0]] * 3 + [games[1]] + [games[2]] * 2, list("abc"))
    np.testing.assert_allclose(weighted, repeated, atol=1e-4)


def test_bootstrap_interval_contains_estimate_and_shrinks_with_data():
    rng = np.random.default_rng(0)
    few = [Game("a", "b", 1.0)] * 3 + [Game("a", "b", 0.0)] * 2
    many = few * 20
    lo1, hi1 = bootstrap_intervals(few, ["a", "b"], bradley_terry, 200, rng, weighted=True)
    lo2, hi2 = bootstrap_intervals(many, ["a", "b"], bradley_terry, 200, rng, weighted=True)
    point = bradley_terry(many, ["a", "b"])
    assert np.all(lo2 <= point + 1e-6) and np.all(point <= hi2 + 1e-6)
    assert (hi2 - lo2)[0] < (hi1 - lo1)[0]


def test_compute_ratings_is_seeded_and_ordered():
    recs = [Rec("a", "b", 2, 0), Rec("b", "a", 0, 1), Rec("b", "c", 1, 1), Rec("c", "a", 0, 3)]
    r1 = compute_ratings(recs, ["a", "b", "c"], n_bootstrap=50, seed=3)
    r2 = compute_ratings(recs, ["a", "b", "c"], n_bootstrap=50, seed=3)
    assert r1 == r2
    assert list(r1.bradley_terry)[0] == "a"
    for table in (r1.elo, r1.bradley_terry):
        for rating in table.values():
            assert rating.low <= rating.rating + 1e-6 and rating.rating <= rating.high + 1e-6


def test_league_table_by_hand(tmp_path):
    recs = [Rec("a", "b", 2, 0), Rec("b", "a", 1, 1), Rec("c", "a", 0, 3, "left", "raised"),
            Rec("b", "c", 0, 1)]
    rows = {r.team: r for r in league_table(recs, ["a", "b", "c", "d"])}
    a, b, c, d = rows["a"], rows["b"], rows["c"], rows["d"]
    assert (a.played, a.won, a.drawn, a.lost, a.goals_for, a.goals_against, a.points) == \
        (3, 2, 1, 0, 6, 1, 7)
    assert (b.won, b.drawn, b.lost, b.goal_difference, b.points) == (0, 1, 2, -3, 1)
    assert (c.won, c.lost, c.forfeits, c.forfeit_reasons) == (1, 1, 1, {"raised": 1})
    assert d.played == 0 and d.rank == 4
    assert [r.team for r in league_table(recs)] == ["a", "c", "b"]
    m = goal_difference_matrix(recs, ["a", "b", "c", "d"])
    assert m[0, 1] == pytest.approx(1.0) and m[1, 0] == pytest.approx(-1.0)
    assert m[0, 2] == pytest.approx(3.0) and np.isnan(m[0, 3])
    ratings = compute_ratings(recs, ["a", "b", "c", "d"], n_bootstrap=20)
    text = write_csv(league_table(recs), tmp_path / "t.csv", ratings).read_text()
    assert text.splitlines()[0].startswith("rank,team,played")
    assert write_json(league_table(recs), tmp_path / "t.json", ratings).exists()
