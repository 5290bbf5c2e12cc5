"""One agent's world model: what it believes about the match, built from its own observation.

The perception layer of the agent (seed 000 §2): a Dict-form ``state`` observation in, a
``WorldModel`` out — absolute team-frame positions (we attack +x, our goal at x = -length/2),
the play mode as the team sees it, and the texts heard from teammates. Nothing here looks at
another agent's observation: a team's agents share no state.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from strategy.geometry import BallRoll
from strategy.memo import remember
from teamenv import PlayMode
from teamenv.errors import TeamEnvError
from teamenv.field import FieldSpec
from teamenv.observation import team_frame

T = TypeVar("T")

INTERCEPT_STEP_S = 0.1
"""The time step (s) at which ``WorldModel.intercepts`` samples the rolling ball's path."""

BELIEF_RESOLUTION_M = 0.01
"""Positions (m) and the ball's velocity (m/s) are rounded to this: float32 observations
differ by ~1e-6 m between observers, and teammates who believe the same should decide the
same (and can share the work: ``belief_key``)."""


@dataclass(frozen=True)
class WorldView:
    """What one agent believes, in its team frame (metres; row k = uniform number k + 1).

    Attributes:
        players: (N, 2) teammate positions, own row included.
        present: (N,) bool, False for teammates not on the field / unknown.
        fallen: (N,) bool.
        ball: (2,) ball position.
        opponents: (M, 2) opponent positions.
        opponents_present: (M,) bool.
    """

    players: NDArray[np.float64]
    present: NDArray[np.bool_]
    fallen: NDArray[np.bool_]
    ball: NDArray[np.float64]
    opponents: NDArray[np.float64]
    opponents_present: NDArray[np.bool_]


def heard_texts(obs: Mapping[str, Any]) -> list[str]:
    """The non-empty texts of ``obs`` heard from teammates or from oneself (opponents' dropped)."""
    texts = obs.get("heard_text", ())
    if not len(texts):
        return []
    info = np.asarray(obs.get("heard", np.zeros((0, 4))))
    if not len(info):
        return []
    ok = _heard_from_team(info).tolist()
    return [text for text, good in zip(texts, ok, strict=False) if text and good]


def _heard_from_team(info: NDArray[np.float64]) -> NDArray[np.bool_]:
    """(..., K) which heard slots of ``info`` (..., K, 4) hold a message from a teammate or
    from oneself (present, from self, from a teammate, direction)."""
    return (info[..., 0] > 0.5) & ((info[..., 1] > 0.5) | (info[..., 2] > 0.5))


def world_view(players: ArrayLike, ball: ArrayLike, opponents: ArrayLike | None = None,
               present: ArrayLike | None = None, fallen: ArrayLike | None = None,
               opponents_present: ArrayLike | None = None) -> WorldView:
    """A ``WorldView`` from arrays (metres, team frame); masks default to all present / upright."""
    p = np.asarray(players, dtype=np.float64)
    n = len(p)
    o = np.zeros((0, 2)) if opponents is None else np.asarray(opponents, dtype=np.float64)
    return WorldView(
        p,
        np.ones(n, dtype=bool) if present is None else np.asarray(present, dtype=bool),
        np.zeros(n, dtype=bool) if fallen is None else np.asarray(fallen, dtype=bool),
        np.asarray(ball, dtype=np.float64),
        o,
        np.ones(len(o), dtype=bool) if opponents_present is None
        else np.asarray(opponents_present, dtype=bool),
    )


class WorldModelError(TeamEnvError, ValueError):
    """An observation a world model cannot be built from (names the agent and the field)."""


