"""Beliefs from the league's restricted vision: each agent's ``WorldModel`` in ``vision`` mode.

In ``vision`` mode an agent is told nothing of its own pose and sees only a 120° cone every
few cycles. ``VisionPerceiver`` keeps, for every agent of a team (batched for speed; each
agent's state is its own and is fed only its own observation and what it heard):

- its pose, by Monte Carlo localization (``strategy.perception.localization``) from odometry
  every cycle and landmark / line sightings on vision cycles;
- the ball, from its own sightings (DBSCAN over a sliding window) merged with the ball
  reports its teammates said (``strategy.perception.ball_belief``);
- its opponents, from its own sightings (per uniform number, with an age limit);
- its teammates, from their said poses (``strategy.perception.team_message``) or, when
  fresher, from its own sightings of them.

``update(observations)`` returns one ``WorldModel`` per agent, the same type the ``state``
mode builds, so everything above perception is the same code in both modes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from strategy.geometry import BallRoll
from strategy.perception.ball_belief import BallEstimate
from strategy.perception.clustering import prepare_kernels as prepare_clustering
from strategy.perception.filtering import FilterParams
from strategy.perception.localization import BatchLocalizer, LocalizationParams, for_camera
from strategy.perception.team_message import TeamReport, decode_team_report, team_message_schema
from strategy.perception.team_sightings import TeamSightings
from strategy.perception.worldmodel import WorldModel, heard_texts
from teamenv import PlayMode
from teamenv.errors import ConfigError
from teamenv.landmarks import from_polar
from teamenv.teams import TeamContext

_MODES = {int(m): m for m in PlayMode}
KICKOFF_MODES = {"BeforeKickOff", "KickOff_Left", "KickOff_Right", "Goal_Left", "Goal_Right"}


@dataclass(frozen=True)
class VisionBeliefParams:
    """How long a teammate's said or seen position stays believed (seconds; opponents and the
    ball age out by ``FilterParams``)."""

    teammate_max_age_s: float = 3.0


class VisionPerceiver:
    """All of one team's agents' beliefs in ``vision`` mode (see the module docstring).

    Args:
        context: the team's context (``observation_mode`` must be ``"vision"``).
        communicate: read teammates' team messages (False: the silent team hears nothing).
        localization, filtering, beliefs: parameters of each part.
    """

    def __init__(self, context: TeamContext, communicate: bool = True,
                 localization: LocalizationParams | None = None,
                 filtering: FilterParams | None = None,
                 beliefs: VisionBeliefParams | None = None,
                 roll: BallRoll | None = None) -> None:
        if context.observation_mode != "vision":
            raise ConfigError(f"VisionPerceiver: the {context.side} team's observation mode is "
                              f"{context.observation_mode!r}, not 'vision'")
        if context.perception is None or context.landmark_kind is None:
            raise ConfigError(f"VisionPerceiver: the {context.side} team's context is in "
                              f"'vision' mode but names no perception config / landmark kind "
                              f"(perception={context.perception!r}); make the env with "
                              f"observation_mode='vision'")
        self.context = context
        self.field = context.field
        self.agents = tuple(context.agents)
        self.index = {agent: k for k, agent in enumerate(self.agents)}
        self._all = list(range(len(self.agents)))
        self.n = context.team_size
        self.cycle_s = context.cycle_s
        self.communicate = communicate
        self.camera_height = float(context.perception.camera_height_m)
        # the particle filter's sensor model follows the camera the team is told about
        self.localization = for_camera(localization or LocalizationParams(), context.perception)
        self.filtering = filtering or FilterParams()
        self.params = beliefs or VisionBeliefParams()
        self.roll = roll or BallRoll()
        self.schema = team_message_schema(self.n, self.field, context.channel)
        self.reset(0)

    def reset(self, seed: int) -> None:
        """Forget everything (a new match); the localizers start from a uniform prior."""
        n = self.n
        self.rng = np.random.default_rng(seed)
        self.localizer = BatchLocalizer(n, self.field, self.context.landmark_kind,
                                        self.camera_height, self.localization, self.rng)
        self.sightings = TeamSightings(n, n, self.filtering, self.roll.advance)
        self.play_mode: int | None = None
        # per listener: teammates' positions (n, n, 2), fallen and when learnt
        self.mate_xy = np.zeros((n, n, 2))
        self.mate_fallen = np.zeros((n, n), dtype=bool)
        self.mate_time = np.full((n, n), -np.inf)
        self.reports: list[list[TeamReport]] = [[] for _ in range(n)]
        self._decoded: dict[str, TeamReport | None] = {}
        self.cycle = 0
        prepare_clustering()  # compiled here, not in the first cycle (its stall watchdog)

    # -- what the team told us it did -------------------------------------------------------
    def beamed(self, agent_index: int, pose: tuple[float, float, float]) -> None:
        """Agent ``agent_index`` asked to be beamed to ``pose`` (team frame): it knows where
        it is, up to the referee's beam noise."""
        self.localizer.beamed(agent_index, np.asarray(pose, dtype=np.float64))

    # -- the cycle --------------------------------------------------------------------------
    def update(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, WorldModel]:
        """Each agent's belief this cycle, from its own observation and what it heard.

        All agents in batched passes (localization, placing sightings, the windows, the
        heard reports), but every array row is one agent's own: agent k's belief depends
        only on agent k's observations and what agent k heard."""
        now = self.cycle * self.cycle_s
        self.cycle += 1
        index = [self.index[a] for a in observations]
        obs = list(observations.values())
        odometry = np.array([o["odometry"] for o in obs], dtype=np.float64)
        gyro = np.array([o["gyro"][0] for o in obs], dtype=np.float64)
        fresh = [bool(o["vision"][0] > 0.5) for o in obs]
        self.localizer.predict(None if index == self._all else index, odometry, gyro)
        rows = [k for k, f in zip(index, fresh, strict=True) if f]
        seen = [o for o, f in zip(obs, fresh, strict=True) if f]
        if rows:
            self.localizer.correct(None if rows == self._all else rows,
                                   np.stack([o["landmarks"] for o in seen]),
                                   np.stack([o["lines"] for o in seen]))
        estimate = self.localizer.estimate()
        poses, spreads = estimate.pose, estimate.spread
        mode = int(obs[0]["play_mode"]) if obs else None
        if mode != self.play_mode and mode != int(PlayMode.PlayOn):
            self.sightings.clear_ball()  # the referee placed the ball: old sightings mislead
        self.play_mode = mode
        if rows:
            self._see(rows, seen, poses, now)
        texts = [heard_texts(o) for o in obs]
        if self.communicate:
            for k, heard in zip(index, texts, strict=True):
                self._hear(k, heard, now)
        balls = self.sightings.ball_beliefs(now)
        opponents, opponents_known = self.sightings.all_opponents(now)
        mates = self.mate_xy.copy()
        present = now - self.mate_time <= self.params.teammate_max_age_s
        fallen = self.mate_fallen.copy()
        velocities = self._velocities(obs, poses[index])
        return {agent: self._world_model(k, o, poses[k], spreads[k], balls[k], mates[k],
                                         present[k], fallen[k], opponents[k],
                                         opponents_known[k], heard, velocity)
                for agent, k, o, heard, velocity in zip(observations, index, obs, texts,
                                                        velocities, strict=True)}

    def _velocities(self, obs: list[Mapping[str, Any]],
                    poses: NDArray[np.float64]) -> NDArray:
        """(A, 2) each agent's walking velocity in the team frame: its odometry turned by its
        believed heading, per cycle_s; ``strategy.geometry.to_team`` of the odometry's own
        dtype (float32 from the env: the cosine and sine are rounded to it, as there)."""
        odometry = np.stack([np.asarray(o["odometry"]) for o in obs])
        if odometry.dtype.kind != "f":  # integers: Python's float arithmetic, as to_team
            odometry = odometry.astype(np.float64)
        headings = poses[:, 2].tolist()
        c = np.array([math.cos(h) for h in headings]).astype(odometry.dtype, copy=False)
        s = np.array([math.sin(h) for h in headings]).astype(odometry.dtype, copy=False)
        forward, left = odometry[:, 0], odometry[:, 1]
        return np.stack((c * forward - s * left, s * forward + c * left), axis=1) / \
            self.cycle_s

    def _see(self, rows: list[int], seen: list[Mapping[str, Any]], poses: NDArray[np.float64],
             now: float) -> None:
        """The ball, opponents and teammates that agents ``rows`` saw this vision cycle, each
        placed from the agent's own pose (one pass for all of them)."""
        agent = np.asarray(rows, dtype=np.intp)
        ball = np.stack([o["ball"] for o in seen])
        opponents = np.stack([o["opponents"] for o in seen])
        mates = np.stack([o["teammates"] for o in seen])
        b_row = np.flatnonzero(ball[:, 0] > 0.5)
        o_row, o_id = np.nonzero(opponents[:, :, 0] > 0.5)
        m_row, m_id = np.nonzero(mates[:, :, 0] > 0.5)
        polar = np.concatenate((ball[b_row, 1:4], opponents[o_row, o_id, 1:4],
                                mates[m_row, m_id, 1:4])).astype(np.float64)
        if not len(polar):
            return
        owner = agent[np.concatenate((b_row, o_row, m_row))]
        xy = self._place(polar, poses, owner)
        n_objects = len(b_row) + len(o_row)
        ids = np.concatenate((agent[b_row] * self.sightings.stride,
                              agent[o_row] * self.sightings.stride + 1 + o_id))
        self.sightings.see_many(now, ids, xy[:n_objects])
        if len(m_row):
            k, j = agent[m_row], m_id
            older = self.mate_time[k, j] < now - 0.5  # a said pose beats a sighting
            self.mate_xy[k[older], j[older]] = xy[n_objects:][older]
            self.mate_time[k[older], j[older]] = now

    def _place(self, polar: NDArray[np.float64], poses: NDArray[np.float64],
               owner: NDArray[np.intp]) -> NDArray[np.float64]:
        """Team-frame (M, 2) ground points of polar sightings (M, 3), sighting i seen from
        ``poses[owner[i]]`` (``body_points_to_team`` per point, its heading's cosine and sine
        by ``math`` as there)."""
        body = from_polar(polar, self.camera_height)
        c = np.array([math.cos(h) for h in poses[:, 2].tolist()])[owner]
        s = np.array([math.sin(h) for h in poses[:, 2].tolist()])[owner]
        f, left = body[:, 0], body[:, 1]
        x, y = poses[owner, 0], poses[owner, 1]
        return np.column_stack((x + c * f - s * left, y + s * f + c * left))

    def _decode(self, text: str) -> TeamReport | None:
        """``decode_team_report`` of ``text``, once per text (every listener hears the same
        texts; the report's arrays are read-only)."""
        try:
            return self._decoded[text]
        except KeyError:
            pass
        report = decode_team_report(self.schema, text)
        if report is not None:
            for a in (report.roles, report.position, report.ball):
                if a is not None:
                    a.setflags(write=False)
        if len(self._decoded) >= 256:
            self._decoded.clear()
        self._decoded[text] = report
        return report

    def _hear(self, k: int, texts: list[str], now: float) -> None:
        reports = []
        for text in texts:
            report = self._decode(text)
            if report is None or report.sender == k or not 0 <= report.sender < self.n:
                continue
            j = report.sender
            reports.append(report)
            self.mate_xy[k, j] = report.position
            self.mate_fallen[k, j] = report.fallen
            self.mate_time[k, j] = now
            if report.ball is not None:
                self.sightings.hear(now, k, report.ball, report.ball_age_cycles * self.cycle_s,
                                    j)
        self.reports[k] = reports

    def _world_model(self, k: int, o: Mapping[str, Any], pose: NDArray[np.float64],
                     spread: float, ball: BallEstimate, mates: NDArray[np.float64],
                     present: NDArray[np.bool_], fallen: NDArray[np.bool_],
                     opponents: NDArray[np.float64], opponents_known: NDArray[np.bool_],
                     heard: list[str], velocity: NDArray) -> WorldModel:
        """Agent ``k``'s world model; ``mates``, ``present``, ``fallen`` are its rows of
        this cycle's copies (written into), the opponents its rows of this estimate's."""
        mode = _MODES.get(int(o["play_mode"])) or PlayMode(int(o["play_mode"]))
        age = ball.age_s
        if ball.position is not None:
            ball_xy = np.array(ball.position, dtype=np.float64)
        elif mode.name in KICKOFF_MODES:  # the rules put the ball on the centre spot
            ball_xy, age = np.zeros(2), 0.0
        else:  # unknown: a placeholder (``ball_known`` is False)
            ball_xy = pose[:2].copy()
        ball_v = np.array(ball.velocity, dtype=np.float64) if ball.velocity is not None else \
            np.zeros(2)
        mates[k] = pose[:2]
        present[k] = True
        fallen[k] = bool(o["body"][0] > 0.5)
        game = o["game"]
        return WorldModel(
            k, pose[:2].copy(), float(pose[2]), velocity, fallen[k], ball_xy, ball_v, mates,
            present, fallen, opponents, opponents_known, np.zeros(self.n, dtype=bool), mode,
            float(game[0]), int(game[1]), (int(game[2]), int(game[3])), tuple(heard),
            self.field, self.roll, b"", float(age), float(spread))
