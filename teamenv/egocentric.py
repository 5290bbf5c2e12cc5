"""Egocentric player slots: the state-mode Box observation re-read as "my nearest teammates,
my nearest opponents", a fixed number of each, sorted by distance and masked.

Why it exists. The env's Box observation lists the other players by uniform number
(``teammate_1 .. teammate_N``, ``opponent_1 .. opponent_N``, the agent's own row included),
which is right for a team that knows its roles but awkward for one network shared by every
player of a side (parameter sharing, the usual way to train a team):

- the same situation reads differently for each player (``left_2`` finds itself in row 2,
  ``left_3`` in row 3), so the network must learn every permutation of the same picture;
- what matters most — the nearest opponent, the closest teammate to pass to — sits in a
  different row every cycle;
- its length grows with the team size, so a network trained 3 v 3 cannot play 5 v 5.

``EgocentricObservation`` keeps the agent's own state, the ball, the play mode and the game
values as they are and replaces the player rows with the ``teammates`` nearest teammates
(itself left out) and the ``opponents`` nearest opponents, each sorted nearest first. A slot
holds the env's five player columns (``rel_x rel_y rel_heading fallen present``); a slot with
nobody in it (fewer players than slots) is all zeros, so ``present`` is its mask. The heard
messages are left out (their count depends on the say channel, and a policy that does not
talk has little use for them). The length no longer depends on the team size: a policy
trained with 2 teammate and 3 opponent slots plays 3 v 3 and 7 v 7 alike.

With ``ball_race=True`` three columns follow (``BALL_RACE_NAMES``): the agent's distance to
the ball, and how much farther from it the nearest upright teammate and the nearest upright
opponent stand (negative: nearer). Why: a team choosing its ball player needs "who is
nearest the ball", which the slots (sorted by distance to the agent, not to the ball) hold
only implicitly; a network cloned from ``full``'s choice without them picked a ball player
other than the rule's in 31 % of open play, on average 2.2 m farther from the ball.

With ``game_state=False`` the ``game.*`` columns (clock, half, score) are left out: a policy
that imitates a rule which never reads them, trained on episodes shorter than a match, would
otherwise meet clock values in a match it never saw (a clone of ``full``'s ball-player
choice trained on 60 s episodes agreed with the rule in 92 % of the first 120 s of a match
and 70 % over a whole half).

Exact and portable: the sort key is ``rel_x**2 + rel_y**2`` (correctly rounded basic
operations, the same on every machine), ties keep uniform-number order (a stable sort), and
the agent's own row is the one at distance exactly 0 (the env writes ``x - x``; two bodies
cannot share a position).
"""

from __future__ import annotations

import numpy as np

from teamenv.box_layout import PLAYER_COLUMNS
from teamenv.errors import ConfigError
from teamenv.slots import state_slot_names

#: The parts of the Box observation kept as they are, in output order before the slots.
_HEAD_PARTS = ("self.", "ball.")
#: The parts kept after the slots.
_TAIL_PARTS = ("play_mode.", "game.")
#: The optional ball-race columns, last (``ball_race=True``).
BALL_RACE_NAMES = ("ball_race.distance", "ball_race.teammate_gap", "ball_race.opponent_gap")
#: The cap of the ball-race columns (m): nobody else in the race reads as this far behind.
BALL_RACE_CAP_M = 20.0


