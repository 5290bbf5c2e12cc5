"""Per-team match statistics from a replay (``MatchStats``), with a stable JSON form.

Every number is defined in ``docs/analytics.md``; in short (per side): possession is the
share of PlayOn cycles after its last contact; passes, shots and set plays follow
``teamenv.analytics.events``; ``xg`` sums the xG model over its kicks on frame; ball progress
is how far the ball moved towards the opponents' goal (PlayOn, in its possession, net);
territory is the ball's mean distance past the centre line towards the opponents' goal over
the whole match, stoppages included (negative: mostly in its own half);
thirds are the PlayOn share of cycles the ball spent in each third seen from the side;
distance walked leaves out beams and placements; a fall is a cycle the player goes down;
messages count what its agents said (and bytes), the channel's drop records of them, and the
messages its agents heard from teammates and from opponents; role agreement (replays with
extras) is the share of PlayOn cycles in which every agent of the side held the same role
assignment.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.analytics.events import (
    OUTCOMES,
    PLAY_ON,
    SET_PLAY_KINDS,
    MatchEvents,
    match_events,
)
from teamenv.analytics.geometry import THIRDS, third_index
from teamenv.analytics.xg import XGModel, kick_features
from teamenv.errors import ConfigError
from teamenv.replay import Replay, load_replay

SCHEMA = "teamenv.match_stats/1"
SIDES = ("left", "right")
WALK_TELEPORT_M = 0.5  # a one-cycle player move longer than this is a beam or placement
SET_PLAY_OUTCOMES = ("goal", "shot", "kept", "lost")


@dataclass
class PlayerStats:
    """One player's numbers (``unum`` = uniform number)."""

    unum: int
    kicks: int = 0
    passes_attempted: int = 0
    passes_completed: int = 0
    shots: int = 0
    xg: float = 0.0
    distance_walked_m: float = 0.0
    falls: int = 0
    messages_sent: int = 0
    mean_x: float = 0.0  # mean position in PlayOn, in the side's attacking frame (+x ahead)
    mean_y: float = 0.0


@dataclass
class TeamStats:
    """One side's numbers for one match (see the module docstring and docs/analytics.md)."""

    side: str
    team: str
    goals: int = 0
    own_goals: int = 0  # goals this side put into its own goal
    possession_pct: float = 0.0
    possession_lost: int = 0
    lost_in_third: dict[str, int] = field(default_factory=lambda: dict.fromkeys(THIRDS, 0))
    lost_at_restart: int = 0
    kicks: int = 0
    kick_outcomes: dict[str, int] = field(default_factory=lambda: dict.fromkeys(OUTCOMES, 0))
    passes_attempted: int = 0
    passes_completed: int = 0
    pass_completion_pct: float | None = None
    shots: int = 0
    attempts_on_frame: int = 0
    xg: float = 0.0
    ball_progress_m: float = 0.0
    territory_m: float = 0.0
    third_pct: dict[str, float] = field(default_factory=lambda: dict.fromkeys(THIRDS, 0.0))
    distance_walked_m: float = 0.0
    falls: int = 0
    messages_sent: int = 0
    message_bytes: int = 0
    messages_dropped: int = 0
    messages_heard_team: int = 0
    messages_heard_opponents: int = 0
    role_agreement_pct: float | None = None
    set_plays: dict[str, dict[str, int]] = field(default_factory=dict)
    players: list[PlayerStats] = field(default_factory=list)

    def metric(self, name: str) -> float:
        """A number by name, for rankings (``goals``, ``xg``, ...)."""
        value = getattr(self, name)
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            raise ConfigError(f"team stats: {name!r} is not a number")
        return float(value)


