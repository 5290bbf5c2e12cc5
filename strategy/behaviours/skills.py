"""What an agent's behaviours know about its body and the pitch: command range, reach, gains."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from strategy.behaviours.navigation import NavigationParams
from strategy.geometry import BallRoll
from teamenv.capabilities import BodyCapabilities
from teamenv.field import FieldSpec


@dataclass(frozen=True)
class Skills:
    """Body and navigation facts the behaviours use.

    Attributes:
        field: the pitch.
        body: what the body can do (``TeamContext.body``: walk range and real speeds, kick
            reach, distance and spread, kick and get-up times), from the locomotion profile.
        kick_max_angle: kicks are aimed at most this far from the body's heading, radians (a
            humanoid kicks forwards; it does not kick behind itself); never more than the
            body can (``body.kick_max_angle_rad``, from the locomotion profile).
        navigation: potential-field and walk-controller gains.
        ball_roll: the ball's drag model (where a rolling ball stops).
        ball_radius: the ball's radius, metres.
        walk_low, walk_high: (3,) range of the walk command (vx, vy m/s, vturn rad/s), the
            body's, as arrays.
        run_speed: how fast (m/s) the body really walks when navigation asks for its top
            speed (the body's ``forward_speed``).
    """

    field: FieldSpec
    body: BodyCapabilities
    kick_max_angle: float = 1.5
    navigation: NavigationParams = field(default_factory=NavigationParams)
    ball_roll: BallRoll = field(default_factory=BallRoll)
    ball_radius: float = 0.042
    walk_low: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    walk_high: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    #: how fast (m/s) the body really walks when navigation asks for its top speed: what
    #: races to the ball and to a kick's landing point are timed with (computed once: body
    #: and navigation are frozen)
    run_speed: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        # a strategy may choose narrower kicks than its body's, never wider
        object.__setattr__(self, "kick_max_angle",
                           min(self.kick_max_angle, self.body.kick_max_angle_rad))
        object.__setattr__(self, "walk_low", np.asarray(self.body.walk_low, dtype=np.float64))
        object.__setattr__(self, "walk_high", np.asarray(self.body.walk_high, dtype=np.float64))
        object.__setattr__(self, "run_speed", self.body.forward_speed(self.navigation.max_speed))

    @property
    def kick_reach(self) -> float:
        """Body centre to ball centre distance within which a kick connects, metres."""
        return self.body.kick_reach

    @property
    def kick_distance_m(self) -> float:
        """How far a full-power kick rolls on average, metres."""
        return self.body.kick_distance_mean_m

    @property
    def contact_m(self) -> float:
        """Body centre to ball centre when the body touches the ball, metres."""
        return self.body.body_radius + self.ball_radius

