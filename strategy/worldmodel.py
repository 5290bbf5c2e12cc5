"""One agent's world model: what it believes about the match, built from its own observation.

The perception layer of the agent (seed 000 §2): a Dict-form ``state`` observation in, a
``WorldModel`` out — absolute team-frame positions (we attack +x, our goal at x = -length/2),
the play mode as the team sees it, and the texts heard from teammates. Nothing here looks at
another agent's observation: a team's agents share no state.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from strategy.positioning import WorldView, heard_texts
from teamenv.errors import TeamEnvError
from teamenv.field import FieldSpec
from teamenv.observation import team_frame
from teamenv import PlayMode


class WorldModelError(TeamEnvError, ValueError):
    """An observation a world model cannot be built from (names the agent and the field)."""


@dataclass(frozen=True)
class WorldModel:
    """What agent ``me`` (index = uniform number - 1) believes this cycle (metres, radians).

    Attributes:
        me: own player index.
        position, heading, velocity, fallen: own pose, walking velocity and state.
        ball, ball_velocity: (2,) each.
        teammates: (N, 2), own row = own position; ``teammates_present``/``_fallen`` masks.
        opponents: (N, 2) with ``opponents_present``/``opponents_fallen``.
        play_mode: team-relative (``_Left`` = our team).
        time_s, half, score: game clock, half (1 or 2), (ours, theirs).
        heard: texts heard this cycle from teammates or oneself.
        field: the pitch.
    """

    me: int
    position: NDArray[np.float64]
    heading: float
    velocity: NDArray[np.float64]
    fallen: bool
    ball: NDArray[np.float64]
    ball_velocity: NDArray[np.float64]
    teammates: NDArray[np.float64]
    teammates_present: NDArray[np.bool_]
    teammates_fallen: NDArray[np.bool_]
    opponents: NDArray[np.float64]
    opponents_present: NDArray[np.bool_]
    opponents_fallen: NDArray[np.bool_]
    play_mode: PlayMode
    time_s: float
    half: int
    score: tuple[int, int]
    heard: tuple[str, ...]
    field: FieldSpec

    @classmethod
    def from_observation(cls, obs: Mapping[str, Any], me: int, field: FieldSpec,
                         agent: str = "") -> WorldModel:
        """Build the world model of agent ``me`` from its Dict-form ``state`` observation."""
        try:
            v = team_frame(obs)
        except (KeyError, TypeError, ValueError) as exc:
            raise WorldModelError(
                f"{agent or f'player {me}'}: cannot read the observation ({type(exc).__name__}: "
                f"{exc}); the team needs Dict-form 'state' observations"
            ) from None
        if not (math.isfinite(v.position[0] + v.position[1] + v.ball[0] + v.ball[1])):
            raise WorldModelError(f"{agent or f'player {me}'}: observation 'self'/'ball' is not "
                                  f"finite: position={v.position.tolist()}, ball={v.ball.tolist()}")
        mates = v.teammates.copy()
        mates[me] = v.position
        present = v.teammates_present.copy()
        present[me] = True
        mates_fallen = v.teammates_fallen.copy()
        mates_fallen[me] = v.fallen
        return cls(me, v.position, v.heading, v.velocity, v.fallen, v.ball, v.ball_velocity,
                   mates, present, mates_fallen, v.opponents, v.opponents_present,
                   v.opponents_fallen, v.play_mode, v.time_s, v.half, v.score,
                   tuple(heard_texts(obs)), field)

    # -- derived beliefs -------------------------------------------------------------------
    @property
    def own_goal(self) -> NDArray[np.float64]:
        return np.array([-self.field.half_length, 0.0])

    @property
    def opponent_goal(self) -> NDArray[np.float64]:
        return np.array([self.field.half_length, 0.0])

    def distance(self, point: NDArray[np.float64]) -> float:
        return math.hypot(point[0] - self.position[0], point[1] - self.position[1])

    def ball_distance(self) -> float:
        return self.distance(self.ball)

    def upright_ball_distances(self) -> NDArray[np.float64]:
        """(N,) each teammate's distance to the ball (own row included); inf for teammates
        absent or fallen."""
        d = np.hypot(self.teammates[:, 0] - self.ball[0], self.teammates[:, 1] - self.ball[1])
        d[~(self.teammates_present & ~self.teammates_fallen)] = np.inf
        return d

    def positioning_view(self) -> WorldView:
        """The view ``strategy.positioning.PositioningAgent`` decides from."""
        return WorldView(self.teammates, self.teammates_present, self.teammates_fallen,
                         self.ball, self.opponents, self.opponents_present)

    def obstacles(self, exclude_self: bool = True) -> NDArray[np.float64]:
        """(M, 2) positions of every present player but oneself (to walk around)."""
        mates = self.teammates[self.teammates_present]
        if exclude_self:
            keep = np.flatnonzero(self.teammates_present) != self.me
            mates = mates[keep]
        return np.concatenate([mates, self.opponents[self.opponents_present]])

    def predicted_ball(self, seconds: float, decel: float = 0.7) -> NDArray[np.float64]:
        """Where the rolling ball will be after ``seconds`` (constant deceleration model)."""
        speed = math.hypot(*self.ball_velocity)
        if speed < 1e-6 or seconds <= 0:
            return self.ball.copy()
        t = min(seconds, speed / decel)
        travel = speed * t - 0.5 * decel * t * t
        return self.ball + self.ball_velocity / speed * travel
