"""The league's reference walking network as a controller: the numpy forward pass is torch's,
the observation is the reference client's layout (radians, training signs, nominal offsets),
and on the server's physics it walks fast and turns without falling."""

from __future__ import annotations

import math

import numpy as np
import pytest

from teamenv.league.errors import LeagueError
from teamenv.league.network_walk import (
    NETWORK_ENVELOPE,
    NETWORK_MOTORS,
    NOMINAL_POSE,
    TRAINING_SIGN,
    NetworkWalkController,
    WalkNetwork,
    observation,
)
from teamenv.league.perception import parse_perception
from teamenv.league.t1 import joint_sensor


@pytest.mark.rl
def test_numpy_forward_pass_equals_torch() -> None:
    """float64 through portable_math against torch's float32 layers on the same weights."""
    torch = pytest.importorskip("torch")
    F = torch.nn.functional
    net = WalkNetwork.load()

    def t(a: np.ndarray):
        return torch.from_numpy(np.ascontiguousarray(a, dtype=np.float32))

    def reference(x):   # torch's own layers on the same weights (Linear takes (out, in))
        h = F.elu(F.layer_norm(F.linear(x, t(net.w1.T), t(net.b1)), (512,), t(net.ln_gain),
                               t(net.ln_bias), eps=1e-6))
        h = F.elu(F.linear(h, t(net.w2.T), t(net.b2)))
        h = F.elu(F.linear(h, t(net.w3.T), t(net.b3)))
        return torch.clip(F.linear(h, t(net.w4.T), t(net.b4)), -10.0, 10.0)

    rng = np.random.default_rng(7)
    x = np.concatenate([rng.normal(size=(32, 78)), 8 * rng.normal(size=(32, 78))]).astype(np.float32)
    want = reference(torch.from_numpy(x)).numpy()
    got = net(x)
    assert got.shape == (64, 23)
    assert np.abs(want).max() == 10.0                       # some outputs hit the clip
    np.testing.assert_allclose(got, want, atol=1e-4, rtol=1e-4)
    np.testing.assert_allclose(np.stack([net(row) for row in x]), want, atol=1e-4, rtol=1e-4)


def _wire(angles_deg: np.ndarray, rates_deg: np.ndarray, gyro_deg=(0.0, 0.0, 0.0),
          quat=(1.0, 0.0, 0.0, 0.0)) -> str:
    joints = "".join(f"(HJ (n {joint_sensor(m)})(ax {a:.4f})(vx {v:.4f}))"
                     for m, a, v in zip(NETWORK_MOTORS, angles_deg, rates_deg, strict=True))
    return ("(time (now 1.0))(GS (t 0.0)(pm PlayOn)(tl A)(tr B)(sl 0)(sr 0))"
            f"(quat (n torso_quat) (q {' '.join(map(str, quat))}))(pos (n torso_pos) (p 0 0 0.67))"
            f"(GYR (n torso_gyro) (rt {' '.join(map(str, gyro_deg))}))" + joints)


def test_observation_is_the_reference_layout_in_radians() -> None:
    n = len(NETWORK_MOTORS)
    angles = np.linspace(-60.0, 60.0, n)                 # degrees on the wire
    rates = np.linspace(300.0, -300.0, n)
    s = math.sqrt(0.5)                                   # the torso rolled 90 degrees about x
    p = parse_perception(_wire(angles, rates, gyro_deg=(573.0, -5730.0, 0.0), quat=(s, s, 0, 0)))
    previous = np.arange(n, dtype=float) - 11.0
    obs = observation(p, (0.7, -0.1, 1.2), previous)
    assert obs.shape == (78,)
    per_joint = obs[:3 * n].reshape(n, 3)
    np.testing.assert_allclose(per_joint[:, 0],
                               (np.radians(angles) * TRAINING_SIGN - NOMINAL_POSE) / 4.6, atol=1e-6)
    np.testing.assert_allclose(per_joint[:, 1], np.radians(rates) * TRAINING_SIGN / 110.0, atol=1e-6)
    np.testing.assert_allclose(per_joint[:, 2], previous / 10.0)
    # gyro in rad/s over 50, clipped to +-1 (10 rad/s -> 0.2; -100 rad/s -> -1)
    np.testing.assert_allclose(obs[69:72], [0.2, -1.0, 0.0], atol=1e-4)
    np.testing.assert_allclose(obs[72:75], [0.7, -0.1, 1.2])
    from scipy.spatial.transform import Rotation

    gravity = Rotation.from_quat([s, 0, 0, s]).inv().apply([0.0, 0.0, -1.0])  # (x, y, z, w)
    np.testing.assert_allclose(obs[75:78], gravity, atol=1e-9)
    np.testing.assert_allclose(gravity, [0.0, -1.0, 0.0], atol=1e-9)


