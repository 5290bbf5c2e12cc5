"""Decision makers (seed 000 §2.4): a field player's and a goalie's.

A decision maker turns the agent's world model and its positioning decision (the position the
team voted for it, marking included) into one ``ControlRequest`` per cycle by choosing among
the behaviours. Both are deterministic functions of what the agent itself believes, so the
team's agents agree on who plays the ball without being told (and, with true-state
observations, always agree); the only memory is the last ball player, for hysteresis.
"""

from __future__ import annotations

import math

import numpy as np

from strategy.behaviours import (
    Skills,
    beam_to,
    choose_pass,
    clear_ball,
    dribble,
    goalie_clear,
    goalie_position,
    goalie_target,
    hold_position,
    kick_to,
    pass_to,
    shoot,
    shot_target,
)
from strategy.behaviours.ball import in_kick_reach, open_aim, quick_kick
from strategy.behaviours.motion import detour, go_to
from strategy.control import ControlRequest
from strategy.navigation import wrap
from strategy.positioning import PositioningDecision
from strategy.setplays import Situation, keep_distance, set_play_taker, situation, take_set_play
from strategy.teams.full_config import FullTeamConfig
from strategy.worldmodel import WorldModel


class FieldPlayerDecisionMaker:
    """Decides for a field player: play the ball when it is the team's ball player, else hold
    its voted formation (or marking) position; set plays and beaming by the play mode."""

    def __init__(self, config: FullTeamConfig, skills: Skills, goalie: int | None) -> None:
        self.config = config
        self.skills = skills
        self.goalie = goalie
        self.ball_player: int | None = None

    def reset(self) -> None:
        self.ball_player = None

    def decide(self, wm: WorldModel, positioning: PositioningDecision) -> ControlRequest:
        if wm.fallen:
            return ControlRequest(behaviour="fallen")
        now = situation(wm.play_mode)
        if now is Situation.BEAM:
            self.ball_player = None
            return self.beam(wm, positioning)
        if now is Situation.OVER:
            return ControlRequest(behaviour="game_over")
        if now in (Situation.THEIR_SET_PLAY, Situation.THEIR_KICKOFF):
            self.ball_player = None
            return self.keep_away(wm, positioning, kickoff=now is Situation.THEIR_KICKOFF)
        if now in (Situation.OUR_SET_PLAY, Situation.OUR_KICKOFF):
            taker = set_play_taker(wm, wm.play_mode, self.goalie)
            self.ball_player = taker
            if taker == wm.me:
                return take_set_play(wm, self.skills, self.config.pass_max_m,
                                     self.config.pass_lane_m)
            return hold_position(wm, positioning.target, self.skills)
        self.ball_player = self.choose_ball_player(wm)
        if self.ball_player == wm.me:
            return self.play_ball(wm)
        if self.config.cover_m > 0 and self.supporter(wm) == wm.me:
            return self.cover(wm)
        return hold_position(wm, positioning.target, self.skills)

    # -- pieces ----------------------------------------------------------------------------
    def beam(self, wm: WorldModel, positioning: PositioningDecision) -> ControlRequest:
        """Beam to the kick-off position once (again only if moved away from it)."""
        target = positioning.target
        if wm.distance(target) > 0.5:
            return beam_to((float(target[0]), float(target[1]), 0.0))
        return hold_position(wm, target, self.skills, behaviour="kickoff_position")

    def keep_away(self, wm: WorldModel, positioning: PositioningDecision,
                  kickoff: bool) -> ControlRequest:
        """Hold the position, kept ``set_play_clearance_m`` from the ball, walking round the
        circle rather than through it."""
        radius = self.config.set_play_clearance_m
        target = keep_distance(positioning.target, wm, radius, kickoff)
        waypoint = detour(wm.position, target, wm.ball, radius)
        if wm.distance(wm.ball) < radius:  # inside already: straight out first
            waypoint = keep_distance(wm.position, wm, radius + 0.3, kickoff)
        request = go_to(wm, waypoint, self.skills, face=wm.ball, behaviour="keep_distance")
        if waypoint is target and wm.distance(target) < self.skills.navigation.arrive_m * 2:
            return hold_position(wm, target, self.skills, behaviour="keep_distance")
        return request

    def choose_ball_player(self, wm: WorldModel) -> int:
        """The upright teammate closest to the ball (the goalie only if nobody else is
        upright); the previous ball player keeps it unless beaten by the hysteresis margin."""
        d = wm.upright_ball_distances()
        if self.goalie is not None and np.isfinite(np.delete(d, self.goalie)).any():
            d[self.goalie] = np.inf
        prev = self.ball_player
        if prev is not None and np.isfinite(d[prev]):
            d[prev] -= self.config.ball_player_hysteresis_m
        return int(np.argmin(d))

    def supporter(self, wm: WorldModel) -> int | None:
        """The upright field player closest to the ball after the ball player (None if
        there is none)."""
        d = wm.upright_ball_distances()
        for k in (self.goalie, self.ball_player):
            if k is not None:
                d[k] = np.inf
        k = int(np.argmin(d))
        return k if np.isfinite(d[k]) else None

    def cover(self, wm: WorldModel) -> ControlRequest:
        """Stand ``cover_m`` goal-side of the ball, on its line to our goal centre: blocks the
        shot and wins the ball if the challenge is lost."""
        goal = wm.own_goal
        to_goal = goal - wm.ball
        dist = math.hypot(to_goal[0], to_goal[1])
        target = wm.ball + to_goal * (min(self.config.cover_m, dist * 0.5) / max(dist, 1e-6))
        return hold_position(wm, target, self.skills, behaviour="cover")

    def play_ball(self, wm: WorldModel) -> ControlRequest:
        """Shoot in range; under pressure near our goal clear; pass to a better-placed free
        teammate; contested (an opponent within ``pressure_m``): kick now in the best
        direction the body allows, else go straight for the ball; open ground: kick long
        into space, or dribble towards the goal."""
        c = self.config
        goal_distance = math.hypot(*(wm.opponent_goal - wm.ball))
        if goal_distance <= c.shoot_range_m:
            target = shot_target(wm)
            now = quick_kick(wm, self.skills, preferred=target)
            if now is not None and now.kick is not None and self._aims_at(wm, now, target):
                return now.named("shoot")
            return shoot(wm, self.skills)
        opps = wm.opponents[wm.opponents_present & ~wm.opponents_fallen]
        clearance = float(np.min(np.hypot(*(opps - wm.ball).T))) if len(opps) else math.inf
        pressure = clearance < c.pressure_m
        own_line = wm.ball[0] + wm.field.half_length
        if pressure and own_line < c.clear_zone_m:
            now = quick_kick(wm, self.skills)
            return now.named("clear") if now is not None else clear_ball(wm, self.skills)
        mate = choose_pass(wm, c.pass_min_gain_m, c.pass_max_m, c.pass_lane_m,
                           c.receiver_free_m, exclude=() if self.goalie is None else (self.goalie,))
        if mate is not None and (pressure or in_kick_reach(wm, self.skills)):
            return pass_to(wm, mate, self.skills)
        if pressure:
            now = quick_kick(wm, self.skills, preferred=open_aim(wm, shot_target(wm)))
            if now is not None:
                return now
            return go_to(wm, wm.ball, self.skills, face=wm.ball, avoid=False,
                         behaviour="challenge")
        if c.advance_kick_clearance_m > 0 and clearance >= c.advance_kick_clearance_m:
            aim = open_aim(wm, shot_target(wm))
            return kick_to(wm, aim, self.skills, power=1.0).named("advance_kick")
        return dribble(wm, shot_target(wm), self.skills, speed=c.dribble_speed)

    @staticmethod
    def _aims_at(wm: WorldModel, request: ControlRequest, target: np.ndarray) -> bool:
        want = math.atan2(target[1] - wm.ball[1], target[0] - wm.ball[0])
        return abs(wrap(wm.heading + request.kick[1] - want)) < 0.05


