"""One agent of a team, layer by layer (seed 000 §2): perception -> world model -> decision
maker -> behaviours -> control requests.

``Player.act`` takes only this agent's own observation (and the texts it heard, which are part
of it) and returns its action; a team is a dict of independent ``Player`` objects.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from strategy.behaviours.control import ControlRequest
from strategy.behaviours.motion import Hold, resolve_holds, search_ball
from strategy.behaviours.skills import Skills
from strategy.decision import FieldPlayerDecisionMaker, GoalieDecisionMaker
from strategy.decision.setplays import Situation, situation, we_kick_off_next
from strategy.perception.worldmodel import WorldModel, WorldView, prime_team_facts, shared
from strategy.positioning import PositioningAgent, PositioningDecision
from strategy.positioning.formation.model import Formation
from strategy.positioning.roles.voting import RoleVoters
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
        makers: the team's decision makers (``decision_makers``), shared by its players so
            that ``decide_team`` decides for all of them in one pass; None: its own.
        voters: the team's ballot boxes (``RoleVoters``, row = player index), so that the
            team's votes are counted in one pass; None: a box of its own.
    """

    def __init__(self, me: int, name: str, side: str, config: FullTeamConfig,
                 formations: Mapping[str, Formation], skills: Skills, channel: str,
                 memo: dict | None = None,
                 talk: RoleVoteTalk | TeamReportTalk | None = None,
                 makers: DecisionMakers | None = None,
                 voters: RoleVoters | None = None) -> None:
        self.me, self.name, self.side = me, name, side
        self.config = config
        self.formations = dict(formations)
        # which formations these are (teammates share them, and so their lookups)
        self.formation_ids = tuple((kind, id(f)) for kind, f in self.formations.items())
        self.skills = skills
        defend = self.formations["defend"]
        self.positioning = PositioningAgent(
            me, defend, skills.field, marking=config.marking_params(), channel=channel,
            say_every=config.say_every, memo=memo,
            voter=None if voters is None else voters.voter(me))
        goalie = defend.goalie_index
        if makers is None:
            makers = decision_makers(config, skills, goalie, memo)
        field_player, goalie_maker = makers
        self.decision: FieldPlayerDecisionMaker | GoalieDecisionMaker = \
            goalie_maker if goalie is not None and me == goalie and goalie_maker is not None \
            else field_player
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
        """This cycle's control request from this agent's belief ``wm`` (``decide_team``
        with n = 1)."""
        return decide_team([self], [wm])[0]

    def position(self, wm: WorldModel) -> tuple[PositioningDecision, str]:
        """This cycle's positioning decision from this agent's belief ``wm``, and what it
        says (``position_team`` with n = 1)."""
        return position_team([self], [wm])[0]

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


DecisionMakers = tuple[FieldPlayerDecisionMaker, GoalieDecisionMaker | None]


def decision_makers(config: FullTeamConfig, skills: Skills, goalie: int | None,
                    memo: dict | None = None) -> DecisionMakers:
    """A team's decision makers: one for its field players, one for its goalie (None
    without one), sharing the team's memory of who plays the ball."""
    field_player = FieldPlayerDecisionMaker(config.decision_params(), skills, goalie, memo)
    if goalie is None:
        return field_player, None
    return field_player, GoalieDecisionMaker(config.decision_params(), skills, goalie, memo,
                                             field_player=field_player)


