"""league-match: options, team names, start poses, the team plugins built and seeded as the
env builds them, their actions turned into effectors (errors name the team and agent), the
result stored in the tournament database; and chaser v static played on the real server."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import teamenv
from teamenv.cli import main
from teamenv.errors import ConfigError, TeamFault, TeamLoadError
from teamenv.league.adapter import RequestEncoder
from teamenv.league.errors import LeagueError
from teamenv.league.match import (
    BEFORE_KICK_OFF_CYCLES,
    LOCOMOTION_PROFILE,
    LeagueMatchOptions,
    check_league_record,
    make_side,
    play_league_match,
    record_league_match,
    server_team_name,
    start_poses,
    team_context,
    team_seeds,
)
from teamenv.league.perception import parse_perception
from teamenv.match import Goal, MatchResult
from teamenv.tournament import ResultStore
from teamenv.tournament.table import league_table
from tests.teamenv.league.recorders import RecordingController
from tests.teamenv.league_teams import ScriptedTeam

DATA = Path(__file__).resolve().parents[1] / "league_data"
SCRIPTED = "tests.teamenv.league_teams:ScriptedTeam"
RAISING = "tests.teamenv.league_teams:RaisingTeam"


def test_options_are_checked():
    with pytest.raises(ConfigError, match=r"team_size must be in \[1, 7\], got 8"):
        LeagueMatchOptions(team_size=8)
    with pytest.raises(ConfigError, match="game_s must be > 0, got 0"):
        LeagueMatchOptions(game_s=0)
    with pytest.raises(ConfigError, match="kick_off must be one of .*, got 'Up'"):
        LeagueMatchOptions(kick_off="Up")
    assert LeagueMatchOptions().match_options().field == "mj7v7"


def test_cli_reports_bad_options(capsys):
    assert main(["league-match", "a", "b", "--team-size", "9", "--no-progress"]) != 0
    assert "team_size must be in [1, 7], got 9" in capsys.readouterr().err


def test_server_team_names_are_legal_and_distinct():
    assert server_team_name("chaser:all_chase=true") == "chaser_all_chase"
    assert server_team_name("chaser", "chaser") == "chaser_R"


def test_start_poses_are_the_envs():
    env = teamenv.parallel_env(field="mj7v7", team_size=3)
    env.reset(seed=0)
    world = env.sim.world.player_poses()
    assert np.allclose(start_poses(3), world[:3])                  # the left team: team frame
    right = world[3:].copy()                                        # the right team, turned by pi
    right[:, :2] *= -1
    right[:, 2] = np.remainder(right[:, 2] + np.pi, 2 * np.pi)
    assert np.allclose(start_poses(3), right, atol=1e-9)
    assert all(x < 0 for x, _, _ in start_poses(7))


def test_team_context_and_seeds_are_the_envs():
    ScriptedTeam.contexts.clear()
    # the env with the league bridge's body (its locomotion profile) and the league's
    # double-touch rule gives the same contexts
    env = teamenv.parallel_env(field="mj7v7", team_size=2, observation_mode="vision", vision="mj",
                               channel="mj", left=SCRIPTED, right=SCRIPTED,
                               locomotion_profile=LOCOMOTION_PROFILE,
                               rules={"double_touch": True})
    env.reset(seed=11)
    assert ScriptedTeam.contexts == [team_context("left", 2), team_context("right", 2)]
    assert env.teams["left"].seeds == [team_seeds(11)[0]]
    assert env.teams["right"].seeds == [team_seeds(11)[1]]
    side = make_side(SCRIPTED + ":x=1", "right", 2, seed=11, other=None)
    assert side.team.seeds == [team_seeds(11)[1]] and side.team.config == {"x": 1}
    assert side.team.context == team_context("right", 2)
    assert LeagueMatchOptions(team_size=2).match_options().vision == "mj"


def _side(spec, action, mode="PlayOn"):
    ScriptedTeam.ACTION = action
    side = make_side(spec, "left", 2, seed=0)
    ctl = RecordingController()
    side.encoders = {u: RequestEncoder(ctl, f"agent {side.server_name}_{u}")
                     for u in (1, 2)}
    p = parse_perception((DATA / "kick_off.txt").read_text().strip())
    p = dataclasses.replace(p, game=dataclasses.replace(p.game, play_mode=mode))
    return side, ctl, {1: p, 2: p}


def test_team_actions_become_effectors():
    seen = []
    side, ctl, percepts = _side(SCRIPTED, {"walk": [0.3, 0.0, 0.1], "say": "aGk="})
    out = side.act(percepts, on_act=lambda s, obs, acts: seen.append((s, sorted(obs), acts)))
    assert out[1] == "(walk)(SPK say 100 aGk=)" and ctl.commands[-1] == pytest.approx((0.3, 0, 0.1))
    assert seen[0][:2] == ("left", ["left_1", "left_2"])
    # the next cycle, a heard "aGk=" counts as a teammate's (agent 2 said it)
    assert "aGk=" in side.said[2]
    side, ctl, percepts = _side(SCRIPTED, {"kick": [1.0, 0.3]})
    side.act(percepts)
    assert ctl.commands[-1][0] > 0.3                     # a kick is a walk through the ball
    side, ctl, percepts = _side(SCRIPTED, {})
    assert side.act(percepts)[1] == "(stand)"             # no walk: stands
    beam = {"beam_request": 1, "beam": [-5.0, 1.0, 0.0]}
    side, ctl, percepts = _side(SCRIPTED, beam, mode="PlayOn")
    assert "beam" not in side.act(percepts)[1]           # refused outside BeforeKickOff / goals
    side, ctl, percepts = _side(SCRIPTED, beam, mode="BeforeKickOff")
    assert side.act(percepts)[1] == "(beam -5 1 0)(stand)"


def test_a_team_that_raises_or_returns_bad_actions_is_named():
    side, _, percepts = _side(RAISING, {})
    with pytest.raises(TeamFault, match=r"team 'tests.teamenv.league_teams:RaisingTeam' \(agents "
                       r"left_1, left_2\): act\(\) raised at game time 0.02 s: ValueError: no idea"):
        side.act(percepts)
    side, _, percepts = _side(SCRIPTED, {"walk": [float("nan"), 0, 0]})
    with pytest.raises(TeamFault, match=r"invalid_action: .*agent 'left_1': walk"):
        side.act(percepts)
    side, _, percepts = _side(SCRIPTED, {"say": "not base64!"})
    with pytest.raises(TeamFault, match="agent 'left_1'.*say"):
        side.act(percepts)
    with pytest.raises(TeamLoadError, match="unknown team 'nosuchteam'"):
        make_side("nosuchteam", "left", 1, seed=0)


def test_cli_names_a_missing_team_before_starting_a_server(capsys):
    assert main(["league-match", "nosuchteam", "static", "--team-size", "1", "--no-progress"]) == 2
    assert "unknown team 'nosuchteam'" in capsys.readouterr().err


@pytest.mark.humanoid
def test_chaser_against_static_on_the_real_server(tmp_path):
    """A 1 v 1 of the registered plugins on rcsssmj: both teams' act() gets observations of
    the env's vision layout every cycle, and the match is stored in the database."""
    pytest.importorskip("rcsssmj")
    pytest.importorskip("mujoco")
    env = teamenv.parallel_env(field="mj7v7", team_size=1, observation_mode="vision",
                               vision="mj", channel="mj")
    space = env.observation_space("left_1")
    calls = {"left": 0, "right": 0}
    fresh = {"left": 0, "right": 0}

    def check(side, observations, actions):
        assert sorted(observations) == [f"{side}_1"] and sorted(actions) == [f"{side}_1"]
        obs = observations[f"{side}_1"]
        assert set(obs) == set(space.spaces)
        assert all(obs[k].shape == space[k].shape for k in obs if k not in ("play_mode",
                                                                             "heard_text"))
        assert space.contains(obs), side
        calls[side] += 1
        fresh[side] += int(obs["vision"][0])

    db = tmp_path / "league.sqlite"
    opts = LeagueMatchOptions(team_size=1, game_s=1.0)
    result = play_league_match("chaser", "static", opts, seed=3, on_act=check)
    record_league_match(db, "lm", result, opts)
    # 10 cycles before the kick-off, then 1 s of play: both teams every cycle
    assert calls["left"] == calls["right"] >= BEFORE_KICK_OFF_CYCLES + 45
    assert fresh["left"] >= calls["left"] // 2 - 1           # a See every 2nd cycle
    assert result.cycles >= 45 and result.team_time_s[0] > 0
    with ResultStore(db) as store:
        tid, tournament = store.get_tournament("lm")
        (rec,) = store.matches(tid)
    assert (rec.left_team, rec.right_team) == ("chaser", "static")
    assert tournament.options.observation_mode == "vision" and tournament.options.vision == "mj"


