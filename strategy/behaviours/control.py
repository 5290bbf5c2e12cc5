"""Control requests: what a behaviour asks the body to do this cycle (walk, kick, beam, say).

The control layer of the agent (seed 000 §2.5): behaviours produce a ``ControlRequest``; the
team turns it into the env's Dict-form action (``to_action``), clipping the walk command to
the range the env accepts. Kept free of anything teamenv-only, so the same requests could
drive a client of the league's server.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from strategy.behaviours.walk_batch import WalkGoal


@dataclass(frozen=True)
class ControlRequest:
    """One cycle's requests of one agent.

    Attributes:
        walk: (vx m/s, vy m/s, vturn rad/s), body frame.
        kick: (power in (0, 1], direction rad body frame), or None for no kick.
        beam: (x, y, rotation) team frame, or None (only honoured while beaming is allowed).
        say: text to say ("" = silent).
        behaviour: name of the behaviour that made the request (for tests and debugging).
        goal: where the walk goes (``walking``): the walk command is computed from it on
            first read, or for the whole team at once by ``resolve_walks``.
    """

    walk: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    kick: tuple[float, float] | None = None
    beam: tuple[float, float, float] | None = None
    say: str = ""
    behaviour: str = "idle"
    goal: WalkGoal | None = field(default=None, repr=False, compare=False)

    @classmethod
    def walking(cls, goal: WalkGoal, behaviour: str) -> ControlRequest:
        """A request to walk to ``goal``; its ``walk`` command is computed when needed."""
        request = cls(None, behaviour=behaviour, goal=goal)  # type: ignore[arg-type]
        del request.__dict__["walk"]  # pending: __getattr__ computes it on first read
        return request

    def __getattr__(self, name: str) -> Any:
        # only reached for a pending walk (the field is absent from the instance dict)
        goal = self.__dict__.get("goal")
        if name != "walk" or goal is None:
            raise AttributeError(name)
        walk = self.__dict__["walk"] = goal.command()
        return walk

    @property
    def pending(self) -> bool:
        """The walk command is not computed yet."""
        return "walk" not in self.__dict__

    def _copy(self, **changes: Any) -> ControlRequest:
        # a copy that keeps a pending walk pending (dataclasses.replace would compute it)
        new = object.__new__(ControlRequest)
        new.__dict__.update(self.__dict__, **changes)
        return new

    def with_say(self, text: str) -> ControlRequest:
        return self._copy(say=text)

    def named(self, behaviour: str) -> ControlRequest:
        """The same request, credited to ``behaviour``."""
        return self._copy(behaviour=behaviour)

    def to_action(self, low: NDArray[np.float64], high: NDArray[np.float64]) -> dict[str, Any]:
        """The env's Dict-form action; the walk command is clipped to [low, high]."""
        return {"walk": np.minimum(np.maximum(self.walk, low), high), **self._extras()}

    def _extras(self) -> dict[str, Any]:
        """The action's entries other than the walk (kick, beam, say)."""
        action: dict[str, Any] = {}
        if self.kick is not None:
            action["kick"] = np.array([min(1.0, max(0.0, self.kick[0])), self.kick[1]])
        if self.beam is not None:
            action["beam"] = np.asarray(self.beam, dtype=np.float64)
            action["beam_request"] = 1
        if self.say:
            action["say"] = self.say
        return action


def team_actions(requests: Mapping[str, ControlRequest], low: NDArray[np.float64],
                 high: NDArray[np.float64]) -> dict[str, dict[str, Any]]:
    """``{agent: request.to_action(low, high)}`` with the team's pending walks computed
    together (``resolve_walks``) and every walk clipped in one pass (the same values)."""
    resolve_walks(list(requests.values()))
    if not requests:
        return {}
    walks = np.minimum(np.maximum(np.array([r.walk for r in requests.values()]), low), high)
    return {agent: {"walk": walk, **request._extras()}
            for walk, (agent, request) in zip(walks, requests.items(), strict=True)}


def resolve_walks(requests: Sequence[ControlRequest]) -> None:
    """Compute the pending walk commands of ``requests`` (a team's, this cycle) together
    (``strategy.behaviours.walk_batch.walk_commands``): the same commands, fewer passes."""
    # imported here: requests stay importable without navigation (and its teamenv errors)
    from strategy.behaviours.walk_batch import walk_commands

    pending = [r for r in requests if "walk" not in r.__dict__]
    for request, walk in zip(pending, walk_commands([r.goal for r in pending]), strict=True):
        request.__dict__["walk"] = walk
