"""Server perceptions -> the env's ``vision``-mode Dict observation (``mj`` profile layout).

``VisionObservationBuilder(side, team_size, team)`` keeps one team's per-agent memory (last
torso pose, cycles since the last ``See``) and turns each agent's ``Perception`` into exactly
the dict a team plugin gets from ``teamenv.parallel_env(observation_mode="vision",
vision="mj", channel="mj", field="mj7v7")``: the same keys, shapes and float32 dtype, rows in
the same order (landmark row k = ``landmarks(field, "mj")`` row k in the team frame, teammate/
opponent row k = uniform number k + 1, own row never present), values in the same units.

Where the server gives something else than the env, the nearest equivalent is filled in
(listed in docs/league.md, "Observation differences"):

- ``landmarks``/``ball``/``teammates``/``opponents``: the server's polar sightings as they
  come (the camera is the T1's head, so the head's pan/tilt and the torso's lean are in them;
  the env's camera is upright along the body heading); players by their ``head`` marker;
  goal-area and penalty-area junctions (not in our table) are left out.
- ``lines``: 0 rows (the ``mj`` profile has none; the server sends no lines).
- ``vision``: fresh = a ``See`` came this cycle; cycles since the last one (before the first
  one: cycles since the agent's first observation).
- ``odometry``: the torso's true displacement over the last cycle in the body frame of the
  cycle's start (from the server's ``pos``/``quat``) -- the env gives what its walk engine
  believes; 0 on the first cycle and after a beam.
- ``gyro``: the true heading change of the cycle from ``quat`` (the env: the same, ``mj``
  gyro noise 0); 0 on the first cycle and after a beam.
- ``body``: fallen = ``falls.is_fallen``: torso tilted more than ``FALL_TILT`` from upright
  or lower than ``FALL_HEIGHT_M`` (the env: its fall model's state); head pan = the ``hj1`` joint angle.
- ``play_mode``: the server's mode (``corner_kick_left`` ...) as ours, team-relative; the
  modes we lack (free kicks, offside, penalties) as a kick-in of the team that takes it.
- ``game``: game time, half 1 (a league match here is one half), own and their score.
- ``heard``/``heard_text``: the server does not say who spoke; a message counts as a
  teammate's when its text is one that a teammate said lately (``teammate_texts``; the
  match loop looks back ``SAID_MEMORY_CYCLES``), else as an opponent's. Slot order as the
  env: teammates, then opponents (never oneself:
  the server does not echo), at most ``max_heard`` (8), direction = the server's integer
  azimuth (its sensor frame).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from comms.profiles import get_profile
from teamenv.config import VISION_PROFILES
from teamenv.field import field_preset
from teamenv.landmarks import landmarks
from teamenv.sim.playmode import PlayMode
from teamenv.sim.vision import vision_layout
from teamenv.spaces import vision_dict_observation_space

from .adapter import observe
from .controller import torso_pose
from .errors import LeagueError
from .falls import is_fallen
from .perception import Perception, Polar

#: cycles a said text is remembered to recognise it when heard (the server delivers it in
#: the second perception after the one it answered; the env in the next)
SAID_MEMORY_CYCLES = 3

#: server play mode -> (our mode kind, team) where the names differ (team None: no team)
_MODE_KINDS: dict[str, str] = {
    "corner_kick": "CornerKick", "goal_kick": "GoalKick",
    # modes the env lacks: a set play of the team that takes it (ball at a spot, the
    # opponents kept away), which is what our kick-in is
    "offside": "KickIn", "free_kick": "KickIn", "direct_free_kick": "KickIn",
    "penalty_kick": "KickIn", "penalty_shoot": "KickIn",
}


def play_mode_index(mode: str, side: str) -> int:
    """The server's play mode ``mode`` as the ``PLAY_MODES`` index team ``side`` sees."""
    try:
        ours = PlayMode[mode]
    except KeyError:
        kind, _, team = mode.rpartition("_")
        if kind not in _MODE_KINDS or team not in ("left", "right"):
            raise LeagueError(f"play mode {mode!r} from the server is unknown") from None
        ours = PlayMode.of(_MODE_KINDS[kind], 0 if team == "left" else 1)
    return int(ours.for_team(0 if side == "left" else 1))


def _wrap(a: float) -> float:
    return math.remainder(a, 2 * math.pi)


