"""How the full team's agents talk: what each hears as role votes, and what each says.

Two protocols over the say channel, chosen once per team by what its perceiver hears
(``talk_for``), so ``Player.decide`` has one path:

- ``RoleVoteTalk`` (``state`` mode): every agent says its own role vector as a ``role_vote``
  text (``strategy.positioning.roles.message``, every ``say_every`` cycles) and counts the
  vectors its teammates said. Beliefs are exact and shared there, so a vector heard before
  the agent's own vector last changed is only stale (``vote_since_own_change``).
- ``TeamReportTalk`` (``vision`` mode): one teammate speaks every ``TALK_PERIOD_CYCLES``, in
  uniform-number order, saying a team report (role vector, pose, ball with its age:
  ``strategy.perception.team_message``); the perceiver decodes the reports each agent heard.
  An agent counts as its own vote the vector it last said (what its teammates hold), so
  agents who heard the same agree.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from strategy.perception.team_message import encode_team_report
from strategy.perception.vision_perceiver import VisionPerceiver
from strategy.perception.worldmodel import WorldModel
from strategy.positioning import PositioningAgent, PositioningDecision
from strategy.teams.full_config import FullTeamConfig

TALK_PERIOD_CYCLES = 2
"""In ``vision`` mode one teammate speaks every this many cycles (the simspark channel lets a
listener hear one teammate message per 2 cycles)."""

Votes = Sequence[tuple[int, NDArray[np.intp]]]


class RoleVoteTalk:
    """``state`` mode: role-vote texts from everyone (see the module docstring)."""

    def __init__(self, config: FullTeamConfig) -> None:
        self.communicate = config.communicate
        self.vote = config.vote
        self.since_own_change = config.vote_since_own_change

    def reset(self) -> None:
        """Nothing is held between cycles (the voters keep the heard vectors)."""

    def votes(self, positioning: PositioningAgent, wm: WorldModel) -> Votes:
        """The role vectors agent ``positioning.me`` heard this cycle."""
        return positioning.heard_votes(wm.heard) if self.communicate else ()

    def own_ballot(self, me: int) -> NDArray[np.intp] | None:
        """None: the agent's own vote is its fresh vector."""
        return None

    def say(self, me: int, cycle: int, wm: WorldModel, decision: PositioningDecision) -> str:
        """The role-vote text positioning wrote for this cycle ("" when silent)."""
        return decision.say if self.communicate else ""


class TeamReportTalk:
    """``vision`` mode: team reports in turn (see the module docstring)."""

    def __init__(self, config: FullTeamConfig, perceiver: VisionPerceiver) -> None:
        self.communicate = config.communicate
        self.vote = config.vote and config.communicate
        self.since_own_change = False
        self.perceiver = perceiver
        self.n = perceiver.n
        self.cycle_s = perceiver.cycle_s
        self.said: list[NDArray[np.intp] | None] = [None] * self.n

    def reset(self) -> None:
        self.said = [None] * self.n

    def votes(self, positioning: PositioningAgent, wm: WorldModel) -> Votes:
        if not self.communicate:
            return ()
        return [(r.sender, r.roles) for r in self.perceiver.reports[positioning.me]]

    def own_ballot(self, me: int) -> NDArray[np.intp] | None:
        """The vector agent ``me`` last said (None before it first spoke)."""
        return self.said[me]

    def my_turn(self, me: int, cycle: int) -> bool:
        """One teammate talks every ``TALK_PERIOD_CYCLES``, in uniform-number order."""
        return cycle % TALK_PERIOD_CYCLES == 0 and (cycle // TALK_PERIOD_CYCLES) % self.n == me

    def say(self, me: int, cycle: int, wm: WorldModel, decision: PositioningDecision) -> str:
        """Agent ``me``'s team report when it is its turn ("" otherwise)."""
        if not (self.communicate and self.my_turn(me, cycle)):
            return ""
        self.said[me] = decision.own_vector.copy()
        return self.report(wm, decision.own_vector)

    def report(self, wm: WorldModel, roles: NDArray[np.intp]) -> str:
        """The team message: the speaker's role vector, pose and ball belief with its age."""
        known = wm.ball_known
        return encode_team_report(self.perceiver.schema, wm.me, roles, wm.position,
                                  wm.heading, wm.fallen, wm.ball if known else None,
                                  int(round(wm.ball_age_s / self.cycle_s)) if known else 0)


def talk_for(config: FullTeamConfig,
             perceiver: object) -> RoleVoteTalk | TeamReportTalk:
    """The protocol a team with ``perceiver`` talks: team reports where the perceiver hears
    them (``VisionPerceiver``), role votes otherwise."""
    if isinstance(perceiver, VisionPerceiver):
        return TeamReportTalk(config, perceiver)
    return RoleVoteTalk(config)
