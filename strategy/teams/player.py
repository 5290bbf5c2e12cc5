"""One agent of a team, layer by layer (seed 000 §2): perception -> world model -> decision
maker -> behaviours -> control requests.

``Player.act`` takes only this agent's own observation (and the texts it heard, which are part
of it) and returns its action; a team is a dict of independent ``Player`` objects.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from strategy.behaviours.control import ControlRequest
from strategy.behaviours.motion import search_ball
from strategy.behaviours.skills import Skills
from strategy.decision import FieldPlayerDecisionMaker, GoalieDecisionMaker
from strategy.decision.setplays import Situation, situation, we_kick_off_next
from strategy.perception.worldmodel import WorldModel, shared
from strategy.positioning import PositioningAgent
from strategy.positioning.formation.model import Formation
from strategy.teams.full_config import FullTeamConfig
from strategy.teams.talk import RoleVoteTalk, TeamReportTalk


class Player:
    """The brain of agent ``name`` (player index ``me``).

    Args:
        me: player index (uniform number - 1).
        name: the agent's name (for error messages).
        side: "left" or "right" (who kicks off a half depends on it).
        config: the team's parameters.
        formations: one formation per situation key of ``FullTeamConfig`` (``attack``,
            ``defend``, ``kickoff-ours``, ``kickoff-theirs``, ``setplay-ours``,
            ``setplay-theirs``), all of the team's size.
        skills: body facts and navigation gains.
        channel: the say channel profile name.
        memo: a cache the team's players share (``strategy.memo``): positioning results
            and the decision makers' team-wide facts (who reaches the ball first, whether we
            control it), so agents that believe the same share the work.
        talk: the team's talk protocol (``strategy.teams.talk``); None: role votes
            (``state`` mode).
    """

    def __init__(self, me: int, name: str, side: str, config: FullTeamConfig,
                 formations: Mapping[str, Formation], skills: Skills, channel: str,
                 memo: dict | None = None,
                 talk: RoleVoteTalk | TeamReportTalk | None = None) -> None:
        self.me, self.name, self.side = me, name, side
        self.config = config
        self.formations = dict(formations)
        self.skills = skills
        defend = self.formations["defend"]
        self.positioning = PositioningAgent(
            me, defend, skills.field, marking=config.marking_params(), channel=channel,
            say_every=config.say_every, memo=memo)
        goalie = defend.goalie_index
        if goalie is not None and me == goalie:
            self.decision: FieldPlayerDecisionMaker | GoalieDecisionMaker = \
                GoalieDecisionMaker(config.decision_params(), skills, goalie, memo)
        else:
            self.decision = FieldPlayerDecisionMaker(config.decision_params(), skills, goalie,
                                                     memo)
        self.memo = memo
        self.channel = channel
        self.talk = RoleVoteTalk(config) if talk is None else talk
        self._beam_slots: dict[int, NDArray[np.float64]] = {}  # by formation (held for life)
        self.reset()

    def reset(self) -> None:
        self.positioning.reset()
        self.decision.reset()
        self.last_request = ControlRequest()
        self.last_decision = None
        self.last_world_model: WorldModel | None = None

    def perceive(self, obs: Mapping[str, Any]) -> WorldModel:
        return WorldModel.from_observation(obs, self.me, self.skills.field, self.name,
                                           self.skills.ball_roll)

    def formation_for(self, wm: WorldModel) -> Formation:
        """The formation the situation calls for."""
        now = situation(wm.play_mode)
        if now is Situation.BEAM:
            ours = we_kick_off_next(wm.play_mode, wm.half, self.side)
            return self.formations["kickoff-ours" if ours else "kickoff-theirs"]
        if now is Situation.OUR_KICKOFF:
            return self.formations["kickoff-ours"]
        if now is Situation.THEIR_KICKOFF:
            return self.formations["kickoff-theirs"]
        if now is Situation.OUR_SET_PLAY:
            return self.formations["setplay-ours"]
        if now is Situation.THEIR_SET_PLAY:
            return self.formations["setplay-theirs"]
        if self.config.switch_formations and shared(self.memo, "control", wm,
                                                        wm.we_control_ball):
            return self.formations["attack"]
        return self.formations["defend"]

    def act(self, obs: Mapping[str, Any]) -> ControlRequest:
        """This cycle's control request, from this agent's ``state`` observation alone."""
        return self.decide(self.perceive(obs))

    def decide(self, wm: WorldModel) -> ControlRequest:
        """This cycle's control request from this agent's belief ``wm``.

        One path for both observation modes: the team's ``talk`` protocol
        (``strategy.teams.talk``) says which role votes the agent heard, what it counts as
        its own vote and what it says this cycle.
        """
        talk = self.talk
        cycle = self.positioning.cycle
        # the anticipated view is a function of the beliefs: their key identifies it
        view = wm.positioning_view(anticipate=True)
        formation = self.formation_for(wm)
        decision = self.positioning.step(view, (), formation, wm.belief_key or None,
                                         votes=talk.votes(self.positioning, wm),
                                         own_ballot=talk.own_ballot(self.me), vote=talk.vote,
                                         since_own_change=talk.since_own_change)
        say = talk.say(self.me, cycle, wm, decision)
        if situation(wm.play_mode) is Situation.BEAM:
            decision = decision._replace(target=self.beam_slot(formation),
                                         position_index=self.me)
        if wm.ball_known or situation(wm.play_mode) in (Situation.BEAM, Situation.OVER) \
                or wm.fallen:
            request = self.decision.decide(wm, decision)
        else:
            request = search_ball(wm, self.skills)
        if say:
            request = request.with_say(say)
        self.last_world_model = wm
        self.last_decision = decision
        self.last_request = request
        return request

    def beam_slot(self, formation: Formation) -> NDArray[np.float64]:
        """Where this agent is beamed before a kick-off: its own position (by uniform number)
        of the kick-off ``formation`` with the ball on the centre spot. Every agent computes
        the same slots without beliefs or votes, so no two are beamed to one spot (the voted
        roles have not settled before the kick-off); once play starts the roles are assigned
        from where they stand."""
        slot = self._beam_slots.get(id(formation))
        if slot is None:
            slot = self._beam_slots[id(formation)] = \
                formation.home_positions(np.zeros(2))[self.me].copy()
        return slot.copy()
