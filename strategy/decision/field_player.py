"""The field player's decision maker (seed 000 §2.4).

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
    dribble,
    hold_position,
    kick_to,
)
from strategy.behaviours.ball import in_kick_reach
from strategy.behaviours.control import ControlRequest
from strategy.behaviours.kick_choice import MIN_SHOT_CHANCE, best_kick
from strategy.behaviours.motion import detour, go_to
from strategy.decision.params import DecisionParams
from strategy.decision.setplays import (
    Situation,
    keep_distance,
    set_play_taker,
    situation,
    take_set_play,
)
from strategy.perception.worldmodel import WorldModel, shared
from strategy.positioning import PositioningDecision

MOVING_BALL_M_S = 1.0
"""Faster than this the ball is rolling (a kick), not being pushed in a dribble: players are
chosen, and run, by where they can meet it."""


class FieldPlayerDecisionMaker:
    """Decides for a field player: play the ball when it is the team's ball player, else hold
    its voted formation (or marking) position; set plays and beaming by the play mode."""

    def __init__(self, config: DecisionParams, skills: Skills, goalie: int | None,
                 memo: dict | None = None) -> None:
        self.config = config
        self.skills = skills
        self.goalie = goalie
        self.memo = memo  # team-wide facts shared by teammates who believe the same
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
        return hold_position(wm, self.pulled(wm, positioning.target), self.skills)

    def pulled(self, wm: WorldModel, target: np.ndarray) -> np.ndarray:
        """The formation position moved ``ball_pull`` of the way towards where the ball will
        stop: the team closes on the ball, so it wins the races for it."""
        pull = self.config.ball_pull
        if pull <= 0:
            return target
        return target + pull * (wm.ball_rest() - target)

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
        """The upright teammate who can be at the ball first (the goalie only if nobody else
        is upright); the previous ball player keeps it unless beaten by the hysteresis margin."""
        d = shared(self.memo, "field_reach", wm, lambda: self._field_reach(wm))
        prev = self.ball_player
        if prev is not None and math.isfinite(d[prev]):
            d = d.copy()
            d[prev] -= self.config.ball_player_hysteresis_m
        return int(np.argmin(d))

    def _field_reach(self, wm: WorldModel) -> np.ndarray:
        d = self.ball_reach(wm)
        if self.goalie is not None:
            others = np.isfinite(d)
            others[self.goalie] = False
            if others.any():
                d[self.goalie] = np.inf
        return d

    def ball_reach(self, wm: WorldModel) -> np.ndarray:
        """(N,) how far each teammate must walk to meet the ball (at rest: its distance;
        rolling: to the earliest point it can intercept it); inf for the absent or fallen."""
        return shared(self.memo, "ball_reach", wm, lambda: self._ball_reach(wm)).copy()

    def _ball_reach(self, wm: WorldModel) -> np.ndarray:
        d = wm.upright_ball_distances()
        if math.hypot(*wm.ball_velocity) < MOVING_BALL_M_S:
            return d
        times, _ = self.intercepts(wm)
        return np.where(np.isfinite(d), times * self.skills.run_speed, np.inf)

    def intercepts(self, wm: WorldModel) -> tuple[np.ndarray, np.ndarray]:
        """Every teammate's earliest meeting time and point with the rolling ball
        (``WorldModel.intercepts`` at the body's real running speed, ``Skills.run_speed``),
        computed once per belief."""
        return shared(self.memo, "intercepts", wm,
                      lambda: wm.intercepts(wm.teammates, self.skills.run_speed))

    def supporter(self, wm: WorldModel) -> int | None:
        """The upright field player closest to the ball after the ball player (None if
        there is none)."""
        return shared(self.memo, ("supporter", self.ball_player), wm,
                      lambda: self._supporter(wm))

    def _supporter(self, wm: WorldModel) -> int | None:
        d = self.ball_reach(wm)
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
        """Run to meet a rolling ball; else choose the kick that wins the race to where the
        ball stops, or scores (``best_kick``). Kick it when we win that race by
        ``kick_min_margin_s``, or when an opponent within ``pressure_m`` leaves no time,
        or to shoot; otherwise dribble towards the goal (round anyone in the way)."""
        c = self.config
        if math.hypot(*wm.ball_velocity) >= MOVING_BALL_M_S and not in_kick_reach(wm, self.skills):
            meet = self.intercepts(wm)[1][wm.me]
            if wm.distance(meet) > 0.5:
                return go_to(wm, meet, self.skills, face=wm.ball, behaviour="intercept")
        choice = best_kick(wm, self.skills.body, self.skills.run_speed,
                           c.kick_possession_weight, c.kick_progress_weight,
                           c.kick_goal_weight, c.kick_follow_up,
                           exclude=() if self.goalie is None else (self.goalie,))
        opps = wm.opponents[wm.opponents_present & ~wm.opponents_fallen]
        clearance = float(np.min(np.hypot(*(opps - wm.ball).T))) if len(opps) else math.inf
        name = ("shoot" if choice.goal_chance >= MIN_SHOT_CHANCE else "kick_at_goal") \
            if choice.shot else "pass" if choice.margin_s > 0 else "clear"
        if choice.shot or clearance < c.pressure_m or choice.margin_s >= c.kick_min_margin_s:
            return kick_to(wm, choice.target, self.skills, power=choice.power, behaviour=name)
        return dribble(wm, wm.opponent_goal, self.skills, speed=c.dribble_speed)
