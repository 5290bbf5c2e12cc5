"""Tests of the walk kinematics: eq. 4, its turn-rate -> 0 limit, and the speed envelope."""

from __future__ import annotations

import numpy as np
import pytest

from locomotion import load_profile
from locomotion.walk import apply_envelope, compose, envelope_norm, omni_displacement, track


def _integrate(vel: np.ndarray, tau: float, steps: int = 20000) -> np.ndarray:
    """Midpoint integration of constant body-frame velocities into the start frame."""
    h = tau / steps
    out = np.zeros_like(vel)
    for i in range(steps):
        psi = vel[:, 2] * (i + 0.5) * h
        out[:, 0] += h * (vel[:, 0] * np.cos(psi) - vel[:, 1] * np.sin(psi))
        out[:, 1] += h * (vel[:, 0] * np.sin(psi) + vel[:, 1] * np.cos(psi))
    out[:, 2] = vel[:, 2] * tau
    return out


def test_eq4_matches_numerical_integration() -> None:
    rng = np.random.default_rng(1)
    vel = rng.uniform([-1, -0.5, -3], [1.5, 0.5, 3], size=(40, 3))
    np.testing.assert_allclose(omni_displacement(vel, 0.3), _integrate(vel, 0.3, 4000), atol=1e-8)


def test_eq4_is_the_paper_formula() -> None:
    """Same numbers as seed 001 eq. 4 written literally (psi[k] = 0.4, w != 0)."""
    vx, vy, w, T, psi = 0.8, -0.2, 1.3, 0.35, 0.4
    s = np.sin(w * T / 2)
    x = 2 * vx / w * s * np.cos(psi + w * T / 2) - 2 * vy / w * s * np.sin(psi + w * T / 2)
    y = 2 * vx / w * s * np.sin(psi + w * T / 2) + 2 * vy / w * s * np.cos(psi + w * T / 2)
    d = omni_displacement(np.array([[vx, vy, w]]), T)[0]
    c, sn = np.cos(psi), np.sin(psi)
    np.testing.assert_allclose(
        [c * d[0] - sn * d[1], sn * d[0] + c * d[1], d[2]], [x, y, w * T], atol=1e-14
    )


@pytest.mark.parametrize("w", [0.0, 1e-300, 1e-12, -1e-9, 1e-6])
def test_turn_rate_to_zero_limit(w: float) -> None:
    vel = np.array([[0.7, -0.3, w]])
    d = omni_displacement(vel, 0.4)
    assert np.all(np.isfinite(d))
    np.testing.assert_allclose(d[0], [0.28, -0.12, w * 0.4], atol=1e-6)


def test_continuous_in_turn_rate() -> None:
    ws = np.array([-1e-3, -1e-7, 0.0, 1e-7, 1e-3])
    vel = np.stack([np.full(5, 1.0), np.full(5, 0.2), ws], axis=1)
    d = omni_displacement(vel, 0.5)
    assert np.all(np.abs(np.diff(d[:, 0])) < 1e-3) and np.all(np.abs(np.diff(d[:, 1])) < 1e-3)


def test_compose_splits_a_step_exactly() -> None:
    vel = np.array([[0.9, 0.1, 0.8], [0.3, -0.2, -2.0]])
    whole = omni_displacement(vel, 0.3)
    parts = compose(omni_displacement(vel, 0.12), omni_displacement(vel, 0.18))
    np.testing.assert_allclose(parts, whole, atol=1e-14)


def test_envelope_is_combined_not_per_axis() -> None:
    p = load_profile("t1_mj")
    env = (p.envelope_vx_forward, p.envelope_vx_backward, p.envelope_vy, p.envelope_turn, 2.0)
    full = np.array([[1.24, 0.0, 0.96]])  # each axis at its own limit
    out = apply_envelope(full, *env)
    assert envelope_norm(out, *env)[0] == pytest.approx(1.0)
    assert out[0, 0] < 1.0 and out[0, 2] < 0.8  # three independent clamps would keep both
    np.testing.assert_allclose(out[0, 0] / out[0, 2], 1.24 / 0.96)  # direction kept
    inside = np.array([[0.5, 0.05, 0.3], [-0.2, 0.0, 0.0]])
    np.testing.assert_array_equal(apply_envelope(inside, *env), inside)


def test_envelope_respected_for_random_commands() -> None:
    p = load_profile("t1_mj")
    env = (
        p.envelope_vx_forward,
        p.envelope_vx_backward,
        p.envelope_vy,
        p.envelope_turn,
        p.envelope_exponent,
    )
    rng = np.random.default_rng(3)
    cmd = rng.uniform(p.command_low * 2, p.command_high * 2, size=(5000, 3))
    out = apply_envelope(track(cmd, p.tracking), *env)
    assert np.all(envelope_norm(out, *env) <= 1.0 + 1e-12)


def test_tracking_reproduces_measured_t1_speeds() -> None:
    p = load_profile("t1_mj")
    cmd = np.array(
        [
            [0.25, 0, 0],
            [0.5, 0, 0],
            [0.75, 0, 0],
            [1.0, 0, 0],
            [1.5, 0, 0],
            [-0.5, 0, 0],
            [0, 0.15, 0],
            [0, 0, 0.5],
            [0, 0, 1.0],
            [2.0, 0, 0],
        ]
    )
    out = track(cmd, p.tracking)
    np.testing.assert_allclose(out[:, 0], [0.26, 0.49, 0.72, 0.91, 1.24, -0.45, 0, 0, 0, 1.24])
    np.testing.assert_allclose(out[6:9, 1:].sum(axis=1), [0.135, 0.51, 0.96])
