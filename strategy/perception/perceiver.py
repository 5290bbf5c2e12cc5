"""One interface for a team's beliefs in either observation mode: ``Perceiver``.

A team asks its perceiver, once a cycle, for every agent's ``WorldModel`` (``update``), tells
it when an agent asked to be beamed (``beamed``) and resets it at a match's start. What is
above perception — positioning, decisions, behaviours — then has one path for both modes:

- ``StatePerceiver`` (``state`` mode): each agent's world model read from its own exact
  observation, the whole team in one numpy pass (``team_world_models``); it keeps no memory.
- ``VisionPerceiver`` (``vision`` mode, ``strategy.perception.vision_perceiver``):
  localization, filtered sightings and the teammates' team messages, per agent.

``perceiver_for`` builds the one the team's context calls for; it is the only place that
looks at the observation mode.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol

from strategy.geometry import BallRoll
from strategy.perception.filtering import FilterParams
from strategy.perception.localization import LocalizationParams
from strategy.perception.team_worldmodels import prepare_kernel as prepare_world_model_kernel
from strategy.perception.team_worldmodels import team_world_models
from strategy.perception.vision_perceiver import VisionPerceiver
from strategy.perception.worldmodel import BELIEF_RESOLUTION_M, WorldModel
from teamenv.teams import TeamContext


class Perceiver(Protocol):
    """What a team needs from its perception, whatever the observation mode."""

    def reset(self, seed: int) -> None:
        """Forget everything: a new match (``seed`` drives any randomness of the beliefs)."""

    def update(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, WorldModel]:
        """Every agent's belief this cycle, each from its own observation and what it heard."""

    def beamed(self, agent_index: int, pose: tuple[float, float, float]) -> None:
        """Agent ``agent_index`` asked to be beamed to ``pose`` (team frame)."""


class StatePerceiver:
    """``state`` mode: each agent's ``WorldModel`` from its own observation, all agents of the
    team in one numpy pass (bit-identical to ``WorldModel.from_observation`` per agent).

    Args:
        context: the team's context.
        roll: the ball's rolling model (for anticipating where it stops).
        resolution: beliefs rounded to this grid (metres; None: exact), so agents that see
            the same share cached work (``strategy.memo``).
        ball_rest: fill each model's ``ball_rest()`` now, once per distinct ball.
    """

    def __init__(self, context: TeamContext, roll: BallRoll | None = None,
                 resolution: float | None = BELIEF_RESOLUTION_M,
                 ball_rest: bool = False) -> None:
        self.field = context.field
        self.index = {agent: k for k, agent in enumerate(context.agents)}
        self.roll = roll
        self.resolution = resolution
        self.ball_rest = ball_rest

    def reset(self, seed: int) -> None:
        """Nothing to forget: a state belief is this cycle's observation alone. The
        compiled rows are loaded now, not in a cycle under a match's stall watchdog."""
        prepare_world_model_kernel()

    def update(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, WorldModel]:
        return team_world_models(observations, self.index, self.field, self.roll,
                                 self.resolution, ball_rest=self.ball_rest)

    def beamed(self, agent_index: int, pose: tuple[float, float, float]) -> None:
        """Nothing to do: the next observation says where the agent stands."""


def perceiver_for(context: TeamContext, *, communicate: bool = True,
                  roll: BallRoll | None = None,
                  resolution: float | None = BELIEF_RESOLUTION_M, ball_rest: bool = False,
                  localization: LocalizationParams | None = None,
                  filtering: FilterParams | None = None) -> StatePerceiver | VisionPerceiver:
    """The perceiver of ``context``'s observation mode.

    ``communicate``: (vision) read the teammates' team messages; ``resolution`` and
    ``ball_rest``: (state) see ``StatePerceiver``; ``localization``, ``filtering``: (vision)
    the parameters of ``VisionPerceiver``'s parts."""
    if context.observation_mode == "vision":
        return VisionPerceiver(context, communicate=communicate, localization=localization,
                               filtering=filtering, roll=roll)
    return StatePerceiver(context, roll=roll, resolution=resolution, ball_rest=ball_rest)
