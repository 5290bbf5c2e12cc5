"""A formation: ball position -> home positions, by Delaunay triangulation + barycentric interpolation.

A formation is a set of *samples*: a ball position (metres, team frame: our goal at
x = -length/2, we attack +x) with one home position per player. The sample ball positions are
triangulated (Delaunay, SciPy/Qhull). For a ball inside a triangle the home positions are the
barycentric (Gouraud) blend of the three samples' home positions, so the mapping is exact at
the samples and continuous across triangle edges. Outside the convex hull of the samples the
rule is selectable:

- ``"nearest"`` (default, as agent2d's ``FormationDT`` does): the home positions of the
  nearest sample ball position;
- ``"project"``: the ball is projected onto the nearest point of the hull boundary and the
  interpolation is done there (continuous everywhere).

A formation with a single sample is *static*: the same home positions for every ball.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from teamenv.errors import ConfigError
from teamenv.field import FieldSpec, field_preset

ROLE_TYPES: tuple[str, ...] = ("G", "DF", "MF", "FW")
"""Role types, as agent2d names them: goalie, defender, midfielder, forward."""

OUTSIDE_RULES: tuple[str, ...] = ("nearest", "project")
"""Rules for a ball outside the convex hull of the samples (see the module docstring)."""

MIN_SAMPLE_SEPARATION_M = 1e-3
"""Two sample ball positions closer than this (metres) are duplicates."""

FIELD_MARGIN_FRACTION = 0.05
"""Sample positions may lie outside the pitch lines by this fraction of the pitch length
(1.5 m on simspark, 5.25 m on fifa); agent2d's files put ball samples 2 m beyond the lines."""


#: barycentric margin under which a ball counts as on a triangle's edge (Qhull's own tolerance
#: is ~100 x machine epsilon; this is wider, so every ball it might place in either neighbour
#: is looked up alone)
_EDGE_MARGIN = 1e-9


class FormationError(ConfigError):
    """A formation (or formation file) is not valid; the message names the formation and field."""


@dataclass(frozen=True)
class Role:
    """One position of a formation: a name ("CenterBack") and a type (one of ``ROLE_TYPES``)."""

    name: str
    type: str


def _as_points(value: ArrayLike, what: str, source: str) -> NDArray[np.float64]:
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise FormationError(f"{source}: {what} must be numbers, got {value!r}") from None
    return arr


