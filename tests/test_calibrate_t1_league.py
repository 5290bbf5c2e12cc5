"""benchmarks/calibrate_t1_league.py turns walk, kick and get-up measurements into a t1_league
profile that the loader accepts (synthetic measurements: the script's arithmetic, not luck)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from locomotion.profile import load_profile
from tests.benchmark_scripts import load_benchmark

ROOT = Path(__file__).resolve().parents[1]
cal = load_benchmark("calibrate_t1_league")


def synthetic_walk() -> dict:
    """A walker that reaches 80 % of vx (capped at 1.2), 0.1 m/s sideways only to the right,
    and 90 % of the turn; one fall at the fastest forward command."""
    axes = {}
    for axis, commands in cal.AXES.items():
        rows = []
        for c in commands:
            if axis == "vx":
                a = max(min(0.8 * c, 1.2), -0.5)
            elif axis == "vy":
                a = -0.1 if c < 0 else 0.02        # barely moves one way
            else:
                a = 0.9 * c
            rows.append({"command": c, "achieved": [a, a + 0.01, a - 0.01],
                         "falls": int(axis == "vx" and c == max(commands))})
        axes[axis] = rows
    return {"walker": "network", "trials": 3, "seconds": 5.0, "axes": axes}


def test_calibration_writes_a_profile_the_loader_accepts(tmp_path):
    rng = np.random.default_rng(0)
    travel = rng.normal(6.0, 1.5, 120).clip(0.5)
    error = rng.normal(0.0, 8.0, 120)
    kicks = tmp_path / "kicks.json"
    kicks.write_text(json.dumps({"rows": [
        {"kicked": True, "travel": float(t), "error_deg": float(e)}
        for t, e in zip(travel, error, strict=True)]
        + [{"kicked": False, "travel": 0.0, "error_deg": 0.0}]}))
    getup = tmp_path / "getup.json"
    getup.write_text(json.dumps([{"success": True, "time_to_up": 3.0},
                                 {"success": True, "time_to_up": 4.0},
                                 {"success": False, "time_to_up": None}]))
    profile = json.loads(cal.PROFILE.read_text())
    half = float(profile["parameters"]["kick_accuracy_half_angle"]["value"])
    params = cal.walk_parameters(synthetic_walk()) | cal.kick_parameters([kicks], half) | \
        cal.getup_parameters(getup)
    updated = cal.update_profile(profile, params, {"note": "synthetic"})
    path = tmp_path / "t1_league.json"
    path.write_text(json.dumps(updated))
    loaded = load_profile(path)            # tables increasing, envelopes consistent
    p = updated["parameters"]
    assert p["kick_distance_mean"]["value"] == pytest.approx(travel.mean(), abs=1e-3)
    assert p["kick_distance_std"]["value"] == pytest.approx(travel.std(ddof=1), abs=1e-3)
    assert p["kick_accuracy"]["value"] == pytest.approx(
        np.mean(np.abs(np.radians(error)) <= half), abs=1e-3)
    assert p["getup_duration"]["value"] == 3.5
    assert p["envelope_vx_forward"]["value"] == pytest.approx(1.2, abs=1e-9)  # medians
    assert p["envelope_turn"]["value"] == pytest.approx(1.8, abs=1e-9)
    vy = np.array(p["tracking_vy"]["value"])
    assert np.all(np.diff(vy[:, 1]) >= 0)  # made non-decreasing
    assert "replaces" in p["tracking_vx"]["note"] and p["tracking_vx"]["kind"] == "measured"
    assert loaded is not None and updated["measurements"]["league_client"]["note"] == "synthetic"


def test_no_successful_get_up_keeps_the_referee_rule(tmp_path):
    getup = tmp_path / "getup.json"
    getup.write_text(json.dumps([{"success": False, "time_to_up": None}] * 4))
    assert cal.getup_parameters(getup) == {}


def test_too_few_kicks_is_an_error(tmp_path):
    kicks = tmp_path / "kicks.json"
    kicks.write_text(json.dumps({"rows": [{"kicked": True, "travel": 5.0, "error_deg": 1.0}]}))
    with pytest.raises(SystemExit, match="need >= 2"):
        cal.kick_parameters([kicks], math.radians(10))


@pytest.mark.humanoid
def test_the_kick_reach_is_the_league_kicks_start_spot(monkeypatch):
    pytest.importorskip("mujoco")
    from teamenv.league import kick

    reach = cal.kick_reach_parameter()["kick_reach"]
    assert reach["kind"] == "derived" and "spot_x" in reach["source"]
    # the shipped t1_league profile carries it: a team asks to kick from where the kick starts
    shipped = json.loads(cal.PROFILE.read_text())["parameters"]["kick_reach"]["value"]
    assert shipped == reach["value"]
    assert shipped >= kick.LEAGUE_KICK.spot_x            # not nearer than the kick spot
    # one source: the spot moves, the reach moves with it
    monkeypatch.setattr(kick, "LEAGUE_KICK", kick.LEAGUE_KICK.with_(spot_x=0.6))
    assert cal.kick_reach_parameter()["kick_reach"]["value"] > reach["value"] + 0.1


def test_the_get_up_time_from_league_replays_counts_each_fall_until_the_robot_stood(
        tmp_path, monkeypatch):
    from types import SimpleNamespace

    import teamenv.replay
    from teamenv.league.replay import RECOVER_CYCLES

    down = np.zeros((1000, 2), bool)
    down[100:250, 0] = True              # 3 s down
    down[300:800, 1] = True              # 10 s: the referee stood it up
    down[990:, 0] = True                 # still down at the end: left out
    (tmp_path / "m1.npz").write_bytes(b"")
    monkeypatch.setattr(teamenv.replay, "load_replay", lambda path: SimpleNamespace(
        fallen=down, metadata={"cycle_s": 0.02}))
    assert RECOVER_CYCLES < 990 - 800
    entry = cal.getup_from_replays(cal.load_replays(tmp_path), tmp_path.name)["getup_duration"]
    assert entry["value"] == pytest.approx(6.5) and entry["kind"] == "measured"
    assert "2 falls" in entry["source"] and "1 still down" in entry["source"]


def test_a_run_without_the_walk_keeps_the_walk_measured_before():
    profile = {"parameters": {}, "measurements": {"league_client": {"walk": {"trials": 3}}}}
    updated = cal.update_profile(profile, {}, {"falls": {"falls": 7}})
    assert updated["measurements"]["league_client"] == {"walk": {"trials": 3},
                                                        "falls": {"falls": 7}}
    assert profile["measurements"]["league_client"] == {"walk": {"trials": 3}}   # not mutated


def test_the_kick_angle_is_the_largest_offset_whose_kicks_pass(tmp_path):
    ka = load_benchmark("league_kick_angle")
    counted = {0.0: 12, 0.25: 11, 0.5: 12, 0.75: 9, 1.0: 12}     # 1.0 passes, after a fail
    rows = [{"offset": o, "struck": k < n, "upright": True, "travel": 1.0, "approach_s": 2.0}
            for o, n in counted.items() for k in range(12)]
    summary = ka.summary(rows)
    assert summary["kick_max_angle"] == 0.5                      # 0.75: 9/12 < 85 %
    path = tmp_path / "angle.json"
    path.write_text(json.dumps({"summary": summary, "rows": rows}))
    params = cal.kick_angle_parameter(path)
    # a profile written before the parameter existed gets it
    profile = json.loads(cal.PROFILE.read_text())
    profile["parameters"].pop("kick_max_angle")
    updated = cal.update_profile(profile, params, {})
    out = tmp_path / "t1_league.json"
    out.write_text(json.dumps(updated))
    assert load_profile(out).kick_max_angle == 0.5
    assert "0.75: 9/12" in updated["parameters"]["kick_max_angle"]["source"]
    assert updated["parameters"]["kick_max_angle"]["note"].startswith("replaces 3.14")
