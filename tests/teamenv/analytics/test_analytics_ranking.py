"""Rankings by goals / xG / composite / territory with intervals (stratified by opponent),
head to head, the separation rule, and a tournament
that stops a pairing once it is separated (a scripted backend: no matches are simulated)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from teamenv.analytics.ranking import (
    MatchMargins,
    head_to_head,
    match_margins,
    matches_to_separate,
    rank_teams,
    separated,
    separated_pairings,
    stratified_bootstrap_interval,
    t_interval,
    usable,
)
from teamenv.errors import ConfigError
from teamenv.match import MatchResult
from teamenv.tournament import round_robin
from teamenv.tournament.backends import Outcome
from teamenv.tournament.runner import run_tournament
from teamenv.tournament.store import ResultStore


def test_margins_and_composite():
    m = MatchMargins("a", "b", {"goals": (2, 1), "xg": (0.5, 1.5)})
    assert (m.margin("goals"), m.margin("xg"), m.margin("composite")) == (1.0, -1.0, 0.0)
    with pytest.raises(ConfigError, match="choose one of"):
        m.margin("points")
    with pytest.raises(ConfigError, match="has no 'xg' numbers"):
        MatchMargins("a", "b", {"goals": (1, 0)}).margin("xg")


def test_rank_teams_orders_and_bounds():
    games = [MatchMargins("a", "b", {"goals": (g, 0), "xg": (1.0 + 0.1 * g, 0.2)})
             for g in (0, 1, 2, 1)]
    ranks = rank_teams(games, "xg", ["a", "b", "c"], n_bootstrap=200, seed=1)
    assert [r.team for r in ranks] == ["a", "b", "c"]  # c never played: last, no interval
    assert ranks[2].matches == 0 and np.isnan(ranks[2].mean)
    a = ranks[0]
    assert a.mean == pytest.approx(np.mean([0.8, 0.9, 1.0, 0.9]))
    assert a.low <= a.mean <= a.high and a.matches == 4
    again = rank_teams(games, "xg", ["a", "b", "c"], n_bootstrap=200, seed=1)
    assert again == ranks  # seeded: same intervals


def test_interval_resamples_within_each_opponent():
    # b beats the weak c by ~10 every time and loses to a by ~1 every time: the schedule fixes
    # how many of each b plays, so b's interval holds only the small luck within each
    # pairing. A pooled bootstrap would let a resample hold mostly wins over c and span ~10.
    rng = np.random.default_rng(3)
    games = []
    for _ in range(6):
        games.append(MatchMargins("a", "b", {"goals": (1.0 + 0.1 * rng.standard_normal(), 0.0)}))
        games.append(MatchMargins("b", "c", {"goals": (10.0 + 0.1 * rng.standard_normal(), 0.0)}))
    ranks = {r.team: r for r in rank_teams(games, "goals", n_bootstrap=500, seed=0)}
    b = ranks["b"]
    assert b.mean == pytest.approx(4.5, abs=0.1)
    assert b.high - b.low < 0.3
    pooled = np.array([m.margin("goals") * (1 if m.a == "b" else -1) for m in games])
    pooled_means = pooled[np.random.default_rng(0).integers(0, 12, (500, 12))].mean(axis=1)
    assert np.ptp(np.percentile(pooled_means, [2.5, 97.5])) > 3.0
    # one group: an ordinary percentile bootstrap of the mean
    low, high = stratified_bootstrap_interval([np.array([1.0, 2.0, 3.0])], 400,
                                              np.random.default_rng(0))
    assert 1.0 <= low < 2.0 < high <= 3.0
    assert stratified_bootstrap_interval([np.array([5.0])], 100, np.random.default_rng(0)) \
        == (5.0, 5.0)


def test_head_to_head_orients_pairings_and_names_the_leader():
    games = [MatchMargins("full", "chaser", {"goals": (1, 0)}),
             MatchMargins("chaser", "full", {"goals": (0, 2)}),
             MatchMargins("full", "chaser", {"goals": (1, 0)}),
             MatchMargins("chaser", "full", {"goals": (0, 1)}),
             MatchMargins("chaser", "static", {"goals": (1, 0)}),
             MatchMargins("static", "chaser", {"goals": (1, 0)}),
             MatchMargins("chaser", "static", {"goals": (0, 0)})]
    pairs = head_to_head(games, "goals")
    assert [(p.a, p.b, p.matches) for p in pairs] == [("chaser", "full", 4),
                                                      ("chaser", "static", 3)]
    cf, cs = pairs
    assert cf.mean == pytest.approx(-5 / 4) and cf.separated and cf.leader() == "full"
    assert cs.mean == 0.0 and not cs.separated and cs.leader() is None


def test_territory_is_read_from_stored_statistics():
    @dataclass
    class Record:
        id: int
        left_team: str
        right_team: str
        left_official: int
        right_official: int

    records = [Record(1, "a", "b", 0, 0), Record(2, "b", "a", 1, 0)]
    stats = {1: {"left": {"xg": 0.1, "territory_m": 4.0}, "right": {"xg": 0.0, "territory_m": -4.0}},
             2: {"left": {"xg": 0.3}, "right": {"xg": 0.0}}}  # stored before territory existed
    margins = match_margins(records, stats)
    assert margins[0].margin("territory") == 8.0
    assert [m.a for m in usable(margins, "territory")] == ["a"]
    assert len(usable(margins, "xg")) == 2
    with pytest.raises(ConfigError, match="no stored match has territory"):
        usable(margins[1:], "territory")


def test_separation_rule():
    assert not separated([1.0, 2.0])  # too few matches
    assert separated([1.0, 2.0, 1.5])
    assert not separated([1.0, -1.0, 0.5, -0.5])
    mean, low, high = t_interval([1.0, 2.0, 3.0])
    assert (mean, round(low, 3), round(high, 3)) == (2.0, -0.484, 4.484)
    assert not separated([1.0, 2.0, 3.0]) and separated([1.0, 2.0, 3.0, 2.0, 2.0])
    assert matches_to_separate([0.0, 1.0, 2.0, 3.0, 2.0, 2.0, 2.0]) == 5
    assert matches_to_separate([1.0, -1.0, 1.0, -1.0]) is None


@dataclass
class _Record:
    id: int
    pairing: str
    swapped: bool
    left_team: str
    right_team: str
    left_official: int
    right_official: int


def test_separated_pairings_see_sides_swapped():
    # "a vs b": a wins by 1 each time, from either side
    recs = [_Record(k, "a vs b", k % 2 == 1, *(("b", "a", 0, 1) if k % 2 else ("a", "b", 1, 0)))
            for k in range(4)]
    recs += [_Record(10 + k, "a vs c", False, "a", "c", k % 2, (k + 1) % 2) for k in range(4)]
    assert separated_pairings(recs, {}, "goals") == {"a vs b"}
    assert separated_pairings(recs, {}, "xg") == set()  # no statistics stored


class _ScriptedBackend:
    """Plays nothing: the chaser wins every match 1-0, from either side."""

    name = "scripted"
    workers = 1

    def __init__(self):
        self.played = []

    def run(self, tasks):
        def outcomes():
            for task in tasks:
                self.played.append(task.index)
                score = (1, 0) if task.left.name == "chaser" else (0, 1)
                yield Outcome(task, MatchResult(task.seed, task.left.name, task.right.name,
                                                score, (), 10, 0.01))
        return outcomes()


def test_tournament_stops_a_separated_pairing(tmp_path):
    t = round_robin("stop", ["static", "chaser"], games_per_pairing=6)
    backend = _ScriptedBackend()
    db = tmp_path / "s.sqlite"
    summary = run_tournament(t, db, backend=backend, progress=False,
                             stop_when_separated="goals")
    # two matches a round; after round 2 four +1 margins separate the pair
    assert backend.played == [0, 1, 2, 3]
    assert summary.stored == 4 and not summary.complete
    assert summary.separated == ("static vs chaser",)
    assert "done (8 scheduled matches not needed" in summary.describe()
    assert "rerun with --resume" not in summary.describe()
    with ResultStore(db) as store:
        assert store.count_matches(summary.tournament_id) == 4
    # without the option, resume plays the rest
    rest = run_tournament(None, db, resume=True, backend=_ScriptedBackend(), progress=False)
    assert rest.complete and rest.played == 8
