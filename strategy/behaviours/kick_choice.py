"""Where to kick: every kick is a race to where the ball stops.

A kick sends the ball as far as the body kicks (``BodyCapabilities``: the profile's mean and
s.d. of a full-power kick, e.g. 8.92 m +- 3.82 m for ``t1_mj``, 1.17 m +- 0.91 m for
``t1_league``, and its aim error), and players walk at the body's real speed, so whoever is
first at the landing point has the ball next. ``best_kick`` scores candidate landing points
(a fan of directions at a few powers, plus shots at the goal mouth) by

    value = possession_weight * tanh(margin / 2) + progress_weight * forward gain
            + goal_weight * P(goal)                               (a shot)
            + goal_weight * follow_up * P(we win) * P(goal from there)   (any other kick)

where ``margin`` (s) is how much sooner our nearest teammate than their nearest player can
reach the landing point (the kicker stands for the kick's duration first; a fallen player
needs its get-up time first), and ``P(goal)`` is the chance the kick's distance and aim
spread put the ball inside the goal mouth; a pass is also worth part (``follow_up``) of the
shot its receiver can take next. A lane an opponent stands in gives the ball to them. Kicks
at the goal mouth are raced for, and credited with ground, at the goal line (see
``best_kick``): a deliberate bias towards kicking at the goal. Every body fact comes from the
``body`` argument (the team's ``TeamContext.body``); this module holds none.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.special import ndtr

import portable_math as pm
from strategy.perception.worldmodel import WorldModel
from teamenv.capabilities import BodyCapabilities

LANE_M = 0.45
"""An opponent this close to the ball's path (before it stops) takes the ball."""

POST_MARGIN_M = 0.15
"""A shot on target passes at least this far inside a post."""

MIN_SHOT_CHANCE = 0.05
"""A kick at the goal with less chance than this is reported as a long kick, not a shot."""

DIRECTIONS = np.deg2rad(np.arange(-90, 91, 15))
POWERS = (0.5, 0.75, 1.0)


@dataclass(frozen=True)
class KickChoice:
    """A kick: aim point (team frame), power, its value, the race margin (s), whether it is
    aimed at the goal mouth, and its chance of a goal."""

    target: NDArray[np.float64]
    power: float
    value: float
    margin_s: float
    shot: bool
    goal_chance: float = 0.0


def goal_probability(wm: WorldModel, aim: NDArray[np.float64], power: float,
                     body: BodyCapabilities) -> float:
    """Chance a kick by ``body`` from the ball at ``aim`` with ``power`` ends in the goal:
    the aim error must keep it inside the posts and the distance must carry it over the
    line."""
    return float(goal_chances(wm.field.half_length, wm.field.half_goal_width,
                              wm.ball[None, :], np.asarray(aim, dtype=np.float64)[None, :],
                              np.array([power]), body)[0])


def goal_chances(half_length: float, half_goal_width: float, balls: NDArray[np.float64],
                 aims: NDArray[np.float64], powers: NDArray[np.float64],
                 body: BodyCapabilities) -> NDArray[np.float64]:
    """(P,) ``goal_probability`` for kicks from ``balls`` (P, 2) at ``aims`` (P, 2)."""
    dx = half_length - balls[:, 0]
    ahead = dx > 0
    dx = np.where(ahead, dx, 1.0)
    to_aim = pm.arctan2(aims[:, 1] - balls[:, 1], aims[:, 0] - balls[:, 0])
    low = pm.arctan2(-half_goal_width + POST_MARGIN_M - balls[:, 1], dx)
    high = pm.arctan2(half_goal_width - POST_MARGIN_M - balls[:, 1], dx)
    aim_sd = max(body.kick_aim_sd_rad, 1e-9)
    p_aim = ndtr((high - to_aim) / aim_sd) - ndtr((low - to_aim) / aim_sd)
    needed = np.hypot(dx, balls[:, 1]) / np.maximum(powers, 1e-6)
    p_far = ndtr((body.kick_distance_mean_m - needed) / max(body.kick_distance_sd_m, 1e-9))
    return np.where(ahead & (high > low), np.maximum(p_aim, 0.0) * p_far, 0.0)


