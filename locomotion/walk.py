"""Omnidirectional walk kinematics (seed 001 eq. 4), tracking curves and the speed envelope."""

from __future__ import annotations

import numpy as np

import portable_math as pm

__all__ = ["omni_displacement", "compose", "track", "apply_envelope"]


def omni_displacement(vel: np.ndarray, tau: float | np.ndarray) -> np.ndarray:
    """Body-frame displacement after walking ``tau`` seconds at constant body-frame velocity.

    This is seed 001 eq. 4 written relative to the pose at the start (psi[k] = 0)::

        dx   = 2 (vx/w) sin(wT/2) cos(wT/2) - 2 (vy/w) sin(wT/2) sin(wT/2)
        dy   = 2 (vx/w) sin(wT/2) sin(wT/2) + 2 (vy/w) sin(wT/2) cos(wT/2)
        dpsi = w T

    with ``2 sin(wT/2)/w = T sinc(wT/2)`` (unnormalised sinc), which is exact for every w and
    tends smoothly to the straight-line step ``(vx T, vy T, 0)`` as the turn rate w -> 0 (no
    division by zero, no branch).

    Args:
        vel: (n, 3) body-frame velocities (vx m/s, vy m/s, w rad/s).
        tau: duration (s), scalar or (n,).

    Returns:
        (n, 3) displacement (dx m, dy m, dpsi rad) in the body frame at the start.
    """
    vx = vel[:, 0]
    vy = vel[:, 1]
    theta = vel[:, 2] * tau
    half = 0.5 * theta
    # sin(h)/h with h = 0 replaced by a tiny number: exactly 1 there, and sin/cos unchanged
    h = np.where(half == 0.0, 1e-300, half)
    s = np.sin(h)
    c = np.cos(h)
    f = s / h * tau
    out = np.empty_like(vel)
    out[:, 0] = f * (vx * c - vy * s)
    out[:, 1] = f * (vx * s + vy * c)
    out[:, 2] = theta
    return out


def compose(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Compose body-frame displacements: ``first`` then ``second`` (expressed after ``first``).

    Args:
        first, second: (n, 3) displacements (m, m, rad).

    Returns:
        (n, 3) total displacement in the frame at the start of ``first``.
    """
    c = np.cos(first[:, 2])
    s = np.sin(first[:, 2])
    out = np.empty_like(first)
    out[:, 0] = first[:, 0] + c * second[:, 0] - s * second[:, 1]
    out[:, 1] = first[:, 1] + s * second[:, 0] + c * second[:, 1]
    out[:, 2] = first[:, 2] + second[:, 2]
    return out


def track(cmd: np.ndarray, tables: tuple[tuple[np.ndarray, np.ndarray], ...]) -> np.ndarray:
    """Map commanded to achieved velocity per axis through measured tracking curves.

    Each axis has a piecewise-linear curve (commanded -> achieved, steady state) measured on the
    real walk; commands beyond the last measured point saturate at its achieved value.

    Args:
        cmd: (n, 3) commanded body-frame velocity (m/s, m/s, rad/s).
        tables: three (commanded, achieved) pairs of increasing 1-D arrays.

    Returns:
        (n, 3) achieved steady-state velocity before the envelope.
    """
    out = np.empty_like(cmd)
    for k in range(3):
        xp, fp = tables[k]
        out[:, k] = np.interp(cmd[:, k], xp, fp)
    return out


def apply_envelope(
    vel: np.ndarray, vx_fwd: float, vx_back: float, vy_max: float, w_max: float, p: float
) -> np.ndarray:
    """Limit forward, side and turn speed *together* (a p-norm ball, not three clamps).

    The velocity is normalised per axis, ``u = (vx/vx_lim, vy/vy_max, w/w_max)`` with
    ``vx_lim = vx_fwd`` forward and ``vx_back`` backward; if ``||u||_p > 1`` the whole vector is
    scaled down by ``1/||u||_p`` (direction of travel kept), so walking at full speed forward
    leaves no room for turning or side-stepping.

    Args:
        vel: (n, 3) body-frame velocity (m/s, m/s, rad/s).
        vx_fwd, vx_back: forward / backward speed limits (m/s, both > 0).
        vy_max: side speed limit (m/s); w_max: turn-rate limit (rad/s).
        p: exponent of the norm (2 = ellipsoid).

    Returns:
        (n, 3) velocity inside the envelope.
    """
    if p == 2.0:
        inv = np.where(
            vel[:, :1] >= 0.0,
            (1.0 / vx_fwd, 1.0 / vy_max, 1.0 / w_max),
            (1.0 / vx_back, 1.0 / vy_max, 1.0 / w_max),
        )
        u = vel * inv
        u *= u
        # u0 + u2, then + u1: the order of NumPy's einsum("ij,ij->i") on AVX2, which this
        # replaced (einsum's order depends on the CPU's SIMD kernel; this is the same on all)
        norm = np.sqrt((u[:, 0] + u[:, 2]) + u[:, 1])
    else:
        ux = vel[:, 0] / np.where(vel[:, 0] >= 0.0, vx_fwd, vx_back)
        norm = pm.power(
            pm.power(np.abs(ux), p) + pm.power(np.abs(vel[:, 1] / vy_max), p)
            + pm.power(np.abs(vel[:, 2] / w_max), p), 1.0 / p)
    scale = 1.0 / np.maximum(norm, 1.0)
    return vel * scale[:, None]


def envelope_norm(
    vel: np.ndarray, vx_fwd: float, vx_back: float, vy_max: float, w_max: float, p: float
) -> np.ndarray:
    """Envelope norm ``||u||_p`` of each velocity (<= 1 inside the envelope); see apply_envelope."""
    ux = vel[:, 0] / np.where(vel[:, 0] >= 0.0, vx_fwd, vx_back)
    return pm.power(pm.power(np.abs(ux), p) + pm.power(np.abs(vel[:, 1] / vy_max), p)
                    + pm.power(np.abs(vel[:, 2] / w_max), p), 1.0 / p)
