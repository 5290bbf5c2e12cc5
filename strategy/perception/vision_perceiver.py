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

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from strategy.geometry import BallRoll, body_points_to_team, to_team
from strategy.perception.ball_belief import BallEstimate
from strategy.perception.filtering import FilterParams
from strategy.perception.localization import BatchLocalizer, LocalizationParams
from strategy.perception.team_message import TeamReport, decode_team_report, team_message_schema
from strategy.perception.team_sightings import TeamSightings
from strategy.perception.worldmodel import WorldModel, heard_texts
from teamenv import PlayMode
from teamenv.errors import ConfigError
from teamenv.landmarks import from_polar
from teamenv.teams import TeamContext

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
        self.n = context.team_size
        self.cycle_s = context.cycle_s
        self.communicate = communicate
        self.camera_height = float(context.perception.camera_height_m)
        self.localization = localization or LocalizationParams()
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
        self.cycle = 0

    # -- what the team told us it did -------------------------------------------------------
    def beamed(self, agent_index: int, pose: tuple[float, float, float]) -> None:
        """Agent ``agent_index`` asked to be beamed to ``pose`` (team frame): it knows where
        it is, up to the referee's beam noise."""
        self.localizer.beamed(agent_index, np.asarray(pose, dtype=np.float64))

    # -- the cycle --------------------------------------------------------------------------
    def update(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, WorldModel]:
        """Each agent's belief this cycle, from its own observation and what it heard."""
        now = self.cycle * self.cycle_s
        self.cycle += 1
        index = [self.index[a] for a in observations]
        obs = list(observations.values())
        odometry = np.array([o["odometry"] for o in obs], dtype=np.float64)
        gyro = np.array([o["gyro"][0] for o in obs], dtype=np.float64)
        fresh = np.array([o["vision"][0] > 0.5 for o in obs])
        self.localizer.predict(index, odometry, gyro)
        if fresh.any():
            rows = [k for k, f in zip(index, fresh, strict=True) if f]
            seen = [o for o, f in zip(obs, fresh, strict=True) if f]
            self.localizer.correct(rows, np.stack([o["landmarks"] for o in seen]),
                                   np.stack([o["lines"] for o in seen]))
        estimate = self.localizer.estimate()
        poses, spreads = estimate.pose, estimate.spread
        mode = int(obs[0]["play_mode"]) if obs else None
        if mode != self.play_mode and mode != int(PlayMode.PlayOn):
            self.sightings.clear_ball()  # the referee placed the ball: old sightings mislead
        self.play_mode = mode
        for k, o, is_fresh in zip(index, obs, fresh, strict=True):
            if is_fresh:
                self._sightings(k, o, poses[k], now)
            if self.communicate:
                self._hear(k, o, now)
        balls = self.sightings.ball_beliefs(now)
        return {agent: self._world_model(k, o, poses[k], spreads[k], balls[k], now)
                for agent, k, o in zip(observations, index, obs, strict=True)}

    def _sightings(self, k: int, o: Mapping[str, Any], pose: NDArray[np.float64],
                   now: float) -> None:
        ball = o["ball"]
        seen_ball = self._place(ball[None, 1:4], pose)[0] if ball[0] > 0.5 else None
        opponents = o["opponents"]
        seen = np.flatnonzero(opponents[:, 0] > 0.5)
        self.sightings.see(now, k, seen_ball, seen, self._place(opponents[seen, 1:4], pose))
        mates = o["teammates"]
        seen = np.flatnonzero(mates[:, 0] > 0.5)
        if seen.size:
            xy = self._place(mates[seen, 1:4], pose)
            older = self.mate_time[k, seen] < now - 0.5  # a said pose beats a sighting
            self.mate_xy[k, seen[older]] = xy[older]
            self.mate_time[k, seen[older]] = now

    def _place(self, polar: NDArray[np.floating], pose: NDArray[np.float64]) -> NDArray:
        """Team-frame (M, 2) ground points of polar sightings seen from ``pose``."""
        body = from_polar(np.asarray(polar, dtype=np.float64), self.camera_height)
        return body_points_to_team(body, pose[0], pose[1], pose[2])

    def _hear(self, k: int, o: Mapping[str, Any], now: float) -> None:
        reports = []
        for text in heard_texts(o):
            report = decode_team_report(self.schema, text)
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
                     spread: float, ball: BallEstimate, now: float) -> WorldModel:
        mode = PlayMode(int(o["play_mode"]))
        age = ball.age_s
        if ball.position is not None:
            ball_xy = np.array(ball.position, dtype=np.float64)
        elif mode.name in KICKOFF_MODES:  # the rules put the ball on the centre spot
            ball_xy, age = np.zeros(2), 0.0
        else:  # unknown: a placeholder (``ball_known`` is False)
            ball_xy = pose[:2].copy()
        ball_v = np.array(ball.velocity, dtype=np.float64) if ball.velocity is not None else \
            np.zeros(2)
        mates = self.mate_xy[k].copy()
        present = now - self.mate_time[k] <= self.params.teammate_max_age_s
        mates[k] = pose[:2]
        present[k] = True
        fallen = self.mate_fallen[k].copy()
        fallen[k] = bool(o["body"][0] > 0.5)
        opponents, opp_present = self.sightings.opponents(now, k)
        odo = o["odometry"]
        velocity = np.array(to_team(odo[0], odo[1], pose[2])) / self.cycle_s
        game = o["game"]
        return WorldModel(
            k, pose[:2].copy(), float(pose[2]), velocity, fallen[k], ball_xy, ball_v, mates,
            present, fallen, np.asarray(opponents, dtype=np.float64),
            np.asarray(opp_present, dtype=bool), np.zeros(self.n, dtype=bool), mode,
            float(game[0]), int(game[1]), (int(game[2]), int(game[3])), tuple(heard_texts(o)),
            self.field, self.roll, b"", float(age), float(spread))
