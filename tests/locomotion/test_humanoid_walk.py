"""Humanoid extra: the LIPM walker walks the T1 in native MuJoCo, and the envelope measurement
turns short runs into a valid profile (CPU, a few seconds)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from locomotion import load_profile

pytestmark = pytest.mark.humanoid

pytest.importorskip("mujoco", reason="needs the humanoid extra: pip install -e '.[humanoid]'")
pytest.importorskip("rcsssmj")


@pytest.fixture(scope="module")
def t1():
    from locomotion.humanoid.t1 import load_t1

    return load_t1()


def test_walker_walks_forward(t1) -> None:
    from locomotion.humanoid.walker import walk_mujoco

    times, poses, fell = walk_mujoco(t1, lambda t, pose: (0.3, 0.0, 0.0), 3.0)
    assert not fell and times[-1] > 2.9
    assert poses[-1, 0] > 0.4  # ~0.6 m: 0.5 s weight shift, then 0.3 m/s after the slew
    assert abs(poses[-1, 1]) < 0.2 and abs(poses[-1, 2]) < 0.3


def test_walker_turns_and_walks_backward(t1) -> None:
    from locomotion.humanoid.walker import walk_mujoco

    _, poses, fell = walk_mujoco(t1, lambda t, pose: (0.0, 0.0, 0.5), 3.0)
    assert not fell and np.unwrap(poses[:, 2])[-1] > 0.6
    _, poses, fell = walk_mujoco(t1, lambda t, pose: (-0.2, 0.0, 0.0), 3.0)
    assert not fell and poses[-1, 0] < -0.2


def test_walker_stops_when_the_command_function_returns_none(t1) -> None:
    from locomotion.humanoid.walker import walk_mujoco

    times, _, fell = walk_mujoco(t1, lambda t, pose: None if t > 0.5 else (0, 0, 0), 3.0)
    assert not fell and times[-1] == pytest.approx(0.5, abs=0.02)


def test_achieved_velocity_is_body_frame() -> None:
    from locomotion.humanoid.envelope import achieved_velocity

    t = np.linspace(0, 4, 401)
    w, v = 0.5, 0.3  # circle: body-frame (0.3, 0, 0.5)
    yaw = w * t
    poses = np.stack([v / w * np.sin(yaw), v / w * (1 - np.cos(yaw)), yaw], axis=1)
    poses[:, 2] = (poses[:, 2] + math.pi) % (2 * math.pi) - math.pi  # wrapped, as measured
    np.testing.assert_allclose(achieved_velocity(t, poses, 1.0), [v, 0.0, w], atol=2e-3)


def test_envelope_measurement_writes_a_valid_profile(t1, tmp_path) -> None:
    from locomotion.humanoid.envelope import envelope_to_profile, measure_envelope
    from locomotion.humanoid.measure import base_profile, write_measured_profile

    cmds = [(0.3, 0.0, 0.0), (-0.2, 0.0, 0.0), (0.0, 0.1, 0.0), (0.0, 0.0, 0.5), (3.0, 0.0, 0.0)]
    env = measure_envelope(cmds, seconds=3.0, t1=t1)
    rows = {tuple(r["command"]): r for r in env["rows"]}
    assert rows[(3.0, 0.0, 0.0)]["fell"]  # far outside the envelope
    assert rows[(0.3, 0.0, 0.0)]["achieved"][0] > 0.2
    prof = envelope_to_profile(base_profile("t1_mj"), env, "pytest", name="t1_test")
    p = load_profile(write_measured_profile(prof, tmp_path / "t1_test.json"))
    assert p.name == "t1_test"
    for k in ("tracking_vx", "envelope_vx_forward", "envelope_turn", "step_period"):
        assert p.kinds[k] == "measured-humanoid" and "pytest" in p.sources[k]
    assert p.envelope_vx_forward == pytest.approx(rows[(0.3, 0.0, 0.0)]["achieved"][0], abs=1e-3)
    assert 3.0 not in p.tracking[0][0]  # the fallen command is not a tracking point
    assert p.tracking[2][0].min() < 0  # turning mirrored from the one measured side
    # falls and kicks stay those of the base profile
    assert p.push_fall_speed_forward == load_profile("t1_mj").push_fall_speed_forward


def test_shipped_lipm_profile_is_humanoid_measured() -> None:
    p = load_profile("t1_lipm")
    assert p.kinds["tracking_vx"] == "measured-humanoid"
    assert p.kinds["envelope_vx_forward"] == "measured-humanoid"
    t1_mj = load_profile("t1_mj")
    assert t1_mj.kinds["tracking_vx"] == "measured"  # the server's numbers stay in t1_mj


def test_walker_started_away_from_the_origin_walks_as_at_the_origin(t1) -> None:
    """Two bugs made the walker depend on where it stood: the preview law ran in world
    coordinates (its bias grows with the distance from (0, 0): reset at (-5, 0), where the
    league server beams a player, it fell within ~1 s), and the IK's first Jacobian after a
    reset came from the kinematic model's old place (8 m away it diverged at once). It now
    runs in the frame of the pose it was reset at, with the model moved there."""
    import dataclasses

    import mujoco

    from locomotion.humanoid.mujoco_sim import _pd, settle_mujoco
    from locomotion.humanoid.walker import LipmWalker, Observer, WalkParams, _gains

    params = WalkParams()

    def walk(x0: float) -> np.ndarray:
        q = t1.q_stance.copy()
        q[0] = x0
        t = _gains(dataclasses.replace(t1, q_stance=q), params)
        data = settle_mujoco(t, 0.3)
        walker, observe = LipmWalker(t, params), Observer(t)
        path = []
        for i in range(1000):  # 2 s at 2 ms
            if i % 5 == 0:
                obs = observe(data.qpos, data.qvel)
                if i == 0:
                    walker.reset(tuple(obs["pose"]))
                path.append(obs["pose"] - [x0, 0.0, 0.0])
                q_ref = walker.update(np.array([0.3, 0.0, 0.0]), obs)
            _pd(t, data, q_ref)
            mujoco.mj_step(t.model, data)
        return np.array(path)

    here, away = walk(0.0), walk(-12.0)
    assert away[-1, 0] > 0.2 and abs(away[-1, 1]) < 0.1  # walked forward, did not fall
    np.testing.assert_allclose(away, here, atol=2e-3)


def _zmp_ref_point_by_point(walker) -> np.ndarray:
    """The walker's ZMP reference as it was computed before it was vectorised."""
    p = walker.p
    out = np.empty((walker.n_prev, 2))
    ss = p.step_period - p.double_support
    land0 = walker._landing()
    for j in range(walker.n_prev):
        tau = walker.t_step + j * p.dt
        if tau < 0:  # initial stand: centre, then move onto the first support foot
            first_sup = walker._zmp_point(walker.plan[0][3])
            mid = 0.5 * (
                walker._zmp_point(walker.feet["Left"]) + walker._zmp_point(walker.feet["Right"])
            )
            a = min(max((tau + p.double_support) / p.double_support, 0.0), 1.0)
            out[j] = mid + a * (first_sup - mid)
            continue
        k = int(tau // p.step_period)
        r = tau - k * p.step_period
        if k >= len(walker.plan):
            k, r = len(walker.plan) - 1, ss
        sup = walker._zmp_point(walker.plan[k][3])
        if r < ss:
            out[j] = sup
        else:  # double support: towards the foot that just landed
            nxt = walker._zmp_point(land0 if k == 0 else walker.plan[k][2])
            out[j] = sup + (r - ss) / p.double_support * (nxt - sup)
    return out


def test_vectorised_zmp_reference_equals_the_point_by_point_one(t1) -> None:
    from locomotion.humanoid.walker import LipmWalker

    walker = LipmWalker(t1)
    walker.reset((-5.0, 2.0, 0.3))
    for k in range(300):  # the stand, then steps under changing commands
        command = (0.3, 0.1, 0.4) if k < 150 else (-0.2, 0.0, -0.5)
        walker.update(np.array(command))
        if k % 7 == 0:
            np.testing.assert_array_equal(walker._zmp_ref(), _zmp_ref_point_by_point(walker))
