"""What an agent's behaviours know about its body and the pitch: command range, reach, gains."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from strategy.behaviours.navigation import NavigationParams
from strategy.geometry import BallRoll
from teamenv.field import FieldSpec


@dataclass(frozen=True)
class Skills:
    """Body and navigation facts the behaviours use.

    Attributes:
        field: the pitch.
        walk_low, walk_high: (3,) range of the walk command (vx, vy m/s, vturn rad/s).
        kick_reach: body centre to ball centre distance within which a kick connects, metres.
        kick_distance_m: how far a full-power kick rolls on average, metres (seed 000 Table 1).
        kick_max_angle: kicks are aimed at most this far from the body's heading, radians (a
            humanoid kicks forwards; it does not kick behind itself).
        navigation: potential-field and walk-controller gains.
        ball_roll: the ball's drag model (where a rolling ball stops).
    """

    field: FieldSpec
    walk_low: NDArray[np.float64]
    walk_high: NDArray[np.float64]
    kick_reach: float = 0.35
    kick_distance_m: float = 8.92
    kick_max_angle: float = 1.5
    navigation: NavigationParams = field(default_factory=NavigationParams)
    ball_roll: BallRoll = field(default_factory=BallRoll)
