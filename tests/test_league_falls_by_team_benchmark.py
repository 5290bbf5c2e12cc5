"""benchmarks/league_falls_by_team.py: falls per team and robot-minute of play from replays."""

from types import SimpleNamespace

import numpy as np
import pytest

from tests.benchmark_scripts import load_benchmark

by_team = load_benchmark("league_falls_by_team")


def replay(left, right, fallen, players):
    play_mode = np.ones(len(fallen), np.int8)
    play_mode[:50] = 0  # 1 s before the kick-off: not play
    return SimpleNamespace(fallen=fallen, players=players, play_mode=play_mode,
                           metadata={"left": left, "right": right, "team_size": 2,
                                     "cycle_s": 0.02})


def test_falls_are_counted_per_team_and_robot_minute_of_play():
    rows = 3050  # 1 s before the kick-off, then 60 s of play: each robot plays one minute
    players = np.zeros((rows, 4, 3))
    players[:, :, 0] = [0.0, 10.0, 20.0, 20.5]  # players 2 and 3 stand 0.5 m apart
    fallen = np.zeros((rows, 4), bool)
    fallen[100:200, 0] = True  # the left team's first robot falls alone
    fallen[1000:1100, 0] = True  # and again, after standing long enough to count twice
    fallen[500:600, 3] = True  # a right-team robot falls beside another robot
    fallen[10:40, 1] = True  # before the kick-off: not counted
    table = by_team.falls_by_team([replay("full", "chaser", fallen, players),
                                   replay("chaser", "static", np.zeros((rows, 4), bool),
                                          players)])
    assert table["full"] == {"falls": 2, "near": 0, "robot_minutes": pytest.approx(2.0)}
    assert table["chaser"] == {"falls": 1, "near": 1, "robot_minutes": pytest.approx(4.0)}
    assert table["static"]["falls"] == 0


def test_an_empty_directory_is_a_clear_error(tmp_path, monkeypatch):
    monkeypatch.setattr("sys.argv", ["league_falls_by_team.py", str(tmp_path)])
    with pytest.raises(SystemExit, match="no \\*.npz replay"):
        by_team.main()
