"""benchmarks/league_fall_fit.py: the league's falls counted alone and near another robot, and
the command-jump fall model fitted to them (synthetic replays for the arithmetic; one short
real teamenv match per setting for the path that plays)."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from tests.benchmark_scripts import load_benchmark

ROOT = Path(__file__).resolve().parents[1]
fit_module = load_benchmark("league_fall_fit")
PROFILE = json.loads((ROOT / "locomotion" / "profiles" / "t1_league.json").read_text())


def synthetic_replay(left="full", right="chaser"):
    """4 robots, 60 s of play after 1 s before kick-off: robot 0 falls alone at 10 s, robot 1
    falls next to robot 2 at 20 s, robot 3 falls before kick-off (not counted)."""
    cycles = 3050
    fallen = np.zeros((cycles, 4), bool)
    fallen[500:700, 0] = True
    fallen[1000:1200, 1] = True
    fallen[10:40, 3] = True
    players = np.zeros((cycles, 4, 3))
    players[:, :, 0] = [[-10.0, 0.0, 0.5, 10.0]]
    play_mode = np.ones(cycles, np.int8)
    play_mode[:50] = 0
    return SimpleNamespace(fallen=fallen, players=players, play_mode=play_mode,
                           metadata={"cycle_s": 0.02, "left": left, "right": right,
                                     "team_size": 2})


def test_falls_are_counted_alone_and_near_during_play_per_robot_minute():
    rates = fit_module.fall_rates([synthetic_replay()])
    assert rates["falls_alone"] == 1 and rates["falls_near"] == 1
    assert rates["robot_minutes"] == pytest.approx(4.0)            # 4 robots x 60 s
    assert rates["alone_per_robot_minute"] == pytest.approx(0.25)
    left, right = (fit_module.fall_rates([synthetic_replay()], side=k) for k in (0, 1))
    assert (left["falls_alone"], left["falls_near"], right["falls_near"]) == (1, 1, 0)
    assert left["robot_minutes"] == right["robot_minutes"] == pytest.approx(2.0)
    stats = load_benchmark("calibrate_t1_league").fall_statistics([synthetic_replay()],
                                                                   Path("/x/replays"))
    assert (stats["falls"], stats["falls_per_robot_minute"], stats["share_within_1_m"]) == (
        2, 0.5, 0.5) and stats["source"].endswith(" on replays")
    assert fit_module.pairings([synthetic_replay(), synthetic_replay("static", "full")]) == [
        ("full", "chaser"), ("static", "full")]


def test_the_fit_keeps_the_grid_point_nearest_the_league(monkeypatch):
    """teamenv's falls stand in as a function of the candidate profile's two numbers: the
    point that gives the league's rates wins, and both parameters say where they came from."""
    target = fit_module.fall_rates([synthetic_replay()])

    def play_rates(path, matches, seconds, team_size, seed0, folder):
        params = json.loads(Path(path).read_text())["parameters"]
        p = params["command_jump_fall_probability"]["value"]
        t = params["command_jump_threshold"]["value"]
        assert matches == [("full", "chaser")] and team_size == 2 and seconds == 30.0
        return {"alone_per_robot_minute": target["alone_per_robot_minute"] * p / 0.2,
                "near_per_robot_minute": target["near_per_robot_minute"] * 1.25 / t}

    monkeypatch.setattr(fit_module, "play_rates", play_rates)
    grid = ((1.0, 0.2), (1.25, 0.2), (1.25, 0.4), (1.5, 0.1))
    params, record = fit_module.fit(PROFILE, [synthetic_replay()], 30.0, grid, seed0=500)
    assert params["command_jump_threshold"]["value"] == 1.25
    assert params["command_jump_fall_probability"]["value"] == 0.2
    assert params["command_jump_threshold"]["kind"] == "derived"
    assert "tuning seeds 500-500" in params["command_jump_threshold"]["source"]
    assert [p["error"] for p in record["grid"]][1] == 0.0 and len(record["grid"]) == 4


def test_the_fit_refuses_replays_without_falls_and_evaluation_seeds():
    calm = synthetic_replay()
    calm.fallen[:] = False
    with pytest.raises(SystemExit, match="no falls"):
        fit_module.fit(PROFILE, [calm])
    with pytest.raises(SystemExit, match="must be tuning seeds"):
        fit_module.fit(PROFILE, [synthetic_replay()], seed0=100_200)


def test_teamenv_falls_more_with_a_likelier_command_jump_fall(tmp_path):
    """The path that plays: the same 1 v 1 league-format match under the profile with a
    command jump that never fells and one that always does (at any jump above 0.05)."""
    rates = []
    for probability in (0.0, 1.0):
        profile = json.loads(json.dumps(PROFILE))
        profile["parameters"]["command_jump_threshold"]["value"] = 0.05
        profile["parameters"]["command_jump_fall_probability"]["value"] = probability
        path = tmp_path / f"p{probability}.json"
        path.write_text(json.dumps(profile))
        rates.append(fit_module.play_rates(path, [("chaser", "chaser")], 6.0, 1, 41_000,
                                           tmp_path))
    never, always = rates
    assert never["falls_alone"] + never["falls_near"] < always["falls_alone"] + always["falls_near"]
    assert always["robot_minutes"] > 0 and not list(tmp_path.glob("*.npz"))


def test_the_calibration_command_fits_with_the_grid_it_is_given(tmp_path, monkeypatch):
    cal = load_benchmark("calibrate_t1_league")
    seen = {}

    def fit(profile, replays, seconds, grid, seed0, source):
        seen.update(grid=grid, seconds=seconds, seed0=seed0)
        entry = {"unit": "1", "kind": "derived", "source": cal.SCRIPT + " --fit-falls: a test"}
        return ({"command_jump_threshold": {"value": 1.25, **entry},
                 "command_jump_fall_probability": {"value": 0.2, **entry}}, {"grid": []})

    monkeypatch.setattr(cal.league_fall_fit, "fit", fit)
    monkeypatch.setattr(cal, "load_replays", lambda folder: [synthetic_replay()])
    out = tmp_path / "t1_league.json"
    assert cal.main(["--skip-walk", "--replays", str(tmp_path), "--fit-falls", "--fit-grid",
                     "1.0:0.1", "1.25:0.2", "--fit-seconds", "30", "--out", str(out)]) == 0
    assert seen == {"grid": ((1.0, 0.1), (1.25, 0.2)), "seconds": 30.0, "seed0": 41_000}
    written = json.loads(out.read_text())
    assert written["parameters"]["command_jump_fall_probability"]["value"] == 0.2
    assert "fall_fit" in written["measurements"]["league_client"]
    assert "the walk's falls fitted" in written["description"]
    with pytest.raises(SystemExit):
        cal.main(["--skip-walk", "--replays", str(tmp_path), "--fit-falls", "--fit-grid", "1.2",
                  "--dry-run"])
