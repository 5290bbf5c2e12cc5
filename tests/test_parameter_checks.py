"""Every parameter dataclass checks its numbers with the one helper (paramkit.check_fields): a
NaN, a negative or a wrong type is an error of its package's layer (``ConfigError`` in teamenv
and strategy, ``CommsError`` in comms) whose message names the class, the field and the
value."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from comms.errors import CommsError
from comms.gridworld import GridSpec
from comms.profiles import SIMSPARK, HearingCapacity
from paramkit import value_repr
from strategy.behaviours.navigation import NavigationParams
from strategy.perception.filtering import FilterParams
from strategy.perception.localization import LocalizationParams
from strategy.positioning.marking import MarkingParams
from strategy.teams.full_config import FullTeamConfig
from teamenv.analytics.xg import XGModel
from teamenv.config import PerceptionConfig, PhysicsConfig, RulesConfig
from teamenv.errors import ConfigError
from teamenv.league.match import LeagueMatchOptions
from teamenv.optimize.cmaes_loop import SearchSettings
from teamenv.scenarios import SCENARIOS
from teamenv.search_space import Range
from teamenv.tournament.schedule import Tournament

NAN = math.nan

# (a valid instance, the field, a bad value, the layer's error type)
CASES = [
    (RulesConfig(), "half_time_s", NAN, ConfigError),
    (RulesConfig(), "goal_pause_s", -1.0, ConfigError),
    (RulesConfig(), "halves", 2.0, ConfigError),
    (RulesConfig(), "change_sides_at_half_time", 1, ConfigError),
    (PhysicsConfig(), "ball_mass", -0.1, ConfigError),
    (PhysicsConfig(), "ball_elasticity", "0.5", ConfigError),
    (PerceptionConfig(), "fov_vertical_deg", NAN, ConfigError),
    (PerceptionConfig(), "false_max", 2.5, ConfigError),
    (PerceptionConfig(), "missed_rate", -0.1, ConfigError),
    (PerceptionConfig(), "false_distance_m", (NAN, 1.0), ConfigError),
    (LeagueMatchOptions(), "game_s", NAN, ConfigError),
    (LeagueMatchOptions(), "team_size", "3", ConfigError),
    (Tournament("t", ("chaser", "static")), "games_per_pairing", 0, ConfigError),
    (Tournament("t", ("chaser", "static")), "seed", -1, ConfigError),
    (Tournament("t", ("chaser", "static")), "stall_timeout_s", NAN, ConfigError),
    (SearchSettings(), "sigma0", NAN, ConfigError),
    (SearchSettings(), "popsize", 1, ConfigError),
    (SearchSettings(), "seed", True, ConfigError),
    (Range(0.0, 1.0), "low", NAN, ConfigError),
    (Range(0.0, 1.0), "digits", 0, ConfigError),
    (XGModel(0.0, (1.0, 1.0, 1.0)), "intercept", NAN, ConfigError),
    (SCENARIOS["one_v_one"], "player_jitter_m", -0.1, ConfigError),
    (SCENARIOS["one_v_one"], "max_duration_s", NAN, ConfigError),
    (FullTeamConfig(), "pressure_m", -1.0, ConfigError),
    (FullTeamConfig(), "say_every", 0, ConfigError),
    (FullTeamConfig(), "nav_k_repulse", 0.5, ConfigError),
    (FullTeamConfig(), "vote", "yes", ConfigError),
    (FullTeamConfig(), "nav_side_steps", "left", ConfigError),
    (MarkingParams(), "mark_distance_m", NAN, ConfigError),
    (MarkingParams(), "max_markers", -1, ConfigError),
    (FilterParams(), "eps_m", -1.0, ConfigError),
    (FilterParams(), "min_samples", 2.5, ConfigError),
    (LocalizationParams(), "sigma_bearing_deg", NAN, ConfigError),
    (LocalizationParams(), "odometry_scale", (1.0, -1.0, 1.0), ConfigError),
    (NavigationParams(), "turn_gain", -1.0, ConfigError),
    (NavigationParams(), "k_attract", NAN, ConfigError),
    (HearingCapacity(), "cost", 0, CommsError),
    (HearingCapacity(), "maximum", -1, CommsError),
    (SIMSPARK, "max_heard", -1, CommsError),
    (SIMSPARK, "hearing_range_m", NAN, CommsError),
    (SIMSPARK, "delay_cycles", 0.5, CommsError),
    (GridSpec(), "nx", 0, CommsError),
    (GridSpec(), "length", NAN, CommsError),
]


@pytest.mark.parametrize(("good", "name", "value", "error"), CASES,
                         ids=[f"{type(c[0]).__name__}.{c[1]}={c[2]!r}" for c in CASES])
def test_a_bad_number_names_class_field_and_value(good, name, value, error):
    with pytest.raises(error) as caught:
        replace(good, **{name: value})
    message = str(caught.value)
    assert f"{type(good).__name__}.{name} must be " in message, message
    assert message.endswith(f", got {value_repr(value)}"), message
