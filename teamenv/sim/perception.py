"""Perception: builds every agent's `state`-mode observation at once, in its team's frame."""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from teamenv.sim.playmode import PlayMode
from teamenv.sim.world import wrap_angle as _wrap

SELF_DIM, BALL_DIM, PLAYER_DIM, GAME_DIM, HEARD_DIM = 7, 4, 5, 4, 4
N_PLAY_MODES = len(PlayMode)


class HeardSlot:
    """What one listener heard this cycle, in slot order (0 self, 1 teammate, 2 opponent...)."""

    __slots__ = ("texts", "info")

    def __init__(self, n_slots: int) -> None:
        self.texts: list[str] = [""] * n_slots
        self.info = np.zeros((n_slots, HEARD_DIM))


def flat_observation_size(team_size: int, heard_slots: int) -> int:
    """Length of the flat (Box) observation vector."""
    return SELF_DIM + BALL_DIM + 2 * team_size * PLAYER_DIM + N_PLAY_MODES + GAME_DIM + \
        heard_slots * HEARD_DIM


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

    def observe(
        self, poses: np.ndarray, velocities: np.ndarray, ball: np.ndarray, fallen: np.ndarray,
        mode: PlayMode, time_s: float, half: int, score: Sequence[int],
        attack_sign: Sequence[float], heard: Sequence[HeardSlot], flat: bool = False,
    ) -> list[Any]:
        """Observations of all 2N agents, in player order (Dict form, or rows when ``flat``)."""
        n, size = len(poses), self.team_size
        sign = np.asarray(attack_sign, dtype=float)[self.team_of]  # (n,)
        x, y, h = poses[:, 0], poses[:, 1], poses[:, 2]
        cos_h, sin_h = np.cos(h), np.sin(h)

        self_obs = np.empty((n, SELF_DIM))
        self_obs[:, 0] = sign * x
        self_obs[:, 1] = sign * y
        self_obs[:, 2] = np.where(sign > 0, h, _wrap(h + np.pi))
        self_obs[:, 3] = sign * velocities[:, 0]
        self_obs[:, 4] = sign * velocities[:, 1]
        self_obs[:, 5] = velocities[:, 2]
        self_obs[:, 6] = fallen

        bdx, bdy = ball[0] - x, ball[1] - y
        ball_obs = np.empty((n, BALL_DIM))
        ball_obs[:, 0] = cos_h * bdx + sin_h * bdy
        ball_obs[:, 1] = -sin_h * bdx + cos_h * bdy
        ball_obs[:, 2] = cos_h * ball[2] + sin_h * ball[3]
        ball_obs[:, 3] = -sin_h * ball[2] + cos_h * ball[3]

        dx = x[None, :] - x[:, None]
        dy = y[None, :] - y[:, None]
        rel = np.empty((n, n, PLAYER_DIM))
        rel[:, :, 0] = cos_h[:, None] * dx + sin_h[:, None] * dy
        rel[:, :, 1] = -sin_h[:, None] * dx + cos_h[:, None] * dy
        rel[:, :, 2] = _wrap(h[None, :] - h[:, None])
        rel[:, :, 3] = fallen[None, :]
        rel[:, :, 4] = 1.0
        left, right = rel[:, :size], rel[:, size:]
        # Own team first for every agent.
        mates = np.where(self.team_of[:, None, None] == 0, left, right)
        opponents = np.where(self.team_of[:, None, None] == 0, right, left)

        game = np.empty((n, GAME_DIM))
        game[:, 0] = time_s
        game[:, 1] = half
        game[:, 2] = np.where(self.team_of == 0, score[0], score[1])
        game[:, 3] = np.where(self.team_of == 0, score[1], score[0])
        modes = (int(mode), int(mode.for_team(1)))

        heard_info = np.stack([slot.info for slot in heard]) if n else \
            np.zeros((0, self.heard_slots, HEARD_DIM))

        if flat:
            mode_onehot = np.zeros((n, N_PLAY_MODES))
            mode_onehot[np.arange(n), np.take(modes, self.team_of)] = 1.0
            return list(np.concatenate([
                self_obs, ball_obs, mates.reshape(n, -1), opponents.reshape(n, -1),
                mode_onehot, game, heard_info.reshape(n, -1)], axis=1).astype(np.float32))

        self_obs = self_obs.astype(np.float32)
        ball_obs = ball_obs.astype(np.float32)
        mates = mates.astype(np.float32)
        opponents = opponents.astype(np.float32)
        game = game.astype(np.float32)
        heard_info = heard_info.astype(np.float32)
        return [
            {
                "self": self_obs[i],
                "ball": ball_obs[i],
                "teammates": mates[i],
                "opponents": opponents[i],
                "play_mode": modes[self.team_of[i]],
                "game": game[i],
                "heard_text": tuple(heard[i].texts),
                "heard": heard_info[i],
            }
            for i in range(n)
        ]