def test_result_is_stored_in_the_tournament_format(tmp_path, capsys):
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
    # a second match under the same name is an error, before playing and when storing
    with pytest.raises(LeagueError, match="tournament 'lm' already holds its league match"):
        check_league_record(db, "lm")
    other = dataclasses.replace(result, left="full", seed=1)
    with pytest.raises(LeagueError, match="full v static was not stored"):
        record_league_match(db, "lm", other, opts)
    check_league_record(db, "another")
    with pytest.raises(LeagueError, match="a team against itself cannot be stored"):
        check_league_record(db, "another", "chaser", "chaser")
    check_league_record(tmp_path / "new.sqlite", "lm")
    assert main(["league-match", "static", "chaser", "--db", str(db), "--name", "lm",
                 "--no-progress"]) == 2
    assert "already holds its league match" in capsys.readouterr().err


@pytest.mark.humanoid
def test_a_team_that_raises_on_the_real_server_stops_everything(monkeypatch):
    pytest.importorskip("rcsssmj")
    pytest.importorskip("mujoco")
    from teamenv.league import match

    from .test_league_server import _wait_gone

    started = []

    class Server(match.LeagueServer):
        def __enter__(self):
            out = super().__enter__()
            started.append((self.pid, self.agent_port, self.monitor_port))
            return out

    monkeypatch.setattr(match, "LeagueServer", Server)
    with pytest.raises(TeamFault, match=r"team on the right side: raised: team "
                       r"'tests.teamenv.league_teams:RaisingTeam' \(agents right_1\): act\(\) "
                       r"raised at game time 0.00 s: ValueError: no idea"):
        play_league_match("static", RAISING, LeagueMatchOptions(team_size=1, game_s=1.0))
    (pid, *ports), = started
    assert _wait_gone(pid, *ports)
