"""play_match, forfeits, replays and the `teamenv match` command."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from teamenv.errors import TeamLoadError
from teamenv.match import MatchOptions, play_match
from teamenv.replay import load_replay

SHORT = MatchOptions(team_size=3, half_time_s=10.0)
ROOT = Path(__file__).resolve().parents[2]


def test_match_is_deterministic_and_complete():
    a = play_match("chaser", "static", seed=4, options=SHORT)
    b = play_match("chaser", "static", seed=4, options=SHORT)
    assert a.score == b.score and a.goals == b.goals and a.cycles == b.cycles
    assert a.forfeit is None
    assert a.cycles >= 2 * 10.0 / 0.02  # both halves were played
    assert a.team_versions[0].startswith("teamenv")


def test_chaser_beats_static_over_seeds():
    goals = np.array([play_match("chaser", "static", seed=s, options=MatchOptions(
        team_size=3, half_time_s=30.0)).score for s in range(3)])
    assert goals[:, 0].sum() > goals[:, 1].sum()


@pytest.mark.parametrize("team,reason", [
    ("tests.teamenv.faulty_teams:RaisingTeam", "raised"),
    ("tests.teamenv.faulty_teams:InvalidTeam", "invalid_action"),
])
def test_faulty_team_forfeits(team, reason):
    result = play_match("static", team, seed=0, options=SHORT)
    assert result.forfeit is not None
    assert result.forfeit.side == "right" and result.forfeit.reason == reason
    assert result.official_score == (3, 0)


def test_slow_team_forfeits():
    result = play_match("tests.teamenv.faulty_teams:SlowTeam", "static", seed=0, options=SHORT,
                        cycle_time_budget_s=0.01)
    assert result.forfeit.side == "left" and result.forfeit.reason == "too_slow"


def test_stalling_team_forfeits():
    result = play_match("static", "tests.teamenv.faulty_teams:StallingTeam", seed=0,
                        options=SHORT, stall_timeout_s=0.5)
    assert result.forfeit.side == "right" and result.forfeit.reason == "stalled"


def test_unknown_team_is_an_error_not_a_forfeit():
    with pytest.raises(TeamLoadError):
        play_match("nope", "static", seed=0, options=SHORT)


def test_replay_round_trip(tmp_path):
    path = tmp_path / "m.npz"
    result = play_match("chaser", "static", seed=1, options=SHORT, replay_path=path)
    replay = load_replay(path)
    assert len(replay) == result.cycles + 1
    assert replay.players.shape == (result.cycles + 1, 6, 3)
    assert tuple(replay.score[-1]) == result.score
    assert replay.metadata["seed"] == 1


def test_cli_match_prints_result_and_writes_gif(tmp_path):
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    gif = tmp_path / "m.gif"
    out = subprocess.run(
        [sys.executable, "-m", "teamenv", "match", "chaser", "static", "--team-size", "2",
         "--half-time", "3", "--gif", str(gif), "--gif-every", "20", "--json"],
        capture_output=True, text=True, env=env, cwd=ROOT, check=True)
    result = json.loads(out.stdout[: out.stdout.rindex("}") + 1])
    assert result["left"] == "chaser" and len(result["score"]) == 2
    assert gif.stat().st_size > 1000


def test_cli_bad_team_exits_2_with_message():
    out = subprocess.run([sys.executable, "-m", "teamenv", "match", "nope", "static"],
                         capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 2
    assert "unknown team 'nope'" in out.stderr
