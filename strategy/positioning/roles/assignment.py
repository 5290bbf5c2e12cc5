"""Dynamic role assignment: give each player one formation position (MMD+MSD², exact; greedy baseline).

The criterion is the one of "Positioning to Win" (MacAlpine, Price, Stone; RoboCup 2012,
SCRAM): among all one-to-one assignments of players to positions, take those that
**minimise the longest distance any player must walk** (MMD), and among those the one that
**minimises the sum of squared distances** (MSD²). It is solved exactly with SciPy's
``linear_sum_assignment`` (Hungarian / shortest augmenting path):

1. ``U``: the longest walk of the min-sum-of-squares assignment (an upper bound of the
   optimal longest walk ``t*``); ``L``: the largest of the players' nearest-position
   distances (a lower bound; also the positions' when the problem is square).
2. ``t*`` is the smallest distance ``t`` in ``[L, U]`` for which a perfect matching exists
   using only pairs at most ``t`` apart. Feasibility is a ``linear_sum_assignment`` on the
   squared distances with the pairs beyond ``t`` set to +inf (it raises if infeasible). The
   search first "tightens" (forbid every pair as long as the current longest walk, re-solve;
   usually 0-2 rounds), then finishes by binary search over the distinct distances.
3. The answer is the min-sum-of-squares assignment using only pairs at most ``t*`` apart
   (each feasibility solve already is that assignment for its threshold).

Fallen players get ``fallen_penalty_m`` added to all their distances (they must stand up
first). Missing players (``available`` False) are left out of the optimisation; the positions
nobody available took go to them in ascending order, so the result is always a permutation.
The goalie (player ``goalie``) is fixed to the formation's goalie position.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linear_sum_assignment
from scipy.spatial.distance import cdist

import portable_math as pm
from teamenv.errors import TeamEnvError

FALLEN_PENALTY_M = 1.0
"""Default extra walking distance (metres) charged to a fallen player (standing up first)."""


class RoleAssignmentError(TeamEnvError, ValueError):
    """Bad input to role assignment (shape, NaN, out-of-range goalie); names the field and value."""


class Assignment(NamedTuple):
    """A role assignment.

    Attributes:
        position_of: (N,) int, the position index given to each player (a permutation of
            0..N-1: the role vector).
        max_distance: the longest walk among the available players, metres (penalties included;
            0 when no player is available).
        sum_squared: the sum of squared walks of the available players, m².
    """

    position_of: NDArray[np.intp]
    max_distance: float
    sum_squared: float


def distance_matrix(
    players: ArrayLike,
    positions: ArrayLike,
    fallen: ArrayLike | None = None,
    fallen_penalty_m: float = FALLEN_PENALTY_M,
) -> NDArray[np.float64]:
    """(N, M) walking distances (metres) from each player (N, 2) to each position (M, 2).

    A fallen player's row (``fallen`` (N,) bool) gets ``fallen_penalty_m`` added.
    """
    p = _points(players, "players")
    q = _points(positions, "positions")
    d = cdist(p, q)
    if fallen is not None:
        f = _mask(fallen, len(p), "fallen")
        if f.any():
            d[f] += float(fallen_penalty_m)
    return d


def solve_mmd_msd2(dist: NDArray[np.float64]) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Exact MMD+MSD² on an (n, m) distance matrix, n <= m (every row gets one column).

    Returns ``(rows, cols)`` as ``linear_sum_assignment`` does. Algorithm: start from the
    min-sum-of-squares assignment (longest walk ``u``); while a perfect matching exists using
    only pairs shorter than ``u``, replace it by the min-sum-of-squares one among those pairs
    ("tightening", usually 0-2 rounds). The last feasible solution is optimal: it is the
    min-sum among a superset of the pairs at most ``t*`` = its own longest walk. After
    ``_TIGHTEN_ROUNDS`` rounds the rest is a binary search over the distances in
    ``[lower bound, u)``, as in the module docstring. (Checking the lower bound first does
    not pay: it costs more than the one infeasible solve it saves.)
    """
    n, m = dist.shape
    if n == 0:
        empty = np.zeros(0, dtype=np.intp)
        return empty, empty
    if n > m:
        raise RoleAssignmentError(f"solve_mmd_msd2: {n} rows but only {m} columns")
    # Small arrays: Python's max over .tolist() is ~4x cheaper than a NumPy reduction.
    sq = dist * dist
    rows, cols = linear_sum_assignment(sq)
    for _ in range(_TIGHTEN_ROUNDS):
        walks = dist[rows, cols].tolist()
        upper = max(walks)
        k = walks.index(upper)
        # Shortcut: the player with the longest walk has no position closer than ``upper``
        # (or, square problems, its position no player closer): ``upper`` is optimal.
        if min(dist[rows[k]].tolist()) >= upper or (
                n == m and min(dist[:, cols[k]].tolist()) >= upper):
            return rows, cols
        try:
            rows, cols = linear_sum_assignment(np.where(dist < upper, sq, np.inf))
        except ValueError:  # no perfect matching with every walk shorter than ``upper``
            return rows, cols
    upper = max(dist[rows, cols].tolist())
    # Rare (a few in 10^4 realistic scenes): finish by binary search between the bounds.
    lower = max(dist.min(axis=1).tolist())
    if n == m:
        lower = max(lower, max(dist.min(axis=0).tolist()))
    if upper <= lower:
        return rows, cols
    cand = np.sort(dist[(dist >= lower) & (dist < upper)], axis=None)
    best = (rows, cols)  # optimal if no candidate below ``upper`` is feasible (see above)
    lo, hi = 0, len(cand) - 1
    while lo <= hi:  # smallest feasible threshold among cand
        mid = (lo + hi) // 2
        try:
            r, c = linear_sum_assignment(np.where(dist <= cand[mid], sq, np.inf))
        except ValueError:  # no perfect matching with pairs <= cand[mid]
            lo = mid + 1
            continue
        best = (r, c)
        hi = mid - 1
    return best


