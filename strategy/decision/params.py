"""The decision makers' parameters, next to the code that reads them.

A team's own config (``strategy.teams.full_config.FullTeamConfig``) validates the user's keys
and builds these; the decision layer never imports a team.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class DecisionParams:
    """What the field player's and the goalie's decisions depend on (metres, m/s, seconds).

    See ``FullTeamConfig`` for the meaning of each field (same names).
    """

    pass_max_m: float = 9.0
    pass_lane_m: float = 1.0
    pressure_m: float = 2.0
    dribble_speed: float = 0.9
    ball_player_hysteresis_m: float = 0.5
    cover_m: float = 3.0
    goalie_line_m: float = 0.5
    goalie_clear_m: float = 3.5
    set_play_clearance_m: float = 2.6
    nav_max_speed: float = 1.2
    kick_possession_weight: float = 2.0
    kick_progress_weight: float = 0.15
    kick_goal_weight: float = 25.0
    kick_min_margin_s: float = 1.0
    kick_follow_up: float = 0.5
    ball_pull: float = 0.5
