"""The full team's parameters: one frozen dataclass, so tournaments and optimizers can vary them.

Every field can be given as a team config key (``teamenv match full chaser --left-config
'{"shoot_range_m": 6}'``, or ``full:shoot_range_m=6`` in a tournament spec). Unknown keys and
bad values are errors that name the field and the value.

Fields an optimizer may vary declare their range or choices in their metadata
(``search(Range(...))``, see ``teamenv.search_space`` and ``teamenv optimize``);
the defaults stay what seeded matches (and the golden hashes) were recorded with.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

from paramkit.checks import check_fields, in_range, invalid, non_negative, one_of
from strategy.behaviours.navigation import NavigationParams
from strategy.decision.params import DecisionParams
from strategy.perception.localization import LocalizationParams
from strategy.positioning.formation.builtin import builtin_formation_names
from strategy.positioning.formation.sized import KINDS
from strategy.positioning.marking import MarkingParams
from teamenv.capabilities import BodyCapabilities
from teamenv.config import build_config
from teamenv.errors import ConfigError
from teamenv.search_space import Choice, Range, search


@dataclass(frozen=True)
class FullTeamConfig:
    """Parameters of the full team (metres, m/s, cycles).

    Formations (a kind from ``strategy.positioning.formation.sized.KINDS`` = the built-in of the team's
    size, or a built-in formation name):
        formation_attack, formation_defend: in play, when we control the ball / when not.
        formation_kickoff_ours, formation_kickoff_theirs, formation_setplay_ours,
        formation_setplay_theirs: at kick-offs and the other set plays.
        switch_formations: False = always ``formation_defend`` in play.
    Marking (``strategy.positioning.marking``, seed 000 §5.4):
        marking: mark dangerous opponents. mark_shoot_range_m, mark_min_ball_distance_m,
        mark_max_behind_ball_m, mark_distance_m, max_markers: its thresholds.
    Playing the ball (``strategy.behaviours.kick_choice.best_kick``: every kick is scored by
    the race to where the ball stops, the ground it gains and its chance of a goal):
        kick_possession_weight: value of winning the race to the landing point (tanh of
            the margin in seconds / 2, times this).
        kick_progress_weight: value of each metre the ball moves towards their goal.
        kick_goal_weight: value of a goal, times the kick's chance of scoring (the shoot
            threshold: a shot is taken when its chance times this beats every pass).
        kick_follow_up: a pass is also worth this fraction of the goal chance of a shot
            from where its receiver wins the ball.
        kick_min_margin_s: kick (pass) only when a teammate wins the race by this many
            seconds; otherwise dribble (unless under pressure or shooting).
        kick_max_angle_rad: kicks are aimed at most this far from the body's heading (the
            env's kick is omnidirectional: about pi; 1.5 = a forward-kicking humanoid, who
            must walk round the ball first).
        pressure_m: an opponent this close to the ball leaves no time to dribble: kick.
        ball_pull: in play, formation positions move this fraction of the way towards
            where the ball will stop (0 = the formation alone).
        pass_max_m, pass_lane_m: at our kick-ins and kick-offs, the longest pass and the
            distance an opponent must keep from its line.
        dribble_speed: walking speed while pushing the ball, m/s.
        ball_player_hysteresis_m: the current ball player keeps the ball unless a teammate
            is this much closer (stops two players swapping every cycle).
        cover_m: the next closest field player stands this far goal-side of the ball, on
            its line to our goal (0 = no cover player).
    Goalie:
        goalie_line_m: stands this far in front of the goal line.
        goalie_clear_m: goes out to clear a ball this close to the goal centre.
    Set plays:
        set_play_clearance_m: distance kept from the ball at the other side's set plays
            (the league's rule is 2 m).
    Communication:
        communicate: say the role vector and vote with the heard ones (False: each agent
            follows its own role vector; the "silent" team).
        vote: adopt the team's vote (False: follow the own role vector but still talk; with
            ``communicate`` it measures what voting alone is worth).
        vote_since_own_change: ``state`` mode: a teammate's vector counts only if heard
            after the agent's own vector last changed. State-mode beliefs are exact and the
            same for every agent, so a vector heard before a change is merely stale (a
            listener hears one teammate per 2 cycles, so most held vectors are ~12 cycles
            old), and counting it holds the team in the old assignment (docs/team_strength.md).
            ``vision`` mode votes on the vectors said in turn and ignores this.
        say_every: say every this many cycles (staggered by uniform number; ``state`` mode;
            in ``vision`` mode one teammate talks every 2 cycles in uniform-number order).
    Perception (``vision`` mode): localization_particles: particles per agent of the Monte
        Carlo localization.
    Navigation (seed 001 eq. 6-10): nav_k_repulse (< 0), nav_influence_m, nav_max_speed;
        nav_side_steps: "both" (side-step either way near a target) or "body" (only to the
        sides the body's locomotion profile walks to, ``NavigationParams.for_body``: the
        league's network does not step left; in paired league and teamenv matches no
        measurable gain and falls leaning up, so not the default: docs/league.md).
    """

    formation_attack: str = field(default="attack", metadata=search(Choice(("attack", "defend"))))
    formation_defend: str = field(default="defend", metadata=search(Choice(("defend", "attack"))))
    formation_kickoff_ours: str = "kickoff-ours"
    formation_kickoff_theirs: str = "kickoff-theirs"
    formation_setplay_ours: str = "setplay-ours"
    formation_setplay_theirs: str = "setplay-theirs"
    switch_formations: bool = field(default=True, metadata=search(Choice((True, False))))
    marking: bool = field(default=True, metadata=search(Choice((True, False))))
    mark_shoot_range_m: float = field(default=9.0, metadata=search(Range(4.0, 15.0)))
    mark_min_ball_distance_m: float = field(default=2.0, metadata=search(Range(0.5, 5.0)))
    mark_max_behind_ball_m: float = field(default=3.0, metadata=search(Range(0.0, 8.0)))
    mark_distance_m: float = field(default=1.5, metadata=search(Range(0.5, 4.0)))
    max_markers: int = field(default=2, metadata=search(Range(0, 4, integer=True)))
    pass_max_m: float = field(default=9.0, metadata=search(Range(4.0, 15.0)))
    pass_lane_m: float = field(default=1.0, metadata=search(Range(0.3, 3.0)))
    pressure_m: float = field(default=2.0, metadata=search(Range(0.5, 5.0)))
    dribble_speed: float = field(default=0.9, metadata=search(Range(0.3, 1.5)))
    ball_player_hysteresis_m: float = field(default=0.5, metadata=search(Range(0.0, 2.0)))
    cover_m: float = field(default=3.0, metadata=search(Range(0.0, 8.0)))
    goalie_line_m: float = field(default=0.5, metadata=search(Range(0.0, 3.0)))
    goalie_clear_m: float = field(default=3.5, metadata=search(Range(1.0, 8.0)))
    set_play_clearance_m: float = field(default=2.6, metadata=search(Range(2.0, 4.0)))
    communicate: bool = True
    vote: bool = True
    vote_since_own_change: bool = True
    localization_particles: int = field(default=50, metadata=in_range(1))
    say_every: int = field(default=1, metadata=in_range(1))
    nav_k_repulse: float = field(default=-0.35, metadata=search(Range(-1.5, -0.05))
                                 | in_range(high=0.0, high_open=True))  # repulsive, eq. 6
    nav_influence_m: float = field(default=1.6, metadata=search(Range(0.5, 4.0)))
    nav_max_speed: float = field(default=1.2, metadata=search(Range(0.6, 1.5)))
    nav_side_steps: str = field(default="both", metadata=one_of("both", "body"))
    kick_max_angle_rad: float = field(default=3.1, metadata=search(Range(0.5, 3.14))
                                      | in_range(0.0, math.pi, low_open=True))
    kick_possession_weight: float = field(default=2.0, metadata=search(Range(0.2, 20.0, "log")))
    kick_progress_weight: float = field(default=0.15, metadata=search(Range(0.01, 1.5, "log")))
    kick_goal_weight: float = field(default=25.0, metadata=search(Range(2.0, 200.0, "log")))
    kick_min_margin_s: float = field(default=1.0, metadata=search(Range(0.0, 3.0)))
    kick_follow_up: float = field(default=0.5, metadata=search(Range(0.0, 1.0)))
    ball_pull: float = field(default=0.5, metadata=search(Range(0.0, 1.0)) | in_range(0.0, 1.0))

    def __post_init__(self) -> None:
        check_fields(self, ConfigError, default=non_negative())  # a number: >= 0 unless declared
        names = set(KINDS) | set(builtin_formation_names())
        for f in fields(self):
            if f.name.startswith("formation_") and getattr(self, f.name) not in names:
                raise invalid(self, f.name, f"a formation kind {KINDS} or a built-in formation "
                              "name", ConfigError)

    @classmethod
    def from_overrides(cls, team: str, overrides: dict) -> FullTeamConfig:
        """The defaults with ``overrides`` applied; an unknown key names the known ones."""
        return build_config(cls, overrides, section=f"{team} team config")

    def marking_params(self) -> MarkingParams | None:
        if not self.marking:
            return None
        return MarkingParams(self.mark_shoot_range_m, self.mark_min_ball_distance_m,
                             self.mark_max_behind_ball_m, self.mark_distance_m, self.max_markers)

    def decision_params(self) -> DecisionParams:
        """The decision makers' share of this config (fields of the same names)."""
        return DecisionParams(**{f.name: getattr(self, f.name) for f in fields(DecisionParams)})

    def localization_params(self) -> LocalizationParams:
        """Monte Carlo localization of ``vision`` mode (particles per agent)."""
        return LocalizationParams(n_particles=self.localization_particles)

    def navigation_params(self, body: BodyCapabilities) -> NavigationParams:
        """The navigation gains, side-stepping as ``nav_side_steps`` says for ``body``."""
        params = NavigationParams(k_repulse=self.nav_k_repulse,
                                  influence_m=self.nav_influence_m, max_speed=self.nav_max_speed)
        return params.for_body(body) if self.nav_side_steps == "body" else params
