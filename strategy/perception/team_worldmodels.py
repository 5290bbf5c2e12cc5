"""The world models of a whole team from their ``state`` observations, in one numpy pass.

``WorldModel.from_observation`` reads one agent's egocentric observation; a team of eleven
calling it eleven times spends most of the time in Python overhead on tiny arrays. Here the
team's observations are stacked and rotated, rounded and keyed together. Each agent still gets
the world model of *its own* observation — only the arithmetic is batched, with the same IEEE
operations in the same order, so every value (and every ``belief_key``) is bit-identical to
``from_observation`` (tested). Observations that are not the env's regular Dict form go
through ``from_observation`` one by one, which names the agent and field in its error.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import numpy as np

from strategy.geometry import BallRoll
from strategy.perception.worldmodel import (
    BELIEF_RESOLUTION_M,
    WorldModel,
    _heard_from_team,
    heard_texts,
)
from teamenv.box_layout import PLAYER_DIM, StackedState
from teamenv.field import FieldSpec
from teamenv.observation import play_mode_of

_new_model = object.__new__


def team_world_models(observations: Mapping[str, Mapping[str, Any]],
                      index: Mapping[str, int], field: FieldSpec,
                      roll: BallRoll | None = None,
                      resolution: float | None = BELIEF_RESOLUTION_M,
                      ball_rest: bool = False) -> dict[str, WorldModel]:
    """``{agent: WorldModel.from_observation(obs, index[agent], field, agent, roll,
    resolution)}`` for every agent in ``observations``, computed per team.

    ``ball_rest``: also fill each model's ``ball_rest()`` now, once for all agents that see
    the same ball (teams that anticipate the ball, like ``full``, read it every cycle)."""
    agents = list(observations)
    if not agents:
        return {}
    block = _stacked(observations)
    stacked = _from_block(block) if block is not None else _stack(observations, agents)
    if stacked is None:
        return _one_by_one(observations, index, field, roll, resolution)
    selfs, balls, players, n = stacked
    agents_n = len(agents)
    count = players.shape[1]
    # rows 0..n-1 teammates, n..count-1 opponents, then own position, ball, ball velocity
    flat = np.empty((agents_n, count + 3, 2))
    present, mates_fallen = np.empty((agents_n, n), bool), np.empty((agents_n, n), bool)
    opponents_present = np.empty((agents_n, n), bool)
    opponents_fallen = np.empty((agents_n, n), bool)
    obstacle_mask = np.empty((agents_n, 2 * n), bool)
    me_rows = np.array([index[agent] for agent in agents], dtype=np.intp)
    if not (0 <= me_rows.min() and me_rows.max() < n):
        return _one_by_one(observations, index, field, roll, resolution)  # it names the agent
    if not _kernel().team_rows(selfs, balls, players, n, me_rows,
                               np.nan if resolution is None else float(resolution), flat,
                               present, mates_fallen, opponents_present, opponents_fallen,
                               obstacle_mask):
        return _one_by_one(observations, index, field, roll, resolution)  # it names the agent
    heading = selfs[:, 2]
    fallen_self = selfs[:, 6] > 0.5
    modes = [play_mode_of(mode) for mode in (
        block.play_modes if block is not None else
        [observations[agent]["play_mode"] for agent in agents])]
    # belief keys: everything but the own pose and the texts heard, as bytes (one row each)
    keys = np.concatenate((
        flat[:, :count].reshape(agents_n, -1).view(np.uint8),
        flat[:, count + 1:].reshape(agents_n, -1).view(np.uint8),
        present.view(np.uint8), mates_fallen.view(np.uint8),
        opponents_present.view(np.uint8), opponents_fallen.view(np.uint8),
        np.array(modes, dtype="<u2").view(np.uint8).reshape(agents_n, 2)), axis=1)
    headings, vx, vy = heading.tolist(), selfs[:, 3].tolist(), selfs[:, 4].tolist()
    fallen_list = fallen_self.tolist()
    if block is not None:
        games = block.values[:, block.spans[3]:block.spans[4]].tolist()
        heard = _heard_texts(block.values[:, block.spans[4]:].astype(np.float64).reshape(
            (len(agents),) + block.heard_shape), block.heard_texts)
    else:
        games = [observations[agent]["game"] for agent in agents]
        heard = _heard(observations, agents)
    roll = roll or BallRoll()
    rests: dict[bytes, Any] = {}
    out = {}
    for a, agent in enumerate(agents):
        rows = flat[a]
        game = games[a]
        wm = _new_model(WorldModel)
        # a frozen dataclass: fill its instance dict (what __init__ would store)
        wm.__dict__.update(
            me=int(me_rows[a]), position=rows[count], heading=headings[a],
            velocity=np.array((vx[a], vy[a])), fallen=fallen_list[a], ball=rows[count + 1],
            ball_velocity=rows[count + 2], teammates=rows[:n], teammates_present=present[a],
            teammates_fallen=mates_fallen[a], opponents=rows[n:count],
            opponents_present=opponents_present[a], opponents_fallen=opponents_fallen[a],
            play_mode=modes[a], time_s=float(game[0]),
            half=int(game[1]), score=(int(game[2]), int(game[3])),
            heard=heard[a] if heard is not None else tuple(heard_texts(observations[agent])),
            field=field,
            roll=roll,
            belief_key=keys[a].tobytes(), ball_age_s=0.0, pose_spread_m=0.0,
            _players=rows[:count], _obstacle_mask=obstacle_mask[a])
        if ball_rest:  # the same pure function of the same ball: computed once per team
            ball_key = rows[count + 1:].tobytes()
            rest = rests.get(ball_key)
            if rest is None:
                rest = rests[ball_key] = roll.rest_point(rows[count + 1], rows[count + 2])
            wm.__dict__["_ball_rest"] = rest
        out[agent] = wm
    return out


def _stack(observations: Mapping[str, Mapping[str, Any]], agents: list[str]):
    """(selfs (A, 7+), balls (A, 4+), players (A, 2n, 5), n) in float64, or None when the
    observations are not all the env's regular Dict form of one shape."""
    if not agents:
        return None
    try:
        first = observations[agents[0]]
        n = len(first["teammates"])
        selfs = np.array([observations[a]["self"] for a in agents], dtype=np.float64)
        balls = np.array([observations[a]["ball"] for a in agents], dtype=np.float64)
        mates = np.array([observations[a]["teammates"] for a in agents], dtype=np.float64)
        opps = np.array([observations[a]["opponents"] for a in agents], dtype=np.float64)
    except (KeyError, TypeError, ValueError):
        return None
    if (selfs.ndim != 2 or selfs.shape[1] < 7 or balls.ndim != 2 or balls.shape[1] < 4
            or mates.ndim != 3 or mates.shape[2] < 5 or opps.ndim != 3
            or opps.shape[1] != n or opps.shape[2] != mates.shape[2]):
        return None
    return selfs, balls, np.concatenate((mates, opps), axis=1), n