class VisionObservationBuilder:
    """One team's ``vision``-mode observations (Dict form, ``mj`` profile) from perceptions.

    Args:
        side: "left" or "right" (the team frame: each side attacks +x).
        team_size: players per side (the rows of ``teammates``/``opponents``).
        team: the team's name on the server (tells teammates from opponents in ``See``).
        field: the pitch of the layout (``mj7v7``, the server's ``fifa7vs7``).
        channel: the say channel (``mj``: 8 heard slots).
    """

    def __init__(self, side: str, team_size: int, team: str, field: str = "mj7v7",
                 channel: str = "mj") -> None:
        if side not in ("left", "right"):
            raise LeagueError(f"side must be 'left' or 'right', not {side!r}")
        self.side, self.team_size, self.team = side, int(team_size), team
        self.field = field_preset(field)
        self.config = VISION_PROFILES["mj"]
        self.channel = get_profile(channel)
        self.heard_slots = int(self.channel.max_heard)
        self.layout = vision_layout(self.field, self.team_size, self.heard_slots, self.config)
        #: the env's observation space of one agent (what every built dict lies in)
        self.space = vision_dict_observation_space(self.layout, self.channel)
        self._off = self.layout.offsets
        names = landmarks(self.field, self.config.landmark_kind).names
        self._row_of = {name: k for k, name in enumerate(names)}
        self.agents = tuple(f"{side}_{k + 1}" for k in range(self.team_size))
        self.reset()

    def reset(self) -> None:
        """A new match: forget every agent's last pose and vision time."""
        self._pose: dict[int, tuple[float, float, float] | None] = {}
        self._since: dict[int, int] = {}

    def note_beam(self, unum: int) -> None:
        """``unum`` was beamed: its next odometry and gyro are 0, not the jump."""
        self._pose[unum] = None

    def agent(self, unum: int) -> str:
        """The env's name of uniform number ``unum`` (``left_3``)."""
        return self.agents[unum - 1]

    # -- one agent -------------------------------------------------------------------------
    def observe(self, unum: int, p: Perception,
                teammate_texts: Iterable[str] = ()) -> dict[str, Any]:
        """Agent ``unum``'s Dict observation of perception ``p``.

        ``teammate_texts``: what this team's other agents said lately (heard messages with
        one of these texts count as a teammate's)."""
        if not 1 <= unum <= self.team_size:
            raise LeagueError(f"team {self.team}: uniform number {unum} is not in "
                              f"1..{self.team_size}")
        who = f"agent {self.team}_{unum}"
        if p.game is None or p.time is None:
            raise LeagueError(f"{who}: perception without time/GS")
        seen = observe(p, self.team, self.side)
        off = self._off
        row = np.zeros(self.layout.size)

        def put(key: str, k: int, polar: Polar) -> None:
            a = off[key][0] + 4 * k
            row[a:a + 4] = (1.0, polar.distance, polar.azimuth, polar.elevation)

        n_landmarks = n_players = 0
        for name, polar in seen.landmarks.items():
            put("landmarks", self._row_of[name], polar)
            n_landmarks += 1
        if seen.ball is not None:
            put("ball", 0, seen.ball)
        for key, players in (("teammates", seen.teammates), ("opponents", seen.opponents)):
            for u, polar in players.items():
                if 1 <= u <= self.team_size and not (key == "teammates" and u == unum):
                    put(key, u - 1, polar)
                    n_players += 1
        since = 0 if seen.vision_update else self._since.get(unum, 0) + 1
        self._since[unum] = since
        a = off["vision"][0]
        row[a:a + 2] = (1.0 if seen.vision_update else 0.0, since)
        a = off["counts"][0]
        row[a:a + 4] = (n_landmarks, n_players, 0, seen.ball is not None)

        # odometry and gyro from the true torso pose (first cycle, after a beam: 0)
        try:
            pose = torso_pose(p)
        except LeagueError as exc:
            raise LeagueError(f"{who}: {exc}") from None
        last = self._pose.get(unum)
        self._pose[unum] = pose
        if last is not None:
            dx, dy = pose[0] - last[0], pose[1] - last[1]
            c, s = math.cos(last[2]), math.sin(last[2])
            turn = _wrap(pose[2] - last[2])
            a = off["odometry"][0]
            row[a:a + 3] = (c * dx + s * dy, -s * dx + c * dy, turn)
            row[off["gyro"][0]] = turn
        head = p.joints.get("q_hj1")
        a = off["body"][0]
        row[a:a + 2] = (float(is_fallen(p)), 0.0 if head is None else head.angle)

        mode = play_mode_index(p.game.play_mode, self.side)
        a = off["play_mode"][0]
        row[a + mode] = 1.0
        a = off["game"][0]
        row[a:a + 4] = (p.game.time, 1.0, seen.own_score, seen.their_score)

        mates = set(teammate_texts)
        heard = sorted(seen.heard_text, key=lambda m: m[1] not in mates)[:self.heard_slots]
        texts = [""] * self.heard_slots
        a = off["heard"][0]
        for slot, (azimuth, text) in enumerate(heard):
            row[a + 4 * slot:a + 4 * slot + 4] = (1.0, 0.0, float(text in mates), azimuth)
            texts[slot] = text
        return self._as_dict(row.astype(np.float32), mode, tuple(texts))

    def _as_dict(self, row: np.ndarray, mode: int, texts: tuple[str, ...]) -> dict[str, Any]:
        """The env's Dict form (``VisionPerception.as_dicts``): views of ``row``."""
        out: dict[str, Any] = {key: rows[0] for key, rows
                               in self.layout.dict_parts(row[None]).items()}
        out["play_mode"] = mode
        out["heard_text"] = texts
        return out

    # -- the team --------------------------------------------------------------------------
    def observe_team(self, perceptions: Mapping[int, Perception],
                     said: Mapping[int, Iterable[str]] | None = None) -> dict[str, dict[str, Any]]:
        """Every agent's observation, keyed by the env's agent names. ``said``: per uniform
        number, the texts that agent said in the last few cycles (the server delivers a
        message two perceptions after it was said); a heard text one of the *other* agents
        of this team said counts as a teammate's."""
        said = said or {}
        out = {}
        for unum, p in perceptions.items():
            mates = {t for u, texts in said.items() if u != unum for t in texts if t}
            out[self.agent(unum)] = self.observe(unum, p, mates)
        return out
