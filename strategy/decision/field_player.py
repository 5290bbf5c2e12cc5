"""The field player's decision maker (seed 000 §2.4).

A decision maker turns the agent's world model and its positioning decision (the position the
team voted for it, marking included) into one ``ControlRequest`` per cycle by choosing among
the behaviours. Both are deterministic functions of what the agent itself believes, so the
team's agents agree on who plays the ball without being told (and, with true-state
observations, always agree); the only memory is the last ball player, for hysteresis.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from strategy.behaviours import (
    Skills,
    beam_to,
    dribble,
    kick_to,
)
from strategy.behaviours.ball import in_kick_reach
from strategy.behaviours.control import ControlRequest
from strategy.behaviours.kick_choice import MIN_SHOT_CHANCE, best_kick
from strategy.behaviours.motion import Hold, detour, go_to, resolve_holds
from strategy.decision.params import DecisionParams
from strategy.decision.setplays import (
    TOUCH_MARGIN_M,
    Situation,
    keep_distance,
    set_play_taker,
    situation,
    take_set_play,
)
from strategy.perception.worldmodel import (
    INTERCEPT_STEP_S,
    WorldModel,
    shared,
    shared_rows_many,
)
from strategy.positioning import PositioningDecision
from teamenv.config import NO_SECOND_TOUCH  # the set plays the double-touch rule covers

#: The open-play options of a field player, by index: play the ball (``play_ball``), stand
#: goal-side of it (``cover``), or hold the voted formation position pulled towards the ball.
#: ``FieldPlayerDecisionMaker.chosen_options`` records which one the team's own rule chose;
#: ``option_override`` makes another decider (a learned policy) choose instead.
OPTIONS = ("play_ball", "cover", "hold")
PLAY_BALL, COVER, HOLD = range(len(OPTIONS))

MOVING_BALL_M_S = 1.0
"""Faster than this the ball is rolling (a kick), not being pushed in a dribble: players are
chosen, and run, by where they can meet it."""


def prepare_reach_kernel() -> None:
    """Compile (or load from numba's cache) the ball reach's kernel now, before a match's
    first cycle runs under its stall watchdog: one belief, one teammate, a rolling ball."""
    from strategy.perception.reach_kernel import reach_rows

    one = np.ones(1)
    reach_rows(np.zeros((1, 2)), np.array([[1.0, 0.0]]), 2.0 * one, one, np.ones(1, bool),
               np.ones((1, 1, 2)), np.ones((1, 1), bool), 0.5 * one, 0.5 * one, 1.0,
               INTERCEPT_STEP_S, np.empty((1, 1)))


class FieldPlayerDecisionMaker:
    """Decides for a team's field players: play the ball when it is the team's ball player,
    else hold its voted formation (or marking) position; set plays and beaming by the play
    mode.

    One maker serves any number of agents: ``plan_all`` decides for all of them in one pass
    (who plays the ball, who supports, where the others stand: arrays over agents), each
    agent from its own belief, with its own memory (the ball player it chose last, by player
    index). ``decide`` is that pass for one agent."""

    def __init__(self, config: DecisionParams, skills: Skills, goalie: int | None,
                 memo: dict | None = None) -> None:
        self.config = config
        self.skills = skills
        self.goalie = goalie
        self.memo = memo  # team-wide facts shared by teammates who believe the same
        self.ball_players: dict[int, int] = {}  # agent index -> the ball player it chose
        #: the league's double-touch rule is in force (``TeamContext.double_touch``): after
        #: our kick-off, kick-in or corner the taker leaves the ball to the others until
        #: another player has reached it
        self.double_touch = False
        #: agent -> the taker of our last set play, which it keeps off the ball
        self.no_second_touch: dict[int, int] = {}
        #: agent -> the open-play option (``OPTIONS``) this maker's own rule chose for it at
        #: its last open-play decision (what a policy that learns the choice is taught)
        self.chosen_options: dict[int, int] = {}
        #: agent -> the option to play instead of the rule's choice (None: the rule decides)
        self.option_override: dict[int, int] | None = None

    def reset(self) -> None:
        self.ball_players.clear()
        self.no_second_touch.clear()
        self.chosen_options.clear()

    def decide(self, wm: WorldModel, positioning: PositioningDecision) -> ControlRequest:
        """One agent's request (``plan_all`` with n = 1, its hold resolved)."""
        return resolve_holds([wm], self.plan_all([wm], [positioning]), self.skills)[0]

    def plan_all(self, wms: Sequence[WorldModel],
                 positionings: Sequence[PositioningDecision]) -> list[ControlRequest | Hold]:
        """Each agent's request, or the ``Hold`` it decided on (resolved with the team's,
        ``resolve_holds``). The agents in open play choose their ball player, supporter and
        pulled position in one array pass."""
        plans: list[ControlRequest | Hold | None] = [None] * len(wms)
        open_play = []
        for i, (wm, positioning) in enumerate(zip(wms, positionings, strict=True)):
            if not wm.fallen and situation(wm.play_mode) is Situation.PLAY_ON:
                open_play.append(i)
                continue
            self.chosen_options.pop(wm.me, None)  # no open-play option while down or in a set play
            plans[i] = ControlRequest(behaviour="fallen") if wm.fallen else \
                self._set_piece(wm, positioning)
        if open_play:
            self._open_play([wms[i] for i in open_play], [positionings[i] for i in open_play],
                            open_play, plans)
        return plans  # type: ignore[return-value]

    def _set_piece(self, wm: WorldModel,
                   positioning: PositioningDecision) -> ControlRequest | Hold:
        self.no_second_touch.pop(wm.me, None)
        now = situation(wm.play_mode)
        if now is Situation.BEAM:
            self.ball_players.pop(wm.me, None)
            return self.beam(wm, positioning)
        if now is Situation.OVER:
            return ControlRequest(behaviour="game_over")
        if now in (Situation.THEIR_SET_PLAY, Situation.THEIR_KICKOFF):
            self.ball_players.pop(wm.me, None)
            return self.keep_away(wm, positioning, kickoff=now is Situation.THEIR_KICKOFF)
        taker = set_play_taker(wm, wm.play_mode, self.goalie)  # ours: a kick-off or set play
        self.ball_players[wm.me] = taker
        if self.double_touch and wm.play_mode.kind in NO_SECOND_TOUCH:
            self.no_second_touch[wm.me] = taker    # from when it is taken (play on)
        if taker == wm.me:
            return take_set_play(wm, self.skills, self.config.pass_max_m,
                                 self.config.pass_lane_m)
        return Hold(positioning.target)

    def _open_play(self, wms: Sequence[WorldModel], positionings: Sequence[PositioningDecision],
                   slots: Sequence[int], plans: list) -> None:
        """Ball player, supporter and pulled position of every agent of ``wms`` (in open
        play) as arrays over agents; fills ``plans[slots[i]]``."""
        c = self.config
        rows = np.arange(len(wms))
        chosen = self.choose_ball_players(wms)
        for wm, k in zip(wms, chosen.tolist(), strict=True):
            self.ball_players[wm.me] = k
        me = np.array([wm.me for wm in wms])
        others = chosen != me
        supporting = np.zeros(len(wms), dtype=bool)
        if c.cover_m > 0 and others.any():
            d = self.ball_reach_rows([wms[i] for i in rows[others].tolist()])
            if self.goalie is not None:
                d[:, self.goalie] = np.inf
            d[np.arange(len(d)), chosen[others]] = np.inf
            k = d.argmin(axis=1)
            found = np.isfinite(d[np.arange(len(d)), k])
            supporting[others] = found & (k == me[others])
        for wm, ball, support in zip(wms, ~others, supporting, strict=True):
            self.chosen_options[wm.me] = PLAY_BALL if ball else COVER if support else HOLD
        if self.option_override is not None:
            others, supporting = self._overridden(me, others, supporting)
        holding = others & ~supporting
        kept = rows[holding].tolist()
        held = iter(self.pulled_all([wms[i] for i in kept],
                                    np.array([p.target for p in positionings])[holding]))
        for i, wm in enumerate(wms):
            if not others[i]:
                plans[slots[i]] = self.play_ball(wm)
            elif supporting[i]:
                plans[slots[i]] = self.cover(wm)
            else:
                plans[slots[i]] = Hold(next(held))

    def _overridden(self, me: np.ndarray, others: np.ndarray, supporting: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray]:
        """``others`` (not playing the ball) and ``supporting`` as ``option_override`` says,
        for the agents it names (the rule's choice for the others)."""
        override = self.option_override or {}
        chosen = np.array([override.get(int(k), -1) for k in me])
        named = chosen >= 0
        others = np.where(named, chosen != PLAY_BALL, others)
        supporting = np.where(named, chosen == COVER, supporting)
        return others, supporting

    def pulled(self, wm: WorldModel, target: np.ndarray) -> np.ndarray:
        """One agent's ``pulled_all``."""
        return self.pulled_all([wm], np.asarray(target, dtype=np.float64)[None])[0]

    def pulled_all(self, wms: Sequence[WorldModel], targets: np.ndarray) -> np.ndarray:
        """(n, 2) each formation position ``targets[i]`` moved ``ball_pull`` of the way
        towards where agent ``i`` believes the ball will stop: the team closes on the ball,
        so it wins the races for it."""
        pull = self.config.ball_pull
        if pull <= 0 or not len(targets):
            return targets
        rests = np.array([wm.ball_rest() for wm in wms])
        return targets + pull * (rests - targets)

    # -- pieces ----------------------------------------------------------------------------
    def beam(self, wm: WorldModel, positioning: PositioningDecision) -> ControlRequest | Hold:
        """Beam to the kick-off position once (again only if moved away from it)."""
        target = positioning.target
        if wm.distance(target) > 0.5:
            return beam_to((float(target[0]), float(target[1]), 0.0))
        return Hold(target, "kickoff_position")

    def keep_away(self, wm: WorldModel, positioning: PositioningDecision,
                  kickoff: bool) -> ControlRequest | Hold:
        """Hold the position, kept ``set_play_clearance_m`` from the ball, walking round the
        circle rather than through it."""
        radius = self.config.set_play_clearance_m
        target = keep_distance(positioning.target, wm, radius, kickoff)
        waypoint = detour(wm.position, target, wm.ball, radius)
        if wm.distance(wm.ball) < radius:  # inside already: straight out first
            waypoint = keep_distance(wm.position, wm, radius + 0.3, kickoff)
        if waypoint is target and wm.distance(target) < self.skills.navigation.arrive_m * 2:
            return Hold(target, "keep_distance")
        return go_to(wm, waypoint, self.skills, face=wm.ball, behaviour="keep_distance")

    def choose_ball_players(self, wms: Sequence[WorldModel]) -> np.ndarray:
        """(n,) for each agent, the upright teammate who can be at the ball first (the goalie
        only if nobody else is upright); the agent's previous ball player keeps it unless
        beaten by the hysteresis margin. One pass over (agents x teammates). Under the
        double-touch rule the taker of our last set play is nobody's ball player until another
        player has reached the ball (``keeps_off_the_ball``)."""
        d = self.ball_reach_rows(wms)
        if self.goalie is not None:  # the goalie only when nobody else is upright
            others = np.isfinite(d)
            others[:, self.goalie] = False
            d[others.any(axis=1), self.goalie] = np.inf
        if self.double_touch:
            for row, wm in enumerate(wms):
                taker = self.keeps_off_the_ball(wm)
                if taker is not None and np.isfinite(np.delete(d[row], taker)).any():
                    d[row, taker] = np.inf
        prev = np.array([self.ball_players.get(wm.me, -1) for wm in wms])
        rows = np.flatnonzero(prev >= 0)
        rows = rows[np.isfinite(d[rows, prev[rows]])]
        d[rows, prev[rows]] -= self.config.ball_player_hysteresis_m
        return d.argmin(axis=1)

    def keeps_off_the_ball(self, wm: WorldModel) -> int | None:
        """The teammate agent ``wm.me`` keeps off the ball under the double-touch rule: the
        taker of the set play that just ended, until another player (teammate or opponent)
        has come within touching distance of the ball in this agent's belief (then it
        forgets it). Touches are not observed, so reaching the ball stands for touching it."""
        taker = self.no_second_touch.get(wm.me)
        if taker is None:
            return None
        near = self.skills.contact_m + TOUCH_MARGIN_M
        mates = np.hypot(*(wm.teammates - wm.ball).T) < near
        mates &= wm.teammates_present
        mates[taker] = False
        opps = (np.hypot(*(wm.opponents - wm.ball).T) < near) & wm.opponents_present
        if mates.any() or opps.any():
            del self.no_second_touch[wm.me]
            return None
        return taker

    def ball_reach(self, wm: WorldModel) -> np.ndarray:
        """(N,) how far each teammate must walk to meet the ball (at rest: its distance;
        rolling: to the earliest point it can intercept it); inf for the absent or fallen."""
        return self.ball_reach_rows([wm])[0]

    def ball_reach_rows(self, wms: Sequence[WorldModel]) -> np.ndarray:
        """(len(wms), N) ``ball_reach`` of each of ``wms``, computed once per belief, the
        beliefs no memo holds in one compiled pass (``strategy.perception.reach_kernel``).
        A new array."""
        return shared_rows_many(self.memo, "ball_reach", wms, self._ball_reach_many)

    def _ball_reach_many(self, wms: list[WorldModel]) -> np.ndarray:
        from strategy.perception.reach_kernel import reach_rows  # numba: on first use

        speeds = [math.hypot(*wm.ball_velocity) for wm in wms]
        rolling = np.array([v >= MOVING_BALL_M_S for v in speeds])
        velocities = np.array([wm.ball_velocity for wm in wms], dtype=np.float64)
        speed = np.array(speeds)
        directions = np.zeros_like(velocities)
        directions[rolling] = velocities[rolling] / speed[rolling, None]
        horizons = np.array([wm.roll.stop_time(v) if moving else 0.0
                             for wm, v, moving in zip(wms, speeds, rolling.tolist(),
                                                      strict=True)])
        out = np.empty((len(wms), len(wms[0].teammates)))
        reach_rows(np.array([wm.ball for wm in wms], dtype=np.float64), directions, speed,
                   horizons, rolling,
                   np.array([wm.teammates for wm in wms], dtype=np.float64),
                   np.array([wm.teammates_present & ~wm.teammates_fallen for wm in wms]),
                   np.array([wm.roll.linear_drag for wm in wms], dtype=np.float64),
                   np.array([wm.roll.rolling_decel for wm in wms], dtype=np.float64),
                   float(self.skills.run_speed), INTERCEPT_STEP_S, out)
        return out

    def intercepts(self, wm: WorldModel) -> tuple[np.ndarray, np.ndarray]:
        """Every teammate's earliest meeting time and point with the rolling ball
        (``WorldModel.intercepts`` at the body's real running speed, ``Skills.run_speed``),
        computed once per belief."""
        return shared(self.memo, "intercepts", wm,
                      lambda: wm.intercepts(wm.teammates, self.skills.run_speed))

    def cover(self, wm: WorldModel) -> Hold:
        """Stand ``cover_m`` goal-side of the ball, on its line to our goal centre: blocks the
        shot and wins the ball if the challenge is lost."""
        goal = wm.own_goal
        to_goal = goal - wm.ball
        dist = math.hypot(to_goal[0], to_goal[1])
        target = wm.ball + to_goal * (min(self.config.cover_m, dist * 0.5) / max(dist, 1e-6))
        return Hold(target, "cover")

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
