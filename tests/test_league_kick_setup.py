"""The league kick's set-up time (``teamenv.league.replay.kick_setups``) on synthetic replays
whose set-ups are known, its summary, and ``kick_prep_time`` fitted to it by
``benchmarks/league_kick_setup_fit.py`` and ``calibrate_t1_league.py --fit-kick-setup``."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from teamenv.league.replay import kick_setup_summary, kick_setups
from tests.benchmark_scripts import load_benchmark

ROOT = Path(__file__).resolve().parents[1]
PROFILE = json.loads((ROOT / "locomotion" / "profiles" / "t1_league.json").read_text())
REACH = 0.49


def synthetic_replay(setup_s: float = 1.5, left: str = "full", right: str = "chaser"):
    """2 robots, 0.02 s cycles, the ball still at the origin, play from row 50 on.

    Robot 0 walks in along -x at 0.5 m/s from 3 m: it is within ``REACH`` from row 50 +
    (3 - 0.49) / 0.01 = 301 on, then steps back out for rows 320-329, is back within reach
    from row 330 (its last arrival) and kicks at row 330 + ``setup_s`` / 0.02; it stays there
    and kicks again 0.5 s later (a set-up from its previous kick). Robot 1 stands 0.3 m from
    the ball on the other side, is down in rows 900-949 and kicks at row 950 (left out:
    down), and robot 0 kicks at row 1000 from 3 m away (left out: out of reach)."""
    rows = 1200
    ball = np.zeros((rows, 4))
    players = np.zeros((rows, 2, 3))
    walk = np.clip(3.0 - 0.01 * (np.arange(rows) - 50), 0.4, 3.0)
    players[:, 0, 0] = -walk
    players[320:330, 0, 0] = -0.6
    players[:, 1, 0] = 0.3
    kick = 330 + round(setup_s / 0.02)
    players[kick + 40:, 0, 0] = -3.0
    fallen = np.zeros((rows, 2), bool)
    fallen[900:950, 1] = True
    play_mode = np.full(rows, 3, np.int8)
    play_mode[:50] = 0
    return SimpleNamespace(
        ball=ball, players=players, fallen=fallen, play_mode=play_mode,
        kick_cycle=np.array([kick, kick + 25, 950, 1000]), kick_player=np.array([0, 0, 1, 0]),
        metadata={"cycle_s": 0.02, "left": left, "right": right, "team_size": 1})


def test_the_set_up_runs_from_the_last_arrival_within_reach_to_the_kick():
    first, again, down, far = kick_setups(synthetic_replay(1.5), REACH)
    assert (first.start, first.why) == (330, "arrival")      # not 301: it left at 320
    assert first.seconds == pytest.approx(1.5)
    assert (again.start, again.why) == (first.row + 1, "previous kick")
    assert again.seconds == pytest.approx(24 * 0.02)
    assert (down.seconds, down.why) == (None, "down")
    assert (far.seconds, far.why) == (None, "out of reach")
    # a wider reach covers the step back out (0.6 m): the set-up is from the first arrival
    wide = kick_setups(synthetic_replay(1.5), 0.65)[0]
    assert wide.start < 301 and wide.seconds > 2.0


def test_the_set_up_stops_at_the_kick_off_and_a_fall_and_counts_a_rolling_ball():
    replay = synthetic_replay(1.0)
    replay.play_mode[360:365] = 0        # a stoppage inside the set-up: it starts after it
    assert kick_setups(replay, REACH)[0].start == 365
    replay = synthetic_replay(1.0)
    replay.fallen[340:345, 0] = True     # down for a moment: the set-up starts when it is up
    assert kick_setups(replay, REACH)[0].start == 345
    replay = synthetic_replay(1.0)       # robot 1 stands; the ball rolls to it and it kicks
    replay.ball[:, 0] = np.clip(5.0 - 0.02 * np.arange(1200), 0.0, None)
    replay.ball[:, 2] = np.where(replay.ball[:, 0] > 0, -1.0, 0.0)
    replay.kick_cycle, replay.kick_player = np.array([260]), np.array([1])
    (setup,) = kick_setups(replay, REACH)
    # the ball is within 0.49 m of robot 1 (x 0.3) from x = 0.79, row 211
    assert (setup.start, setup.why, setup.ball_speed) == (211, "arrival", 1.0)


def test_the_summary_counts_the_set_ups_and_the_kicks_left_out():
    setups = kick_setups(synthetic_replay(1.5), REACH) + kick_setups(synthetic_replay(0.5),
                                                                     REACH)
    summary = kick_setup_summary(setups)
    assert (summary["kicks"], summary["n"]) == (8, 4)
    assert summary["left_out"] == {"down": 2, "out of reach": 2}
    assert summary["began"] == {"arrival": 2, "previous kick": 2}
    assert summary["median_s"] == pytest.approx((0.48 + 0.5) / 2)
    assert summary["mean_s"] == pytest.approx((1.5 + 0.5 + 0.48 * 2) / 4)
    assert summary["max_s"] == pytest.approx(1.5) and summary["ball_moving"] == 0
    assert kick_setup_summary([])["n"] == 0


fit_module = load_benchmark("league_kick_setup_fit")


def teamenv_like(prep: float):
    """What teamenv gives under ``kick_prep_time`` = prep: the team asks 0.1 s after the
    arrival (set-up prep + 0.1 s)."""
    return [synthetic_replay(round(prep + 0.1, 2))]


def test_the_fit_finds_the_prep_time_that_gives_the_league_median(monkeypatch):
    league = [synthetic_replay(1.3)]      # league set-ups 1.3 and 0.48 s: median 0.89 s
    seen = []

    def play_profile(profile, matches, seconds, team_size, seed0, folder):
        seen.append((matches, seconds, team_size, seed0))
        return teamenv_like(profile["parameters"]["kick_prep_time"]["value"])

    monkeypatch.setattr(fit_module, "play_profile", play_profile)
    monkeypatch.setattr(fit_module, "per_match", lambda replays: {"matches": len(replays)})
    params, record = fit_module.fit(PROFILE, league, 30.0, grid=(0.2, 0.6, 1.0))
    # teamenv median (prep + 0.1 + 0.48) / 2 = 0.89 at prep = 1.2: beyond the grid's 1.0
    assert params["kick_prep_time"]["value"] == 1.0 and "nearest" in record["how"]
    params, record = fit_module.fit(PROFILE, league, 30.0, grid=(0.2, 1.0, 1.3))
    assert params["kick_prep_time"]["value"] == pytest.approx(1.2)
    assert "linear between 1 and 1.3" in record["how"]
    entry = params["kick_prep_time"]
    assert entry["kind"] == "measured" and entry["unit"] == "s"
    assert "2 kicks of 1 league matches" in entry["source"]
    assert seen[0] == ([("full", "chaser")], 30.0, 1, fit_module.SEED0)
    assert [p["kick_prep_time"] for p in record["grid"]] == [0.2, 1.0, 1.3]
    with pytest.raises(SystemExit, match="kick_duration"):
        fit_module.fit(PROFILE, league, grid=(0.5, 2.0))
    with pytest.raises(SystemExit, match="tuning seeds"):
        fit_module.fit(PROFILE, league, grid=(0.5,), seed0=100_200)


def test_crossing_interpolates_and_falls_back_to_the_nearest_point():
    assert fit_module.crossing([(0.5, 0.6), (1.0, 1.1)], 0.8)[0] == pytest.approx(0.7)
    assert fit_module.crossing([(0.5, 0.6), (1.0, 1.1)], 0.3)[0] == 0.5
    assert fit_module.crossing([(0.5, 0.6), (1.0, 1.1)], 2.0)[0] == 1.0


def test_the_calibration_command_writes_the_fitted_prep_time(tmp_path, monkeypatch):
    cal = load_benchmark("calibrate_t1_league")
    league = [synthetic_replay(1.3), synthetic_replay(1.3, "static", "full")]

    def play_profile(profile, matches, seconds, team_size, seed0, folder):
        assert matches == [("full", "chaser")] and seconds == 30.0    # --fit-matches 1
        return teamenv_like(profile["parameters"]["kick_prep_time"]["value"])

    monkeypatch.setattr(cal.league_kick_setup_fit, "play_profile", play_profile)
    monkeypatch.setattr(cal.league_kick_setup_fit, "per_match", lambda replays: {})
    monkeypatch.setattr(cal, "load_replays", lambda folder: league)
    out = tmp_path / "t1_league.json"
    assert cal.main(["--skip-walk", "--skip-getup", "--replays", str(tmp_path / "replays"),
                     "--fit-kick-setup", "--fit-prep-grid", "0.5", "1.3", "--fit-seconds",
                     "30", "--fit-matches", "1", "--out", str(out)]) == 0
    written = json.loads(out.read_text())
    entry = written["parameters"]["kick_prep_time"]
    assert entry["value"] == pytest.approx(1.2)
    assert entry["kind"] == "measured"
    assert entry["source"].startswith(cal.SCRIPT + " --fit-kick-setup")
    assert "4 kicks of 2 league matches in replays" in entry["source"]
    before = PROFILE["parameters"]["kick_prep_time"]
    assert entry["note"] == f"replaces {before['value']!r} ({before['kind']})"
    assert written["parameters"]["getup_duration"] == PROFILE["parameters"]["getup_duration"]
    assert "kick_setup_fit" in written["measurements"]["league_client"]
    assert "set-up time fitted" in written["description"]
    with pytest.raises(SystemExit):
        cal.main(["--skip-walk", "--fit-kick-setup", "--dry-run"])
