"""Closed-form poses from two seen landmarks: the two-post triangle of seed 002 §2.4 and the
two-circle intersection of seed 000 §3 (Fig. 1a). Both give two mirror-image candidates.

Sightings are the body-frame ground coordinates the source calls ``u`` (forward) and ``v``
(left), or, for the circles, the ground distance and the azimuth (+ left). Poses are
``x, y, psi`` in the team frame. Everything is vectorized: leading axes broadcast.

The two candidates of a pair of landmarks P1, P2 are mirror images across the line through
them. The distances alone cannot tell them apart; the bearings can (a rigid motion keeps the
order of the two landmarks in view, the mirror reverses it): each candidate's heading is
computed from both bearings, and the mirror candidate's two headings disagree. ``residual``
is that disagreement (rad, 0 on noise-free input for the true candidate). For two goal posts
the mirror candidate lies behind the goal line, off the field, and is rejected there.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

import portable_math as pm
from teamenv.field import FieldSpec


def _wrap(a: NDArray[np.float64]) -> NDArray[np.float64]:
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def _headings(px: NDArray, py: NDArray, p1: NDArray, p2: NDArray, az1: NDArray,
              az2: NDArray) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Heading (circular mean of the two landmarks' votes) and the votes' disagreement."""
    h1 = pm.arctan2(p1[..., 1] - py, p1[..., 0] - px) - az1
    h2 = pm.arctan2(p2[..., 1] - py, p2[..., 0] - px) - az2
    diff = _wrap(h2 - h1)
    return _wrap(h1 + 0.5 * diff), np.abs(diff)