class Formation:
    """Maps a ball position (metres, team frame) to one home position per player.

    Construct from roles and samples (every argument is validated; a bad one raises
    ``FormationError`` naming the formation, the field and the value), or read one with
    ``strategy.positioning.formation.read_formation`` / ``builtin_formation`` / ``import_agent2d``.

    Args:
        roles: one ``Role`` per player, index i = uniform number i + 1 (role 0 is the goalie
            when the formation has one).
        ball: (S, 2) sample ball positions, metres.
        positions: (S, N, 2) home positions per sample and player, metres.
        field: the pitch the coordinates are measured on (a preset name, a ``FieldSpec``, or a
            (length, width) pair in metres); positions must lie on it, within a margin of
            ``FIELD_MARGIN_FRACTION`` of its length.
        name: a label used in error messages and plots.
        description: free text (kept when the formation is written to a file).
        outside: rule for a ball outside the samples' convex hull, one of ``OUTSIDE_RULES``.
    """

    def __init__(
        self,
        roles: Sequence[Role],
        ball: ArrayLike,
        positions: ArrayLike,
        *,
        field: str | FieldSpec | tuple[float, float] = "simspark",
        name: str = "formation",
        description: str = "",
        outside: Literal["nearest", "project"] = "nearest",
    ) -> None:
        self.name = str(name)
        self.description = str(description)
        src = f"formation {self.name!r}"
        self.field_size = _field_size(field, src)
        self.roles: tuple[Role, ...] = _check_roles(roles, src)
        self._goalie = next((i for i, r in enumerate(self.roles) if r.type == "G"), None)
        if outside not in OUTSIDE_RULES:
            raise FormationError(f"{src}: outside must be one of {OUTSIDE_RULES}, got {outside!r}")
        self.outside: str = outside
        ball_arr = _as_points(ball, "ball", src)
        pos_arr = _as_points(positions, "positions", src)
        n = len(self.roles)
        if ball_arr.ndim != 2 or ball_arr.shape[1] != 2 or ball_arr.shape[0] == 0:
            raise FormationError(
                f"{src}: ball must have shape (samples, 2) with at least one sample, "
                f"got shape {ball_arr.shape}"
            )
        s = ball_arr.shape[0]
        if pos_arr.ndim != 3 or pos_arr.shape[0] != s or pos_arr.shape[2] != 2:
            raise FormationError(
                f"{src}: positions must have shape ({s}, players, 2), got shape {pos_arr.shape}"
            )
        if pos_arr.shape[1] != n:
            raise FormationError(
                f"{src}: positions: {pos_arr.shape[1]} players per sample but {n} roles"
            )
        _check_finite_on_field(ball_arr, pos_arr, self.field_size, src)
        _check_duplicates(ball_arr, src)
        self._ball = ball_arr.copy()
        self._positions = pos_arr.copy()
        self._ball.flags.writeable = False
        self._positions.flags.writeable = False
        self._flat = self._positions.reshape(s, n * 2)
        self._tri = None
        self._affine: NDArray[np.float64] | None = None
        if s >= 3:
            self._build_triangulation(src)
        elif s == 2:
            raise FormationError(
                f"{src}: samples: 2 samples cannot be triangulated; give 1 (a static "
                f"formation) or at least 3 that are not all on one line"
            )

    # ------------------------------------------------------------------ construction helpers
    def _build_triangulation(self, src: str) -> None:
        from scipy.spatial import Delaunay, QhullError

        # Collinear if every sample lies within MIN_SAMPLE_SEPARATION_M of the line through the
        # centroid and the farthest sample (no LAPACK: its thread pool is slow to wake up).
        centred = self._ball - self._ball.mean(axis=0)
        far = centred[np.argmax(np.einsum("ij,ij->i", centred, centred))]
        unit = far / max(float(np.hypot(*far)), 1e-12)
        off_line = np.abs(centred[:, 0] * unit[1] - centred[:, 1] * unit[0])
        if float(off_line.max()) < MIN_SAMPLE_SEPARATION_M:
            raise FormationError(
                f"{src}: samples: the {len(self._ball)} sample ball positions are degenerate "
                f"(all on one line); they cannot be triangulated"
            )
        try:
            tri = Delaunay(self._ball)
        except QhullError as exc:  # pragma: no cover - rank check catches the usual cases
            raise FormationError(f"{src}: samples: triangulation failed: {exc}") from None
        if len(tri.coplanar):
            i = int(tri.coplanar[0, 0])
            raise FormationError(
                f"{src}: samples[{i}].ball = {tuple(self._ball[i].tolist())} is degenerate: it is not a "
                f"vertex of the triangulation (too close to another sample)"
            )
        self._tri = tri
        # Per triangle, one affine map from (bx, by, 1) to the 2N flattened home positions:
        # barycentric weights w = M @ (bx, by, 1) (from Qhull's transform), positions = w @ P
        # with P the corners' home positions, so positions = (bx, by, 1) @ (M.T @ P).
        t = _barycentric_transforms(tri)  # (T, 3, 2): rows 0-1 the inverse map, row 2 offset
        tmat, off = t[:, :2, :], t[:, 2, :]
        tr = np.einsum("tij,tj->ti", tmat, off)
        m = np.empty((len(t), 3, 3))
        m[:, :2, :2] = tmat
        m[:, :2, 2] = -tr
        m[:, 2, :2] = -tmat.sum(axis=1)
        m[:, 2, 2] = 1.0 + tr.sum(axis=1)
        corners = self._flat[tri.simplices]  # (T, 3, 2N)
        self._affine = np.einsum("tki,tkj->tij", m, corners)  # (T, 3, 2N)
        hull = tri.convex_hull  # (H, 2) sample index pairs
        self._hull = hull
        self._hull_a = self._ball[hull[:, 0]]
        self._hull_d = self._ball[hull[:, 1]] - self._hull_a
        self._hull_len2 = np.einsum("ij,ij->i", self._hull_d, self._hull_d)

    # ------------------------------------------------------------------ properties
    @property
    def n_players(self) -> int:
        """Number of players (roles)."""
        return len(self.roles)

    @property
    def n_samples(self) -> int:
        """Number of samples."""
        return int(self._ball.shape[0])

    @property
    def ball_samples(self) -> NDArray[np.float64]:
        """(S, 2) sample ball positions, metres (read-only view)."""
        return self._ball

    @property
    def sample_positions(self) -> NDArray[np.float64]:
        """(S, N, 2) home positions per sample, metres (read-only view)."""
        return self._positions

    @property
    def simplices(self) -> NDArray[np.intp]:
        """(T, 3) sample indices of the Delaunay triangles (empty for a static formation)."""
        if self._tri is None:
            return np.zeros((0, 3), dtype=np.intp)
        return self._tri.simplices

    @property
    def is_static(self) -> bool:
        """True if the formation has one sample (home positions ignore the ball)."""
        return self._tri is None

    @property
    def goalie_index(self) -> int | None:
        """Index of the goalie role (type "G"), or None if the formation has none."""
        return self._goalie

    # ------------------------------------------------------------------ lookup
    def home_positions(self, ball: ArrayLike) -> NDArray[np.float64]:
        """Home positions (N, 2), metres, for one ball position (x, y) in metres."""
        b = np.asarray(ball, dtype=np.float64).reshape(-1)
        if b.shape != (2,) or not math.isfinite(b[0] + b[1]):
            raise FormationError(
                f"formation {self.name!r}: ball must be a finite (x, y) in metres, got {ball!r}"
            )
        return self._lookup(b[None, :])[0]

    def home_positions_many(self, balls: ArrayLike) -> NDArray[np.float64]:
        """Home positions (M, N, 2), metres, for M ball positions (M, 2) in metres, each the
        bits of ``home_positions`` of that ball alone (e.g. every agent's belief at once)."""
        b = np.asarray(balls, dtype=np.float64)
        if b.ndim != 2 or b.shape[1] != 2 or not np.isfinite(b).all():
            raise FormationError(
                f"formation {self.name!r}: balls must be finite with shape (M, 2), "
                f"got shape {b.shape}"
            )
        return self._lookup(b)

    def _lookup(self, b: NDArray[np.float64]) -> NDArray[np.float64]:
        """Home positions (M, N, 2) of checked balls b (M, 2): in the triangle that holds the
        ball, the affine map ``(bx, by, 1) @ affine``, summed as ``einsum`` sums it for one
        ball (``(bx a0 + by a1) + a2``, element-wise, so a ball's bits do not depend on the
        others); outside the hull ``outside``'s rule."""
        m, n = b.shape[0], self.n_players
        if self._tri is None:
            return np.broadcast_to(self._positions[0], (m, n, 2)).copy()
        s = self._tri.find_simplex(b)
        if m > 1:
            # Qhull's search for the next ball starts in the last one's triangle: a ball on an
            # edge (in two triangles) may be found in the other one than when looked up alone,
            # whose map gives the same place with other rounding. Those are looked up alone.
            for k in np.flatnonzero(self._near_edge(b, s)).tolist():
                s[k] = self._tri.find_simplex(b[k])
        inside = s >= 0
        out = np.empty((m, n * 2))
        if inside.all():
            affine = self._affine[s]
            bi = b
        else:
            affine = self._affine[s[inside]]
            bi = b[inside]
        rows = bi[:, 0, None] * affine[:, 0]
        rows += bi[:, 1, None] * affine[:, 1]
        rows += affine[:, 2]
        out[inside] = rows
        result = out.reshape(m, n, 2)
        for k in np.flatnonzero(~inside).tolist():  # one by one, as a lone ball is
            result[k] = self._outside(b[k][None, :])[0]
        return result

    def _near_edge(self, b: NDArray[np.float64], s: NDArray[np.intp]) -> NDArray[np.bool_]:
        """Balls whose triangle ``s`` holds them within a margin of an edge (or that are
        outside: s < 0, handled apart)."""
        t = self._tri.transform[np.maximum(s, 0)]  # type: ignore[union-attr]
        d = b - t[:, 2]
        c0 = t[:, 0, 0] * d[:, 0] + t[:, 0, 1] * d[:, 1]
        c1 = t[:, 1, 0] * d[:, 0] + t[:, 1, 1] * d[:, 1]
        nearest = np.minimum(np.minimum(c0, c1), 1.0 - c0 - c1)
        return (s >= 0) & (nearest < _EDGE_MARGIN)

    def _outside(self, b: NDArray[np.float64]) -> NDArray[np.float64]:
        """Home positions (M, N, 2) for balls (M, 2) outside the hull, by ``self.outside``."""
        n = self.n_players
        if self.outside == "nearest":
            d2 = ((b[:, None, :] - self._ball[None, :, :]) ** 2).sum(axis=2)
            # ties (equidistant samples): the lowest sample index, deterministically
            return self._positions[np.argmin(d2, axis=1)].copy()
        # "project": nearest point of the hull boundary, interpolated along that hull edge
        rel = b[:, None, :] - self._hull_a[None, :, :]  # (M, H, 2)
        t = np.clip(np.einsum("mhj,hj->mh", rel, self._hull_d) / self._hull_len2, 0.0, 1.0)
        q = self._hull_a[None] + t[:, :, None] * self._hull_d[None]
        d2 = ((b[:, None, :] - q) ** 2).sum(axis=2)
        h = np.argmin(d2, axis=1)
        th = t[np.arange(len(b)), h][:, None]
        i, j = self._hull[h, 0], self._hull[h, 1]
        out = (1.0 - th) * self._flat[i] + th * self._flat[j]
        return out.reshape(len(b), n, 2)

    # ------------------------------------------------------------------ transforms
    def mirrored(self, flip_x: bool = True, flip_y: bool = True) -> Formation:
        """The formation with x and/or y negated (ball samples and home positions alike).

        The default (both) is the rotation by pi that takes a formation from our team frame to
        the other side's frame (and back): what ``teamenv`` does to the right team's world.
        ``flip_y`` alone swaps the wings (left back <-> right back); role names are kept.
        """
        sign = np.array([-1.0 if flip_x else 1.0, -1.0 if flip_y else 1.0])
        return Formation(
            self.roles, self._ball * sign, self._positions * sign,
            field=self.field_size, name=self.name, description=self.description,
            outside=self.outside,  # type: ignore[arg-type]
        )

    def scaled_to(self, field: str | FieldSpec | tuple[float, float]) -> Formation:
        """The formation scaled from its pitch to ``field`` (x by the length ratio, y by width)."""
        target = _field_size(field, f"formation {self.name!r}")
        scale = np.array([target[0] / self.field_size[0], target[1] / self.field_size[1]])
        if np.allclose(scale, 1.0, rtol=0.0, atol=1e-12):
            return self
        return Formation(
            self.roles, self._ball * scale, self._positions * scale,
            field=target, name=self.name, description=self.description,
            outside=self.outside,  # type: ignore[arg-type]
        )

    def with_outside(self, outside: Literal["nearest", "project"]) -> Formation:
        """The same formation with another outside-the-hull rule."""
        return Formation(
            self.roles, self._ball, self._positions,
            field=self.field_size, name=self.name, description=self.description,
            outside=outside,
        )

    def __repr__(self) -> str:
        return (
            f"Formation(name={self.name!r}, players={self.n_players}, samples={self.n_samples}, "
            f"field={self.field_size[0]:g}x{self.field_size[1]:g} m, outside={self.outside!r})"
        )