@functools.cache
def _kernel():
    """The compiled rows (``worldmodel_kernel``), imported on first use (numba takes a few
    tenths of a second to import)."""
    from strategy.perception import worldmodel_kernel

    return worldmodel_kernel


def prepare_kernel() -> None:
    """Compile (or load from numba's cache) the kernel now, before a match's first cycle
    runs under its stall watchdog."""
    one = np.zeros((1, 2, PLAYER_DIM))
    masks = [np.empty((1, 1), bool) for _ in range(4)]
    _kernel().team_rows(np.zeros((1, 7)), np.zeros((1, 4)), one, 1, np.zeros(1, np.intp),
                        0.01, np.empty((1, 5, 2)), *masks, np.empty((1, 2), bool))


def _stacked(observations: Mapping[str, Any]) -> StackedState | None:
    """The env's stacked rows of these observations, where it hands them over that way
    (``teamenv.lazy.LazyObservations.stacked``: no per-agent dicts built)."""
    stacked = getattr(observations, "stacked", None)
    return stacked() if callable(stacked) else None


def _from_block(block: StackedState):
    """``_stack``'s arrays from the env's stacked rows (the same float64 values: each
    float32 entry converted exactly, as ``np.array(..., dtype=np.float64)`` of the views)."""
    values = block.values
    o_ball, o_players, o_mode = block.spans[0], block.spans[1], block.spans[2]
    selfs = values[:, :o_ball].astype(np.float64)
    balls = values[:, o_ball:o_players].astype(np.float64)
    players = values[:, o_players:o_mode].astype(np.float64).reshape(len(values), -1,
                                                                     PLAYER_DIM)
    return selfs, balls, players, block.team_size


def _heard(observations: Mapping[str, Mapping[str, Any]],
           agents: list[str]) -> list[tuple[str, ...]] | None:
    """Per agent, ``heard_texts`` of its observation, the slot tests in one pass (None when
    the slots are not all of one shape: then one by one)."""
    try:
        info = np.array([observations[a]["heard"] for a in agents], dtype=np.float64)
        texts = [observations[a]["heard_text"] for a in agents]
    except (KeyError, ValueError, TypeError):
        return None
    return _heard_texts(info, texts)


def _heard_texts(info: np.ndarray, texts: list) -> list[tuple[str, ...]] | None:
    """Per agent, the texts of its heard slots that pass ``_heard_from_team`` (``info``:
    (agents, slots, columns) float64)."""
    if info.ndim != 3 or info.shape[2] < 3:
        return None
    ok = _heard_from_team(info).tolist()
    return [tuple(t for t, good in zip(said, fine, strict=False) if t and good)
            for said, fine in zip(texts, ok, strict=True)]


def _one_by_one(observations, index, field, roll, resolution) -> dict[str, WorldModel]:
    return {agent: WorldModel.from_observation(obs, index[agent], field, agent, roll, resolution)
            for agent, obs in observations.items()}

