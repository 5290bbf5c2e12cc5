"""league-match without a server: options, team names, beam poses, the stand-in behaviour, and
the result stored in the tournament database (read back by the tournament code)."""

from __future__ import annotations

import math

import pytest

from teamenv.cli import main
from teamenv.errors import ConfigError
from teamenv.league.adapter import LeagueObservation
from teamenv.league.match import (
    LeagueMatchOptions,
    chase_ball,
    home_position,
    record_league_match,
    server_team_name,
)
from teamenv.league.perception import Polar
from teamenv.match import Goal, MatchResult
from teamenv.tournament import ResultStore
from teamenv.tournament.table import league_table


def test_options_are_checked():
    with pytest.raises(ConfigError, match="team_size 8 is not in 1..7"):
        LeagueMatchOptions(team_size=8)
    with pytest.raises(ConfigError, match="game_s 0"):
        LeagueMatchOptions(game_s=0)
    with pytest.raises(ConfigError, match="kick_off 'Up'"):
        LeagueMatchOptions(kick_off="Up")
    assert LeagueMatchOptions().match_options().field == "mj7v7"


def test_cli_reports_bad_options(capsys):
    assert main(["league-match", "a", "b", "--team-size", "9", "--no-progress"]) != 0
    assert "team_size 9" in capsys.readouterr().err


def test_server_team_names_are_legal_and_distinct():
    assert server_team_name("chaser:all_chase=true") == "chaser_all_chase"
    assert server_team_name("chaser", "chaser") == "chaser_R"


def test_home_positions_are_in_the_own_half_and_distinct():
    poses = [home_position(u) for u in range(1, 8)]
    assert all(x < 0 for x, _, _ in poses) and len(set(poses)) == 7


def test_chase_ball_walks_to_a_seen_ball_and_searches_otherwise():
    mem: dict = {}
    seen = LeagueObservation(1.0, "PlayOn", 0, 0, True, ball=Polar(3.0, 0.2, -0.3))
    r = chase_ball(seen, mem)
    assert r.walk[0] > 0.25 and r.walk[2] > 0
    assert chase_ball(LeagueObservation(1.5, "PlayOn", 0, 0, False), mem).walk == r.walk
    lost = chase_ball(LeagueObservation(2.5, "PlayOn", 0, 0, False), mem)
    assert lost.walk[0] == 0 and lost.walk[2] != 0
    behind = chase_ball(LeagueObservation(3.0, "PlayOn", 0, 0, True, ball=Polar(2, math.pi, 0)), {})
    assert behind.walk[0] == 0


def test_result_is_stored_in_the_tournament_format(tmp_path):
    db = tmp_path / "league.sqlite"
    opts = LeagueMatchOptions(team_size=2, game_s=5.0)
    result = MatchResult(seed=0, left="chaser", right="static", score=(1, 0),
                         goals=(Goal(3.2, "left", None, None),), cycles=250, wall_s=40.0,
                         options=opts.match_options())
    record_league_match(db, "lm", result, opts)
    with ResultStore(db) as store:
        tid, tournament = store.get_tournament("lm")
        (rec,) = store.matches(tid)
    assert (rec.left_team, rec.right_team, rec.left_score, rec.right_score) == ("chaser", "static", 1, 0)
    assert tournament.options.field == "mj7v7" and tournament.options.team_size == 2
    table = league_table([rec])
    assert table[0].team == "chaser" and table[0].points == 3