def _barycentric_transforms(tri: object) -> NDArray[np.float64]:
    """``tri.transform``, computed with BLAS limited to one thread.

    SciPy computes it (also lazily, inside the first ``find_simplex``) with one small LAPACK
    call per triangle; with a multi-threaded OpenBLAS on a busy machine every call waits for
    the thread pool, measured at ~1.2 s for 64 triangles instead of 0.5 ms. Once computed it
    is cached on ``tri`` and lookups make no BLAS call.
    """
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - threadpoolctl comes with scikit-learn
        return tri.transform  # type: ignore[attr-defined]
    with threadpool_limits(limits=1, user_api="blas"):
        return tri.transform  # type: ignore[attr-defined]


def _field_size(field: str | FieldSpec | tuple[float, float], src: str) -> tuple[float, float]:
    if isinstance(field, (str, FieldSpec)):
        try:
            spec = field_preset(field)
        except ConfigError as exc:
            raise FormationError(f"{src}: {exc}") from None
        return (float(spec.length), float(spec.width))
    try:
        length, width = (float(v) for v in field)  # type: ignore[union-attr]
    except (TypeError, ValueError):
        raise FormationError(
            f"{src}: field must be a preset name, a FieldSpec or (length, width) in metres, "
            f"got {field!r}"
        ) from None
    if not (np.isfinite(length) and np.isfinite(width) and length > 0 and width > 0):
        raise FormationError(f"{src}: field size must be positive metres, got {field!r}")
    return (length, width)


