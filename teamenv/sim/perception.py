"""Perception: builds every agent's `state`-mode observation at once, in its team's frame."""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import Any

import numpy as np

from teamenv.box_layout import (
    HEARD_DIM,
    PLAYER_DIM,
    SELF_DIM,
    StackedState,
    StateLayout,
    play_mode_and_game_block,
)
from teamenv.sim.playmode import PlayMode


@functools.cache
def _state_rows():
    """The compiled row kernel, imported on the first observation: importing numba takes a
    few tenths of a second that ``import teamenv`` should not pay."""
    from teamenv.sim.kernels import state_rows

    return state_rows


class StatePerception:
    """Egocentric true-state observations for 2N agents (players 0..N-1 left, N..2N-1 right).

    Each team sees the world rotated so it attacks +x: a right-team agent's world is turned
    by pi (x -> -x, y -> -y, heading -> heading + pi), which keeps left and right turns
    (a mirror would swap them). Positions of the ball and players are relative to the agent,
    in its body frame; ``self`` is absolute in the team frame.
    """

    def __init__(self, team_size: int, heard_slots: int) -> None:
        self.team_size = team_size
        self.heard_slots = heard_slots
        self.team_of = np.repeat([0, 1], team_size)
        n = 2 * team_size
        self._team_list = self.team_of.tolist()
        # Column order of the players for each agent: own team first (uniform order).
        order = [np.arange(n), np.r_[np.arange(team_size, n), np.arange(team_size)]]
        self._cols = np.stack([order[t] for t in self._team_list]) if n else \
            np.zeros((0, 0), dtype=np.intp)
        # One float32 row per agent, laid out as the flat observation (``StateLayout``); the
        # Dict parts are views of it. The kernel writes player columns 5 wide.
        assert PLAYER_DIM == 5
        self.layout = StateLayout(team_size, heard_slots)
        offsets = self.layout.offsets
        self._o_ball = offsets["ball"][0]
        self._o_players = offsets["teammates"][0]
        self._o_mode = offsets["play_mode"][0]
        self._o_game = offsets["game"][0]
        self._o_heard = offsets["heard"][0]
        self._offsets = np.array([self._o_ball, self._o_players, self._o_mode, self._o_game,
                                  self._o_heard], dtype=np.intp)
        self._width = self.layout.size
        # Parts that change only with the attack directions, play mode, half or score.
        self._sign_key: tuple | None = None
        self._block_key: tuple | None = None

    def observe(
        self, poses: np.ndarray, velocities: np.ndarray, ball: np.ndarray, fallen: np.ndarray,
        mode: PlayMode, time_s: float, half: int, score: Sequence[int],
        attack_sign: Sequence[float], heard_info: np.ndarray, heard_texts: Sequence[tuple],
        flat: bool = False, lazy: bool = False,
    ) -> list[Any]:
        """Observations of all 2N agents, in player order (Dict form, or rows when ``flat``).
        ``lazy`` (Dict form): an ``ObservationRows`` sequence whose dicts are built on first
        access, with the same values as the list.

        ``heard_info`` (n, K, 4): present, from self, from a teammate, direction per heard
        slot; ``heard_texts``: per agent, a tuple of K texts ("" = empty slot)."""
        n = len(poses)
        team_of = self.team_of
        key = tuple(attack_sign)
        if key != self._sign_key:
            self._sign = np.asarray(attack_sign, dtype=float)[team_of]  # (n,)
            self._sign_key = key
        # Play-mode one-hot, half and scores: rebuilt only when one of them changes.
        modes = (int(mode), int(mode.for_team(1)))
        key = (modes, half, tuple(score))
        if key != self._block_key:
            self._block = play_mode_and_game_block(team_of, modes, half, score)
            self._block_key = key
            self._team_modes = [modes[t] for t in self._team_list]
        h = poses[:, 2]
        out = np.empty((n, self._width), dtype=np.float32)
        _state_rows()(
            poses, velocities, ball, fallen, np.cos(h), np.sin(h), self._sign, self._cols,
            self._block, time_s, heard_info.reshape(n, -1), self._offsets, out)
        if flat:
            return list(out)
        observations = ObservationRows(self, out, heard_texts)
        return observations if lazy else list(observations)


class ObservationRows(Sequence):
    """The Dict observations of one ``StatePerception.observe`` call, each agent's dict built
    on first access (then kept): the same dicts, of the same views, as the eager list."""

    __slots__ = ("_out", "_texts", "_modes", "_built", "_spans", "_size", "_heard_shape")

    def __init__(self, perception: StatePerception, out: np.ndarray,
                 heard_texts: Sequence[tuple]) -> None:
        self._out = out
        self._texts = heard_texts
        self._modes = perception._team_modes
        self._built: list[dict | None] = [None] * len(out)
        p = perception
        self._spans = (p._o_ball, p._o_players, p._o_mode, p._o_game, p._o_heard)
        self._size = p.team_size
        self._heard_shape = (p.heard_slots, HEARD_DIM)

    def __len__(self) -> int:
        return len(self._built)

    def stacked(self, rows: Sequence[int]) -> StackedState:
        """The observations of agents ``rows`` (player indices) as one array of their flat
        rows, for a team that reads its agents together instead of dict by dict: the values
        every Dict view of those agents holds (a copy, taken now)."""
        rows = list(rows)
        return StackedState(self._out[rows], [self._texts[r] for r in rows],
                            [self._modes[r] for r in rows], self._spans, self._size,
                            self._heard_shape)

    def __getitem__(self, i):  # type: ignore[override]
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        obs = self._built[i]
        if obs is None:
            row = self._out[i]
            o_ball, o_players, o_mode, o_game, o_heard = self._spans
            players = row[o_players:o_mode].reshape(-1, PLAYER_DIM)
            size = self._size
            obs = self._built[i] = {
                "self": row[:SELF_DIM], "ball": row[o_ball:o_players],
                "teammates": players[:size], "opponents": players[size:],
                "play_mode": self._modes[i], "game": row[o_game:o_heard],
                "heard_text": self._texts[i],
                "heard": row[o_heard:].reshape(self._heard_shape)}
        return obs
