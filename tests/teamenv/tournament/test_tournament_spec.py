"""Team spec parsing, override values, and validation before anything runs."""

from __future__ import annotations

import pytest

from teamenv.errors import TeamLoadError
from teamenv.match import MatchOptions
from teamenv.tournament import (
    TeamSpec,
    TeamSpecError,
    Tournament,
    TournamentConfigError,
    parse_team_spec,
    round_robin,
    run_tournament,
    validate_specs,
)
from teamenv.tournament.store import ResultStore

PICKY = "tests.teamenv.tournament_faulty_teams:PickyTeam"
SMALL = MatchOptions(team_size=2, half_time_s=2.0, halves=1)


@pytest.mark.parametrize("text, name, config", [
    ("chaser", "chaser", {}),
    ("chaser:all_chase=true", "chaser", {"all_chase": True}),
    ("formation:cfg=defensive", "formation", {"cfg": "defensive"}),
    ("pkg.mod:Cls", "pkg.mod:Cls", {}),
    ("pkg.mod:Cls:depth=0.4,n=3,flag=False,x=none", "pkg.mod:Cls",
     {"depth": 0.4, "n": 3, "flag": False, "x": None}),
    ("a:s='12',t=\"x y\"", "a", {"s": "12", "t": "x y"}),
    ("a:path=/tmp/a:b", "a", {"path": "/tmp/a:b"}),
    ("a:x=-1e-3,y=nan", "a", {"x": -0.001, "y": "nan"}),
])
def test_parse(text, name, config):
    spec = parse_team_spec(text)
    assert spec.name == name and spec.config_dict == config
    assert parse_team_spec(spec.label) == spec  # the label is canonical and round-trips


def test_label_is_canonical():
    assert parse_team_spec("a:y=2,x=1").label == parse_team_spec("a:x=1,y=2").label == "a:x=1,y=2"


@pytest.mark.parametrize("text, words", [
    ("", "expected"), ("chaser:a=1,a=2", "twice"), ("chaser:a=1,", "not 'key=value'"),
    (":a=1", "missing team name"), ("chaser:=3", "overrides must look like"),
    ("chaser:a=1,b", "'b' is not 'key=value'"),
])
def test_parse_errors(text, words):
    with pytest.raises(TeamSpecError, match=words):
        parse_team_spec(text)


def test_spec_of_rejects_non_scalars():
    with pytest.raises(TeamSpecError, match="must be a bool"):
        TeamSpec.of("chaser", {"x": [1, 2]})


@pytest.mark.parametrize("text, words", [
    ("nosuchteam", "unknown team 'nosuchteam'"),
    ("chaser:bogus=1", "bogus"),
    ("static:depth=7", "depth must be in"),
    ("no_such_module:Team", "cannot import module"),
    (f"{PICKY}:mode=c", "mode must be 'a' or 'b'"),
])
def test_validation_names_the_spec(text, words):
    with pytest.raises(TeamSpecError, match=words) as info:
        validate_specs([parse_team_spec(text)], SMALL)
    assert text in str(info.value) or parse_team_spec(text).label in str(info.value)
    assert isinstance(info.value, TeamLoadError)


def test_validation_accepts_good_overrides():
    versions = validate_specs([parse_team_spec(f"{PICKY}:mode=b,depth=0.3"),
                               parse_team_spec("chaser")], SMALL)
    assert set(versions) == {f"{PICKY}:depth=0.3,mode=b", "chaser"}


def test_bad_match_options():
    with pytest.raises(TournamentConfigError, match="moon"):
        validate_specs([], MatchOptions(field="moon"))
    with pytest.raises(TournamentConfigError, match="team_size"):
        validate_specs([], MatchOptions(team_size=40))


@pytest.mark.parametrize("kwargs, words", [
    (dict(teams=("chaser",)), "at least two"),
    (dict(teams=("chaser", "chaser")), "more than once"),
    (dict(teams=("chaser", "static"), games_per_pairing=0), "games_per_pairing"),
    (dict(teams=("chaser", "static"), format="swiss"), "format"),
    (dict(teams=("static",), format="gauntlet"), "challenger"),
    (dict(teams=("chaser", "static"), seed=-1), "seed"),
    (dict(teams=("chaser", "static"), options={"bogus": 1}), "bogus"),
])
def test_bad_definitions(kwargs, words):
    with pytest.raises(TournamentConfigError, match=words):
        Tournament(name="t", **kwargs)


def test_bad_spec_fails_before_anything_runs(tmp_path):
    db = tmp_path / "t.sqlite"
    t = round_robin("t", ["chaser", "static", "chaser:bogus=1"], games_per_pairing=1,
                    options=SMALL)
    with pytest.raises(TeamSpecError, match="chaser:bogus=1"):
        run_tournament(t, db, progress=False, jobs=1)
    with ResultStore(db) as store:
        assert store.tournament_names() == []  # nothing was created, nothing ran


def test_cli_bad_spec_exits_with_clear_error(tmp_path, capsys):
    from teamenv.cli import main

    code = main(["tournament", "run", "chaser", "nosuchteam", "--db", str(tmp_path / "t.sqlite"),
                 "--team-size", "2", "--half-time", "2", "--no-progress"])
    assert code == 2
    assert "unknown team 'nosuchteam'" in capsys.readouterr().err
