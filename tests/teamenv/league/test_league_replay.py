"""League matches on LocalServer: recorded as teamenv replays that the env's statistics read,
deterministic for a seed, and played in parallel by the league backend."""

from __future__ import annotations

import numpy as np
import pytest

pytestmark = pytest.mark.humanoid
pytest.importorskip("rcsssmj")
pytest.importorskip("mujoco")

from teamenv.errors import ConfigError  # noqa: E402
from teamenv.league.errors import LeagueError  # noqa: E402
from teamenv.league.match import (  # noqa: E402
    BEFORE_KICK_OFF_CYCLES,
    LeagueMatchOptions,
    play_league_match,
)

OPTS = LeagueMatchOptions(team_size=2, game_s=3.0, server="local")


def test_a_local_match_is_recorded_and_replays_bit_for_bit(tmp_path) -> None:
    from teamenv.analytics.stats import replay_stats
    from teamenv.replay import load_replay

    a, b = tmp_path / "a.npz", tmp_path / "b.npz"
    ra = play_league_match("chaser", "static", OPTS, seed=7, replay_path=a)
    rb = play_league_match("chaser", "static", OPTS, seed=7, replay_path=b)
    assert ra.score == rb.score and ra.cycles == rb.cycles == 150
    ea, eb = load_replay(a), load_replay(b)
    for name in ("ball", "players", "fallen", "play_mode", "touch_cycle", "kick_cycle"):
        np.testing.assert_array_equal(getattr(ea, name), getattr(eb, name))
    # one row per cycle from the beam on: BeforeKickOff, then the kick-off and play
    assert len(ea) == 150 + BEFORE_KICK_OFF_CYCLES and ea.players.shape == (len(ea), 4, 3)
    assert ea.play_mode[0] == 0 and ea.metadata["left"] == "chaser"
    assert ea.players[0, 0, 0] < 0 < ea.players[0, 2, 0]     # left team in its own half
    moved = np.hypot(*(ea.players[-1, :2, :2] - ea.players[0, :2, :2]).T)
    assert moved.max() > 0.5                                 # the chasers walked
    stats = replay_stats(a)                                  # the env's statistics read it
    assert stats.left.team == "chaser" and stats.left.distance_walked_m > 0.5
    assert stats.cycles == len(ea) - 1


def test_replays_need_the_local_server(tmp_path) -> None:
    with pytest.raises(ConfigError, match="a replay needs server='local'"):
        play_league_match("chaser", "static", LeagueMatchOptions(team_size=1, game_s=1.0),
                          replay_path=tmp_path / "x.npz")
    from teamenv.league.tournament import run_league_tournament

    with pytest.raises(LeagueError, match="league replays need server='local'"):
        run_league_tournament("rr", tmp_path / "x.sqlite", ["chaser", "static"],
                              LeagueMatchOptions(team_size=1, game_s=1.0),
                              replay_dir=tmp_path)


def test_league_round_robin_in_two_processes_with_statistics(tmp_path) -> None:
    from teamenv.league.tournament import run_league_tournament
    from teamenv.tournament import ResultStore

    db = tmp_path / "lt.sqlite"
    summary = run_league_tournament("rr", db, ["chaser", "static"],
                                    LeagueMatchOptions(team_size=1, game_s=2.0), server="local",
                                    workers=2, replay_dir=tmp_path / "replays")
    assert summary.played == 2
    with ResultStore(db) as store:
        tid, _ = store.get_tournament("rr")
        matches = store.matches(tid)
        stats = store.team_stats(tid)
    assert {(m.left_team, m.right_team) for m in matches} == {("chaser", "static"),
                                                             ("static", "chaser")}
    assert len(stats) == 2 and all(s["left"]["distance_walked_m"] >= 0 for s in stats.values())


def test_a_robot_flickering_across_the_fall_test_falls_once() -> None:
    from teamenv.league.replay import latch_falls

    down = np.zeros((80, 2), bool)
    down[10:13, 0] = down[14, 0] = down[16:18, 0] = True   # lying half on its side
    down[10:12, 1] = down[60:62, 1] = True                   # two real falls, 48 cycles apart
    fallen = latch_falls(down, recover=25)
    falls = (np.diff(fallen.astype(np.int8), axis=0) == 1).sum(axis=0)
    assert falls.tolist() == [1, 2]
    assert fallen[17 + 24, 0] and not fallen[17 + 25, 0]     # up again after 25 cycles up