class GoalieDecisionMaker:
    """Decides for the goalie: guard the goal on the ball line, clear a ball that comes close,
    take our goal kicks, and beam to the goal at kick-offs."""

    def __init__(self, config: FullTeamConfig, skills: Skills, goalie: int) -> None:
        self.config = config
        self.skills = skills
        self.goalie = goalie
        self.field_player = FieldPlayerDecisionMaker(config, skills, goalie)

    def reset(self) -> None:
        self.field_player.reset()

    def decide(self, wm: WorldModel, positioning: PositioningDecision) -> ControlRequest:
        if wm.fallen:
            return ControlRequest(behaviour="fallen")
        now = situation(wm.play_mode)
        if now in (Situation.BEAM, Situation.OVER, Situation.THEIR_SET_PLAY,
                   Situation.THEIR_KICKOFF):
            if now is Situation.BEAM or now is Situation.OVER:
                return self.field_player.decide(wm, positioning)
            return self.field_player.keep_away(wm, _at(positioning, self._guard(wm)),
                                               kickoff=now is Situation.THEIR_KICKOFF)
        if now is Situation.OUR_SET_PLAY and set_play_taker(wm, wm.play_mode,
                                                            self.goalie) == wm.me:
            return take_set_play(wm, self.skills, self.config.pass_max_m,
                                 self.config.pass_lane_m)
        if now is Situation.PLAY_ON and self.should_clear(wm):
            return goalie_clear(wm, self.skills)
        return goalie_position(wm, self.skills, self.config.goalie_line_m)

    def should_clear(self, wm: WorldModel) -> bool:
        """The ball is within ``goalie_clear_m`` of our goal centre, in front of the line."""
        return (math.hypot(*(wm.ball - wm.own_goal)) <= self.config.goalie_clear_m
                and wm.ball[0] > -wm.field.half_length)

    def _guard(self, wm: WorldModel) -> np.ndarray:
        return goalie_target(wm, self.config.goalie_line_m)


def _at(decision: PositioningDecision, target: np.ndarray) -> PositioningDecision:
    return decision._replace(target=target)
