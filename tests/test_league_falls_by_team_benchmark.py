"""benchmarks/league_falls_by_team.py: falls per team and robot-minute from league replays."""

import json

import numpy as np
import pytest

from tests.benchmark_scripts import load_benchmark

by_team = load_benchmark("league_falls_by_team")


def write_replay(path, left, right, fallen, players):
    meta = {"left": left, "right": right, "team_size": 2, "cycle_s": 0.02}
    np.savez(path, fallen=fallen, players=players,
             metadata=np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8))


def test_falls_are_counted_per_team_and_robot_minute(tmp_path):
    rows = 3000  # 60 s of 20 ms cycles: each robot plays one minute
    players = np.zeros((rows, 4, 3), np.float32)
    players[:, :, 0] = [0.0, 10.0, 20.0, 20.5]  # players 2 and 3 stand 0.5 m apart
    fallen = np.zeros((rows, 4), bool)
    fallen[100:200, 0] = True  # the left team's first robot falls alone
    fallen[1000:1100, 0] = True  # and again, after standing long enough to count twice
    fallen[500:600, 3] = True  # a right-team robot falls beside another robot
    write_replay(tmp_path / "a.npz", "full", "chaser", fallen, players)
    write_replay(tmp_path / "b.npz", "chaser", "static", np.zeros((rows, 4), bool), players)
    table, matches = by_team.falls_by_team(tmp_path)
    assert matches == 2
    assert table["full"] == {"falls": 2, "robot_minutes": pytest.approx(2.0), "near": 0}
    assert table["chaser"] == {"falls": 1, "robot_minutes": pytest.approx(4.0), "near": 1}
    assert table["static"]["falls"] == 0


def test_an_empty_directory_is_a_clear_error(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr("sys.argv", ["league_falls_by_team.py", str(tmp_path)])
    with pytest.raises(SystemExit, match="no \\*.npz replay"):
        by_team.main()
