"""The goalie's decision maker: guard the goal, clear close balls, take goal kicks."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from strategy.behaviours import Skills, goalie_clear, goalie_target
from strategy.behaviours.control import ControlRequest
from strategy.behaviours.motion import Hold, resolve_holds
from strategy.decision.field_player import FieldPlayerDecisionMaker
from strategy.decision.params import DecisionParams
from strategy.decision.setplays import Situation, set_play_taker, situation, take_set_play
from strategy.perception.worldmodel import WorldModel
from strategy.positioning import PositioningDecision


class GoalieDecisionMaker:
    """Decides for the goalie: guard the goal on the ball line, clear a ball that comes close,
    take our goal kicks, and beam to the goal at kick-offs. ``plan_all`` decides for any
    number of agents (a team has one goalie), ``decide`` for one.

    ``field_player``: the team's field-player decision maker, for what the goalie does as a
    field player does (beaming, keeping away at their set plays); None: its own."""

    def __init__(self, config: DecisionParams, skills: Skills, goalie: int,
                 memo: dict | None = None,
                 field_player: FieldPlayerDecisionMaker | None = None) -> None:
        self.config = config
        self.skills = skills
        self.goalie = goalie
        self.field_player = field_player if field_player is not None else \
            FieldPlayerDecisionMaker(config, skills, goalie, memo)

    def reset(self) -> None:
        self.field_player.reset()

    def decide(self, wm: WorldModel, positioning: PositioningDecision) -> ControlRequest:
        """One agent's request (``plan_all`` with n = 1, its hold resolved)."""
        return resolve_holds([wm], self.plan_all([wm], [positioning]), self.skills)[0]

    def plan_all(self, wms: Sequence[WorldModel],
                 positionings: Sequence[PositioningDecision]) -> list[ControlRequest | Hold]:
        """Each agent's request, or the ``Hold`` it decided on (``resolve_holds``)."""
        return [self.plan(wm, p) for wm, p in zip(wms, positionings, strict=True)]

    def plan(self, wm: WorldModel, positioning: PositioningDecision) -> ControlRequest | Hold:
        if wm.fallen:
            return ControlRequest(behaviour="fallen")
        now = situation(wm.play_mode)
        if now in (Situation.BEAM, Situation.OVER, Situation.THEIR_SET_PLAY,
                   Situation.THEIR_KICKOFF):
            if now is Situation.BEAM or now is Situation.OVER:
                return self.field_player.plan_all([wm], [positioning])[0]
            return self.field_player.keep_away(wm, _at(positioning, self._guard(wm)),
                                               kickoff=now is Situation.THEIR_KICKOFF)
        if now is Situation.OUR_SET_PLAY and set_play_taker(wm, wm.play_mode,
                                                            self.goalie) == wm.me:
            return take_set_play(wm, self.skills, self.config.pass_max_m,
                                 self.config.pass_lane_m)
        if now is Situation.PLAY_ON and self.should_clear(wm):
            return goalie_clear(wm, self.skills)
        return Hold(self._guard(wm), "goalie_position")

    def should_clear(self, wm: WorldModel) -> bool:
        """The ball is within ``goalie_clear_m`` of our goal centre, in front of the line."""
        return (math.hypot(*(wm.ball - wm.own_goal)) <= self.config.goalie_clear_m
                and wm.ball[0] > -wm.field.half_length)

    def _guard(self, wm: WorldModel) -> np.ndarray:
        return goalie_target(wm, self.config.goalie_line_m)


def _at(decision: PositioningDecision, target: np.ndarray) -> PositioningDecision:
    return decision._replace(target=target)
