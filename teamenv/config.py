"""Frozen config dataclasses, one per concern; building one from a dict rejects unknown keys."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any, TypeVar

from paramkit import Registry
from paramkit.checks import check_fields, in_range, invalid, non_negative, one_of, positive
from teamenv.errors import ConfigError
from teamenv.landmarks import LANDMARK_KINDS

T = TypeVar("T")


#: the set plays whose taker may not touch the ball again before another player has, under
#: the league's double-touch rule (rcsssmj's ``soccer_referee``: kick-off, throw-in, corner
#: kick and free kicks; not the goal kick)
NO_SECOND_TOUCH = ("KickOff", "KickIn", "CornerKick")
#: a taker's touch within this long (s) of its first is the same touch (rcsssmj)
DOUBLE_TOUCH_S = 1.0


@dataclass(frozen=True)
class RulesConfig:
    """Referee rules (seconds of game time, metres)."""

    half_time_s: float = field(default=300.0, metadata=positive())
    halves: int = field(default=2, metadata=one_of(1, 2))
    before_kickoff_s: float = field(default=0.2, metadata=non_negative())
    goal_pause_s: float = field(default=3.0, metadata=positive())
    kickoff_timeout_s: float = field(default=15.0, metadata=positive())
    set_play_timeout_s: float = field(default=15.0, metadata=positive())
    set_play_distance: float = field(default=2.0, metadata=positive())
    change_sides_at_half_time: bool = False
    #: the league's (rcsssmj) double-touch rule: after a kick-off, kick-in or corner kick of a
    #: team of more than one player, the taker's next touch before anyone else's, more than
    #: ``DOUBLE_TOUCH_S`` after its first, is a foul: a kick-in for the other side where the
    #: ball lies (the league's indirect free kick; ``NO_SECOND_TOUCH`` names the set plays)
    double_touch: bool = False
    beam_noise_xy: float = field(default=0.05, metadata=non_negative())
    beam_noise_rot: float = field(default=0.05, metadata=non_negative())

    def __post_init__(self) -> None:
        check_fields(self, ConfigError)


@dataclass(frozen=True)
class PhysicsConfig:
    """The 2D world: ball (SimSpark ball: radius 0.042 m, 26 g), rolling drag, substeps.

    The ball's speed decays each cycle as ``v <- max(0, v*exp(-linear_drag*dt) - rolling_decel*dt)``,
    so a ball launched at about 5.2 m/s rolls 9 m (the source documents' strong kick).
    """

    cycle_s: float = field(default=0.02, metadata=positive())
    ball_radius: float = field(default=0.042, metadata=positive())
    ball_mass: float = field(default=0.026, metadata=positive())
    ball_linear_drag: float = field(default=0.4, metadata=non_negative())
    ball_rolling_decel: float = field(default=0.3, metadata=non_negative())
    ball_max_speed: float = field(default=12.0, metadata=positive())
    ball_elasticity: float = field(default=0.6, metadata=in_range(0.0, 1.0))
    player_elasticity: float = field(default=0.2, metadata=in_range(0.0, 1.0))
    max_substep_travel: float = field(default=0.04, metadata=positive())
    world_margin: float = field(default=1.5, metadata=positive())

    def __post_init__(self) -> None:
        check_fields(self, ConfigError)


@dataclass(frozen=True)
class PerceptionConfig:
    """The ``vision`` observation mode's camera (metres, degrees, cycles).

    The defaults are the ``simspark`` profile (SimSpark's RestrictedVisionPerceptor); see
    ``VISION_PROFILES`` for both league profiles.

    Attributes:
        update_period_cycles: a vision update on cycles where ``cycle % period == 0``; on
            other cycles nothing is seen (every present mask 0).
        fov_horizontal_deg, fov_vertical_deg: full opening angles of the camera's cone
            (seen when ``|azimuth| <= fov_horizontal_deg / 2`` and ``|elevation| <=
            fov_vertical_deg / 2``), in (0, 360].
        min_distance_m: sightings closer than this (3D distance) are dropped.
        distance_sigma_rel: distance noise, a fraction of the distance
            (``d += d * N(0, distance_sigma_rel)``; SimSpark: 0.0965 % = 0.000965).
        azimuth_sigma_deg, elevation_sigma_deg: angle noise (Gaussian, degrees).
        calibration_error_m: a per-match, per-agent camera offset drawn uniformly in
            ``±calibration_error_m`` per axis at reset and added to every camera-relative
            vector before the polar conversion.
        truncate_decimals: None, or round every value toward zero to this many decimals
            (degrees for angles, metres for distances) as RCSSServerMJ does.
        camera_height_m: the camera above the ground (hand-entered: NAO 0.5, T1 1.1).
        landmark_kind: the landmark table (``teamenv.landmarks``): "simspark" or "mj".
        lines: report the field lines (clipped to the horizontal cone).
        occlusion: a sighting is hidden when a nearer player's disc covers its azimuth.
        gyro_sigma_rad: noise of the gyro (the heading change of the cycle, rad).
        missed_rate: chance that a sighting that would be reported is lost (a detector's
            false negative), each sighting of each update on its own.
        misclassified_rate: chance that a seen landmark or ball is reported under another
            world object's name (uniform over the other landmarks and the ball): its polar
            values land in that object's row.
        false_rate, false_max: each update draws ``false_max`` chances of ``false_rate`` each
            for a false detection: a world object's name (uniform over the landmarks and the
            ball) at a uniform azimuth and elevation inside the cone and a uniform distance
            in ``false_distance_m``.
        false_distance_m: (low, high) distance range of false detections, metres.
    """

    update_period_cycles: int = field(default=3, metadata=in_range(1))
    fov_horizontal_deg: float = field(default=120.0, metadata=in_range(0, 360, low_open=True))
    fov_vertical_deg: float = field(default=120.0, metadata=in_range(0, 360, low_open=True))
    min_distance_m: float = field(default=0.1, metadata=non_negative())
    distance_sigma_rel: float = field(default=0.000965, metadata=non_negative())
    azimuth_sigma_deg: float = field(default=0.1480, metadata=non_negative())
    elevation_sigma_deg: float = field(default=0.1225, metadata=non_negative())
    calibration_error_m: float = field(default=0.005, metadata=non_negative())
    truncate_decimals: int | None = field(default=None, metadata=in_range(0, 6))
    camera_height_m: float = field(default=0.5, metadata=positive())
    landmark_kind: str = field(default="simspark", metadata=one_of(*LANDMARK_KINDS))
    lines: bool = True
    occlusion: bool = False
    gyro_sigma_rad: float = field(default=0.002, metadata=non_negative())
    missed_rate: float = field(default=0.0, metadata=in_range(0.0, 1.0))
    misclassified_rate: float = field(default=0.0, metadata=in_range(0.0, 1.0))
    false_rate: float = field(default=0.0, metadata=in_range(0.0, 1.0))
    false_max: int = field(default=5, metadata=in_range(0, 100))
    false_distance_m: tuple[float, float] = field(default=(0.5, 15.0), metadata=non_negative())

    def __post_init__(self) -> None:
        if isinstance(self.false_distance_m, list):  # as JSON gives it
            object.__setattr__(self, "false_distance_m", tuple(self.false_distance_m))
        check_fields(self, ConfigError)
        low, high = self.false_distance_m
        if low > high:
            raise invalid(self, "false_distance_m", "(low, high) metres with low <= high",
                          ConfigError)

    @property
    def noisy(self) -> bool:
        """True when any sighting noise or calibration error is on."""
        return (self.distance_sigma_rel > 0 or self.azimuth_sigma_deg > 0 or
                self.elevation_sigma_deg > 0 or self.calibration_error_m > 0)

    @property
    def detection_errors(self) -> bool:
        """True when sightings can be missed, misclassified or made up."""
        return (self.missed_rate > 0 or self.misclassified_rate > 0 or
                (self.false_rate > 0 and self.false_max > 0))


def build_config(cls: type[T], value: T | Mapping[str, Any] | None, base: T | None = None,
                 *, section: str | None = None,
                 error: Callable[[str], Exception] = ConfigError) -> T:
    """Return ``value`` as a ``cls``: None gives the defaults (or ``base``), a mapping
    overrides them.

    Unknown keys are an error, never ignored: ``error`` (default ``ConfigError``) naming
    ``section`` (default: the class's name without ``Config``, lower case) and the known keys.
    """
    if value is None:
        return cls() if base is None else base
    if isinstance(value, cls):
        return value
    if not isinstance(value, Mapping):
        raise error(f"{cls.__name__}: expected a mapping or {cls.__name__}, got {value!r}")
    known = {f.name for f in fields(cls)}  # type: ignore[arg-type]
    unknown = sorted(set(value) - known)
    if unknown:
        raise error(f"{section or _section_name(cls)}: unknown key(s) {unknown}; known keys "
                    f"are {sorted(known)}")
    return replace(cls() if base is None else base, **dict(value))


def _section_name(cls: type) -> str:
    return cls.__name__.removesuffix("Config").lower()


#: The vision profiles by name (``observation_mode="vision"``, option ``vision=``): a
#: ``paramkit.Registry``, as the channel profiles (``comms.PROFILES``) and the locomotion
#: profiles (``locomotion.PROFILES``) are. ``VISION_PROFILES.register("wide", replace(
#: VISION_PROFILES["mj"], fov_horizontal_deg=180.0))`` adds one that ``vision="wide"`` takes.
#: The league's:
#: ``simspark``: SimSpark's RestrictedVisionPerceptor (an update every 3 cycles, 120° x 120°,
#: noise sigma 0.0965 % of the distance, 0.1480° azimuth, 0.1225° elevation, calibration error
#: up to 0.005 m per axis; flags, goal posts and lines; NAO camera height 0.5 m, hand-entered).
#: ``mj``: RCSSServerMJ 0.2.1 (every 2nd cycle, ±60° both ways, no noise, markers only, values
#: truncated to 2 decimals; T1 camera height 1.1 m, hand-entered).
#: ``mj_noisy``: ``mj`` with the detection model of the server's next vision
#: (``OfficialVisionGenerator`` in a public RCSSServerMJ fork's ``vision_generator.py``):
#: distance noise sigma 1 % of the distance, azimuth and elevation noise sigma 0.5°, 1 % of
#: sightings missed, 5 % of landmark and ball sightings misclassified, up to 5 false
#: detections per update at 0.1 % each (0.5-15 m), and occlusion by the players.
_MJ = PerceptionConfig(
    update_period_cycles=2, distance_sigma_rel=0.0, azimuth_sigma_deg=0.0,
    elevation_sigma_deg=0.0, calibration_error_m=0.0, truncate_decimals=2,
    camera_height_m=1.1, landmark_kind="mj", lines=False, gyro_sigma_rad=0.0,
)
VISION_PROFILES: Registry[PerceptionConfig] = Registry("vision profile", ConfigError)
VISION_PROFILES.register("simspark", PerceptionConfig())
VISION_PROFILES.register("mj", _MJ)
VISION_PROFILES.register("mj_noisy", replace(
    _MJ, distance_sigma_rel=0.01, azimuth_sigma_deg=0.5, elevation_sigma_deg=0.5,
    occlusion=True, missed_rate=0.01, misclassified_rate=0.05, false_rate=0.001,
    false_max=5, false_distance_m=(0.5, 15.0),
))


def perception_config(vision: str | None,
                      perception: PerceptionConfig | Mapping[str, Any] | None) -> PerceptionConfig:
    """The profile ``vision`` (None: "simspark") with ``perception`` on top: a mapping
    overrides single fields (unknown keys are an error), a PerceptionConfig replaces it."""
    base = VISION_PROFILES.get("simspark" if vision is None else vision)
    return build_config(PerceptionConfig, perception, base=base)