def test_controller_sends_the_reference_targets_and_gains() -> None:
    n = len(NETWORK_MOTORS)
    p = parse_perception(_wire(np.zeros(n), np.zeros(n)))
    ctl = NetworkWalkController()
    msg = ctl.step((0.5, 0.0, 0.0), p)
    action = ctl.network(observation(p, (0.5, 0.0, 0.0), np.zeros(n)))
    want = np.degrees((NOMINAL_POSE + 0.5 * action) * TRAINING_SIGN)
    parts = msg.strip("()").split(")(")
    assert [part.split()[0] for part in parts] == list(NETWORK_MOTORS)
    for part, q in zip(parts, want, strict=True):
        _, target, dq, kp, kd, tau = part.split()
        assert float(target) == pytest.approx(q, abs=1e-3)
        assert (float(dq), float(kp), float(kd), float(tau)) == (0.0, 25.0, 0.6, 0.0)
    # the next observation carries this action; reset forgets it
    np.testing.assert_array_equal(ctl._previous_action, action)
    ctl.reset()
    assert not ctl._previous_action.any()


def test_envelope_and_bad_input() -> None:
    assert NETWORK_ENVELOPE.limit((3.0, 0.0, 0.0)) == pytest.approx((1.5, 0.0, 0.0))
    assert NETWORK_ENVELOPE.limit((0.0, 0.0, -4.0)) == pytest.approx((0.0, 0.0, -2.0))
    p = parse_perception(_wire(np.zeros(len(NETWORK_MOTORS)), np.zeros(len(NETWORK_MOTORS))))
    del p.joints["q_rlj6"]
    with pytest.raises(LeagueError, match="no joint 'q_rlj6'"):
        NetworkWalkController().stand(p)


def test_a_weights_file_without_a_layer_is_named(tmp_path) -> None:
    np.savez(tmp_path / "w.npz", fc1_weight=np.zeros((512, 78), np.float32))
    with pytest.raises(LeagueError, match="no array 'fc1_bias'"):
        WalkNetwork.load(tmp_path / "w.npz")


def _velocity(r, after_s: float) -> np.ndarray:
    from locomotion.humanoid.envelope import achieved_velocity

    return achieved_velocity(r.times, r.poses, after_s)


@pytest.mark.humanoid
@pytest.mark.parametrize("command, start, check", [
    # forward: a team asking for 3 m/s gets the envelope's 1.5 (about 1.2 m/s achieved)
    ((3.0, 0.0, 0.0), (-14.0, 5.0, 0.3), lambda v: v[0] > 0.9),
    ((0.0, 0.0, -1.5), (-9.0, -4.0, 2.5), lambda v: v[2] < -1.0),
])
def test_the_network_walks_fast_and_turns_on_local_server(command, start, check) -> None:
    pytest.importorskip("rcsssmj")
    pytest.importorskip("mujoco")
    from teamenv.league.walk_trial import walk_trial

    r = walk_trial(NetworkWalkController(), lambda t: command, 3.5, stand_s=0.6, start=start)
    assert not r.fell and r.upright_s == 3.5
    v = _velocity(r, 1.5)                 # the last 2 s, after the robot has sped up
    assert check(v), v


@pytest.mark.humanoid
def test_the_network_walks_on_the_real_server() -> None:
    pytest.importorskip("rcsssmj")
    pytest.importorskip("mujoco")
    from teamenv.league.walk_trial import walk_trial

    r = walk_trial(NetworkWalkController(), lambda t: (1.0, 0.0, 0.0), 3.0, stand_s=0.6,
                   start=(-10.0, 2.0, 0.0), real_server=True)
    assert not r.fell
    gained = r.poses[-1, :2] - r.poses[0, :2]
    assert gained[0] > 1.5 and abs(gained[1]) < 1.0, gained   # ~0.9 m/s for ~2.5 s


def test_elu_computes_expm1_only_where_kept_with_the_same_bits() -> None:
    """``_elu`` skips expm1 where x > 0: the values are those of the full ``where``."""
    import portable_math as pm
    from teamenv.league.network_walk import _elu

    rng = np.random.default_rng(0)
    x = rng.standard_normal(20000) * 10.0 ** rng.integers(-8, 3, 20000)
    x = np.concatenate([x, [0.0, -0.0, np.nan, np.inf, -np.inf, -800.0, 5e-324, -5e-324]])
    for shaped in (x, x[:14 * 1000].reshape(14, 1000)):
        full = np.where(shaped > 0, shaped, pm.expm1(np.minimum(shaped, 0.0)))
        assert _elu(shaped).tobytes() == full.tobytes()
    assert _elu(x).tobytes() != np.maximum(x, 0.0).tobytes()       # it does compute expm1