def position_team(players: Sequence[Player], wms: Sequence[WorldModel]
                  ) -> list[tuple[PositioningDecision, str]]:
    """Each player's positioning decision from its own belief, and what it says, for the
    team in one pass (``PositioningAgent.step_all``: the votes of players whose ballot boxes
    are rows of one ``RoleVoters`` counted together); the formation and the anticipated view
    looked up once per distinct belief.

    One path for both observation modes: the team's ``talk`` protocol
    (``strategy.teams.talk``) says which role votes each agent heard, what it counts as its
    own vote and what it says this cycle.
    """
    # beliefs of their own (vision mode): the team's ball facts in one pass
    prime_team_facts([wm for wm in wms if not wm.belief_key])
    looked_up: dict[tuple, tuple[Formation, WorldView]] = {}
    formations, views = [], []
    for player, wm in zip(players, wms, strict=True):
        # a function of the beliefs (their key) and of who the player is on which side
        key = (wm.belief_key, wm.half, player.side, player.formation_ids, id(player.config))
        found = looked_up.get(key) if wm.belief_key else None
        if found is None:
            found = looked_up[key] = (player.formation_for(wm),
                                      wm.positioning_view(anticipate=True))
        formations.append(found[0])
        views.append(found[1])
    talks = [player.talk for player in players]
    cycles = [player.positioning.cycle for player in players]
    first = talks[0]
    if any((t.vote, t.since_own_change) != (first.vote, first.since_own_change) for t in talks):
        decisions = [PositioningAgent.step_all(  # players that vote differently: one by one
            [p.positioning], [view], [formation], [wm.belief_key or None],
            [talk.votes(p.positioning, wm)], [talk.own_ballot(p.me)], vote=talk.vote,
            since_own_change=talk.since_own_change)[0]
            for p, wm, talk, view, formation in zip(players, wms, talks, views, formations,
                                                    strict=True)]
    else:
        decisions = PositioningAgent.step_all(
            [p.positioning for p in players], views, formations,
            [wm.belief_key or None for wm in wms],
            [talk.votes(p.positioning, wm) for p, wm, talk in zip(players, wms, talks,
                                                                  strict=True)],
            [talk.own_ballot(p.me) for p, talk in zip(players, talks, strict=True)],
            vote=first.vote, since_own_change=first.since_own_change)
    out = []
    for player, wm, talk, cycle, decision, formation in zip(players, wms, talks, cycles,
                                                            decisions, formations, strict=True):
        say = talk.say(player.me, cycle, wm, decision)
        if situation(wm.play_mode) is Situation.BEAM:
            decision = decision._replace(target=player.beam_slot(formation),
                                         position_index=player.me)
        out.append((decision, say))
    return out


def decide_team(players: Sequence[Player], wms: Sequence[WorldModel]) -> list[ControlRequest]:
    """The control requests of ``players[i]`` from its own belief ``wms[i]``, in passes over
    the team: every agent's positioning, then each decision maker's agents together
    (``plan_all``: ball players, supporters, pulled positions as arrays over agents), then
    every hold of the team together (``resolve_holds``); the walks follow in one pass when
    the actions are built (``team_actions``)."""
    steps = position_team(players, wms)
    plans: list[ControlRequest | Hold | None] = [None] * len(players)
    groups: dict[int, tuple[Any, list[int]]] = {}
    for i, (player, wm) in enumerate(zip(players, wms, strict=True)):
        if wm.ball_known or wm.fallen or \
                situation(wm.play_mode) in (Situation.BEAM, Situation.OVER):
            groups.setdefault(id(player.decision), (player.decision, []))[1].append(i)
        else:
            plans[i] = search_ball(wm, player.skills)
    for maker, rows in groups.values():
        planned = maker.plan_all([wms[i] for i in rows], [steps[i][0] for i in rows])
        for i, plan in zip(rows, planned, strict=True):
            plans[i] = plan
    skills = {id(player.skills): player.skills for player in players}
    if len(skills) == 1:
        requests = resolve_holds(wms, plans, players[0].skills)  # type: ignore[arg-type]
    else:  # players with their own skills: each resolves its own
        requests = [resolve_holds([wm], [plan], player.skills)[0]  # type: ignore[list-item]
                    for player, wm, plan in zip(players, wms, plans, strict=True)]
    out = []
    for player, wm, (decision, say), request in zip(players, wms, steps, requests,
                                                   strict=True):
        if say:
            request = request.with_say(say)
        player.last_world_model = wm
        player.last_decision = decision
        player.last_request = request
        out.append(request)
    return out
