"""A league match on ``LocalServer`` recorded as a teamenv replay (format 2), so the league's
matches get the same statistics (``teamenv.analytics.stats.match_stats``) as the env's.

Every cycle the recorder reads the server's simulation (the monitor's view, ground truth): the
ball (x, y, vx, vy), each robot's torso (x, y, yaw), who is down (the observation's fall test:
torso tilted past 60 degrees or lower than 0.4 m; ``latch_falls``: a robot stays fallen until it
has been up for ``RECOVER_CYCLES``, so one lying robot flickering across the test is one fall),
the game state of the perceptions (time,
play mode, score), and which robots touch the ball (MuJoCo contacts between the ball and a
robot's geoms). The server has no kick action (our kick is a walk through the ball, see
``adapter.RequestEncoder``), so a **kick** is a ball contact by a robot whose team asked it to
kick in the last ``KICK_WINDOW_CYCLES`` cycles, at most one per ``KICK_GRACE_CYCLES``; its
distance and direction are what the ball then did (its travel until the next contact, rest or
3 s, and the direction of that displacement), where the env records the kick it planned. Other
contacts are touches. A goal is a score change, credited to the last robot that touched the
ball. Messages: ``say_bytes`` from what each robot said; ``say_drops`` and ``heard_from`` are
not known (zeros), so the message statistics of a league replay are partial.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from teamenv.field import field_preset
from teamenv.replay import event_arrays, write_replay

from .controller import CYCLE_S, quat_yaw
from .falls import torso_down
from .observation import play_mode_index
from .perception import GameState

#: a robot that was down counts as up again only after this many cycles in a row up (a robot
#: lying half on its side flickers across the 60-degree test; that is one fall, not several)
RECOVER_CYCLES = 25
KICK_WINDOW_CYCLES = 10
KICK_GRACE_CYCLES = 15
KICK_FOLLOW_CYCLES = 150  # 3 s: how long the ball is followed to measure a kick


def latch_falls(down: np.ndarray, recover: int = RECOVER_CYCLES) -> np.ndarray:
    """(T, P) fallen flags from the per-cycle fall test ``down``: once down, a robot stays
    fallen until it has been up for ``recover`` cycles in a row."""
    down = np.asarray(down, bool)
    out = np.zeros_like(down)
    fallen = np.zeros(down.shape[1:], bool)
    up_for = np.zeros(down.shape[1:], np.int64)
    for t in range(len(down)):
        up_for = np.where(down[t], 0, up_for + 1)
        fallen = down[t] | (fallen & (up_for < recover))
        out[t] = fallen
    return out


# how many cycles before a fall the other robots' distance is read (before the fall moves them)
FALL_LOOKBACK_CYCLES = 5


@dataclass(frozen=True)
class FallEvent:
    """A robot going down in a league replay: the cycle (row), the player index (0..2N-1,
    left team first) and the distance to the nearest other robot ``FALL_LOOKBACK_CYCLES``
    before."""

    row: int
    player: int
    nearest_m: float


def fall_events(replay: Any) -> list[FallEvent]:
    """Every fall in a league replay (``latch_falls`` over its per-cycle fall flags, so a robot
    flickering across the fall test falls once), in order."""
    fallen = latch_falls(replay.fallen).astype(np.int8)
    out = []
    for row, i in np.argwhere(np.diff(fallen, axis=0) == 1):
        row, i = int(row) + 1, int(i)
        xy = replay.players[max(row - FALL_LOOKBACK_CYCLES, 0), :, :2]
        d = np.hypot(*(xy - xy[i]).T)
        d[i] = np.inf
        out.append(FallEvent(row, i, float(d.min())))
    return out


def down_times(replay: Any, cycle_s: float) -> tuple[np.ndarray, int]:
    """How long each fall in a league replay kept the robot down (s): from the fall's first
    cycle to the first cycle of the ``RECOVER_CYCLES`` up that ended it (``latch_falls``), so
    a get-up that needed a second try or the referee counts whole; and how many falls were
    still down when the replay ended (left out of the times)."""
    fallen = latch_falls(replay.fallen)
    steps = np.diff(fallen.astype(np.int8), axis=0)
    times, open_at_end = [], 0
    for player in range(fallen.shape[1]):
        rises = np.flatnonzero(steps[:, player] == 1) + 1
        ends = np.flatnonzero(steps[:, player] == -1) + 1   # first cycle not latched
        for row in rises:
            later = ends[ends > row]
            if not len(later):
                open_at_end += 1
                continue
            times.append((int(later[0]) - RECOVER_CYCLES + 1 - int(row)) * cycle_s)
    return np.asarray(times, float), open_at_end


#: play modes in which no kick is set up: before the kick-off, after a goal, at the end
NOT_IN_PLAY = (0, 10, 11, 12)   # PlayMode BeforeKickOff, Goal_Left, Goal_Right, GameOver
#: a ball at least this fast (m/s) when the set-up began "came to" the kicker
BALL_MOVING_M_S = 0.2


@dataclass(frozen=True)
class KickSetup:
    """One kick's set-up in a replay (league or teamenv): the kick's row and player (0..2N-1,
    left team first), the row its set-up began (``None``: not measured, ``why`` says
    why), the set-up time ``seconds`` (``None`` likewise) and the ball's speed when it began.
    ``why``: ``"arrival"`` (the kicker came within reach), ``"previous kick"`` (it stayed
    within reach since its own previous kick, where this set-up began), ``"start"`` (within
    reach from the replay's first row), or, unmeasured, ``"out of reach"``, ``"down"``,
    ``"not in play"`` (the kicker's state in the row before the kick)."""

    row: int
    player: int
    start: int | None
    seconds: float | None
    why: str
    ball_speed: float


def kick_setups(replay: Any, reach: float, cycle_s: float | None = None) -> list[KickSetup]:
    """Each kick's **set-up time** in ``replay``: from the row the kicker last came within
    ``reach`` (m, torso or body centre to ball centre) of the ball and stayed there, upright
    and in play, until the kick's row (the foot-ball contact).

    The set-up is the unbroken run of rows before the kick row in which the kicker was
    within ``reach``, not fallen (``replay.fallen``) and the play mode was not
    ``NOT_IN_PLAY``; it ends in the row before the kick and begins at the run's first row, or
    the row after the kicker's own previous kick when the run goes back past that (a kick
    that left the ball within reach starts the next set-up). The time is (kick row - first
    row) x ``cycle_s`` (the replay's by default). Whatever moved the ball into reach counts,
    the kicker walking or the ball rolling (``ball_speed`` tells them apart). A kick whose
    kicker, in the row before it, was out of reach, down or out of play has no set-up
    (``seconds`` None): the league recorder counts a contact within 10 cycles of a kick
    request as a kick, wherever the robot stood."""
    if cycle_s is None:
        cycle_s = float(replay.metadata["cycle_s"])
    if replay.kick_cycle is None or not len(replay.kick_cycle):
        return []
    ball = np.asarray(replay.ball, np.float64)
    players = np.asarray(replay.players, np.float64)
    fallen = np.asarray(replay.fallen, bool) if replay.fallen is not None else \
        np.zeros(players.shape[:2], bool)
    in_play = ~np.isin(np.asarray(replay.play_mode), NOT_IN_PLAY)
    previous: dict[int, int] = {}
    out = []
    for row, player in zip(replay.kick_cycle.tolist(), replay.kick_player.tolist(),
                           strict=True):
        row, player = int(row), int(player)
        floor = previous.get(player, -1) + 1   # the first row after its previous kick
        previous[player] = row
        if row < 1:
            out.append(KickSetup(row, player, None, None, "start", 0.0))
            continue
        d = np.hypot(*(ball[:row, :2] - players[:row, player, :2]).T)
        ok = (d <= reach) & ~fallen[:row, player] & in_play[:row]
        last = row - 1
        if not ok[last]:
            why = ("not in play" if not in_play[last] else "down" if fallen[last, player]
                   else "out of reach")
            out.append(KickSetup(row, player, None, None, why, 0.0))
            continue
        gaps = np.flatnonzero(~ok[floor:row])   # rows of the window that break the run
        start = floor + (int(gaps[-1]) + 1 if len(gaps) else 0)
        why = "arrival" if len(gaps) else "previous kick" if floor > 0 else "start"
        out.append(KickSetup(row, player, start, (row - start) * cycle_s, why,
                             float(np.hypot(*ball[start, 2:4]))))
    return out


def kick_setup_summary(setups: list[KickSetup]) -> dict[str, Any]:
    """Count, mean, median, standard deviation and quartiles (s) of the measured set-up
    times in ``setups``, how many began at an arrival, at a previous kick or the start, how
    many with the ball moving, and how many kicks were left out, by why."""
    times = np.array([s.seconds for s in setups if s.seconds is not None], float)
    left_out: dict[str, int] = {}
    began: dict[str, int] = {}
    for s in setups:
        into = began if s.seconds is not None else left_out
        into[s.why] = into.get(s.why, 0) + 1
    out: dict[str, Any] = {"kicks": len(setups), "n": int(len(times)), "began": began,
                           "left_out": left_out,
                           "ball_moving": sum(s.seconds is not None
                                              and s.ball_speed >= BALL_MOVING_M_S
                                              for s in setups)}
    if len(times):
        q10, q25, q75, q90 = np.percentile(times, [10, 25, 75, 90])
        out |= {"mean_s": round(float(times.mean()), 3),
                "median_s": round(float(np.median(times)), 3),
                "std_s": round(float(times.std(ddof=1)), 3) if len(times) > 1 else 0.0,
                "p10_s": round(float(q10), 3), "p25_s": round(float(q25), 3),
                "p75_s": round(float(q75), 3), "p90_s": round(float(q90), 3),
                "max_s": round(float(times.max()), 3)}
    return out


class LeagueReplayRecorder:
    """Records a ``LocalServer`` match; ``record(game, kicking, said)`` once per cycle (after
    the perceptions), ``save(path, metadata)`` at the end.

    ``teams``: the server names of the left and right team; ``kicking``: player indices
    (0..2N-1, left team first) whose team asked them to kick this cycle; ``said``: (2N,)
    bytes each said this cycle."""

    def __init__(self, server: Any, teams: tuple[str, str], team_size: int,
                 field: str = "mj7v7") -> None:
        import mujoco

        self.sim = server.sim
        self.n = team_size
        self.field = field_preset(field)
        self.field_name = field
        m = self.sim.mj_model
        self._ball_q = m.joint("ball-root").qposadr[0]
        self._ball_v = m.joint("ball-root").dofadr[0]
        self._ball_geom = m.geom("ball").id
        prefixes = []
        for team in teams:
            for unum in range(1, team_size + 1):
                agent = server._agents[(team, unum)]
                prefixes.append(agent.agent_id.prefix)
        self._root_q = np.array([m.joint(p + "root").qposadr[0] for p in prefixes])
        self._geom_player = np.full(m.ngeom, -1, dtype=np.int64)
        for g in range(m.ngeom):
            name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g) or ""
            for i, p in enumerate(prefixes):
                if name.startswith(p):
                    self._geom_player[g] = i
        self._rows: list[dict[str, Any]] = []
        self._window = np.zeros(2 * team_size, dtype=np.int64)
        self._last_kick = np.full(2 * team_size, -10**9, dtype=np.int64)
        self._kicks: list[tuple[int, int]] = []
        self._touches: list[tuple[int, int]] = []
        self._goals: list[tuple[int, int, int]] = []
        self._last_toucher = -1
        self._score = (0, 0)

    def record(self, game: GameState, kicking: set[int], said: np.ndarray) -> None:
        d = self.sim.mj_data
        row = len(self._rows)
        ball = np.array([*d.qpos[self._ball_q:self._ball_q + 2],
                         *d.qvel[self._ball_v:self._ball_v + 2]], dtype=np.float32)
        players = np.zeros((2 * self.n, 3), np.float32)
        fallen = np.zeros(2 * self.n, bool)
        for i, a in enumerate(self._root_q):
            x, y, z, *quat = d.qpos[a:a + 7]
            players[i] = (x, y, quat_yaw(*quat))
            fallen[i] = torso_down(quat, z)
        self._rows.append({"ball": ball, "players": players, "fallen": fallen,
                           "mode": play_mode_index(game.play_mode, "left"),
                           "score": (game.score_left, game.score_right), "time": game.time,
                           "said": np.asarray(said, np.uint8)})
        for i in kicking:
            self._window[i] = KICK_WINDOW_CYCLES
        touching = set()
        for c in d.contact[:d.ncon]:
            g = c.geom2 if c.geom1 == self._ball_geom else c.geom1 \
                if c.geom2 == self._ball_geom else -1
            if g >= 0 and self._geom_player[g] >= 0:
                touching.add(int(self._geom_player[g]))
        if row > 0:
            for i in sorted(touching):
                if self._window[i] > 0 and row - self._last_kick[i] > KICK_GRACE_CYCLES:
                    self._kicks.append((row, i))
                    self._last_kick[i] = row
                else:
                    self._touches.append((row, i))
                self._last_toucher = i
            score = (game.score_left, game.score_right)
            for team in (0, 1):
                for _ in range(max(0, score[team] - self._score[team])):
                    self._goals.append((row, team, self._last_toucher))
            self._score = score
        self._window = np.maximum(self._window - 1, 0)

    def _kick_outcomes(self, ball: np.ndarray) -> list[tuple[int, int, float, float]]:
        """Each kick's realised distance and world direction (what the ball then did)."""
        contacts = sorted({r for r, _ in self._kicks} | {r for r, _ in self._touches})
        out = []
        for row, player in self._kicks:
            later = [r for r in contacts if r > row + 2]
            end = min(later[0] if later else len(ball) - 1, row + KICK_FOLLOW_CYCLES,
                      len(ball) - 1)
            seg = ball[row - 1:end + 1, :2].astype(np.float64)
            travel = float(np.sum(np.hypot(*np.diff(seg, axis=0).T))) if len(seg) > 1 else 0.0
            dx, dy = seg[-1] - seg[0]
            out.append((row, player, travel, math.atan2(dy, dx) if travel > 0 else 0.0))
        return out

    def arrays(self) -> dict[str, np.ndarray]:
        t, n2 = len(self._rows), 2 * self.n
        ball = np.stack([r["ball"] for r in self._rows]) if t else np.zeros((0, 4), np.float32)
        kicks, touches, goals = self._kick_outcomes(ball), self._touches, self._goals
        return {
            "ball": ball,
            "players": np.stack([r["players"] for r in self._rows]),
            "play_mode": np.asarray([r["mode"] for r in self._rows], np.int8),
            "score": np.asarray([r["score"] for r in self._rows], np.int16),
            "time_s": np.asarray([r["time"] for r in self._rows], np.float64),
            "attack_sign": np.ones(t, np.int8),    # one half: left attacks +x
            "fallen": latch_falls(np.stack([r["fallen"] for r in self._rows])),
            **event_arrays(kicks, touches, goals),
            "say_bytes": np.stack([r["said"] for r in self._rows]),
            "say_drops": np.zeros((t, n2), np.uint16),
            "heard_from": np.zeros((t, n2), np.uint32),
        }

    def save(self, path: str | Path, metadata: dict[str, Any]) -> Path:
        f = self.field
        meta = dict(metadata, field=self.field_name, team_size=self.n,
                    cycle_s=CYCLE_S, half_length=float(f.half_length),
                    half_width=float(f.half_width), half_goal_width=float(f.half_goal_width),
                    extras=False, world="league (rcsssmj LocalServer)")
        return write_replay(path, self.arrays(), meta)
