"""Perception: builds every agent's `state`-mode observation at once, in its team's frame."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from teamenv.box_layout import (
    HEARD_DIM,
    PLAYER_DIM,
    SELF_DIM,
    StateLayout,
    play_mode_and_game_block,
)
from teamenv.sim.playmode import PlayMode
from teamenv.sim.world import wrap_angle as _wrap


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
        # One float64 row per agent, laid out as the flat observation (``StateLayout``); the
        # Dict parts are views of its float32 copy.
        self.layout = StateLayout(team_size, heard_slots)
        offsets = self.layout.offsets
        self._o_ball = offsets["ball"][0]
        self._o_players = offsets["teammates"][0]
        self._o_mode = offsets["play_mode"][0]
        self._o_game = offsets["game"][0]
        self._o_heard = offsets["heard"][0]
        self._width = self.layout.size
        # Parts that change only with the attack directions, play mode, half or score.
        self._sign_key: tuple | None = None
        self._block_key: tuple | None = None
        self._buffer: np.ndarray | None = None

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
        # A scratch buffer kept between calls (``out`` below is a copy): its constant "present"
        # column and the play-mode/half/score block are written only when they change.
        rows = self._buffer
        if rows is None or len(rows) != n:
            rows = self._buffer = np.empty((n, self._width))
            rows[:, self._o_players:self._o_mode].reshape(n, n, PLAYER_DIM)[:, :, 4] = 1.0
            self._block_key = None
            # x (or y) of every other player (own team first), then of the ball, then the
            # ball's velocity component: (n, n + 2), rotated into each body frame at once.
            self._dx = np.empty((n, n + 2))
            self._dy = np.empty((n, n + 2))
        key = tuple(attack_sign)
        if key != self._sign_key:
            sign = np.asarray(attack_sign, dtype=float)[team_of]  # (n,)
            self._sign, self._sign2, self._sign_pos = sign, sign[:, None], sign > 0
            self._sign_key = key
        sign2 = self._sign2
        x, y, h = poses[:, 0], poses[:, 1], poses[:, 2]
        cos_h, sin_h = np.cos(h), np.sin(h)

        rows[:, 0:2] = sign2 * poses[:, :2]
        rows[:, 2] = np.where(self._sign_pos, h, _wrap(h + np.pi))
        rows[:, 3:5] = sign2 * velocities[:, :2]
        rows[:, 5] = velocities[:, 2]
        rows[:, 6] = fallen

        # Every other player (own team first), the ball and the ball's velocity, relative to
        # each agent in its body frame: x' = c dx + s dy, y' = -s dx + c dy.
        cols = self._cols
        dx, dy, col_x = self._dx, self._dy, x[:, None]
        np.subtract(x[cols], col_x, out=dx[:, :n])
        np.subtract(ball[0], x, out=dx[:, n])
        dx[:, n + 1] = ball[2]
        np.subtract(y[cols], y[:, None], out=dy[:, :n])
        np.subtract(ball[1], y, out=dy[:, n])
        dy[:, n + 1] = ball[3]
        c, s, ms = cos_h[:, None], sin_h[:, None], -sin_h[:, None]
        along = c * dx + s * dy
        across = ms * dx + c * dy
        rel = rows[:, self._o_players:self._o_mode].reshape(n, n, PLAYER_DIM)
        rel[:, :, 0] = along[:, :n]
        rel[:, :, 1] = across[:, :n]
        o = self._o_ball
        rows[:, o:o + 4:2] = along[:, n:]  # ball x, ball vx
        rows[:, o + 1:o + 4:2] = across[:, n:]  # ball y, ball vy
        rel[:, :, 2] = _wrap(h[cols] - h[:, None])
        rel[:, :, 3] = fallen[cols]

        # Play-mode one-hot, half and scores: rebuilt only when one of them changes.
        modes = (int(mode), int(mode.for_team(1)))
        key = (modes, half, tuple(score))
        if key != self._block_key:
            self._block = play_mode_and_game_block(team_of, modes, half, score)
            self._block_key = key
            self._team_modes = [modes[t] for t in self._team_list]
            rows[:, self._o_mode:self._o_heard] = self._block
        rows[:, self._o_game] = time_s
        rows[:, self._o_heard:] = heard_info.reshape(n, -1)

        out = rows.astype(np.float32)
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