_TIGHTEN_ROUNDS = 3


def solve_greedy(dist: NDArray[np.float64]) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Greedy baseline on an (n, m) distance matrix: repeatedly take the closest free pair."""
    n, m = dist.shape
    order = np.argsort(dist, axis=None, kind="stable")
    row_done = np.zeros(n, dtype=bool)
    col_done = np.zeros(m, dtype=bool)
    rows, cols = [], []
    for k in order:
        i, j = divmod(int(k), m)
        if row_done[i] or col_done[j]:
            continue
        row_done[i] = col_done[j] = True
        rows.append(i)
        cols.append(j)
        if len(rows) == n:
            break
    r = np.asarray(rows, dtype=np.intp)
    c = np.asarray(cols, dtype=np.intp)
    idx = np.argsort(r)
    return r[idx], c[idx]


def assign_roles(
    players: ArrayLike,
    positions: ArrayLike,
    *,
    available: ArrayLike | None = None,
    fallen: ArrayLike | None = None,
    goalie: int | None = 0,
    goalie_position: int = 0,
    fallen_penalty_m: float = FALLEN_PENALTY_M,
    method: str = "mmd_msd2",
) -> Assignment:
    """Assign each of N players (N, 2) one of N positions (N, 2), metres, team frame.

    Args:
        players: believed player positions, index i = uniform number i + 1.
        positions: the formation's home positions (after marking, if any).
        available: (N,) bool, False for a missing player (not on the field, or unknown).
        fallen: (N,) bool, True for a fallen player (charged ``fallen_penalty_m`` metres).
        goalie: the goalie's player index, fixed to ``goalie_position``; None: no fixed goalie.
        goalie_position: the formation's goalie position index.
        fallen_penalty_m: extra distance for fallen players, metres.
        method: "mmd_msd2" (exact, default) or "greedy" (closest free pair first; baseline).

    Returns:
        An ``Assignment`` whose ``position_of`` is a permutation of 0..N-1.

    This is ``assign_roles_all`` of one problem.
    """
    p = _points(players, "players")
    q = _points(positions, "positions")
    n = len(p)
    if len(q) != n:
        raise RoleAssignmentError(
            f"assign_roles: positions has {len(q)} rows, expected {n} (one per player)"
        )
    avail = None if available is None else _mask(available, n, "available")[None]
    fall = None if fallen is None else _mask(fallen, n, "fallen")[None]
    return _assign_all(p[None], q[None], avail, fall, goalie, goalie_position,
                       fallen_penalty_m, method)[0]


def assign_roles_all(
    players: ArrayLike,
    positions: ArrayLike,
    *,
    available: ArrayLike | None = None,
    fallen: ArrayLike | None = None,
    goalie: int | None = 0,
    goalie_position: int = 0,
    fallen_penalty_m: float = FALLEN_PENALTY_M,
    method: str = "mmd_msd2",
) -> list[Assignment]:
    """``assign_roles`` of A problems of one size at once (e.g. every agent of a team, each on
    its own belief): players, positions (A, N, 2); available, fallen (A, N) bool. Each
    problem gets the assignment ``assign_roles`` gives it alone, bit for bit: the distances
    are computed for all problems in one pass (as ``cdist`` does: ``sqrt(dx*dx + dy*dy)``),
    the exact search runs per problem."""
    p = _points(players, "players", stacked=True)
    q = _points(positions, "positions", stacked=True)
    if q.shape != p.shape:
        raise RoleAssignmentError(
            f"assign_roles_all: positions has shape {q.shape}, expected {p.shape} (one per "
            "player of each problem)"
        )
    shape = p.shape[:2]
    avail = None if available is None else _mask(available, shape, "available")
    fall = None if fallen is None else _mask(fallen, shape, "fallen")
    return _assign_all(p, q, avail, fall, goalie, goalie_position, fallen_penalty_m, method)


def _assign_all(p: NDArray[np.float64], q: NDArray[np.float64],
                avail_all: NDArray[np.bool_] | None, fall_all: NDArray[np.bool_] | None,
                goalie: int | None, goalie_position: int, fallen_penalty_m: float,
                method: str) -> list[Assignment]:
    """The assignments of checked problems p, q (A, N, 2); masks (A, N) or None."""
    n = p.shape[1]
    if method == "mmd_msd2":
        solver = solve_mmd_msd2
    elif method == "greedy":
        solver = solve_greedy
    else:
        raise RoleAssignmentError(
            f"assign_roles: method must be 'mmd_msd2' or 'greedy', got {method!r}"
        )
    if not (fallen_penalty_m >= 0 and math.isfinite(fallen_penalty_m)):
        raise RoleAssignmentError(
            f"assign_roles: fallen_penalty_m must be >= 0 metres, got {fallen_penalty_m!r}"
        )
    if goalie is not None and not (0 <= goalie < n and 0 <= goalie_position < n):
        raise RoleAssignmentError(
            f"assign_roles: goalie={goalie!r}, goalie_position={goalie_position!r} must be in "
            f"0..{n - 1}"
        )
    dist_all = _distances(p, q)
    finite = np.isfinite(dist_all.reshape(len(p), -1).sum(axis=1)).tolist()
    # Small arrays: Python's min/max over .tolist() is ~4x cheaper than a NumPy reduction.
    whole = [True] * len(p) if avail_all is None else avail_all.all(axis=1).tolist()
    any_fallen = [False] * len(p) if fall_all is None else fall_all.any(axis=1).tolist()
    out = []
    for a in range(len(p)):
        avail = None if whole[a] else avail_all[a]  # type: ignore[index]
        dist = dist_all[a]
        if not finite[a]:  # one check for both inputs (cheap when finite)
            dist = _finite_distances(p[a], q[a], avail)
        if any_fallen[a]:
            dist[fall_all[a]] += float(fallen_penalty_m)  # type: ignore[index]
        out.append(_assign_one(dist, avail, solver, goalie, goalie_position))
    return out


def _distances(p: NDArray[np.float64], q: NDArray[np.float64]) -> NDArray[np.float64]:
    """(A, N, M) distances of players p (A, N, 2) to positions q (A, M, 2): ``cdist``'s
    Euclidean arithmetic (the squares summed in axis order, then the root), all at once."""
    dx = p[:, :, None, 0] - q[:, None, :, 0]
    dy = p[:, :, None, 1] - q[:, None, :, 1]
    dx *= dx
    dy *= dy
    dx += dy
    return np.sqrt(dx, out=dx)


def _finite_distances(p: NDArray[np.float64], q: NDArray[np.float64],
                      avail: NDArray[np.bool_] | None) -> NDArray[np.float64]:
    """The distances of a problem with a non-finite input: an error naming it, unless every
    non-finite player is unavailable (its distances are then computed from the origin)."""
    if not np.isfinite(q).all():
        raise RoleAssignmentError("assign_roles: positions must be finite metres")
    bad = ~np.isfinite(p).all(axis=1)
    if avail is not None:
        bad &= avail
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise RoleAssignmentError(
            f"assign_roles: players[{i}] = {tuple(p[i].tolist())} is not finite (mark it unavailable)"
        )
    return _distances(np.where(np.isfinite(p), p, 0.0)[None], q[None])[0]


def _assign_one(dist: NDArray[np.float64], avail: NDArray[np.bool_] | None, solver,
                goalie: int | None, goalie_position: int) -> Assignment:
    """One problem's assignment from its distances (penalties added); ``avail`` None: all."""
    n = len(dist)
    if avail is None and goalie == 0 and goalie_position == 0:  # the usual case: a view
        sub = dist[1:, 1:]
        r, c = solver(sub)  # square: r is 0..n-2 in order
        position_of = np.empty(n, dtype=np.intp)
        position_of[0] = 0
        np.add(c, 1, out=position_of[1:])
        walks = sub[r, c].tolist()
        g = float(dist[0, 0])
        return Assignment(position_of, max([*walks, g]), math.fsum(w * w for w in walks) + g * g)
    position_of = np.full(n, -1, dtype=np.intp)
    if avail is None and goalie is None:
        r, c = solver(dist)
        position_of[r] = c
        d = dist[r, c]
    else:
        free_rows = np.ones(n, dtype=bool) if avail is None else avail.copy()
        free_cols = np.ones(n, dtype=bool)
        if goalie is not None:
            position_of[goalie] = goalie_position
            free_rows[goalie] = False
            free_cols[goalie_position] = False
        ri = np.flatnonzero(free_rows)
        ci = np.flatnonzero(free_cols)
        r, c = solver(dist[np.ix_(ri, ci)])
        position_of[ri[r]] = ci[c]
        d = dist[ri[r], ci[c]]
        if goalie is not None and (avail is None or avail[goalie]):
            d = np.append(d, dist[goalie, goalie_position])
        missing = np.flatnonzero(position_of < 0)
        if len(missing):
            taken = np.zeros(n, dtype=bool)
            taken[position_of[position_of >= 0]] = True
            position_of[missing] = np.flatnonzero(~taken)
    if len(d) == 0:
        return Assignment(position_of, 0.0, 0.0)
    return Assignment(position_of, max(d.tolist()), float(pm.matmul(d, d)))


def _points(value: ArrayLike, name: str, stacked: bool = False) -> NDArray[np.float64]:
    """``value`` as float64 points, (N, 2) or, ``stacked``, (A, N, 2) metres."""
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise RoleAssignmentError(f"{name} must be numbers, got {value!r}") from None
    ndim, shape = (3, "(A, N, 2)") if stacked else (2, "(N, 2)")
    if a.ndim != ndim or a.shape[-1] != 2:
        raise RoleAssignmentError(f"{name} must have shape {shape} in metres, got shape {a.shape}")
    return a


def _mask(value: ArrayLike, shape: int | tuple[int, ...], name: str) -> NDArray[np.bool_]:
    a = np.asarray(value)
    shape = (shape,) if isinstance(shape, int) else shape
    if a.shape != shape:
        shown = f"({shape[0]},)" if len(shape) == 1 else str(shape)
        raise RoleAssignmentError(f"{name} must have shape {shown}, got shape {a.shape}")
    return a if a.dtype == np.bool_ else a.astype(bool)
