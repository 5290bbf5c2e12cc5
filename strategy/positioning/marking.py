"""Marking (ITAndroids TDP 2019, §5.4): replace formation positions by marking positions.

Three steps, all in the team frame (metres; our goal centre at (-length/2, 0); we attack +x,
so the opponents attack -x):

1. **Choose the dangerous opponents.** An opponent (present in our world model) is marked if
   all four conditions hold:

   - *close enough to take a shot*: its distance to our goal centre is at most
     ``shoot_range_m``;
   - *not the closest opponent to the ball* (that one is pressed by our ball chaser; ties
     broken by the lower index);
   - *not too close to the ball*: its distance to the ball is at least ``min_ball_distance_m``;
   - *not too far behind the ball*: it is at most ``max_behind_ball_m`` further from our goal
     line than the ball (``opp_x - ball_x <= max_behind_ball_m``; "behind" seen from the
     opponents' attacking direction).

   If more opponents qualify than ``max_markers`` allows, the ones closest to our goal centre
   are kept.
2. **Marking positions**: ``mark_distance_m`` (1.5 m) from each marked opponent along the line
   from it to our goal centre (the goal centre itself if the opponent is closer than that).
3. **Replace formation positions**: the marking positions replace formation positions chosen
   by the Hungarian algorithm (``linear_sum_assignment``) minimising the sum of distances
   between the replaced formation positions and the marking positions; protected positions
   (the goalie's) are never replaced. Role assignment then runs on the result.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linear_sum_assignment
from scipy.spatial.distance import cdist

from paramkit.checks import check_fields, non_negative
from teamenv.errors import ConfigError, TeamEnvError
from teamenv.field import FieldSpec, field_preset


class MarkingError(TeamEnvError, ValueError):
    """Bad input to marking (shape, NaN, negative distance); names the field and value."""


class MarkingParamsError(MarkingError, ConfigError):
    """A ``MarkingParams`` value is not valid: a ``MarkingError`` and, as every bad parameter,
    a ``ConfigError``."""


@dataclass(frozen=True)
class MarkingParams:
    """Thresholds of the marking heuristic, metres (defaults sized for the simspark pitch).

    Attributes:
        shoot_range_m: an opponent this close to our goal centre can shoot.
        min_ball_distance_m: opponents closer than this to the ball are not marked.
        max_behind_ball_m: opponents more than this behind the ball (further from our goal
            line than the ball) are not marked.
        mark_distance_m: a marker stands this far from its opponent, towards our goal centre.
        max_markers: at most this many opponents are marked (None: one per replaceable
            formation position).
    """

    shoot_range_m: float = field(default=9.0, metadata=non_negative())
    min_ball_distance_m: float = field(default=2.0, metadata=non_negative())
    max_behind_ball_m: float = field(default=3.0, metadata=non_negative())
    mark_distance_m: float = field(default=1.5, metadata=non_negative())
    max_markers: int | None = field(default=3, metadata=non_negative())

    def __post_init__(self) -> None:
        check_fields(self, MarkingParamsError)

    @classmethod
    def for_field(cls, field: str | FieldSpec, **overrides: object) -> MarkingParams:
        """Defaults scaled to ``field``: shooting and behind-the-ball ranges grow with its length
        (simspark 30 m is the reference); the ball and marking distances stay as they are."""
        spec = field_preset(field)
        k = spec.length / 30.0
        base = cls()
        unknown = sorted(set(overrides) - set(cls.__dataclass_fields__))
        if unknown:
            raise MarkingError(f"MarkingParams.for_field: unknown parameter(s) {unknown}")
        values: dict[str, object] = {"shoot_range_m": base.shoot_range_m * k,
                                     "max_behind_ball_m": base.max_behind_ball_m * k}
        values.update(overrides)
        return replace(base, **values)  # type: ignore[arg-type]


class MarkingResult(NamedTuple):
    """What marking did.

    Attributes:
        positions: (N, 2) formation positions with the marking positions put in, metres.
        marked: indices of the marked opponents.
        marking_positions: (K, 2) the marking positions, in the order of ``marked``, metres.
        replaced: (K,) the formation position index each marking position replaced.
    """

    positions: NDArray[np.float64]
    marked: NDArray[np.intp]
    marking_positions: NDArray[np.float64]
    replaced: NDArray[np.intp]


def dangerous_opponents(
    ball: ArrayLike,
    opponents: ArrayLike,
    field: str | FieldSpec,
    params: MarkingParams | None = None,
    present: ArrayLike | None = None,
) -> NDArray[np.intp]:
    """Indices of the opponents to mark (see the module docstring), closest to our goal first.

    Args:
        ball: ball position (x, y), metres, team frame.
        opponents: (M, 2) opponent positions, metres, team frame.
        field: the pitch (our goal centre is at (-length/2, 0)).
        params: thresholds (default: ``MarkingParams.for_field(field)``).
        present: (M,) bool, False for opponents not in the world model (never marked).
    """
    spec = field_preset(field)
    prm = MarkingParams.for_field(spec) if params is None else params
    b = _point(ball, "ball")
    opp = _points(opponents, "opponents")
    here = None if present is None else _mask(present, len(opp), "present")
    return _dangerous(b, opp, here, -spec.half_length, prm)


def _dangerous(b: NDArray[np.float64], opp: NDArray[np.float64], here: NDArray[np.bool_] | None,
               goal_x: float, prm: MarkingParams) -> NDArray[np.intp]:
    # A plain loop: for ~11 opponents it is several times cheaper than a dozen NumPy calls.
    bx, by = float(b[0]), float(b[1])
    flags = None if here is None else here.tolist()
    closest, closest_d = -1, math.inf
    found: list[tuple[float, int]] = []
    for i, (x, y) in enumerate(opp.tolist()):
        if flags is not None and not flags[i]:
            continue
        if not (math.isfinite(x) and math.isfinite(y)):
            raise MarkingError(f"opponents[{i}] = ({x}, {y}) is not finite (mark it not present)")
        d_ball = math.hypot(x - bx, y - by)
        if d_ball < closest_d:  # strict: the lowest index wins ties
            closest, closest_d = i, d_ball
        d_goal = math.hypot(x - goal_x, y)
        if (d_goal <= prm.shoot_range_m and d_ball >= prm.min_ball_distance_m
                and x - bx <= prm.max_behind_ball_m):
            found.append((d_goal, i))
    found.sort()  # closest to our goal first (ties: lower index)
    return np.array([i for _, i in found if i != closest], dtype=np.intp)


def marking_positions(
    opponents: ArrayLike, field: str | FieldSpec, mark_distance_m: float = 1.5
) -> NDArray[np.float64]:
    """(K, 2) positions ``mark_distance_m`` from each opponent (K, 2) towards our goal centre, m."""
    spec = field_preset(field)
    return _marking_positions(_points(opponents, "opponents"), -spec.half_length,
                              float(mark_distance_m))


def _marking_positions(opp: NDArray[np.float64], goal_x: float,
                       mark_distance_m: float) -> NDArray[np.float64]:
    out = []
    for x, y in opp.tolist():  # a handful of opponents: a loop beats NumPy's call overhead
        dx, dy = goal_x - x, -y
        dist = math.hypot(dx, dy)
        # the goal centre itself for an opponent closer to it than mark_distance_m
        scale = min(dist, mark_distance_m) / dist if dist > 0 else 0.0
        out.append((x + dx * scale, y + dy * scale))
    return np.array(out, dtype=np.float64).reshape(-1, 2)


def apply_marking(
    home_positions: ArrayLike,
    ball: ArrayLike,
    opponents: ArrayLike,
    field: str | FieldSpec,
    params: MarkingParams | None = None,
    present: ArrayLike | None = None,
    protected: Sequence[int] = (0,),
) -> MarkingResult:
    """Replace the formation positions nearest the marking positions (Hungarian, sum of distances).

    Args:
        home_positions: (N, 2) formation positions, metres, team frame.
        ball, opponents, field, params, present: as for ``dangerous_opponents``.
        protected: formation position indices never replaced (default: the goalie's, 0).

    Returns:
        A ``MarkingResult``; run ``assign_roles`` on its ``positions``.
    """
    spec = field_preset(field)
    prm = MarkingParams.for_field(spec) if params is None else params
    home = _points(home_positions, "home_positions")
    b = _point(ball, "ball")
    opp = _points(opponents, "opponents")
    here = None if present is None else _mask(present, len(opp), "present")
    marked = _dangerous(b, opp, here, -spec.half_length, prm)
    free = _free_positions(len(home), tuple(protected))
    limit = len(free) if prm.max_markers is None else min(prm.max_markers, len(free))
    marked = marked[:limit]
    out = home.copy()
    if len(marked) == 0:
        empty = np.zeros(0, dtype=np.intp)
        return MarkingResult(out, empty, np.zeros((0, 2)), empty)
    marks = _marking_positions(opp[marked], -spec.half_length, prm.mark_distance_m)
    rows, cols = linear_sum_assignment(cdist(marks, home[free]))
    replaced = free[cols]
    out[replaced] = marks[rows]
    return MarkingResult(out, marked, marks, replaced)


@functools.lru_cache(maxsize=64)
def _free_positions(n: int, protected: tuple[int, ...]) -> NDArray[np.intp]:
    protected = tuple(int(i) for i in protected)
    for i in protected:
        if not 0 <= i < n:
            raise MarkingError(f"protected position {i} is not in 0..{n - 1}")
    free = np.array([i for i in range(n) if i not in protected], dtype=np.intp)
    free.flags.writeable = False
    return free


def _point(value: ArrayLike, name: str) -> NDArray[np.float64]:
    a = np.asarray(value, dtype=np.float64).reshape(-1)
    if a.shape != (2,) or not math.isfinite(a[0] + a[1]):
        raise MarkingError(f"{name} must be a finite (x, y) in metres, got {value!r}")
    return a


def _points(value: ArrayLike, name: str) -> NDArray[np.float64]:
    a = np.asarray(value, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 2:
        raise MarkingError(f"{name} must have shape (M, 2) in metres, got shape {a.shape}")
    return a


def _mask(value: ArrayLike, n: int, name: str) -> NDArray[np.bool_]:
    a = np.asarray(value)
    if a.shape != (n,):
        raise MarkingError(f"{name} must have shape ({n},), got shape {a.shape}")
    return a.astype(bool)