def _check_roles(roles: Sequence[Role], src: str) -> tuple[Role, ...]:
    out = tuple(roles)
    if not out:
        raise FormationError(f"{src}: roles: at least one role is needed")
    for i, role in enumerate(out):
        if not isinstance(role, Role):
            raise FormationError(f"{src}: roles[{i}] must be a Role, got {role!r}")
        if not isinstance(role.name, str) or not role.name:
            raise FormationError(f"{src}: roles[{i}].name must be a non-empty string, "
                                 f"got {role.name!r}")
        if role.type not in ROLE_TYPES:
            raise FormationError(
                f"{src}: roles[{i}].type must be one of {ROLE_TYPES}, got {role.type!r}"
            )
    goalies = [i for i, r in enumerate(out) if r.type == "G"]
    if len(goalies) > 1:
        raise FormationError(f"{src}: roles: more than one goalie (type 'G') at {goalies}")
    if goalies and goalies[0] != 0:
        raise FormationError(
            f"{src}: roles[{goalies[0]}].type = 'G': the goalie must be role 0 (uniform 1)"
        )
    return out


def _check_finite_on_field(
    ball: NDArray[np.float64], pos: NDArray[np.float64], size: tuple[float, float], src: str
) -> None:
    margin = FIELD_MARGIN_FRACTION * size[0]
    hx, hy = size[0] / 2.0 + margin, size[1] / 2.0 + margin
    for label, arr in (("ball", ball), ("players", pos)):
        bad = ~np.isfinite(arr).all(axis=-1) | (np.abs(arr[..., 0]) > hx) | (
            np.abs(arr[..., 1]) > hy
        )
        if bad.any():
            idx = tuple(int(v) for v in np.argwhere(bad)[0])
            where = f"samples[{idx[0]}].ball" if label == "ball" else (
                f"samples[{idx[0]}].players[{idx[1]}]"
            )
            value = tuple(float(v) for v in arr[idx])
            raise FormationError(
                f"{src}: {where} = {value} is off the field ({size[0]:g} x {size[1]:g} m, "
                f"margin {margin:g} m) or not finite"
            )


def _check_duplicates(ball: NDArray[np.float64], src: str) -> None:
    if len(ball) < 2:
        return
    d2 = ((ball[:, None, :] - ball[None, :, :]) ** 2).sum(axis=2)
    np.fill_diagonal(d2, np.inf)
    close = np.argwhere(d2 < MIN_SAMPLE_SEPARATION_M**2)
    if len(close):
        i, j = sorted(int(v) for v in close[0])
        raise FormationError(
            f"{src}: samples[{j}].ball = {tuple(float(v) for v in ball[j])} duplicates "
            f"samples[{i}].ball (closer than {MIN_SAMPLE_SEPARATION_M} m)"
        )
