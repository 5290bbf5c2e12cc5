"""The referee: play modes, scoring, out of bounds, set-play placement and distances, halves."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from teamenv.config import DOUBLE_TOUCH_S, NO_SECOND_TOUCH, RulesConfig
from teamenv.field import FieldSpec
from teamenv.sim.playmode import SET_PLAYS, PlayMode
from teamenv.sim.world import World


@dataclass(frozen=True)
class RefereeEvent:
    """Something the referee decided: a goal, a play-mode change, a drop ball, half time."""

    kind: str  # "goal", "play_mode", "drop_ball", "half_time", "game_over", "double_touch"
    time_s: float
    team: int | None = None
    player: int | None = None  # player index (goals: the last toucher)
    play_mode: str | None = None


class Referee:
    """Applies the league's rules to a World once per cycle, after physics.

    Players 0..N-1 are team 0 (left), N..2N-1 team 1 (right). ``attack_sign[t]`` is +1 when
    team t attacks the goal at +x. Game time stands still in BeforeKickOff, as in SimSpark.
    """

    def __init__(self, field: FieldSpec, rules: RulesConfig, team_size: int, cycle_s: float,
                 player_radius: float, ball_radius: float) -> None:
        self.field, self.rules, self.team_size, self.cycle_s = field, rules, team_size, cycle_s
        self.player_radius, self.ball_radius = player_radius, ball_radius
        self.team_of = np.repeat([0, 1], team_size)
        self.reset()

    def reset(self) -> None:
        self.mode = PlayMode.BeforeKickOff
        self.time_s = 0.0
        self.half = 1
        self.score = [0, 0]
        self.mode_cycles = 0
        self.attack_sign = [1.0, -1.0]
        self.last_touch: int | None = None
        self.set_play_spot: tuple[float, float] = (0.0, 0.0)
        self.kickoff_team = 0
        #: (player, game time of its first touch): a set play's taker, until another touches
        self.no_second_touch: tuple[int, float] | None = None

    # -- queries ---------------------------------------------------------------------------
    @property
    def beam_allowed(self) -> bool:
        return self.mode in (PlayMode.BeforeKickOff, PlayMode.Goal_Left, PlayMode.Goal_Right)

    @property
    def game_over(self) -> bool:
        return self.mode == PlayMode.GameOver

    @property
    def ball_held(self) -> bool:
        """True while the ball waits at its spot (before kick-off, set plays not yet taken)."""
        return self.mode == PlayMode.BeforeKickOff or self.mode.kind in SET_PLAYS or \
            self.mode.kind == "KickOff"

    # -- the cycle -------------------------------------------------------------------------
    def start_positions(self, team: int) -> np.ndarray:
        """(N, 3) default start poses (world frame) for a team: a spread in its own half."""
        n, f = self.team_size, self.field
        sign = self.attack_sign[team]
        poses = np.zeros((n, 3))
        poses[0] = (-f.half_length + 0.5, 0.0, 0.0)  # goalie
        rest = n - 1
        if rest:
            cols = max(1, math.ceil(math.sqrt(rest)))
            rows = math.ceil(rest / cols)
            for k in range(rest):
                col, row = divmod(k, rows)
                x = -f.half_length * (0.75 - 0.6 * (col + 1) / (cols + 1))
                y = f.half_width * 0.8 * ((row + 1) / (rows + 1) * 2 - 1)
                poses[k + 1] = (x, y, 0.0)
        poses[:, 0] = np.minimum(poses[:, 0], -(f.center_circle_radius + self.player_radius + 0.3))
        poses[:, :2] *= sign
        poses[:, 2] = 0.0 if sign > 0 else math.pi
        return poses

    def place_for_start(self, world: World) -> None:
        """Put every player at its start pose and the ball on the centre spot."""
        for team in (0, 1):
            for k, (x, y, h) in enumerate(self.start_positions(team)):
                world.place_player(team * self.team_size + k, x, y, h)
        world.place_ball(0.0, 0.0)

    def update(self, world: World, touchers: list[int]) -> list[RefereeEvent]:
        """Apply the rules after a physics cycle. ``touchers``: players that touched or kicked
        the ball this cycle, in order."""
        events: list[RefereeEvent] = []
        if self.mode == PlayMode.GameOver:
            return events
        if touchers:
            self.last_touch = touchers[-1]
        self.mode_cycles += 1
        if self.mode != PlayMode.BeforeKickOff:
            self.time_s = round(self.time_s + self.cycle_s, 9)
        mode_s = self.mode_cycles * self.cycle_s
        kind, owner = self.mode.kind, self.mode.team

        if self._half_ends():
            return self._end_half(world, events)
        if self.mode == PlayMode.BeforeKickOff:
            world.place_ball(0.0, 0.0)
            if mode_s >= self.rules.before_kickoff_s - 1e-9:
                self._start_kickoff(world, self.kickoff_team, events)
        elif kind == "Goal":
            if mode_s >= self.rules.goal_pause_s - 1e-9:
                self._start_kickoff(world, 1 - owner, events)
        elif kind == "KickOff" or kind in SET_PLAYS:
            taken = [p for p in touchers if self.team_of[p] == owner]
            if taken:
                if self.rules.double_touch and self.team_size > 1 and kind in NO_SECOND_TOUCH:
                    self.no_second_touch = (taken[0], self.time_s)
                self._set_mode(PlayMode.PlayOn, events)
                self._check_ball(world, events)
            else:
                timeout = self.rules.kickoff_timeout_s if kind == "KickOff" \
                    else self.rules.set_play_timeout_s
                world.place_ball(*self.set_play_spot)
                if mode_s >= timeout - 1e-9:
                    # The league drops the ball: play on from where it lies.
                    events.append(RefereeEvent("drop_ball", self.time_s, owner))
                    self._set_mode(PlayMode.PlayOn, events)
                else:
                    self._keep_opponents_away(world, owner, kickoff=(kind == "KickOff"))
        elif self.mode == PlayMode.PlayOn:
            if self.no_second_touch is not None and touchers and \
                    self._double_touch(world, touchers, events):
                return events
            self._check_ball(world, events)
        return events

    def _double_touch(self, world: World, touchers: list[int],
                      events: list[RefereeEvent]) -> bool:
        """Apply the double-touch rule to this cycle's touches; True if it was a foul."""
        taker, since = self.no_second_touch  # type: ignore[misc]
        for p in touchers:
            if p != taker:
                self.no_second_touch = None   # someone else touched it: the taker is free
                return False
            if self.time_s - since > DOUBLE_TOUCH_S + 1e-9:
                self.no_second_touch = None
                other = 1 - int(self.team_of[taker])
                events.append(RefereeEvent("double_touch", self.time_s, int(self.team_of[taker]),
                                           taker))
                x, y = world.ball_state()[:2]
                f = self.field
                spot = (float(np.clip(x, -f.half_length, f.half_length)),
                        float(np.clip(y, -f.half_width, f.half_width)))
                self._start_set_play(world, "KickIn", other, spot, events)
                return True
        return False

    # -- rules -----------------------------------------------------------------------------
    def _half_ends(self) -> bool:
        end = self.half * self.rules.half_time_s
        return self.time_s >= end - 1e-9 and self.mode != PlayMode.BeforeKickOff

    def _end_half(self, world: World, events: list[RefereeEvent]) -> list[RefereeEvent]:
        if self.half >= self.rules.halves:
            events.append(RefereeEvent("game_over", self.time_s))
            self._set_mode(PlayMode.GameOver, events)
            return events
        self.half += 1
        if self.rules.change_sides_at_half_time:
            self.attack_sign = [-s for s in self.attack_sign]
        self.kickoff_team = 1  # the other team kicks off the second half
        events.append(RefereeEvent("half_time", self.time_s))
        self._set_mode(PlayMode.BeforeKickOff, events)
        self.place_for_start(world)
        return events

    def _check_ball(self, world: World, events: list[RefereeEvent]) -> None:
        f, r = self.field, self.ball_radius
        x, y = world.ball_state()[:2]
        if abs(x) > f.half_length + r:
            goal_side = 1.0 if x > 0 else -1.0
            attacker = 0 if self.attack_sign[0] == goal_side else 1
            defender = 1 - attacker
            if abs(y) < f.half_goal_width:
                self.score[attacker] += 1
                events.append(RefereeEvent("goal", self.time_s, attacker, self.last_touch))
                self._set_mode(PlayMode.of("Goal", attacker), events)
                world.place_ball(x, y)
                return
            last_team = None if self.last_touch is None else int(self.team_of[self.last_touch])
            corner_y = math.copysign(f.half_width, y)
            if last_team == defender:
                self._start_set_play(world, "CornerKick", attacker,
                                     (goal_side * f.half_length, corner_y), events)
            else:
                spot_x = goal_side * (f.half_length - f.penalty_length / 2)
                self._start_set_play(world, "GoalKick", defender, (spot_x, 0.0), events)
        elif abs(y) > f.half_width + r:
            last_team = 0 if self.last_touch is None else int(self.team_of[self.last_touch])
            spot = (float(np.clip(x, -f.half_length, f.half_length)), math.copysign(f.half_width, y))
            self._start_set_play(world, "KickIn", 1 - last_team, spot, events)

    def _start_set_play(self, world: World, kind: str, team: int, spot: tuple[float, float],
                        events: list[RefereeEvent]) -> None:
        self.set_play_spot = (float(spot[0]), float(spot[1]))
        world.place_ball(*self.set_play_spot)
        self._set_mode(PlayMode.of(kind, team), events)
        self._keep_opponents_away(world, team, kickoff=False)

    def _start_kickoff(self, world: World, team: int, events: list[RefereeEvent]) -> None:
        self.set_play_spot = (0.0, 0.0)
        world.place_ball(0.0, 0.0)
        self._set_mode(PlayMode.of("KickOff", team), events)
        self._keep_own_half(world, team=None)
        self._keep_opponents_away(world, team, kickoff=True)

    def _set_mode(self, mode: PlayMode, events: list[RefereeEvent]) -> None:
        if mode != PlayMode.PlayOn:
            self.no_second_touch = None       # a new set play (or a goal) lifts the restriction
        if mode != self.mode:
            self.mode = mode
            self.mode_cycles = 0
            events.append(RefereeEvent("play_mode", self.time_s, mode.team, None, mode.name))

    def _keep_own_half(self, world: World, team: int | None) -> None:
        """Move players of ``team`` (both if None) found in the opponents' half back, mirrored."""
        poses = world.player_poses()
        sign = np.asarray(self.attack_sign, dtype=float)[self.team_of]
        wrong = sign * poses[:, 0] > -self.player_radius  # the test below, for all at once
        if team is not None:
            wrong &= self.team_of == team
        for i in np.flatnonzero(wrong).tolist():
            x, y, h = poses[i]
            t = int(self.team_of[i])
            new_x = -self.attack_sign[t] * max(abs(x), self.player_radius + 0.05)
            world.place_player(i, new_x, y, h)

    def _keep_opponents_away(self, world: World, owner: int, kickoff: bool) -> None:
        """Opponents of ``owner`` stay ``set_play_distance`` from the ball (and, at kick-off,
        out of the centre circle and in their own half)."""
        bx, by = self.set_play_spot
        radius = self.rules.set_play_distance
        if kickoff:
            radius = max(radius, self.field.center_circle_radius)
            self._keep_own_half(world, team=1 - owner)
        poses = world.player_poses()
        # Only players inside the square around the spot can be inside the circle.
        near = (self.team_of != owner) & (np.abs(poses[:, 0] - bx) < radius + 1e-6) & \
            (np.abs(poses[:, 1] - by) < radius + 1e-6)
        for i in np.flatnonzero(near).tolist():
            x, y, h = poses[i]
            dx, dy = x - bx, y - by
            dist = math.hypot(dx, dy)
            if dist < radius:
                if dist < 1e-9:  # exactly on the spot: step back towards own goal
                    dx, dy, dist = -self.attack_sign[int(self.team_of[i])], 0.0, 1.0
                k = (radius + 1e-6) / dist
                world.place_player(i, bx + dx * k, by + dy * k, h)