def best_kick(wm: WorldModel, body: BodyCapabilities, walk_speed: float,
              possession_weight: float, progress_weight: float, goal_weight: float,
              follow_up: float = 0.0, exclude: tuple[int, ...] = ()) -> KickChoice:
    """The most valuable kick by ``body`` from where the ball is (see the module doc);
    ``walk_speed`` (m/s): how fast players really run to the landing point.

    The candidates: a fan of ``DIRECTIONS`` about the line to the goal centre at each of
    ``POWERS`` (ending at the body's mean reach), and shots at three points of the goal
    mouth. A kick at the goal mouth is credited (race and ground gained) at the goal line,
    not where a mean kick would stop: a deliberate bias towards kicking at the goal. The
    ball goes in, goes out for a corner or goal kick, or is fought for in their box; against
    the built-in opponents this beat racing it at the mean kick length (2-0 vs 0-0). A
    player seen lying needs its get-up first (its fall is mostly over when it is seen down).
    A shot through a crowd keeps half its chance (deflections). A pass is worth the shot its
    receiver can take from where it wins the ball. Scored in compiled loops
    (``kick_kernel``), the normal CDF in one SciPy call."""
    kernel = _kernel()
    f = wm.field
    shots, powers, is_shot = _candidates(f.half_length, f.half_goal_width)
    mates_usable = np.array(wm.teammates_present, dtype=bool)
    for k in exclude:
        mates_usable[k] = False
    mates_usable[wm.me] = False
    total = len(powers)
    cand = np.empty((kernel.ROWS, total))
    z = np.empty(6 * total)
    shot_ok, used = kernel.candidates(
        _floats(wm.ball), _floats(wm.opponent_goal), _floats(wm.position),
        _floats(wm.teammates), mates_usable, _bools(wm.teammates_fallen), _floats(wm.opponents),
        _bools(wm.opponents_present), _bools(wm.opponents_fallen), DIRECTIONS, _POWERS, shots,
        is_shot, np.array((f.half_length, f.half_width, f.half_goal_width, LANE_M, POST_MARGIN_M)),
        np.array((body.kick_distance_mean_m, walk_speed, body.getup_s, body.kick_duration_s,
                  max(body.kick_aim_sd_rad, 1e-9), max(body.kick_distance_sd_m, 1e-9))),
        cand, z)
    value, p_goal = np.empty(total), np.empty(total)
    k = kernel.choose(float(wm.ball[0]), cand, is_shot, shot_ok, ndtr(z[:used]),
                      np.array((possession_weight, progress_weight, goal_weight, follow_up)),
                      value, p_goal)
    return KickChoice(cand[kernel.END_X:kernel.END_Y + 1, k].copy(), float(powers[k]),
                      float(value[k]), float(cand[kernel.MARGIN, k]), bool(is_shot[k]),
                      float(p_goal[k]) if is_shot[k] else 0.0)


@functools.cache
def _kernel():
    """The compiled loops, imported on the first kick choice (numba takes a few tenths of a
    second to import)."""
    from strategy.behaviours import kick_kernel

    return kick_kernel


def prepare_kernel() -> None:
    """Compile (or load from numba's cache) the kernel's loops now, before a match's first
    cycle runs under its stall watchdog: a cold compile takes seconds."""
    kernel = _kernel()
    shots, powers, is_shot = _candidates(10.0, 1.0)
    two, mask = np.zeros((2, 2)), np.ones(2, dtype=bool)
    cand, z = np.empty((kernel.ROWS, len(powers))), np.zeros(6 * len(powers))
    kernel.candidates(np.zeros(2), np.array((10.0, 0.0)), np.zeros(2), two, mask, ~mask, two,
                      mask, ~mask, DIRECTIONS, _POWERS, shots, is_shot,
                      np.array((10.0, 7.0, 1.0, LANE_M, POST_MARGIN_M)),
                      np.ones(6), cand, z)
    kernel.choose(0.0, cand, is_shot, True, z, np.ones(4), np.empty(len(powers)),
                  np.empty(len(powers)))


def _floats(x) -> NDArray[np.float64]:
    return np.ascontiguousarray(x, dtype=np.float64)


def _bools(x) -> NDArray[np.bool_]:
    return np.ascontiguousarray(x, dtype=bool)


_POWERS = np.array(POWERS)
_CANDIDATES: dict[tuple[float, float], tuple[NDArray[np.float64], NDArray[np.float64],
                                             NDArray[np.bool_]]] = {}


def _candidates(half_length: float, half_goal_width: float
                ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """The fixed part of ``best_kick``'s candidates on a pitch: the shots' aim points at the
    goal mouth, every candidate's power and which are shots (after the fan of directions at
    each of ``POWERS``). Held per pitch; do not modify."""
    key = (half_length, half_goal_width)
    fixed = _CANDIDATES.get(key)
    if fixed is None:
        ys = np.linspace(-0.6, 0.6, 3) * half_goal_width
        shots = np.column_stack([np.full(len(ys), half_length + 1.0), ys])
        powers = np.array([p for p in POWERS for _ in DIRECTIONS] + [1.0] * len(shots))
        is_shot = np.zeros(len(powers), dtype=bool)
        is_shot[-len(shots):] = True
        fixed = _CANDIDATES[key] = (shots, powers, is_shot)
    return fixed
