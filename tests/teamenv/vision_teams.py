"""A tiny team that plays from ``vision`` observations only (for the env, match and
tournament tests; the built-in teams are strategy's business)."""

from __future__ import annotations

import math

import numpy as np

from teamenv.errors import ConfigError
from teamenv.landmarks import landmarks
from teamenv.teams import TeamContext


class BallTurner:
    """Turns until it sees the ball, walks at it and kicks it forward when it is close.

    It reads only what vision gives: the ball's sighting (distance, azimuth, elevation from a
    camera ``context.perception.camera_height_m`` up) and knows the landmark table
    ``context.landmark_kind`` names (it checks the table's size against the observation).
    """

    def __init__(self, context: TeamContext) -> None:
        if context.observation_mode != "vision" or context.perception is None:
            raise ConfigError(f"BallTurner: plays in vision mode only, got "
                              f"{context.observation_mode!r}")
        self.context = context
        self.n_landmarks = len(landmarks(context.field, context.landmark_kind))
        self.seen_ball = 0  # sightings of the ball over the match (the tests read it)
        self.last: dict[str, dict] = {}

    def reset(self, seed: int) -> None:
        self.seen_ball = 0
        self.last = {}

    def act(self, observations):
        out = {}
        for agent, obs in observations.items():
            assert obs["landmarks"].shape == (self.n_landmarks, 4)
            if obs["vision"][0] < 0.5 and agent in self.last:  # no new look: keep going
                out[agent] = self.last[agent]
                continue
            present, dist, az, el = (float(v) for v in obs["ball"])
            walk, kick = [0.0, 0.0, 0.8], [0.0, 0.0]
            if present > 0.5:
                self.seen_ball += 1
                ground = dist * math.cos(el)
                walk = [0.8, 0.0, max(-1.5, min(1.5, 2.0 * az))]
                if ground < self.context.kick_reach and abs(az) < 0.5:
                    kick = [1.0, 0.0]
            out[agent] = self.last[agent] = {"walk": np.array(walk, np.float32),
                                             "kick": np.array(kick, np.float32)}
        return out