@dataclass
class MatchStats:
    """Both sides' statistics of one match, the shots with their xG and the pass networks.

    ``to_json()`` is the stable form other tools read (schema ``SCHEMA``)."""

    left: TeamStats
    right: TeamStats
    seed: int | None
    field: str
    team_size: int
    cycles: int
    duration_s: float
    play_on_s: float
    score: tuple[int, int]
    possession_changes: int
    has_extras: bool
    shots: list[dict[str, Any]] = field(default_factory=list)
    pass_network: dict[str, list[list[int]]] = field(default_factory=dict)
    xg_model: dict[str, Any] = field(default_factory=dict)

    @property
    def teams(self) -> tuple[TeamStats, TeamStats]:
        return self.left, self.right

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict: ``schema``, match facts, ``teams`` {left, right} with every
        TeamStats field (players as a list), ``shots`` and ``pass_network`` (per side, rows
        [from unum, to unum, completed passes])."""
        out = {"schema": SCHEMA}
        for key, value in asdict(self).items():
            if key in ("left", "right"):
                continue
            out[key] = list(value) if isinstance(value, tuple) else value
        out["teams"] = {"left": asdict(self.left), "right": asdict(self.right)}
        return _finite(out)

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> MatchStats:
        if data.get("schema") != SCHEMA:
            raise ConfigError(f"match stats: schema {data.get('schema')!r}, expected {SCHEMA!r}")
        teams = {}
        for side in SIDES:
            values = dict(data["teams"][side])
            values["players"] = [PlayerStats(**p) for p in values.get("players", [])]
            teams[side] = TeamStats(**values)
        rest = {k: v for k, v in data.items() if k not in ("schema", "teams")}
        rest["score"] = tuple(rest["score"])
        return cls(left=teams["left"], right=teams["right"], **rest)

    def summary(self) -> str:
        """A plain-text table of the main numbers, one column per side."""
        rows = [("goals", "goals"), ("xG", "xg"), ("shots (on frame)", None),
                ("possession %", "possession_pct"), ("passes (completed)", None),
                ("ball progress m", "ball_progress_m"), ("territory m", "territory_m"),
                ("thirds % d/m/a", None),
                ("distance walked m", "distance_walked_m"), ("falls", "falls"),
                ("messages sent (bytes)", None), ("dropped / heard team", None),
                ("role agreement %", "role_agreement_pct"), ("set plays (taken)", None)]
        lines = [f"{self.left.team} {self.score[0]} - {self.score[1]} {self.right.team}   "
                 f"(seed {self.seed}, {self.field} {self.team_size} v {self.team_size}, "
                 f"{self.cycles} cycles, {self.duration_s:.0f} s, in play {self.play_on_s:.0f} "
                 f"s, {self.possession_changes} possession changes)",
                 f"{'':24s}{'left: ' + self.left.team:>24s}{'right: ' + self.right.team:>24s}"]
        for label, key in rows:
            cells = []
            for t in self.teams:
                if key is not None:
                    v = getattr(t, key)
                    cells.append("-" if v is None else (f"{v:.2f}" if isinstance(v, float)
                                                        else str(v)))
                elif label.startswith("shots"):
                    cells.append(f"{t.shots} ({t.attempts_on_frame})")
                elif label.startswith("passes"):
                    cells.append(f"{t.passes_attempted} ({t.passes_completed})")
                elif label.startswith("thirds"):
                    cells.append("/".join(f"{t.third_pct[k]:.0f}" for k in THIRDS))
                elif label.startswith("messages"):
                    cells.append(f"{t.messages_sent} ({t.message_bytes})")
                elif label.startswith("dropped"):
                    cells.append(f"{t.messages_dropped} / {t.messages_heard_team}")
                else:
                    awarded = sum(v["awarded"] for v in t.set_plays.values())
                    taken = sum(v["taken"] for v in t.set_plays.values())
                    cells.append(f"{awarded} ({taken})")
            lines.append(f"{label:24s}{cells[0]:>24s}{cells[1]:>24s}")
        return "\n".join(lines)


def _finite(value: Any) -> Any:
    """NaN/inf become None (JSON has no NaN); numpy scalars become Python numbers."""
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def replay_stats(path: str | Path, model: XGModel | None = None) -> MatchStats:
    """``match_stats`` of the replay file at ``path``."""
    return match_stats(load_replay(path), model)


def match_stats(replay: Replay, model: XGModel | None = None,
                events: MatchEvents | None = None) -> MatchStats:
    """Both sides' statistics of a format-2 replay (``model``: the xG model, default the
    shipped one; ``events``: already computed ``match_events(replay)``)."""
    events = events if events is not None else match_events(replay)
    model = model if model is not None else XGModel.load()
    meta = replay.metadata
    n = replay.team_size
    t = len(replay)
    cycle_s = float(meta["cycle_s"])
    half_length = float(meta["half_length"])
    mode = replay.play_mode.astype(np.int64)
    play_on = mode == PLAY_ON
    n_play_on = int(play_on.sum())
    names = (meta.get("left", "left"), meta.get("right", "right"))
    teams = [TeamStats(side, str(name)) for side, name in zip(SIDES, names, strict=True)]
    for ts in teams:
        ts.players = [PlayerStats(k + 1) for k in range(n)]
        ts.set_plays = {k: dict.fromkeys(("awarded", "taken", *SET_PLAY_OUTCOMES), 0)
                        for k in SET_PLAY_KINDS}

    # goals
    for team, player in zip(replay.goal_team.tolist(), replay.goal_player.tolist(),
                            strict=True):
        teams[team].goals += 1
        if player >= 0 and player // n != team:
            teams[1 - team].own_goals += 1

    # possession and where it was lost
    for side in (0, 1):
        ts = teams[side]
        if n_play_on:
            ts.possession_pct = 100.0 * float(np.sum(play_on & (events.possession == side))) \
                / n_play_on
        lost = events.change_loser == side
        ts.possession_lost = int(lost.sum())
        ts.lost_at_restart = int((lost & events.change_restart).sum())
        for k, name in enumerate(THIRDS):
            ts.lost_in_third[name] = int((lost & (events.change_third == k)).sum())

    # kicks, passes, shots, xG
    attempts = events.attempts
    xg = model.probability(kick_features(attempts)) if attempts else np.zeros(0)
    xg_of = {id(k): float(p) for k, p in zip(attempts, xg, strict=True)}
    network: dict[str, dict[tuple[int, int], int]] = {s: {} for s in SIDES}
    time_s = replay.time_s
    for k in events.kicks:
        ts = teams[k.team]
        ps = ts.players[k.player % n]
        ts.kicks += 1
        ps.kicks += 1
        ts.kick_outcomes[k.outcome] += 1
        if k.is_pass:
            ts.passes_attempted += 1
            ps.passes_attempted += 1
            if k.completed:
                ts.passes_completed += 1
                ps.passes_completed += 1
                edge = (k.player % n + 1, k.receiver % n + 1)
                network[SIDES[k.team]][edge] = network[SIDES[k.team]].get(edge, 0) + 1
        else:
            p = xg_of[id(k)]
            ts.attempts_on_frame += 1
            ts.xg += p
            ps.xg += p
        if k.shot:
            ts.shots += 1
            ps.shots += 1
    shots = [{"side": SIDES[k.team], "unum": k.player % n + 1,
              "time_s": float(time_s[k.row]), "x": k.start[0], "y": k.start[1],
              "distance_m": k.goal_distance, "angle_rad": k.goal_angle,
              "blockers": k.blockers, "in_reach": k.shot, "xg": xg_of[id(k)],
              "outcome": k.outcome} for k in attempts]
    for ts in teams:
        if ts.passes_attempted:
            ts.pass_completion_pct = 100.0 * ts.passes_completed / ts.passes_attempted

    # ball progress and thirds
    ball_x = replay.ball[:, 0].astype(np.float64)
    dx = np.zeros(t)
    dx[1:] = np.diff(ball_x)
    dx[events.ball_step == 0.0] = 0.0  # placements
    for side in (0, 1):
        ts = teams[side]
        sign = events.team_sign[:, side]
        mine = play_on & (events.possession == side)
        ts.ball_progress_m = float(np.sum(dx[mine] * sign[mine]))
        ts.territory_m = float(np.mean(ball_x * sign)) if t else 0.0
        if n_play_on:
            third = third_index(ball_x[play_on], sign[play_on], half_length)
            counts = np.bincount(third, minlength=3)
            for k, name in enumerate(THIRDS):
                ts.third_pct[name] = 100.0 * float(counts[k]) / n_play_on

    _bodies(replay, events, teams, play_on)
    _messages(replay, teams)
    _roles(replay, teams, play_on)
    for sp in events.set_plays:
        row = teams[sp.team].set_plays[sp.kind]
        row["awarded"] += 1
        row["taken"] += int(sp.taken)
        row[sp.outcome] += 1

    score = tuple(int(v) for v in replay.score[-1]) if t else (0, 0)
    return MatchStats(
        left=teams[0], right=teams[1], seed=meta.get("seed"), field=str(meta.get("field")),
        team_size=n, cycles=max(t - 1, 0), duration_s=float(time_s[-1]) if t else 0.0,
        play_on_s=n_play_on * cycle_s, score=score,
        possession_changes=int(len(events.change_row)), has_extras=replay.has_extras,
        shots=shots,
        pass_network={s: [[a, b, c] for (a, b), c in sorted(network[s].items())]
                      for s in SIDES},
        xg_model=model.to_json())


def _bodies(replay: Replay, events: MatchEvents, teams: list[TeamStats],
            play_on: np.ndarray) -> None:
    """Distance walked, falls and mean positions, per player."""
    n = replay.team_size
    xy = replay.players[:, :, :2].astype(np.float64)
    step = np.hypot(*np.moveaxis(np.diff(xy, axis=0), -1, 0))  # (T-1, 2N)
    step[step > WALK_TELEPORT_M] = 0.0
    walked = step.sum(axis=0)
    fallen = replay.fallen.astype(np.int8)
    falls = (np.diff(fallen, axis=0) == 1).sum(axis=0) + fallen[0]
    for i in range(2 * n):
        ts, ps = teams[i // n], teams[i // n].players[i % n]
        ps.distance_walked_m = float(walked[i])
        ps.falls = int(falls[i])
        if play_on.any():
            sign = events.team_sign[play_on, i // n]
            ps.mean_x = float(np.mean(xy[play_on, i, 0] * sign))
            ps.mean_y = float(np.mean(xy[play_on, i, 1] * sign))
    for ts in teams:
        ts.distance_walked_m = float(sum(p.distance_walked_m for p in ts.players))
        ts.falls = int(sum(p.falls for p in ts.players))


def popcount32(values: np.ndarray) -> np.ndarray:
    """Number of set bits of each uint32 value."""
    v = np.ascontiguousarray(values, dtype=np.uint32)
    return np.unpackbits(v.view(np.uint8).reshape(*v.shape, 4), axis=-1).sum(axis=-1)


def _messages(replay: Replay, teams: list[TeamStats]) -> None:
    n = replay.team_size
    said = replay.say_bytes
    drops = replay.say_drops
    sent = (said > 0) | (drops > 0)
    talk_rows = np.flatnonzero(replay.heard_from.any(axis=1))
    heard = replay.heard_from[talk_rows]
    own_bits = np.left_shift(np.uint32(1), np.arange(2 * n, dtype=np.uint32))
    left_mask = np.uint32((1 << n) - 1)
    right_mask = np.uint32(((1 << (2 * n)) - 1) ^ ((1 << n) - 1))
    for side in (0, 1):
        ts = teams[side]
        cols = slice(side * n, (side + 1) * n)
        mates, others = (left_mask, right_mask) if side == 0 else (right_mask, left_mask)
        ts.messages_sent = int(sent[:, cols].sum())
        ts.message_bytes = int(said[:, cols].astype(np.int64).sum())
        ts.messages_dropped = int(drops[:, cols].astype(np.int64).sum())
        mine = heard[:, cols]
        ts.messages_heard_team = int(popcount32(mine & (mates & ~own_bits[cols])).sum())
        ts.messages_heard_opponents = int(popcount32(mine & others).sum())
        per_player = sent[:, cols].sum(axis=0)
        for k, ps in enumerate(ts.players):
            ps.messages_sent = int(per_player[k])


def role_agreement(replay: Replay) -> np.ndarray | None:
    """(T, 2) per row and side: 1 when every agent holds the same role assignment, 0 when
    they differ, NaN when it is not known for every agent (None: no extras recorded).

    With ``role_vector`` recorded the agents' vectors are compared; with only each agent's
    own ``role``, the side agrees when no two agents claim the same role."""
    if not replay.has_extras:
        return None
    n = replay.team_size
    out = np.full((len(replay), 2), np.nan)
    for side in (0, 1):
        cols = slice(side * n, (side + 1) * n)
        vectors = replay.role_vector[:, cols].astype(np.int64)  # (T, n, n)
        known_vec = (vectors >= 0).all(axis=(1, 2))
        same = (vectors == vectors[:, :1]).all(axis=(1, 2))
        roles = replay.role[:, cols].astype(np.int64)
        known_role = (roles >= 0).all(axis=1)
        ordered = np.sort(roles, axis=1)
        distinct = (np.diff(ordered, axis=1) != 0).all(axis=1)
        out[:, side] = np.where(known_vec, same, np.where(known_role, distinct, np.nan))
    return out


def _roles(replay: Replay, teams: list[TeamStats], play_on: np.ndarray) -> None:
    agree = role_agreement(replay)
    if agree is None:
        return
    for side in (0, 1):
        values = agree[play_on, side]
        values = values[~np.isnan(values)]
        if values.size:
            teams[side].role_agreement_pct = 100.0 * float(values.mean())


def stats_json(stats: MatchStats) -> str:
    return json.dumps(stats.to_json(), indent=2)
