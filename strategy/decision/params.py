"""The decision makers' parameters, next to the code that reads them.

A team's own config (``strategy.teams.full_config.FullTeamConfig``) validates the user's keys
and builds these; the decision layer never imports a team.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class DecisionParams:
    """What the field player's and the goalie's decisions depend on (metres, m/s, seconds).

    No defaults here: a team's config holds them (``FullTeamConfig``, where each field of the
    same name is documented) and builds this with ``decision_params()``.
    """

    pass_max_m: float
    pass_lane_m: float
    pressure_m: float
    dribble_speed: float
    ball_player_hysteresis_m: float
    cover_m: float
    goalie_line_m: float
    goalie_clear_m: float
    set_play_clearance_m: float
    kick_possession_weight: float
    kick_progress_weight: float
    kick_goal_weight: float
    kick_min_margin_s: float
    kick_follow_up: float
    ball_pull: float
