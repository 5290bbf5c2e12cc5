"""Reflexes a policy file may ask for on top of its network (``kick_gate_m``,
``walk_to_ball``): rules over Box actions that read where the ball is in a ``state``-mode Box
observation, applied every cycle."""

from __future__ import annotations

import numpy as np

import portable_math as pm
from teamenv.box_layout import KICK_POWER, WALK, StateLayout

#: Columns of the ball's position relative to the player (body frame, ``ball.rel_x``,
#: ``ball.rel_y``) in a state-mode Box observation: the same for every team size.
_BALL_START = StateLayout(0, 0).offsets["ball"][0]
_BALL_REL = slice(_BALL_START, _BALL_START + 2)
_VX, _VY, _VTURN = range(WALK.start, WALK.stop)


def gate_kicks(obs_batch: np.ndarray, actions: np.ndarray, gate_m: float) -> np.ndarray:
    """``actions`` (Box, one row per agent) with the kick power set to 0 on rows whose
    state-mode observation puts the ball farther than ``gate_m`` metres away."""
    rel = np.asarray(obs_batch, dtype=np.float64)[:, _BALL_REL]
    far = np.hypot(rel[:, 0], rel[:, 1]) > gate_m
    if far.any():
        actions = actions.copy()
        actions[far, KICK_POWER] = 0.0
    return actions


def approach_ball(obs_batch: np.ndarray, actions: np.ndarray, gate_m: float) -> np.ndarray:
    """``actions`` with the walk entries (Box units) replaced: towards the ball (turn rate
    2 x its bearing, clipped; full speed ahead when the bearing is within 0.6 rad, 0.2
    otherwise) on rows whose state-mode observation puts the ball farther than ``gate_m``,
    zero (stand for the kick) on the others."""
    rel = np.asarray(obs_batch, dtype=np.float64)[:, _BALL_REL]
    bearing = pm.arctan2(rel[:, 1], rel[:, 0])
    far = np.hypot(rel[:, 0], rel[:, 1]) > gate_m
    actions = actions.copy()
    actions[:, _VX] = np.where(far, np.where(np.abs(bearing) < 0.6, 1.0, 0.2), 0.0)
    actions[:, _VY] = 0.0
    actions[:, _VTURN] = np.where(far, np.clip(2.0 * bearing, -1.0, 1.0), 0.0)
    return actions


def apply_reflexes(obs_batch: np.ndarray, actions: np.ndarray, kick_gate_m: float | None,
                   walk_to_ball: bool) -> np.ndarray:
    """A policy file's reflexes on ``actions``: the walk at the ball (``walk_to_ball``), then
    the kick gate (``kick_gate_m``; None: neither)."""
    if kick_gate_m is None:
        return actions
    if walk_to_ball:
        actions = approach_ball(obs_batch, actions, kick_gate_m)
    return gate_kicks(obs_batch, actions, kick_gate_m)
