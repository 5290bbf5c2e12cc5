"""Match events from a replay's arrays: ball contacts, possession, kicks and how each ended,
passes, shots, possession changes, set plays (vectorised over cycles with numpy; loops only
over kicks and set plays, a few hundred per match).

Definitions (those of ``benchmarks/goal_rarity.py``, which counts them live):

- a *contact* is a kick (the kicker's foot) or a physics touch of a player's body; within a
  cycle kicks come first. *Possession* belongs to the side that made the last contact.
- a kick *ends* at the first of: a contact by anyone else, or by the kicker after
  ``KICK_GRACE_CYCLES`` (``teammate`` / ``blocked`` / ``self``), a goal (``goal``), a whistle
  for a kick-in, corner or goal kick (``out``), the end of a half (``half``), or the ball
  coming to rest in play (``stopped``, slower than ``STOPPED_SPEED``); ``open`` when the
  replay ends first. Ties within a cycle go in that order.
- a kick is *on frame* when its world direction crosses the opponents' goal line between the
  posts; a *shot* is an on-frame kick whose crossing lies no further than its commanded
  distance + ``REACH_MARGIN_M`` (it can reach the goal).
- a *pass* is a kick that is not on frame; it is *completed* when it ends with a teammate's
  contact (the receiver).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from teamenv.analytics.geometry import (
    goal_distance_angle,
    goal_line_crossing,
    in_shot_cone,
    third_index,
)
from teamenv.errors import ConfigError
from teamenv.replay import Replay
from teamenv.sim.playmode import PlayMode

#: the kicker's own contacts in the kick's first cycles are the kick itself, not a re-touch
KICK_GRACE_CYCLES = 5
STOPPED_SPEED = 0.05  # m/s: a ball slower than this has come to rest
REACH_MARGIN_M = 0.5  # a shot may cross the goal line this much beyond its distance
TELEPORT_M = 1.0  # a one-cycle ball move longer than this is a placement, not travel
PLAY_ON = int(PlayMode.PlayOn)
OUT_MODES = np.array([int(PlayMode.of(k, t)) for k in ("KickIn", "CornerKick", "GoalKick")
                      for t in (0, 1)])
HALF_END_MODES = np.array([int(PlayMode.BeforeKickOff), int(PlayMode.GameOver)])
SET_PLAY_KINDS = ("KickOff", "KickIn", "CornerKick", "GoalKick")
OUTCOMES = ("teammate", "blocked", "self", "goal", "out", "half", "stopped", "open")


@dataclass(frozen=True)
class Kick:
    """One kick: replay row, kicker (player index), side (0 left, 1 right), where the ball lay
    (m), commanded distance (m) and world direction (rad), shot facts, how it ended."""

    row: int
    player: int
    team: int
    start: tuple[float, float]
    distance: float
    direction: float
    on_frame: bool
    shot: bool
    goal_distance: float  # distance to the goal's centre (m)
    goal_angle: float  # opening angle between the posts (rad)
    blockers: int  # opponents inside the shot cone at the kick
    outcome: str
    end_row: int
    receiver: int  # player whose contact ended the kick, -1 for none
    travel_m: float  # how far the ball went until the kick ended

    @property
    def is_pass(self) -> bool:
        return not self.on_frame

    @property
    def completed(self) -> bool:
        return self.outcome == "teammate"


@dataclass(frozen=True)
class SetPlay:
    """A set play awarded to ``team``: its kind, the row it was whistled, the row play went
    on, whether the awarded side made the first contact (``taken``) and what followed within
    ``SET_PLAY_HORIZON_S``: ``goal``, ``shot``, ``kept`` (possession still the side's) or
    ``lost``."""

    kind: str
    team: int
    row: int
    restart_row: int
    taken: bool
    outcome: str


SET_PLAY_HORIZON_S = 10.0


@dataclass(frozen=True)
class MatchEvents:
    """Everything ``match_events`` derives from one replay."""

    contact_row: np.ndarray  # (C,) rows of the contacts, in order
    contact_player: np.ndarray  # (C,)
    contact_team: np.ndarray  # (C,)
    possession: np.ndarray  # (T,) side that made the last contact, -1 before the first
    kicks: tuple[Kick, ...]
    set_plays: tuple[SetPlay, ...]
    change_row: np.ndarray  # (P,) rows where possession changed side
    change_loser: np.ndarray  # (P,) the side that lost it
    change_third: np.ndarray  # (P,) third of the ball, seen by the loser (0, 1, 2)
    change_restart: np.ndarray  # (P,) bool: lost at a restart (previous row not PlayOn)
    ball_step: np.ndarray  # (T,) ball travel into each row (m; 0 for placements)
    team_sign: np.ndarray  # (T, 2) attack direction of each side per row

    @property
    def passes(self) -> tuple[Kick, ...]:
        return tuple(k for k in self.kicks if k.is_pass)

    @property
    def shots(self) -> tuple[Kick, ...]:
        return tuple(k for k in self.kicks if k.shot)

    @property
    def attempts(self) -> tuple[Kick, ...]:
        """Kicks on frame (the shots' superset the xG model rates)."""
        return tuple(k for k in self.kicks if k.on_frame)


def require_events(replay: Replay, source: str = "replay") -> None:
    """Raise ConfigError when the replay lacks the arrays statistics need (format 1)."""
    if not replay.has_events:
        raise ConfigError(f"{source}: format {replay.metadata.get('format')} replay has no "
                          "kicks, touches, falls or messages; statistics need a format-2 "
                          "replay (record the match again with this teamenv)")


def match_events(replay: Replay) -> MatchEvents:
    """Contacts, possession, kicks, set plays and possession changes of a format-2 replay."""
    require_events(replay)
    meta = replay.metadata
    n = replay.team_size
    half_length = float(meta["half_length"])
    half_goal_width = float(meta["half_goal_width"])
    t = len(replay)
    mode = replay.play_mode.astype(np.int64)
    sign_left = replay.attack_sign.astype(float)
    team_sign = np.stack([sign_left, -sign_left], axis=1)
    ball = replay.ball.astype(np.float64)

    # contacts: kicks before touches within a row (a stable sort keeps that order)
    rows = np.concatenate([replay.kick_cycle, replay.touch_cycle]).astype(np.int64)
    players = np.concatenate([replay.kick_player, replay.touch_player]).astype(np.int64)
    order = np.argsort(rows, kind="stable")
    contact_row, contact_player = rows[order], players[order]
    contact_team = contact_player // n
    last = np.searchsorted(contact_row, np.arange(t), side="right") - 1
    possession = np.full(t, -1, dtype=np.int64)
    if len(contact_team):
        possession = np.where(last >= 0, contact_team[np.maximum(last, 0)], -1)

    # possession changes
    changed = np.flatnonzero(contact_team[1:] != contact_team[:-1]) + 1
    change_row = contact_row[changed]
    change_loser = contact_team[changed - 1]
    loser_sign = team_sign[change_row, change_loser]
    change_third = third_index(ball[change_row - 1, 0], loser_sign, half_length)
    change_restart = mode[np.maximum(change_row - 1, 0)] != PLAY_ON

    # ball travel per row, placements (teleports) removed
    step = np.zeros(t)
    step[1:] = np.hypot(np.diff(ball[:, 0]), np.diff(ball[:, 1]))
    step[step > TELEPORT_M] = 0.0
    travel = np.cumsum(step)

    speed = np.hypot(ball[:, 2], ball[:, 3])
    stopped_rows = np.flatnonzero((mode == PLAY_ON) & (speed < STOPPED_SPEED))
    entered = np.flatnonzero(np.diff(mode) != 0) + 1
    out_rows = entered[np.isin(mode[entered], OUT_MODES)]
    half_rows = entered[np.isin(mode[entered], HALF_END_MODES)]
    goal_rows = np.sort(replay.goal_cycle.astype(np.int64))

    kicks = []
    kick_pos = np.flatnonzero(order < len(replay.kick_cycle))  # kicks' places in the contacts
    for c in kick_pos:
        row = int(contact_row[c])
        player = int(contact_player[c])
        team = player // n
        sign = float(team_sign[row, team])
        start = (float(ball[row - 1, 0]), float(ball[row - 1, 1]))
        idx = int(order[c])
        distance = float(replay.kick_distance[idx])
        direction = float(replay.kick_direction[idx])
        cross = goal_line_crossing(start, direction, sign, half_length)
        on_frame = cross is not None and abs(cross[1]) < half_goal_width
        shot = on_frame and cross[0] <= distance + REACH_MARGIN_M
        goal_distance, goal_angle = goal_distance_angle(start, sign, half_length,
                                                        half_goal_width)
        opponents = replay.players[row - 1, (1 - team) * n:(2 - team) * n, :2]
        blockers = int(in_shot_cone(start, opponents, sign, half_length,
                                    half_goal_width).sum())
        # the end: the first qualifying contact, then referee and ball events
        end_row, outcome, receiver = t, "open", -1
        for j in range(c + 1, len(contact_row)):
            p, r = int(contact_player[j]), int(contact_row[j])
            if p == player and r - row <= KICK_GRACE_CYCLES:
                continue
            end_row, receiver = r, p
            outcome = "self" if p == player else ("teammate" if p // n == team else "blocked")
            break
        for name, candidates, strict in (("goal", goal_rows, False), ("out", out_rows, False),
                                         ("half", half_rows, False),
                                         ("stopped", stopped_rows, True)):
            i = np.searchsorted(candidates, row, side="right" if strict else "left")
            if i < len(candidates) and int(candidates[i]) < end_row:
                end_row, outcome, receiver = int(candidates[i]), name, -1
        end = min(end_row, t - 1)
        kicks.append(Kick(row, player, team, start, distance, direction, bool(on_frame),
                          bool(shot), goal_distance, goal_angle, blockers, outcome, end_row,
                          receiver, float(travel[end] - travel[row])))

    set_plays = _set_plays(mode, entered, contact_row, contact_team, possession, kicks,
                           goal_rows, replay.goal_team, float(meta["cycle_s"]))
    return MatchEvents(contact_row, contact_player, contact_team, possession, tuple(kicks),
                       set_plays, change_row, change_loser, change_third, change_restart, step,
                       team_sign)


def _set_plays(mode: np.ndarray, entered: np.ndarray, contact_row: np.ndarray,
               contact_team: np.ndarray, possession: np.ndarray, kicks: list[Kick],
               goal_rows: np.ndarray, goal_team: np.ndarray, cycle_s: float
               ) -> tuple[SetPlay, ...]:
    t = len(mode)
    horizon = int(round(SET_PLAY_HORIZON_S / cycle_s))
    play_on_rows = entered[mode[entered] == PLAY_ON]
    shot_rows = np.array([k.row for k in kicks if k.shot], dtype=np.int64)
    shot_teams = np.array([k.team for k in kicks if k.shot], dtype=np.int64)
    goal_team = np.asarray(goal_team, dtype=np.int64)
    out = []
    for row in entered:
        m = PlayMode(int(mode[row]))
        if m.kind not in SET_PLAY_KINDS or m.team is None:
            continue
        team = int(m.team)
        i = np.searchsorted(play_on_rows, row)
        restart = int(play_on_rows[i]) if i < len(play_on_rows) else t
        first = np.searchsorted(contact_row, row, side="left")
        taken = first < len(contact_row) and int(contact_row[first]) <= restart and \
            int(contact_team[first]) == team
        until = min(restart + horizon, t - 1)
        window = (goal_rows >= restart) & (goal_rows <= until)
        if np.any(goal_team[window] == team):
            outcome = "goal"
        elif np.any((shot_rows >= row) & (shot_rows <= until) & (shot_teams == team)):
            outcome = "shot"
        elif restart < t and possession[until] == team:
            outcome = "kept"
        else:
            outcome = "lost"
        out.append(SetPlay(m.kind, team, int(row), restart, bool(taken), outcome))
    return tuple(out)
