"""Frozen config dataclasses, one per concern; building one from a dict rejects unknown keys."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any, Callable, Mapping, TypeVar

from teamenv.errors import ConfigError

T = TypeVar("T")


@dataclass(frozen=True)
class RulesConfig:
    """Referee rules (seconds of game time, metres)."""

    half_time_s: float = 300.0
    halves: int = 2
    before_kickoff_s: float = 0.2
    goal_pause_s: float = 3.0
    kickoff_timeout_s: float = 15.0
    set_play_timeout_s: float = 15.0
    set_play_distance: float = 2.0
    change_sides_at_half_time: bool = False
    beam_noise_xy: float = 0.05
    beam_noise_rot: float = 0.05

    def __post_init__(self) -> None:
        _positive(self, "half_time_s", "goal_pause_s", "kickoff_timeout_s", "set_play_timeout_s",
                  "set_play_distance")
        _non_negative(self, "before_kickoff_s", "beam_noise_xy", "beam_noise_rot")
        if self.halves not in (1, 2):
            raise ConfigError(f"rules.halves: must be 1 or 2, got {self.halves!r}")


@dataclass(frozen=True)
class PhysicsConfig:
    """The 2D world: ball (SimSpark ball: radius 0.042 m, 26 g), rolling drag, substeps.

    The ball's speed decays each cycle as ``v <- max(0, v*exp(-linear_drag*dt) - rolling_decel*dt)``,
    so a ball launched at about 5.2 m/s rolls 9 m (the source documents' strong kick).
    """

    cycle_s: float = 0.02
    ball_radius: float = 0.042
    ball_mass: float = 0.026
    ball_linear_drag: float = 0.4
    ball_rolling_decel: float = 0.3
    ball_max_speed: float = 12.0
    ball_elasticity: float = 0.6
    player_elasticity: float = 0.2
    max_substep_travel: float = 0.04
    world_margin: float = 1.5

    def __post_init__(self) -> None:
        _positive(self, "cycle_s", "ball_radius", "ball_mass", "ball_max_speed",
                  "max_substep_travel", "world_margin")
        _non_negative(self, "ball_linear_drag", "ball_rolling_decel")
        for name in ("ball_elasticity", "player_elasticity"):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise ConfigError(f"physics.{name}: must be in [0, 1], got {value!r}")


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

    update_period_cycles: int = 3
    fov_horizontal_deg: float = 120.0
    fov_vertical_deg: float = 120.0
    min_distance_m: float = 0.1
    distance_sigma_rel: float = 0.000965
    azimuth_sigma_deg: float = 0.1480
    elevation_sigma_deg: float = 0.1225
    calibration_error_m: float = 0.005
    truncate_decimals: int | None = None
    camera_height_m: float = 0.5
    landmark_kind: str = "simspark"
    lines: bool = True
    occlusion: bool = False
    gyro_sigma_rad: float = 0.002
    missed_rate: float = 0.0
    misclassified_rate: float = 0.0
    false_rate: float = 0.0
    false_max: int = 5
    false_distance_m: tuple[float, float] = (0.5, 15.0)

    def __post_init__(self) -> None:
        period = self.update_period_cycles
        if isinstance(period, bool) or not isinstance(period, int) or period < 1:
            raise ConfigError(f"perception.update_period_cycles: must be an int >= 1, got "
                              f"{period!r}")
        for name in ("fov_horizontal_deg", "fov_vertical_deg"):
            value = getattr(self, name)
            if not (_is_number(value) and 0.0 < value <= 360.0):
                raise ConfigError(f"perception.{name}: must be in (0, 360], got {value!r}")
        _positive(self, "camera_height_m")
        _non_negative(self, "min_distance_m", "distance_sigma_rel", "azimuth_sigma_deg",
                      "elevation_sigma_deg", "calibration_error_m", "gyro_sigma_rad")
        dec = self.truncate_decimals
        if dec is not None and (isinstance(dec, bool) or not isinstance(dec, int) or
                                not 0 <= dec <= 6):
            raise ConfigError(f"perception.truncate_decimals: must be None or an int in 0..6, "
                              f"got {dec!r}")
        if self.landmark_kind not in ("simspark", "mj"):
            raise ConfigError(f"perception.landmark_kind: must be one of ['simspark', 'mj'], "
                              f"got {self.landmark_kind!r}")
        for name in ("lines", "occlusion"):
            value = getattr(self, name)
            if not isinstance(value, bool):
                raise ConfigError(f"perception.{name}: must be True or False, got {value!r}")
        for name in ("missed_rate", "misclassified_rate", "false_rate"):
            value = getattr(self, name)
            if not (_is_number(value) and 0.0 <= value <= 1.0):
                raise ConfigError(f"perception.{name}: must be a probability in [0, 1], got "
                                  f"{value!r}")
        fmax = self.false_max
        if isinstance(fmax, bool) or not isinstance(fmax, int) or not 0 <= fmax <= 100:
            raise ConfigError(f"perception.false_max: must be an int in 0..100, got {fmax!r}")
        span = self.false_distance_m
        if isinstance(span, list):
            span = tuple(span)
            object.__setattr__(self, "false_distance_m", span)
        if not (isinstance(span, (tuple, list)) and len(span) == 2
                and all(_is_number(v) for v in span) and 0.0 <= span[0] <= span[1]):
            raise ConfigError(f"perception.false_distance_m: must be (low, high) metres with "
                              f"0 <= low <= high, got {span!r}")

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


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and \
        math.isfinite(value)


def _positive(obj: Any, *names: str) -> None:
    for name in names:
        value = getattr(obj, name)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ConfigError(f"{_section(obj)}.{name}: must be a finite number > 0, got {value!r}")


def _non_negative(obj: Any, *names: str) -> None:
    for name in names:
        value = getattr(obj, name)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
            raise ConfigError(f"{_section(obj)}.{name}: must be a finite number >= 0, got {value!r}")


def _section(obj: Any) -> str:
    return _section_name(type(obj))


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


#: The league's vision profiles (``observation_mode="vision"``, option ``vision=``).
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
VISION_PROFILES: dict[str, PerceptionConfig] = {
    "simspark": PerceptionConfig(),
    "mj": _MJ,
    "mj_noisy": replace(
        _MJ, distance_sigma_rel=0.01, azimuth_sigma_deg=0.5, elevation_sigma_deg=0.5,
        occlusion=True, missed_rate=0.01, misclassified_rate=0.05, false_rate=0.001,
        false_max=5, false_distance_m=(0.5, 15.0),
    ),
}


def perception_config(vision: str | None,
                      perception: PerceptionConfig | Mapping[str, Any] | None) -> PerceptionConfig:
    """The profile ``vision`` (None: "simspark") with ``perception`` on top: a mapping
    overrides single fields (unknown keys are an error), a PerceptionConfig replaces it."""
    name = "simspark" if vision is None else vision
    if not isinstance(name, str) or name not in VISION_PROFILES:
        raise ConfigError(f"vision: unknown profile {vision!r}; choose one of "
                          f"{sorted(VISION_PROFILES)}")
    return build_config(PerceptionConfig, perception, base=VISION_PROFILES[name])

