"""The full team: formations, role voting over the say channel, marking, set plays, passing,
a goalie — eleven (or N) independent agents, each deciding from its own observation.

A template for a serious team: copy this file, change ``FullTeamConfig`` (or the decision
makers in ``strategy.decision``), and register your class as a ``teamenv.teams`` entry
point.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from strategy.behaviours.control import team_actions
from strategy.behaviours.kick_choice import prepare_kernel as prepare_kick_kernel
from strategy.behaviours.skills import Skills
from strategy.behaviours.walk_batch import prepare_kernel as prepare_walk_kernel
from strategy.decision.field_player import prepare_reach_kernel
from strategy.geometry import BallRoll
from strategy.perception.perceiver import perceiver_for
from strategy.positioning.formation.sized import team_formation
from strategy.positioning.roles.voting import RoleVoters
from strategy.teams.full_config import FullTeamConfig
from strategy.teams.player import Player, decide_team, decision_makers
from strategy.teams.talk import talk_for
from teamenv.errors import ConfigError
from teamenv.teams import TeamContext

FORMATION_KEYS = {
    "attack": "formation_attack", "defend": "formation_defend",
    "kickoff-ours": "formation_kickoff_ours", "kickoff-theirs": "formation_kickoff_theirs",
    "setplay-ours": "formation_setplay_ours", "setplay-theirs": "formation_setplay_theirs",
}


class FullTeam:
    """The complete built-in team. Config keys: the fields of ``FullTeamConfig``."""

    name = "full"
    defaults: Mapping[str, Any] = {}

    def __init__(self, context: TeamContext, **config: Any) -> None:
        if context.observation_mode not in ("state", "vision"):
            raise ConfigError(f"{self.name} team: plays in observation mode 'state' or "
                              f"'vision', got {context.observation_mode!r}")
        self.context = context
        self.config = FullTeamConfig.from_overrides(self.name, {**self.defaults, **config})
        # the body's capabilities (the locomotion profile's, through the context) reach every
        # behaviour and decision through Skills
        self.skills = Skills(context.field, context.body,
                             kick_max_angle=self.config.kick_max_angle_rad,
                             navigation=self.config.navigation_params(context.body),
                             ball_roll=BallRoll(context.ball_linear_drag,
                                                context.ball_rolling_decel),
                             ball_radius=context.ball_radius)
        self.low, self.high = self.skills.walk_low, self.skills.walk_high
        formations = {kind: team_formation(getattr(self.config, key), context.team_size,
                                           context.field)
                      for kind, key in FORMATION_KEYS.items()}
        # one perceiver whatever the observation mode: exact beliefs in one numpy pass
        # (state), or localization, filtering and team messages per agent (vision)
        self.perceiver = perceiver_for(context, communicate=self.config.communicate,
                                       roll=self.skills.ball_roll, ball_rest=True,
                                       localization=self.config.localization_params())
        self.talk = talk_for(self.config, self.perceiver)
        memo: dict = {}  # pure results by exact inputs, shared (see strategy.memo)
        # one field-player and one goalie decision maker for the team: all its agents
        # decide in one pass (decide_team), each from its own belief
        makers = decision_makers(self.config, self.skills, formations["defend"].goalie_index,
                                 memo)
        makers[0].double_touch = context.double_touch   # the league's rule, when in force
        self.field_maker = makers[0]
        # and one set of ballot boxes: the team's votes counted in one pass
        voters = RoleVoters(context.team_size, range(len(context.agents)))
        self.players = {
            agent: Player(k, agent, context.side, self.config, formations, self.skills,
                          context.channel, memo, self.talk, makers, voters)
            for k, agent in enumerate(context.agents)
        }

    def reset(self, seed: int) -> None:
        # decisions are deterministic; the seed drives the particle filters of vision mode
        for player in self.players.values():
            player.reset()
        self.talk.reset()
        self.perceiver.reset(seed)
        # compiled here, not in a cycle that runs under a match's stall watchdog
        prepare_kick_kernel()
        prepare_walk_kernel()
        prepare_reach_kernel()

    def annotations(self) -> dict[str, dict[str, Any]]:
        """What each agent believed and decided last cycle, for replays with extras
        (``teamenv.replay.ANNOTATION_KEYS``, team frame): own pose, ball, the formation
        position voted for it (role) and the team's role vector as it holds it."""
        out = {}
        for agent, player in self.players.items():
            wm, decision = player.last_world_model, player.last_decision
            if wm is not None and decision is not None:
                out[agent] = {"pose": (*wm.position, wm.heading), "ball": tuple(wm.ball),
                              "role": decision.position_index,
                              "role_vector": decision.team_vector}
        return out

    def act(self, observations: Mapping[str, Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
        wms = self.perceiver.update(observations)
        players = [self.players[agent] for agent in wms]
        requests = dict(zip(wms, decide_team(players, list(wms.values())), strict=True))
        for player, request in zip(players, requests.values(), strict=True):
            if request.beam is not None:
                self.perceiver.beamed(player.me, request.beam)
        # the team's walk commands in one pass, clipped in one pass
        return team_actions(requests, self.low, self.high)
