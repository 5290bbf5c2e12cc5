"""Humanoid extra: a short real brax rollout of the league's T1 produces a valid measured profile."""

from __future__ import annotations

import json

import numpy as np
import pytest

from locomotion import load_profile

pytestmark = pytest.mark.humanoid

pytest.importorskip("brax", reason="needs the humanoid extra: pip install -e '.[humanoid]'")
pytest.importorskip("mujoco")
pytest.importorskip("rcsssmj")

SPEEDS = (0.0, 2.0)  # m/s forward: stands / clearly falls
SIM_S = 0.6
SETTLE_S = 0.1


@pytest.fixture(scope="module")
def t1():
    from locomotion.humanoid.t1 import load_t1

    return load_t1()


@pytest.fixture(scope="module")
def brax_grid(t1):
    from locomotion.humanoid.measure import measure_push_grid

    return measure_push_grid(
        "brax", SPEEDS, directions=("forward",), sim_s=SIM_S, settle_s=SETTLE_S, t1=t1
    )


def test_t1_comes_from_rcsssmj(t1) -> None:
    from locomotion.humanoid.t1 import t1_model_path

    assert t1_model_path().name == "robot.xml" and "rcsssmj" in str(t1_model_path())
    assert t1.model.nu == 23 and t1.model.njnt == 24  # 23 hinges (ankles included) + root
    assert t1.mass == pytest.approx(31.614, abs=0.01)
    assert t1.mass == pytest.approx(load_profile("t1_mj").mass, abs=0.01)


def test_brax_rollout_stands_and_falls(brax_grid) -> None:
    r = brax_grid["directions"]["forward"]
    assert r["min_height"][0] > 0.6  # unpushed: still standing under PD
    assert r["min_height"][1] < 0.3 and r["fall_time"][1] is not None  # 2 m/s push: on the ground


def test_brax_and_mujoco_agree_on_the_subset(t1, brax_grid) -> None:
    from locomotion.humanoid.measure import measure_push_grid

    mj = measure_push_grid(
        "mujoco", SPEEDS, directions=("forward",), sim_s=SIM_S, settle_s=SETTLE_S, t1=t1
    )
    b, m = brax_grid["directions"]["forward"], mj["directions"]["forward"]
    assert (np.array(b["min_height"]) < 0.35).tolist() == (
        np.array(m["min_height"]) < 0.35
    ).tolist()
    assert b["fall_time"][1] == pytest.approx(m["fall_time"][1], abs=0.1)


def test_measurement_writes_a_valid_profile(brax_grid, tmp_path) -> None:
    from locomotion.humanoid.measure import (
        analyse_push_grid,
        base_profile,
        fall_duration_from_grid,
        measurements_to_profile,
        write_measured_profile,
    )

    analysis = analyse_push_grid(brax_grid)
    assert analysis["forward"]["bracket"] == [0.0, 2.0]
    fall = fall_duration_from_grid(brax_grid, analysis)
    prof = measurements_to_profile(
        base_profile("t1_mj"), analysis, "brax", "pytest", fall, brax_grid
    )
    out = write_measured_profile(prof, tmp_path / "t1_measured.json")
    p = load_profile(out)
    assert p.push_fall_speed_forward == pytest.approx(1.0)
    assert p.kinds["push_fall_speed_forward"] == "measured-humanoid"
    assert "brax" in p.sources["push_fall_speed_forward"]
    assert p.fall_duration == pytest.approx(fall)
    # not measured in this run: kept from the shipped profile
    assert p.push_fall_speed_side == load_profile("t1_mj").push_fall_speed_side
    assert "forward" in json.loads(out.read_text())["measurements"]["humanoid_brax"]["analysis"]


def test_hand_entered_override_is_kept(brax_grid) -> None:
    from locomotion.humanoid.measure import analyse_push_grid, base_profile, measurements_to_profile

    base = base_profile("t1_mj")
    base["parameters"]["push_fall_speed_forward"] = {
        "value": 0.5,
        "unit": "m/s",
        "kind": "hand-entered",
        "source": "test",
        "note": "overrides measurement",
    }
    prof = measurements_to_profile(base, analyse_push_grid(brax_grid), "brax", "pytest")
    assert prof["parameters"]["push_fall_speed_forward"]["value"] == 0.5


def test_walker_steps_in_place_in_mujoco(t1) -> None:
    """The 3D-LIPM walker keeps the T1 up while stepping in place for 3 s."""
    from locomotion.humanoid.walker import walk_mujoco

    times, poses, fell = walk_mujoco(t1, lambda t, pose: (0.0, 0.0, 0.0), 3.0)
    assert not fell and times[-1] > 2.9
    assert np.hypot(*poses[-1, :2]) < 0.3
