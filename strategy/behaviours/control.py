"""Control requests: what a behaviour asks the body to do this cycle (walk, kick, beam, say).

The control layer of the agent (seed 000 §2.5): behaviours produce a ``ControlRequest``; the
team turns it into the env's Dict-form action (``to_action``), clipping the walk command to
the range the env accepts. Kept free of anything teamenv-only, so the same requests could
drive a client of the league's server.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class ControlRequest:
    """One cycle's requests of one agent.

    Attributes:
        walk: (vx m/s, vy m/s, vturn rad/s), body frame.
        kick: (power in (0, 1], direction rad body frame), or None for no kick.
        beam: (x, y, rotation) team frame, or None (only honoured while beaming is allowed).
        say: text to say ("" = silent).
        behaviour: name of the behaviour that made the request (for tests and debugging).
    """

    walk: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    kick: tuple[float, float] | None = None
    beam: tuple[float, float, float] | None = None
    say: str = ""
    behaviour: str = "idle"

    def with_say(self, text: str) -> ControlRequest:
        return ControlRequest(self.walk, self.kick, self.beam, text, self.behaviour)

    def named(self, behaviour: str) -> ControlRequest:
        """The same request, credited to ``behaviour``."""
        return replace(self, behaviour=behaviour)

    def to_action(self, low: NDArray[np.float64], high: NDArray[np.float64]) -> dict[str, Any]:
        """The env's Dict-form action; the walk command is clipped to [low, high]."""
        walk = np.minimum(np.maximum(self.walk, low), high)
        action: dict[str, Any] = {"walk": walk}
        if self.kick is not None:
            action["kick"] = np.array([min(1.0, max(0.0, self.kick[0])), self.kick[1]])
        if self.beam is not None:
            action["beam"] = np.asarray(self.beam, dtype=np.float64)
            action["beam_request"] = 1
        if self.say:
            action["say"] = self.say
        return action
