"""Tests of Bodies.step: walk timing, envelope, acceleration, falls, get-up, kicks, determinism."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from locomotion import Bodies, StepInputError, load_profile
from locomotion.walk import compose, envelope_norm, omni_displacement

DT = 0.02


def _run(b: Bodies, cmd, cycles: int, rng=None, impacts=None, kick=None):
    """Step ``cycles`` times with a fixed command; return the list of results."""
    rng = rng if rng is not None else np.random.default_rng(0)
    n = b.n
    cmd = np.broadcast_to(np.asarray(cmd, dtype=float), (n, 3))
    z = np.zeros(n)
    out = []
    for i in range(cycles):
        req, power, aim = (np.zeros(n, bool), z, z) if kick is None else kick(i)
        imp = z if impacts is None else impacts(i)
        out.append(b.step(cmd, req, power, aim, imp, rng, DT))
    return out


def _pose(results, player: int = 0) -> np.ndarray:
    pose = np.zeros((1, 3))
    for r in results:
        pose = compose(pose, r.delta_pose[player : player + 1])
    return pose[0]


@pytest.fixture
def t1():
    return load_profile("t1_mj")


def test_contract_shapes(t1) -> None:
    b = Bodies(t1, 22)
    r = _run(b, [0.5, 0, 0], 1)[0]
    for f in ("delta_pose", "velocity", "odometry"):
        assert getattr(r, f).shape == (22, 3)
    for f in ("kick_now", "kick_distance", "kick_direction", "fallen", "can_act", "fell"):
        assert getattr(r, f).shape == (22,)
    assert r.kick_now.dtype == bool and r.fallen.dtype == bool and r.can_act.dtype == bool
    assert not r.fallen.any() and r.can_act.all()


def test_first_command_starts_at_once_and_reaches_steady_speed(t1) -> None:
    b = Bodies(t1, 1)
    res = _run(b, [1.0, 0, 0], 300)
    assert res[0].delta_pose[0, 0] > 0
    assert res[-1].velocity[0, 0] == pytest.approx(0.91)  # measured T1 tracking at 1.0


def test_command_changes_only_at_step_boundaries(t1) -> None:
    b = Bodies(t1, 1)
    rng = np.random.default_rng(0)
    z = np.zeros(1)
    k = int(round(t1.step_period / DT))  # 15 cycles per step
    vels = []
    for i in range(3 * k):
        cmd = np.array([[0.5 if i < k + 3 else 0.0, 0, 0]])
        vels.append(b.step(cmd, np.zeros(1, bool), z, z, z, rng, DT).velocity[0, 0])
    vels = np.array(vels)
    # boundaries at t = 0, T, 2T: the ends of cycles k-1, 2k-1 (velocity is reported at the end
    # of a cycle); the change commanded at cycle k+3 takes effect only at the boundary at 2T
    assert np.all(vels[: k - 1] == vels[0]) and np.all(vels[k - 1 : 2 * k - 1] == vels[k - 1])
    assert vels[k - 1] > vels[0]  # still accelerating towards 0.49 m/s
    assert vels[2 * k - 1] < vels[2 * k - 2]
    assert np.all(vels[2 * k - 1 : 3 * k - 1] == vels[2 * k - 1])


def test_boundary_inside_a_cycle_is_split_exactly(t1) -> None:
    b = Bodies(t1, 1)
    rng = np.random.default_rng(0)
    z = np.zeros(1)
    cmd = np.array([[0.3, 0.05, 0.4]])
    b.step(cmd, np.zeros(1, bool), z, z, z, rng, 0.02)
    v0 = b.velocity.copy()
    b.phase[:] = t1.step_period - 0.005  # boundary 5 ms into the next 20 ms cycle
    cmd2 = np.array([[0.6, 0.0, -0.2]])
    r = b.step(cmd2, np.zeros(1, bool), z, z, z, rng, 0.02)
    expected = compose(omni_displacement(v0, 0.005), omni_displacement(r.velocity, 0.015))
    np.testing.assert_allclose(r.delta_pose, expected, atol=1e-15)
    assert b.phase[0] == pytest.approx(0.015)


def test_acceleration_limited_per_step(t1) -> None:
    b = Bodies(t1, 1)
    res = _run(b, [1.5, 0, 0], 200)
    v = np.array([r.velocity[0, 0] for r in res])
    dv = np.diff(np.concatenate([[0.0], v]))
    assert np.max(dv) <= t1.accel[0] * t1.step_period + 1e-12
    assert v[-1] == pytest.approx(t1.envelope_vx_forward)


def test_envelope_respected_under_random_commands(t1) -> None:
    b = Bodies(t1, 22)
    rng = np.random.default_rng(5)
    z = np.zeros(22)
    env = (
        t1.envelope_vx_forward,
        t1.envelope_vx_backward,
        t1.envelope_vy,
        t1.envelope_turn,
        t1.envelope_exponent,
    )
    for _ in range(600):
        cmd = rng.uniform(t1.command_low, t1.command_high, size=(22, 3))
        r = b.step(cmd, np.zeros(22, bool), z, z, z, rng, DT)
        assert np.all(envelope_norm(r.velocity, *env) <= 1 + 1e-9)
        # the displacement over one cycle never beats the envelope either
        assert np.all(np.abs(r.delta_pose[:, 2]) <= t1.envelope_turn * DT + 1e-12)
        assert np.all(
            np.hypot(r.delta_pose[:, 0], r.delta_pose[:, 1]) <= t1.envelope_vx_forward * DT + 1e-12
        )


def test_straight_walk_distance_is_eq4(t1) -> None:
    b = Bodies(t1, 1)
    res = _run(b, [0.5, 0, 0.5], 750)  # 15 s, as the T1 measurement
    v = res[-1].velocity[0]
    # steady state equals the tracking curve inside the envelope
    np.testing.assert_allclose(v, [0.49, 0, 0.51])
    pose = _pose(res[-100:])
    np.testing.assert_allclose(pose, omni_displacement(v[None], 100 * DT)[0], atol=1e-12)


def test_determinism(t1) -> None:
    def trace(seed: int):
        b = Bodies(t1, 22)
        rng = np.random.default_rng(seed)
        crng = np.random.default_rng(99)
        out = []
        for _ in range(400):
            cmd = crng.uniform(t1.command_low, t1.command_high, size=(22, 3))
            req = crng.random(22) < 0.02
            imp = crng.exponential(8.0, 22)
            r = b.step(cmd, req, np.full(22, 0.8), crng.uniform(-1, 1, 22), imp, rng, DT)
            out.append(
                np.concatenate(
                    [
                        r.delta_pose.ravel(),
                        r.odometry.ravel(),
                        r.kick_distance,
                        r.kick_direction,
                        r.fallen,
                        r.can_act,
                    ]
                )
            )
        return np.array(out)

    a, b = trace(7), trace(7)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, trace(8))


def test_reset_restores_initial_state(t1) -> None:
    b = Bodies(t1, 3)
    _run(b, [1.0, 0.1, 0.5], 50, impacts=lambda i: np.full(3, 100.0))
    b.reset()
    assert not b.fallen.any() and b.can_act.all() and not b.velocity.any()


# ---------------------------------------------------------------- falls and get-up
def test_big_impact_falls_and_gets_up_on_time(t1) -> None:
    b = Bodies(t1, 2)
    big = t1.impact_fall_impulse_high + 1.0
    res = _run(
        b, [0.8, 0, 0], 400, impacts=lambda i: np.array([big, 0.0]) if i == 50 else np.zeros(2)
    )
    fallen = np.array([r.fallen[0] for r in res])
    down_cycles = int(round((t1.fall_duration + t1.getup_duration) / DT))
    assert not fallen[:50].any()
    assert (
        res[50].fell[0]
        and fallen[50 : 50 + down_cycles].all()
        and not fallen[50 + down_cycles :].any()
    )
    can_act = np.array([r.can_act[0] for r in res])
    assert np.array_equal(can_act, ~fallen)
    # no motion while down, even though walking is commanded; the other player never fell
    assert not np.any([r.delta_pose[0].any() for r in res[50 : 50 + down_cycles]])
    assert not any(r.fallen[1] for r in res)
    # after the get-up the first step starts at once (the next cycle), from standing
    assert not res[50 + down_cycles].delta_pose[0].any()
    after = res[50 + down_cycles + 1]
    assert 0 < after.velocity[0, 0] <= t1.accel[0] * t1.step_period + 1e-12


def test_small_impacts_never_fall_and_fall_probability_ramps(t1) -> None:
    n = 4000
    b = Bodies(t1, n)
    rng = np.random.default_rng(2)
    lo, hi = t1.impact_fall_impulse_low, t1.impact_fall_impulse_high
    imp = np.concatenate([np.full(1000, 0.99 * lo), np.full(3000, 0.5 * (lo + hi))])
    r = b.step(np.zeros((n, 3)), np.zeros(n, bool), np.zeros(n), np.zeros(n), imp, rng, DT)
    assert not r.fell[:1000].any()
    assert r.fell[1000:].mean() == pytest.approx(0.5, abs=0.04)


def test_push_thresholds_depend_on_direction(t1) -> None:
    b = Bodies(t1, 6)
    rng = np.random.default_rng(0)
    below, above = 0.95, 1.05
    f, bk, s = t1.push_fall_speed_forward, t1.push_fall_speed_backward, t1.push_fall_speed_side
    b.push(
        np.arange(6),
        np.array(
            [
                [below * f, 0],
                [above * f, 0],
                [-below * bk, 0],
                [-above * bk, 0],
                [0, below * s],
                [0, -above * s],
            ]
        ),
    )
    r = _run(b, [0, 0, 0], 1, rng=rng)[0]
    np.testing.assert_array_equal(r.fell, [False, True, False, True, False, True])
    assert b.push_threshold(np.array([0.0]))[0] == pytest.approx(f)
    assert b.push_threshold(np.array([np.pi / 2]))[0] == pytest.approx(s)


def test_over_fast_command_change_can_fall(t1) -> None:
    n = 2000
    b = Bodies(t1, n)
    rng = np.random.default_rng(4)
    z = np.zeros(n)
    nok = np.zeros(n, bool)
    for _ in range(200):
        b.step(np.tile([1.5, 0, 0], (n, 1)), nok, z, z, z, rng, DT)
    k = int(round(t1.step_period / DT))
    fell = np.zeros(n, bool)
    for _ in range(k):  # one step boundary with a full reversal demanded
        fell |= b.step(np.tile([-1.0, 0, 0], (n, 1)), nok, z, z, z, rng, DT).fell
    assert fell.mean() == pytest.approx(t1.command_jump_fall_probability, abs=0.03)
    # a gentle change never falls
    b2 = Bodies(t1, n)
    res = _run(b2, [0.5, 0.0, 0.3], 200, rng=rng)
    assert not any(r.fell.any() for r in res)


def test_fall_cancels_kick(t1) -> None:
    b = Bodies(t1, 1)
    big = np.array([t1.impact_fall_impulse_high + 1])
    res = _run(
        b,
        [0, 0, 0],
        100,
        kick=lambda i: (np.array([i == 0]), np.ones(1), np.zeros(1)),
        impacts=lambda i: big if i == 5 else np.zeros(1),
    )
    assert not any(r.kick_now[0] for r in res)


# ---------------------------------------------------------------- kicks
def test_kick_timing(t1) -> None:
    b = Bodies(t1, 2)
    res = _run(
        b,
        [0.6, 0, 0],
        200,
        kick=lambda i: (np.array([i >= 30, False]), np.array([1.0, 1.0]), np.zeros(2)),
    )
    now = np.array([r.kick_now[0] for r in res])
    prep = int(round(t1.kick_prep_time / DT))
    dur = int(round(t1.kick_duration / DT))
    assert np.flatnonzero(now).tolist() == [30 + prep, 30 + dur + prep]  # repeated request
    can = np.array([r.can_act[0] for r in res])
    assert not can[30 : 30 + dur - 1].any() and can[30 + dur - 1]
    # standing still while kicking; the other player keeps walking
    assert not np.any([r.delta_pose[0].any() for r in res[30 : 30 + dur - 1]])
    assert all(r.delta_pose[1, 0] > 0 for r in res[1:])
    assert not any(r.kick_now[1] for r in res)


def test_kick_requires_power(t1) -> None:
    b = Bodies(t1, 1)
    res = _run(b, [0, 0, 0], 100, kick=lambda i: (np.ones(1, bool), np.zeros(1), np.zeros(1)))
    assert not any(r.kick_now[0] or not r.can_act[0] for r in res)


def test_immediate_kick_with_zero_prep(t1) -> None:
    p = dataclasses.replace(t1, kick_prep_time=0.0)
    b = Bodies(p, 1)
    res = _run(b, [0, 0, 0], 3, kick=lambda i: (np.array([i == 0]), np.ones(1), np.zeros(1)))
    assert res[0].kick_now[0] and not res[1].kick_now[0]


def test_kick_spread_statistics(t1) -> None:
    n = 20000
    p = dataclasses.replace(t1, kick_prep_time=0.0)
    b = Bodies(p, n)
    rng = np.random.default_rng(11)
    aim = np.full(n, 0.3)
    r = b.step(np.zeros((n, 3)), np.ones(n, bool), np.ones(n), aim, np.zeros(n), rng, DT)
    assert r.kick_now.all()
    d = r.kick_distance
    assert d.min() >= t1.kick_distance_min and d.max() <= t1.kick_distance_max
    assert d.mean() == pytest.approx(t1.kick_distance_mean, abs=0.1)  # symmetric truncation
    # clipped (not resampled) at +-2 sigma, so the std stays close to Table 1's
    assert d.std() == pytest.approx(t1.kick_distance_std, rel=0.06)
    err = r.kick_direction - aim
    accurate = np.mean(np.abs(err) <= t1.kick_accuracy_half_angle)
    assert accurate == pytest.approx(0.645, abs=0.015)  # source 000 Table 1
    # half power: half the distance
    b2 = Bodies(p, n)
    r2 = b2.step(np.zeros((n, 3)), np.ones(n, bool), np.full(n, 0.5), aim, np.zeros(n), rng, DT)
    assert r2.kick_distance.mean() == pytest.approx(0.5 * t1.kick_distance_mean, abs=0.1)


# ---------------------------------------------------------------- odometry
def test_odometry_slip(t1) -> None:
    b = Bodies(t1, 500)
    res = _run(b, [0.8, 0.1, 0.4], 300)
    true = np.sum([r.delta_pose for r in res], axis=0)
    odo = np.sum([r.odometry for r in res], axis=0)
    ratio = odo.mean(axis=0) / true.mean(axis=0)
    np.testing.assert_allclose(ratio, t1.odometry_scale, rtol=0.01)
    assert np.std(odo[:, 0] / true[:, 0]) > 0


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("arg", "value", "pattern"),
    [
        ("walk_cmd", np.zeros((3, 2)), r"'walk_cmd'.*\(4, 3\)"),
        ("kick_request", np.zeros(3, bool), r"'kick_request'.*\(4,\)"),
        ("impacts", np.zeros((4, 1)), r"'impacts'"),
        ("dt", 0.0, r"'dt' = 0\.0"),
        ("dt", 1.0, r"'dt' = 1\.0.*step_period"),
    ],
)
def test_bad_step_input(t1, arg, value, pattern) -> None:
    b = Bodies(t1, 4)
    kw = dict(
        walk_cmd=np.zeros((4, 3)),
        kick_request=np.zeros(4, bool),
        kick_power=np.zeros(4),
        kick_dir=np.zeros(4),
        impacts=np.zeros(4),
        rng=np.random.default_rng(0),
        dt=DT,
    )
    kw[arg] = value
    with pytest.raises(StepInputError, match=pattern):
        b.step(**kw)


def test_bad_constructor(t1) -> None:
    with pytest.raises(StepInputError, match="n_players"):
        Bodies(t1, 0)
    with pytest.raises(StepInputError, match="profile"):
        Bodies("t1_mj", 3)  # type: ignore[arg-type]


def test_a_kick_aimed_beyond_kick_max_angle_does_not_start(t1) -> None:
    p = dataclasses.replace(t1, kick_prep_time=0.0, kick_max_angle=0.5)
    aims = np.array([0.3, -0.45, 1.0, -2.5, 2 * np.pi + 0.3])   # the last wraps to 0.3
    b = Bodies(p, len(aims))
    res = _run(b, [0, 0, 0], 2, kick=lambda i: (np.full(len(aims), i == 0),
                                                np.ones(len(aims)), aims))
    assert res[0].kick_now.tolist() == [True, True, False, False, True]
    # the omnidirectional default starts every aim
    b = Bodies(dataclasses.replace(t1, kick_prep_time=0.0), len(aims))
    res = _run(b, [0, 0, 0], 1, kick=lambda i: (np.ones(len(aims), bool),
                                                np.ones(len(aims)), aims))
    assert res[0].kick_now.all()


def _noisy_walk(bodies: Bodies, rng: np.random.Generator, cycles: int) -> list[bytes]:
    plan = np.random.default_rng(3)
    out = []
    for _ in range(cycles):
        n = bodies.n
        res = bodies.step(plan.uniform(-1.5, 1.5, (n, 3)), plan.random(n) < 0.1,
                          plan.random(n), plan.uniform(-3, 3, n),
                          np.where(plan.random(n) < 0.1, plan.uniform(0, 30, n), 0.0), rng)
        out.append(res.odometry.tobytes() + res.fell.tobytes() + res.kick_distance.tobytes())
    return out


@pytest.mark.parametrize("copier", ["deepcopy", "pickle"])
def test_a_copied_body_steps_on_as_the_original(copier) -> None:
    # a body pickled to a worker or deep-copied carries the compiled step's state (counters,
    # caches, the stages' scratch) with it
    import copy
    import pickle

    profile = dataclasses.replace(load_profile("t1_mj"), odometry_noise=(0.05, 0.05, 0.05))
    bodies = Bodies(profile, 6)
    rng = np.random.default_rng(5)
    _noisy_walk(bodies, rng, 40)
    if copier == "deepcopy":
        twin, twin_rng = copy.deepcopy((bodies, rng))
    else:
        twin, twin_rng = pickle.loads(pickle.dumps((bodies, rng)))
    assert _noisy_walk(twin, twin_rng, 60) == _noisy_walk(bodies, rng, 60)


def test_a_new_generator_is_drawn_from() -> None:
    # an env reset hands the bodies a new generator: every draw comes from the one handed in
    profile = dataclasses.replace(load_profile("t1_mj"), odometry_noise=(0.05, 0.05, 0.05))
    bodies = Bodies(profile, 4)
    first = np.random.default_rng(1)
    _noisy_walk(bodies, first, 5)
    state = first.bit_generator.state
    second = np.random.default_rng(2)
    _noisy_walk(bodies, second, 5)
    assert first.bit_generator.state == state
    assert second.bit_generator.state != np.random.default_rng(2).bit_generator.state


def test_the_kernel_reads_the_profile_where_bodies_put_it(t1) -> None:
    # Bodies lays out the kernel's inputs without importing it (numba is imported on the first
    # step): the sizes and the order of its parameter vector must be the kernel's
    from locomotion import step_kernel as k

    b = Bodies(t1, 3)
    assert b._params.shape == (k.N_PARAMS,)
    assert b._counts.shape == (k.N_COUNTS,)
    assert b._flags.shape == (3, 3) and b._scratch.shape == (4, 3)
    assert b._vectors.shape == (4, 3)
    expected = {
        k.P_T: t1.step_period, k.P_VX_FWD: t1.envelope_vx_forward,
        k.P_VX_BACK: t1.envelope_vx_backward, k.P_VY: t1.envelope_vy,
        k.P_TURN: t1.envelope_turn, k.P_EXPONENT: t1.envelope_exponent,
        k.P_J_LO: t1.impact_fall_impulse_low, k.P_J_HI: t1.impact_fall_impulse_high,
        k.P_JUMP_THRESHOLD: t1.command_jump_threshold,
        k.P_JUMP_PROBABILITY: t1.command_jump_fall_probability,
        k.P_DOWN_TIME: t1.fall_duration + t1.getup_duration,
        k.P_KICK_SIGMA: t1.kick_direction_std, k.P_KICK_MAX_ANGLE: t1.kick_max_angle,
        k.P_KICK_PREP: t1.kick_prep_time, k.P_KICK_DURATION: t1.kick_duration,
        k.P_KICK_MEAN: t1.kick_distance_mean, k.P_KICK_STD: t1.kick_distance_std,
        k.P_KICK_MIN: t1.kick_distance_min, k.P_KICK_MAX: t1.kick_distance_max,
    }
    assert {i: float(b._params[i]) for i in expected} == pytest.approx(expected)
    assert b._vectors[k.V_DV] == pytest.approx(np.asarray(t1.accel) * t1.step_period)
    assert b._vectors[k.V_LIM_BACK][0] == t1.envelope_vx_backward
    assert b._vectors[k.V_ODOMETRY_SCALE] == pytest.approx(t1.odometry_scale)