def two_post_candidates(u1: ArrayLike, v1: ArrayLike, u2: ArrayLike, v2: ArrayLike,
                        post1: ArrayLike, post2: ArrayLike
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Both candidate poses of seed 002 §2.4, vectorized.

    Steps of the source: the direct distances ``d = sqrt(u² + v²)`` (eq. 1), the goal width
    as the robot sees it, ``|(u1, v1) - (u2, v2)|`` (eq. 2), the triangle's angles at the two
    posts by the law of cosines (eq. 3-5), the two lines from the posts at those angles and
    their intersection (eq. 6-9; here in vector form: the triangle with the posts' true
    baseline and the seen angles, on either side of the baseline), and the heading from the
    bearing of each post, ``atan2(v, u)`` (eq. 10's beta), combined as a circular mean.

    Args:
        u1, v1, u2, v2: forward / left ground coordinates of post 1 and post 2 (body frame).
        post1, post2: (..., 2) team-frame ground positions of the two posts.

    Returns:
        ``poses`` (..., 2, 3) both candidates, ``residual`` (..., 2): the disagreement of the
        headings the two posts give (rad). Degenerate input (the robot on the line through
        the posts, a post at distance 0) gives NaN.
    """
    u1, v1, u2, v2 = (np.asarray(a, dtype=np.float64) for a in (u1, v1, u2, v2))
    p1, p2 = np.asarray(post1, dtype=np.float64), np.asarray(post2, dtype=np.float64)
    d1, d2 = np.hypot(u1, v1), np.hypot(u2, v2)                  # eq. 1
    seen_width = np.hypot(u1 - u2, v1 - v2)                      # eq. 2
    with np.errstate(divide="ignore", invalid="ignore"):
        cos1 = (d2 * d2 - d1 * d1 - seen_width ** 2) / (-2.0 * d1 * seen_width)  # eq. 3-5
        cos2 = (d1 * d1 - d2 * d2 - seen_width ** 2) / (-2.0 * d2 * seen_width)
        a1 = pm.arccos(np.clip(cos1, -1.0, 1.0))
        a2 = pm.arccos(np.clip(cos2, -1.0, 1.0))
        base = p2 - p1
        width = np.hypot(base[..., 0], base[..., 1])
        ex, ey = base[..., 0] / width, base[..., 1] / width       # along the baseline
        t1 = width * np.sin(a2) / np.sin(a1 + a2)                 # eq. 6-9: the intersection
        t1 = np.where(np.sin(a1 + a2) > 1e-12, t1, np.nan)
    poses, residual = [], []
    for side in (1.0, -1.0):                                      # either side of the baseline
        rx = np.cos(a1) * ex - side * np.sin(a1) * ey
        ry = np.cos(a1) * ey + side * np.sin(a1) * ex
        px, py = p1[..., 0] + t1 * rx, p1[..., 1] + t1 * ry
        psi, res = _headings(px, py, p1, p2, pm.arctan2(v1, u1), pm.arctan2(v2, u2))  # eq. 10
        poses.append(np.stack((px, py, psi), axis=-1))
        residual.append(res)
    return np.stack(poses, axis=-2), np.stack(residual, axis=-1)


def two_post_pose(seen1: ArrayLike, seen2: ArrayLike, post1: ArrayLike, post2: ArrayLike,
                  field: FieldSpec | None = None, margin_m: float = 0.25
                  ) -> NDArray[np.float64]:
    """The robot's pose from two seen goal posts (seed 002 §2.4): the candidate poses.

    Args:
        seen1, seen2: ``(u, v)``: forward and left ground distance (m) of post 1 and post 2
            in the body frame, as the source's robot reports them.
        post1, post2: ``(x, y)`` of the two posts in the team frame (e.g. the ``xyz[:, :2]``
            rows of ``teamenv.landmarks.landmarks``).
        field: when given, a candidate farther than ``margin_m`` outside the pitch is
            rejected (the mirror candidate of two goal posts lies behind the goal line).

    Returns:
        (M, 3) candidate poses ``x, y, psi``, M in 0..2, best first (the smaller heading
        disagreement of the two posts). Exact on noise-free input: the true pose comes first.
    """
    u1, v1 = np.asarray(seen1, dtype=np.float64)
    u2, v2 = np.asarray(seen2, dtype=np.float64)
    poses, residual = two_post_candidates(u1, v1, u2, v2, post1, post2)
    keep = np.isfinite(poses).all(axis=-1)
    if field is not None:
        keep &= on_field(poses[:, 0], poses[:, 1], field, margin_m)
    poses, residual = poses[keep], residual[keep]
    return poses[np.argsort(residual, kind="stable")]


def two_landmark_candidates(l1: ArrayLike, l2: ArrayLike, g1: ArrayLike, az1: ArrayLike,
                            g2: ArrayLike, az2: ArrayLike
                            ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Both candidate poses from two landmarks by circle intersection (seed 000 Fig. 1a).

    Args:
        l1, l2: (..., 2) team-frame ground positions of the landmarks.
        g1, g2: seen ground distances (m); az1, az2: seen azimuths (rad, + left).

    Returns:
        ``poses`` (..., 2, 3) and ``residual`` (..., 2) as ``two_post_candidates``. When the
        circles miss each other (noise), the nearest point of the baseline is used (both
        candidates coincide in position).
    """
    p1, p2 = np.asarray(l1, dtype=np.float64), np.asarray(l2, dtype=np.float64)
    g1, g2 = np.asarray(g1, dtype=np.float64), np.asarray(g2, dtype=np.float64)
    az1, az2 = np.asarray(az1, dtype=np.float64), np.asarray(az2, dtype=np.float64)
    base = p2 - p1
    dist = np.maximum(np.hypot(base[..., 0], base[..., 1]), 1e-9)
    ex, ey = base[..., 0] / dist, base[..., 1] / dist
    along = (g1 * g1 - g2 * g2 + dist * dist) / (2.0 * dist)
    across = np.sqrt(np.maximum(g1 * g1 - along * along, 0.0))
    poses, residual = [], []
    for side in (1.0, -1.0):
        px = p1[..., 0] + along * ex - side * across * ey
        py = p1[..., 1] + along * ey + side * across * ex
        psi, res = _headings(px, py, p1, p2, az1, az2)
        poses.append(np.stack((px, py, psi), axis=-1))
        residual.append(res)
    return np.stack(poses, axis=-2), np.stack(residual, axis=-1)


def on_field(x: ArrayLike, y: ArrayLike, field: FieldSpec, margin_m: float = 0.0
             ) -> NDArray[np.bool_]:
    """Elementwise: (x, y) lies on ``field`` grown by ``margin_m`` (NaN: False)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    return (np.abs(x) <= field.half_length + margin_m) & (np.abs(y) <= field.half_width + margin_m)