@dataclass(frozen=True)
class WorldModel:
    """What agent ``me`` (index = uniform number - 1) believes this cycle (metres, radians).

    Attributes:
        me: own player index.
        position, heading, velocity, fallen: own pose, walking velocity and state.
        ball, ball_velocity: (2,) each.
        teammates: (N, 2), own row = own position; ``teammates_present``/``_fallen`` masks.
        opponents: (N, 2) with ``opponents_present``/``opponents_fallen``.
        play_mode: team-relative (``_Left`` = our team).
        time_s, half, score: game clock, half (1 or 2), (ours, theirs).
        heard: texts heard this cycle from teammates or oneself.
        field: the pitch.
        roll: the ball's drag model (to predict where a rolling ball goes).
        belief_key: bytes identifying everything but the own pose and the texts heard;
            teammates with equal keys believe the same about the pitch.
        ball_age_s: how old the ball belief is (0 in ``state`` mode; inf: unknown, and
            ``ball`` is only a placeholder).
        pose_spread_m: the localization's position spread (0 in ``state`` mode).
    """

    me: int
    position: NDArray[np.float64]
    heading: float
    velocity: NDArray[np.float64]
    fallen: bool
    ball: NDArray[np.float64]
    ball_velocity: NDArray[np.float64]
    teammates: NDArray[np.float64]
    teammates_present: NDArray[np.bool_]
    teammates_fallen: NDArray[np.bool_]
    opponents: NDArray[np.float64]
    opponents_present: NDArray[np.bool_]
    opponents_fallen: NDArray[np.bool_]
    play_mode: PlayMode
    time_s: float
    half: int
    score: tuple[int, int]
    heard: tuple[str, ...]
    field: FieldSpec
    roll: BallRoll = BallRoll()
    belief_key: bytes = b""
    ball_age_s: float = 0.0
    pose_spread_m: float = 0.0

    @property
    def ball_known(self) -> bool:
        """The agent has some idea where the ball is (``ball_age_s`` is finite)."""
        return math.isfinite(self.ball_age_s)

    @classmethod
    def from_observation(cls, obs: Mapping[str, Any], me: int, field: FieldSpec,
                         agent: str = "", roll: BallRoll | None = None,
                         resolution: float | None = BELIEF_RESOLUTION_M) -> WorldModel:
        """Build the world model of agent ``me`` from its Dict-form ``state`` observation.

        ``resolution``: positions are rounded to it (see ``BELIEF_RESOLUTION_M``); None keeps
        the observation's values."""
        try:
            v = team_frame(obs)
        except (KeyError, TypeError, ValueError) as exc:
            raise WorldModelError(
                f"{agent or f'player {me}'}: cannot read the observation ({type(exc).__name__}: "
                f"{exc}); the team needs Dict-form 'state' observations"
            ) from None
        if not (math.isfinite(v.position[0] + v.position[1] + v.ball[0] + v.ball[1])):
            raise WorldModelError(f"{agent or f'player {me}'}: observation 'self'/'ball' is not "
                                  f"finite: position={v.position.tolist()}, ball={v.ball.tolist()}")
        n = len(v.teammates)
        # one rounding pass over everything: rows 0..n-1 teammates, n..2n-1 opponents, then
        # own position, ball, ball velocity
        flat = np.concatenate((v.teammates, v.opponents, (v.position, v.ball, v.ball_velocity)))
        if resolution is not None:
            flat = _rounded(flat, resolution)
        mates, opponents = flat[:n], flat[n:2 * n]
        position, ball, ball_velocity = flat[2 * n], flat[2 * n + 1], flat[2 * n + 2]
        mates[me] = position
        present = v.teammates_present.copy()
        present[me] = True
        mates_fallen = v.teammates_fallen.copy()
        mates_fallen[me] = v.fallen
        key = b"".join((flat[:2 * n].tobytes(), flat[2 * n + 1:].tobytes(),
                        present.tobytes(), mates_fallen.tobytes(),
                        v.opponents_present.tobytes(), v.opponents_fallen.tobytes(),
                        int(v.play_mode).to_bytes(2, "little")))
        wm = cls(me, position, v.heading, v.velocity, v.fallen, ball, ball_velocity,
                 mates, present, mates_fallen, opponents, v.opponents_present,
                 v.opponents_fallen, v.play_mode, v.time_s, v.half, v.score,
                 tuple(heard_texts(obs)), field, roll or BallRoll(), key)
        wm.__dict__["_players"] = flat[:2 * n]  # the same rows, contiguous (for obstacles)
        return wm

    # -- derived beliefs -------------------------------------------------------------------
    @property
    def own_goal(self) -> NDArray[np.float64]:
        return np.array([-self.field.half_length, 0.0])

    @property
    def opponent_goal(self) -> NDArray[np.float64]:
        return np.array([self.field.half_length, 0.0])

    def distance(self, point: NDArray[np.float64]) -> float:
        return math.hypot(point[0] - self.position[0], point[1] - self.position[1])

    def ball_distance(self) -> float:
        return self.distance(self.ball)

    def upright_ball_distances(self) -> NDArray[np.float64]:
        """(N,) each teammate's distance to the ball (own row included); inf for teammates
        absent or fallen."""
        d = np.hypot(self.teammates[:, 0] - self.ball[0], self.teammates[:, 1] - self.ball[1])
        d[~(self.teammates_present & ~self.teammates_fallen)] = np.inf
        return d

    def positioning_view(self, anticipate: bool = False) -> WorldView:
        """The view ``strategy.positioning.PositioningAgent`` decides from (``anticipate``:
        with the ball where it will stop, so the team moves with a kick, not after it)."""
        ball = self.ball_rest() if anticipate else self.ball
        return WorldView(self.teammates, self.teammates_present, self.teammates_fallen,
                         ball, self.opponents, self.opponents_present)

    def obstacles(self, exclude_self: bool = True) -> NDArray[np.float64]:
        """(M, 2) positions of every present player but oneself (to walk around)."""
        rows, mask = self.obstacle_rows(exclude_self)
        return rows[mask]

    def obstacle_rows(self, exclude_self: bool = True
                      ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """(every player row: teammates then opponents, the mask of the present ones but
        oneself): ``obstacles() == rows[mask]``. Do not modify the mask."""
        mask = self.__dict__.get("_obstacle_mask") if exclude_self else None
        if mask is None:  # not precomputed by team_world_models
            mask = np.concatenate((self.teammates_present, self.opponents_present))
            if exclude_self:
                mask[self.me] = False
        both = self.__dict__.get("_players")
        if both is None:
            both = np.concatenate((self.teammates, self.opponents))
        return both, mask

    def we_control_ball(self) -> bool:
        """Our closest upright player is nearer the ball than theirs (or the ball is in their
        half and nobody of theirs is close); ``ball_controls`` of this model alone."""
        control = self.__dict__.get("_control")
        if control is None:  # computed once per world model (frozen: bypass __setattr__)
            control = self.__dict__["_control"] = ball_controls([self])[0]
        return control

    def ball_rest(self) -> NDArray[np.float64]:
        """Where the ball will stop rolling (on a free pitch). Do not modify the result."""
        rest = self.__dict__.get("_ball_rest")
        if rest is None:  # computed once per world model (frozen: bypass __setattr__)
            rest = self.__dict__["_ball_rest"] = self.roll.rest_point(self.ball,
                                                                      self.ball_velocity)
        return rest

    def intercepts(self, positions: NDArray[np.float64], speed_m_s: float,
                   step_s: float = INTERCEPT_STEP_S
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """For players at ``positions`` (M, 2) walking at ``speed_m_s``: the earliest time
        (s) each can be at the rolling ball, and where. A ball at rest: its distance / speed."""
        speed = math.hypot(self.ball_velocity[0], self.ball_velocity[1])
        horizon = self.roll.stop_time(speed)
        times = np.arange(0.0, horizon + step_s, step_s)
        path = self.roll.positions(self.ball, self.ball_velocity, times)  # (T, 2)
        gaps = np.hypot(positions[:, None, 0] - path[None, :, 0],
                        positions[:, None, 1] - path[None, :, 1])  # (M, T)
        reach = gaps / speed_m_s
        ok = reach <= times[None, :]
        first = np.where(ok.any(axis=1), ok.argmax(axis=1), len(times) - 1)
        when = np.maximum(reach[np.arange(len(positions)), first], times[first])
        return when, path[first]


def ball_controls(wms: Sequence[WorldModel]) -> list[bool]:
    """``we_control_ball`` of each of ``wms`` (one team's: equal numbers of players) in one
    pass over their stacked arrays, each from its own belief."""
    balls = np.array([wm.ball for wm in wms])
    ours = _nearest(np.array([wm.teammates for wm in wms]), balls,
                    np.array([wm.teammates_present & ~wm.teammates_fallen for wm in wms]))
    theirs = _nearest(np.array([wm.opponents for wm in wms]), balls,
                      np.array([wm.opponents_present & ~wm.opponents_fallen for wm in wms]))
    return ((ours < theirs - 0.3) | ((balls[:, 0] > 0) & (theirs > 3.0))).tolist()


def _nearest(players: NDArray[np.float64], balls: NDArray[np.float64],
             upright: NDArray[np.bool_]) -> NDArray[np.float64]:
    """(A,) each row's distance from its ball (A, 2) to its nearest upright player (A, N, 2);
    inf for none."""
    d = np.hypot(players[..., 0] - balls[:, 0, None], players[..., 1] - balls[:, 1, None])
    return np.where(upright, d, np.inf).min(axis=1, initial=np.inf)


def prime_team_facts(wms: Sequence[WorldModel]) -> None:
    """Fill each of ``wms``'s ``we_control_ball()`` and ``ball_rest()`` now, in one pass over
    the team (agents with beliefs of their own: vision mode); the same values as one by
    one. Models that already hold them are left alone."""
    by_roll: dict[int, list[WorldModel]] = {}
    for wm in wms:
        if "_ball_rest" not in wm.__dict__:
            by_roll.setdefault(id(wm.roll), []).append(wm)
    for todo in by_roll.values():
        rests = todo[0].roll.rest_points(np.array([wm.ball for wm in todo]),
                                         np.array([wm.ball_velocity for wm in todo]))
        for wm, rest in zip(todo, rests, strict=True):
            wm.__dict__["_ball_rest"] = rest
    todo = [wm for wm in wms if "_control" not in wm.__dict__]
    if todo:
        for wm, control in zip(todo, ball_controls(todo), strict=True):
            wm.__dict__["_control"] = control


def _rounded(values: NDArray[np.floating], r: float = BELIEF_RESOLUTION_M) -> NDArray[np.float64]:
    return np.round(np.asarray(values, dtype=np.float64) / r) * r + 0.0  # + 0.0: no -0.0


def shared(memo: dict | None, name: Hashable, wm: WorldModel, compute: Callable[[], T]) -> T:
    """``compute()``, cached in ``memo`` under ``name`` and the agent's beliefs: teammates
    who believe the same compute a team-wide fact once. A belief without a key (``vision``
    mode: nobody else believes exactly this) keeps its facts to itself, computed once per
    world model. Callers must not modify the result."""
    hit = _held(memo, name, wm)
    return _hold(memo, name, wm, compute()) if hit is _NOT_HELD else hit


def shared_rows_many(memo: dict | None, name: Hashable, wms: Sequence[WorldModel],
                     compute_many: Callable[[list[WorldModel]], NDArray[Any]]) -> NDArray[Any]:
    """(n, ...) row i = what ``shared(memo, name, wms[i], ...)`` holds, looked up once per
    distinct belief among ``wms`` (a team's agents mostly believe the same); the beliefs no
    memo holds computed in one call, ``compute_many(models)`` -> (len(models), ...) rows, row
    i ``models[i]``'s (a compiled pass over the team's beliefs). A new array: the caller may
    modify it."""
    distinct: list[WorldModel] = []
    index: list[int] = []
    seen: dict[bytes, int] = {}
    for wm in wms:
        k = seen.get(wm.belief_key, -1) if wm.belief_key else -1
        if k < 0:
            k = len(distinct)
            if wm.belief_key:
                seen[wm.belief_key] = k
            distinct.append(wm)
        index.append(k)
    rows: list[Any] = [_held(memo, name, wm) for wm in distinct]
    todo = [k for k, row in enumerate(rows) if row is _NOT_HELD]
    if todo:
        computed = compute_many([distinct[k] for k in todo])
        for k, row in zip(todo, computed, strict=True):
            rows[k] = _hold(memo, name, distinct[k], row)
    table = np.array(rows)
    return table if len(rows) == len(index) else table[index]


_NOT_HELD = object()


def _held(memo: dict | None, name: Hashable, wm: WorldModel) -> Any:
    """What ``shared`` holds for ``name`` and ``wm``'s belief, else ``_NOT_HELD``."""
    if not wm.belief_key:
        return wm.__dict__.get("_facts", {}).get(name, _NOT_HELD)
    return _NOT_HELD if memo is None else memo.get((name, wm.belief_key), _NOT_HELD)


def _hold(memo: dict | None, name: Hashable, wm: WorldModel, value: T) -> T:
    """Keep ``value`` where ``shared`` looks for ``name`` and ``wm``'s belief."""
    if not wm.belief_key:
        wm.__dict__.setdefault("_facts", {})[name] = value  # frozen: bypass __setattr__
    elif memo is not None:
        remember(memo, (name, wm.belief_key), value)
    return value