class EgocentricObservation:
    """Maps state-mode Box observations (one row per agent) to egocentric rows.

    Args:
        team_size: players per side of the env the raw rows come from.
        heard_slots: heard-message slots of its say channel (``env.sim.heard_slots``).
        teammates: teammate slots (nearest first, the agent itself never among them).
        opponents: opponent slots (nearest first).

    Output layout (``names``): ``self.*`` (7), ``ball.*`` (4), ``teammate_near_k.*`` and
    ``opponent_near_k.*`` (5 each, ``PLAYER_COLUMNS``), ``play_mode.*`` (13), ``game.*`` (4).
    ``self`` and ``ball`` keep their places at the front, so a policy file's reflexes (kick
    gate, walk to the ball), which read ``ball.rel_x``/``ball.rel_y`` at columns 7-8, read the
    same values from a raw or an egocentric row.
    """

    def __init__(self, team_size: int, heard_slots: int, teammates: int = 2,
                 opponents: int = 3, ball_race: bool = False, game_state: bool = True) -> None:
        for name, value in (("team_size", team_size), ("heard_slots", heard_slots),
                            ("teammates", teammates), ("opponents", opponents)):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
                raise ConfigError(f"egocentric slots: {name} must be an int >= 0, got {value!r}")
        if team_size < 1:
            raise ConfigError(f"egocentric slots: team_size must be >= 1, got {team_size!r}")
        if not isinstance(ball_race, (bool, np.bool_)):
            raise ConfigError(f"egocentric slots: ball_race must be true or false, got "
                              f"{ball_race!r}")
        self.ball_race = bool(ball_race)
        if not isinstance(game_state, (bool, np.bool_)):
            raise ConfigError(f"egocentric slots: game_state must be true or false, got "
                              f"{game_state!r}")
        self.game_state = bool(game_state)
        self.team_size, self.heard_slots = int(team_size), int(heard_slots)
        self.teammates, self.opponents = int(teammates), int(opponents)
        raw = state_slot_names(self.team_size, self.heard_slots)
        self.raw_size = len(raw)
        index = {name: k for k, name in enumerate(raw)}
        width = len(PLAYER_COLUMNS)
        self._head = np.array([k for k, n in enumerate(raw) if n.startswith(_HEAD_PARTS)])
        tail = _TAIL_PARTS if self.game_state else _TAIL_PARTS[:1]
        self._tail = np.array([k for k, n in enumerate(raw) if n.startswith(tail)])
        self._mates = index[f"teammate_1.{PLAYER_COLUMNS[0]}"]
        self._opps = index[f"opponent_1.{PLAYER_COLUMNS[0]}"]
        self._width = width
        self.names = tuple(
            [raw[k] for k in self._head]
            + [f"teammate_near_{s + 1}.{c}" for s in range(self.teammates) for c in PLAYER_COLUMNS]
            + [f"opponent_near_{s + 1}.{c}" for s in range(self.opponents) for c in PLAYER_COLUMNS]
            + [raw[k] for k in self._tail]
            + (list(BALL_RACE_NAMES) if self.ball_race else []))
        self._ball = index["ball.rel_x"]
        self.size = len(self.names)

    @classmethod
    def for_env(cls, env, teammates: int = 2, opponents: int = 3, ball_race: bool = False,
                game_state: bool = True) -> EgocentricObservation:
        """The transform for the state-mode Box observations of ``env`` (a parallel env)."""
        env = env.unwrapped
        if env.perception is not None:
            raise ConfigError("egocentric slots: state-mode observations only (the env uses "
                              "vision)")
        return cls(env.team_size, env.sim.heard_slots, teammates, opponents, ball_race,
                   game_state)

    def __call__(self, raw: np.ndarray) -> np.ndarray:
        """Egocentric rows (float32) for ``raw`` (n, raw_size) or one row (raw_size,)."""
        rows = np.asarray(raw, dtype=np.float32)
        single = rows.ndim == 1
        if single:
            rows = rows[None]
        if rows.ndim != 2 or rows.shape[1] != self.raw_size:
            raise ConfigError(f"egocentric slots: observations of shape {np.shape(raw)}, "
                              f"expected (n, {self.raw_size}) (state mode, team_size "
                              f"{self.team_size}, {self.heard_slots} heard slots)")
        n, size, width = len(rows), self.team_size, self._width
        mates = rows[:, self._mates:self._mates + size * width].reshape(n, size, width)
        opps = rows[:, self._opps:self._opps + size * width].reshape(n, size, width)
        # The agent's own row (distance exactly 0) sorts first among its teammates: drop it.
        own_dropped = self._nearest(mates, size)[:, 1:]
        parts = [rows[:, self._head],
                 self._slots(mates, own_dropped, self.teammates),
                 self._slots(opps, self._nearest(opps, size), self.opponents),
                 rows[:, self._tail]]
        if self.ball_race:
            parts.append(self._ball_race(rows[:, self._ball:self._ball + 2], mates, opps))
        out = np.concatenate(parts, axis=1)
        return out[0] if single else out

    @staticmethod
    def _ball_race(ball: np.ndarray, mates: np.ndarray, opps: np.ndarray) -> np.ndarray:
        """(n, 3): the agent's distance to the ball, and how much farther from it the
        nearest upright teammate (the agent left out) and the nearest upright opponent are
        (negative: nearer), capped at +-``BALL_RACE_CAP_M``."""
        b = ball.astype(np.float64)
        mine = np.sqrt(b[:, 0] * b[:, 0] + b[:, 1] * b[:, 1])

        def gap(players: np.ndarray, drop_own: bool) -> np.ndarray:
            dx = players[:, :, 0].astype(np.float64) - b[:, None, 0]
            dy = players[:, :, 1].astype(np.float64) - b[:, None, 1]
            d = np.sqrt(dx * dx + dy * dy)
            out_of_race = (players[:, :, 4] <= 0.0) | (players[:, :, 3] > 0.0)
            if drop_own:  # the agent's own row: at distance exactly 0 from itself
                out_of_race |= (players[:, :, 0] == 0.0) & (players[:, :, 1] == 0.0)
            d[out_of_race] = np.inf
            return np.minimum(d.min(axis=1) - mine, BALL_RACE_CAP_M)

        out = np.stack([mine, gap(mates, True), gap(opps, False)], axis=1)
        return np.clip(out, -BALL_RACE_CAP_M, BALL_RACE_CAP_M).astype(np.float32)

    @staticmethod
    def _nearest(players: np.ndarray, count: int) -> np.ndarray:
        """Row indices of ``players`` (n, count, 5) by distance, nearest first; absent
        players (present == 0) last."""
        dist2 = players[:, :, 0].astype(np.float64) ** 2 + players[:, :, 1].astype(np.float64) ** 2
        dist2[players[:, :, 4] <= 0.0] = np.inf
        return np.argsort(dist2, axis=1, kind="stable")[:, :count]

    def _slots(self, players: np.ndarray, order: np.ndarray, slots: int) -> np.ndarray:
        """``slots`` rows of ``players`` in ``order``, zero rows where there are too few."""
        n = len(players)
        out = np.zeros((n, slots, self._width), dtype=np.float32)
        take = min(slots, order.shape[1])
        if take:
            picked = np.take_along_axis(players, order[:, :take, None], axis=1)
            out[:, :take] = picked * (picked[:, :, 4:5] > 0.0)  # absent: all zeros
        return out.reshape(n, slots * self._width)
