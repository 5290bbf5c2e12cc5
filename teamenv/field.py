"""Field geometry and the league's field presets (metres; the centre spot is the origin)."""

from __future__ import annotations

from dataclasses import dataclass, fields

from teamenv.errors import ConfigError


@dataclass(frozen=True)
class FieldSpec:
    """Dimensions of one pitch, in metres.

    x runs along the length (goal to goal), y across; the left team's goal is at x = -length/2.
    ``goal_height`` (crossbar), ``penalty_spot_distance`` (from the goal line; 0 = no
    penalty spot) and the goal area (``goal_area_length`` from the goal line by
    ``goal_area_width`` across; 0 = none; RCSSServerMJ's "goalie area") place the vision
    landmarks (``teamenv.landmarks``). ``penalty_length`` / ``penalty_width`` are the
    penalty area's depth from the goal line and its width across.
    """

    name: str
    length: float
    width: float
    goal_width: float
    goal_depth: float
    penalty_length: float
    penalty_width: float
    center_circle_radius: float
    goal_post_radius: float
    default_team_size: int
    goal_height: float = 0.8
    penalty_spot_distance: float = 0.0
    goal_area_length: float = 0.0
    goal_area_width: float = 0.0

    @property
    def half_length(self) -> float:
        return self.length / 2.0

    @property
    def half_width(self) -> float:
        return self.width / 2.0

    @property
    def half_goal_width(self) -> float:
        return self.goal_width / 2.0

    def contains(self, x: float, y: float, margin: float = 0.0) -> bool:
        """True if (x, y) lies on the pitch, lines included, grown by ``margin`` metres."""
        return abs(x) <= self.half_length + margin and abs(y) <= self.half_width + margin


# simspark: the classic 3D league (rcssserver3d naosoccersim.rb defaults).
# mj7v7: RCSSServerMJ's "fifa7vs7" field, the default of its "ssim" rules (7 v 7, 5-minute
# halves); fifa: RCSSServerMJ's "fifa" field (a full-size pitch). Both are read against the
# installed server's rcsssmj.games.soccer.soccer_fields (tests/teamenv/league/test_field_league.py).
FIELD_PRESETS: dict[str, FieldSpec] = {
    "simspark": FieldSpec(
        name="simspark", length=30.0, width=20.0, goal_width=2.1, goal_depth=0.6,
        penalty_length=1.8, penalty_width=3.9, center_circle_radius=2.0,
        goal_post_radius=0.05, default_team_size=11, goal_height=0.8,
    ),
    "mj7v7": FieldSpec(
        name="mj7v7", length=55.0, width=36.0, goal_width=3.66, goal_depth=1.0,
        penalty_length=9.0, penalty_width=16.5, center_circle_radius=5.5,
        goal_post_radius=0.05, default_team_size=7, goal_height=1.83,
        penalty_spot_distance=7.32, goal_area_length=4.0, goal_area_width=7.3,
    ),
    "fifa": FieldSpec(
        name="fifa", length=105.0, width=68.0, goal_width=7.32, goal_depth=1.6,
        penalty_length=16.5, penalty_width=40.32, center_circle_radius=9.15,
        goal_post_radius=0.05, default_team_size=11, goal_height=2.44,
        penalty_spot_distance=11.0, goal_area_length=5.5, goal_area_width=18.32,
    ),
}


def field_preset(name: str | FieldSpec) -> FieldSpec:
    """Return the preset called ``name`` (or ``name`` itself if it already is a FieldSpec)."""
    if isinstance(name, FieldSpec):
        return name
    try:
        return FIELD_PRESETS[name]
    except KeyError:
        raise ConfigError(
            f"field: unknown preset {name!r}; choose one of {sorted(FIELD_PRESETS)}"
        ) from None


FIELD_SPEC_KEYS = tuple(f.name for f in fields(FieldSpec))
