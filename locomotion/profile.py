"""Robot profiles: versioned JSON files holding every locomotion parameter and its source."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from statistics import NormalDist
from typing import Any

import numpy as np

from paramkit import Registry

from .errors import LocomotionError, ProfileError

__all__ = [
    "FORMAT",
    "FORMAT_VERSION",
    "PARAMETERS",
    "PROFILES",
    "Profile",
    "load_profile",
    "profile_from_dict",
    "shipped_profiles",
    "PROFILE_DIR",
]

FORMAT_VERSION = 1
FORMAT = f"teamenv.locomotion.profile/{FORMAT_VERSION}"
PROFILE_DIR = Path(__file__).resolve().parent / "profiles"
KINDS = ("measured", "measured-humanoid", "literature", "derived", "hand-entered")

# name -> (shape, unit, low, high, low_open, description).  shape: () scalar, (3,) vector,
# "table" list of [commanded, achieved] pairs.  low/high bound every element.
_INF = math.inf
PARAMETERS: dict[str, tuple[Any, str, float, float, bool, str]] = {
    "step_period": (
        (),
        "s",
        0.0,
        2.0,
        True,
        "duration T of one step; commands switch at step boundaries",
    ),
    "tracking_vx": ("table", "m/s", -5.0, 5.0, False, "commanded -> achieved forward speed"),
    "tracking_vy": ("table", "m/s", -5.0, 5.0, False, "commanded -> achieved side speed"),
    "tracking_turn": ("table", "rad/s", -10.0, 10.0, False, "commanded -> achieved turn rate"),
    "envelope_vx_forward": ((), "m/s", 0.0, 5.0, True, "fastest forward walk"),
    "envelope_vx_backward": ((), "m/s", 0.0, 5.0, True, "fastest backward walk (positive)"),
    "envelope_vy": ((), "m/s", 0.0, 5.0, True, "fastest side walk"),
    "envelope_turn": ((), "rad/s", 0.0, 10.0, True, "fastest turn"),
    "envelope_exponent": ((), "1", 1.0, 16.0, False, "p of the combined p-norm envelope"),
    "accel_vx": ((), "m/s^2", 0.0, 50.0, True, "forward acceleration limit"),
    "accel_vy": ((), "m/s^2", 0.0, 50.0, True, "side acceleration limit"),
    "accel_turn": ((), "rad/s^2", 0.0, 100.0, True, "turn acceleration limit"),
    "command_low": (
        (3,),
        "m/s, m/s, rad/s",
        -10.0,
        0.0,
        False,
        "low bound of the walk command space",
    ),
    "command_high": (
        (3,),
        "m/s, m/s, rad/s",
        0.0,
        10.0,
        False,
        "high bound of the walk command space",
    ),
    "push_fall_speed_forward": (
        (),
        "m/s",
        0.0,
        10.0,
        True,
        "push speed that topples a standing robot, pushed forward",
    ),
    "push_fall_speed_backward": ((), "m/s", 0.0, 10.0, True, "same, pushed backward"),
    "push_fall_speed_side": ((), "m/s", 0.0, 10.0, True, "same, pushed sideways"),
    "command_jump_threshold": (
        (),
        "1",
        0.0,
        10.0,
        True,
        "normalised velocity change demanded at a step boundary above which the walk may fall",
    ),
    "command_jump_fall_probability": (
        (),
        "1",
        0.0,
        1.0,
        False,
        "probability of a fall per over-fast change",
    ),
    "fall_duration": ((), "s", 0.0, 30.0, False, "time from losing balance to lying on the ground"),
    "getup_duration": ((), "s", 0.0, 60.0, False, "time to stand up again"),
    "kick_prep_time": (
        (),
        "s",
        0.0,
        10.0,
        False,
        "time from the kick request to foot-ball contact",
    ),
    "kick_duration": ((), "s", 0.0, 10.0, True, "whole kick motion, request to standing again"),
    "kick_reach": (
        (),
        "m",
        0.0,
        2.0,
        True,
        "body centre to ball centre distance at which a kick connects",
    ),
    "kick_distance_mean": ((), "m", 0.0, 100.0, True, "mean ball travel at full power"),
    "kick_distance_std": ((), "m", 0.0, 100.0, False, "std of ball travel at full power"),
    "kick_distance_min": (
        (),
        "m",
        0.0,
        100.0,
        False,
        "lowest ball travel at full power (truncation)",
    ),
    "kick_distance_max": (
        (),
        "m",
        0.0,
        100.0,
        True,
        "highest ball travel at full power (truncation)",
    ),
    "kick_accuracy": (
        (),
        "1",
        0.0,
        1.0,
        True,
        "fraction of kicks within kick_accuracy_half_angle of the aim",
    ),
    "kick_accuracy_half_angle": (
        (),
        "rad",
        0.0,
        math.pi,
        True,
        "half-angle that counts as accurate",
    ),
    "kick_max_angle": ((), "rad", 0.0, math.pi, True,
                       "largest angle between the heading and a kick's direction that the "
                       "body kicks from where it stands (beyond it: turn, or walk round the "
                       "ball, first)"),
    "odometry_scale": (
        (3,),
        "1",
        0.0,
        10.0,
        True,
        "odometry / true displacement per channel (slip)",
    ),
    "odometry_noise": ((3,), "1", 0.0, 10.0, False, "relative std of odometry per channel"),
    "body_radius": ((), "m", 0.0, 2.0, True, "radius of the body's 2D collision disc"),
    "mass": ((), "kg", 0.0, 500.0, True, "robot mass"),
}
#: parameters a profile may leave out (files written before they existed): the value, kind
#: and source used then
OPTIONAL_PARAMETERS: dict[str, tuple[float, str, str]] = {
    "kick_max_angle": (math.pi, "hand-entered",
                       "not in this profile: kicks in any direction (the env's kick model)"),
}
_TOP_KEYS = {"format", "version", "name", "robot", "description", "parameters", "measurements"}
_REQUIRED_TOP = {"format", "version", "name", "robot", "description", "parameters"}
_PARAM_KEYS = {"value", "unit", "source", "kind", "note"}


@dataclass(frozen=True)
class Profile:
    """Validated locomotion parameters of one robot (SI units: m, s, rad, kg).

    Build with :func:`load_profile`; ``sources`` maps each parameter to where its number came
    from, ``kinds`` to measured / literature / derived / hand-entered.
    """

    name: str
    version: int
    robot: str
    description: str
    step_period: float
    tracking: tuple[tuple[np.ndarray, np.ndarray], ...]
    envelope_vx_forward: float
    envelope_vx_backward: float
    envelope_vy: float
    envelope_turn: float
    envelope_exponent: float
    accel: np.ndarray
    command_low: np.ndarray
    command_high: np.ndarray
    push_fall_speed_forward: float
    push_fall_speed_backward: float
    push_fall_speed_side: float
    command_jump_threshold: float
    command_jump_fall_probability: float
    fall_duration: float
    getup_duration: float
    kick_prep_time: float
    kick_duration: float
    kick_reach: float
    kick_distance_mean: float
    kick_distance_std: float
    kick_distance_min: float
    kick_distance_max: float
    kick_accuracy: float
    kick_accuracy_half_angle: float
    kick_max_angle: float
    odometry_scale: np.ndarray
    odometry_noise: np.ndarray
    body_radius: float
    mass: float
    sources: Mapping[str, str] = field(repr=False)
    kinds: Mapping[str, str] = field(repr=False)
    path: str | None = field(default=None, repr=False)
    measurements: Mapping[str, Any] = field(default_factory=dict, repr=False)

    @property
    def kick_direction_std(self) -> float:
        """Std (rad) of the kick-direction error, Gaussian, such that a fraction
        ``kick_accuracy`` of kicks lands within ``kick_accuracy_half_angle`` of the aim."""
        z = NormalDist().inv_cdf(0.5 * (1.0 + min(self.kick_accuracy, 1.0 - 1e-9)))
        return self.kick_accuracy_half_angle / z

    @property
    def impact_fall_impulse_low(self) -> float:
        """Impulse (N*s) below which a collision never topples: mass x weakest push speed."""
        return self.mass * min(
            self.push_fall_speed_forward, self.push_fall_speed_backward, self.push_fall_speed_side
        )

    @property
    def impact_fall_impulse_high(self) -> float:
        """Impulse (N*s) above which a collision always topples: mass x strongest push speed."""
        return self.mass * max(
            self.push_fall_speed_forward, self.push_fall_speed_backward, self.push_fall_speed_side
        )


#: The locomotion profiles by name (a ``paramkit.Registry``, as the vision profiles
#: ``teamenv.config.VISION_PROFILES`` and the channel profiles ``comms.PROFILES`` are): every
#: shipped file of ``PROFILE_DIR`` under its stem. A value is a profile file's path (read and
#: validated by each ``load_profile``, as a file given by path is) or a ``Profile``.
#: ``PROFILES.register("my_robot", Path("my_robot.json"))`` adds one that ``load_profile`` and
#: the env's ``locomotion_profile=`` then take by name.
PROFILES: Registry[Path | Profile] = Registry("locomotion profile", LocomotionError)
for _file in sorted(PROFILE_DIR.glob("*.json")):
    PROFILES.register(_file.stem, _file)


def shipped_profiles() -> list[str]:
    """Names of the profiles shipped in ``locomotion/profiles/``."""
    return sorted(p.stem for p in PROFILE_DIR.glob("*.json"))


def load_profile(name_or_path: str | Path) -> Profile:
    """Load and validate a profile by name (``"t1_mj"``: a shipped one, or one added to
    ``PROFILES``) or by path to a JSON file.

    Raises:
        ProfileError: the file is missing, is not JSON, or any field is missing, unknown,
            of the wrong type or out of range (the message names field and value).
    """
    text_name = str(name_or_path)
    path = Path(name_or_path)
    if not (text_name.endswith(".json") or path.exists()):
        if text_name not in PROFILES:
            raise ProfileError(
                text_name,
                "name",
                text_name,
                f"no such shipped profile or registered name (known: "
                f"{', '.join(PROFILES.names())}) and no such file",
            )
        registered = PROFILES.get(text_name)
        if isinstance(registered, Profile):
            return registered
        path = Path(registered)
    if not path.is_file():
        raise ProfileError(text_name, "path", str(path), "file does not exist")
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ProfileError(text_name, "path", str(path), f"cannot be read: {exc}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise ProfileError(text_name, "json", str(path), f"not UTF-8 text: byte "
                           f"{raw[exc.start]:#04x} at line {line} ({exc.reason})") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ProfileError(text_name, "json", str(path), f"not valid JSON: {exc}") from None
    except (ValueError, RecursionError) as exc:  # e.g. an integer of over 4300 digits
        raise ProfileError(text_name, "json", str(path), f"not readable JSON: {exc}") from None
    return profile_from_dict(data, label=str(path), path=str(path))


def _num(label: str, key: str, x: Any) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise ProfileError(label, key, x, "must be a number")
    if not math.isfinite(x):
        raise ProfileError(label, key, x, "must be finite")
    return float(x)


def _check_range(label: str, key: str, x: float, spec: tuple[Any, ...]) -> None:
    _, unit, lo, hi, lo_open, _ = spec
    if (x <= lo if lo_open else x < lo) or x > hi:
        bracket = "(" if lo_open else "["
        raise ProfileError(label, key, x, f"out of range {bracket}{lo}, {hi}] {unit}")


def profile_from_dict(data: Any, label: str = "<dict>", path: str | None = None) -> Profile:
    """Validate a profile given as a parsed JSON object; see :func:`load_profile`."""
    if not isinstance(data, dict):
        raise ProfileError(label, "<root>", type(data).__name__, "must be a JSON object")
    unknown = set(data) - _TOP_KEYS
    if unknown:
        raise ProfileError(label, sorted(unknown)[0], data[sorted(unknown)[0]], "unknown key")
    for key in sorted(_REQUIRED_TOP - set(data)):
        raise ProfileError(label, key, None, "missing")
    if data["format"] != FORMAT:
        raise ProfileError(
            label,
            "format",
            data["format"],
            f"must be {FORMAT!r} (this code reads format version {FORMAT_VERSION})",
        )
    if (
        isinstance(data["version"], bool)
        or not isinstance(data["version"], int)
        or data["version"] < 1
    ):
        raise ProfileError(
            label,
            "version",
            data["version"],
            "must be a positive integer (the profile's data version)",
        )
    for key in ("name", "robot", "description"):
        if not isinstance(data[key], str) or not data[key]:
            raise ProfileError(label, key, data[key], "must be a non-empty string")
    label = f"{data['name']} ({label})"
    params = data["parameters"]
    if not isinstance(params, dict):
        raise ProfileError(label, "parameters", type(params).__name__, "must be a JSON object")
    unknown = set(params) - set(PARAMETERS)
    if unknown:
        k = sorted(unknown)[0]
        raise ProfileError(label, f"parameters.{k}", params[k], "unknown parameter")
    values: dict[str, Any] = {}
    sources: dict[str, str] = {}
    kinds: dict[str, str] = {}
    for key, spec in PARAMETERS.items():
        fq = f"parameters.{key}"
        if key not in params and key in OPTIONAL_PARAMETERS:
            values[key], kinds[key], sources[key] = OPTIONAL_PARAMETERS[key]
            continue
        if key not in params:
            raise ProfileError(label, fq, None, f"missing ({spec[5]}, {spec[1]})")
        entry = params[key]
        if not isinstance(entry, dict):
            raise ProfileError(
                label, fq, entry, 'must be an object {"value", "unit", "source", "kind"}'
            )
        bad = set(entry) - _PARAM_KEYS
        if bad:
            k = sorted(bad)[0]
            raise ProfileError(label, f"{fq}.{k}", entry[k], "unknown key")
        for k in ("value", "unit", "source", "kind"):
            if k not in entry:
                raise ProfileError(label, f"{fq}.{k}", None, "missing")
        if not isinstance(entry["source"], str) or not entry["source"].strip():
            raise ProfileError(
                label, f"{fq}.source", entry["source"], "every number needs a non-empty source"
            )
        if entry["kind"] not in KINDS:
            raise ProfileError(label, f"{fq}.kind", entry["kind"], f"must be one of {KINDS}")
        if entry["unit"] != spec[1]:
            raise ProfileError(label, f"{fq}.unit", entry["unit"], f"must be {spec[1]!r}")
        sources[key] = entry["source"]
        kinds[key] = entry["kind"]
        v = entry["value"]
        shape = spec[0]
        if shape == ():
            x = _num(label, fq, v)
            _check_range(label, fq, x, spec)
            values[key] = x
        elif shape == (3,):
            if not isinstance(v, list) or len(v) != 3:
                raise ProfileError(label, fq, v, "must be a list of 3 numbers")
            arr = np.array([_num(label, f"{fq}[{i}]", e) for i, e in enumerate(v)])
            for i, e in enumerate(arr):
                _check_range(label, f"{fq}[{i}]", float(e), spec)
            values[key] = arr
        else:  # table
            if not isinstance(v, list) or len(v) < 2:
                raise ProfileError(
                    label, fq, v, "must be a list of at least 2 [commanded, achieved] pairs"
                )
            pairs = []
            for i, pr in enumerate(v):
                if not isinstance(pr, list) or len(pr) != 2:
                    raise ProfileError(
                        label, f"{fq}[{i}]", pr, "must be a [commanded, achieved] pair"
                    )
                c = _num(label, f"{fq}[{i}][0]", pr[0])
                a = _num(label, f"{fq}[{i}][1]", pr[1])
                _check_range(label, f"{fq}[{i}]", c, spec)
                _check_range(label, f"{fq}[{i}]", a, spec)
                pairs.append((c, a))
            xp = np.array([p[0] for p in pairs])
            fp = np.array([p[1] for p in pairs])
            if np.any(np.diff(xp) <= 0):
                raise ProfileError(label, fq, v, "commanded values must be strictly increasing")
            if np.any(np.diff(fp) < 0):
                raise ProfileError(label, fq, v, "achieved values must be non-decreasing")
            if not (xp[0] <= 0.0 <= xp[-1]) or abs(float(np.interp(0.0, xp, fp))) > 1e-9:
                raise ProfileError(label, fq, v, "must span commanded 0 and map 0 to 0")
            values[key] = (xp, fp)
    # cross-field checks
    for axis, key in ((0, "envelope_vx_forward"), (1, "envelope_vy"), (2, "envelope_turn")):
        tk = ("tracking_vx", "tracking_vy", "tracking_turn")[axis]
        top = float(values[tk][1][-1])
        if top > values[key] * (1 + 1e-9):
            raise ProfileError(
                label,
                f"parameters.{tk}",
                top,
                f"achieves more than parameters.{key} = {values[key]}",
            )
    if -float(values["tracking_vx"][1][0]) > values["envelope_vx_backward"] * (1 + 1e-9):
        raise ProfileError(
            label,
            "parameters.tracking_vx",
            float(values["tracking_vx"][1][0]),
            f"backward speed beyond parameters.envelope_vx_backward = {values['envelope_vx_backward']}",
        )
    if values["kick_prep_time"] > values["kick_duration"]:
        raise ProfileError(
            label,
            "parameters.kick_prep_time",
            values["kick_prep_time"],
            f"longer than parameters.kick_duration = {values['kick_duration']}",
        )
    if (
        not values["kick_distance_min"]
        <= values["kick_distance_mean"]
        <= values["kick_distance_max"]
    ):
        raise ProfileError(
            label,
            "parameters.kick_distance_mean",
            values["kick_distance_mean"],
            "must lie between kick_distance_min and kick_distance_max",
        )
    if np.any(values["command_low"] >= values["command_high"]):
        raise ProfileError(
            label,
            "parameters.command_low",
            values["command_low"].tolist(),
            "must be below command_high on every axis",
        )
    measurements = data.get("measurements", {})
    if not isinstance(measurements, dict):
        raise ProfileError(label, "measurements", measurements, "must be a JSON object")
    for arr_key in ("command_low", "command_high", "odometry_scale", "odometry_noise"):
        values[arr_key].setflags(write=False)
    accel = np.array([values.pop("accel_vx"), values.pop("accel_vy"), values.pop("accel_turn")])
    accel.setflags(write=False)
    tracking = (values.pop("tracking_vx"), values.pop("tracking_vy"), values.pop("tracking_turn"))
    return Profile(
        name=data["name"],
        version=data["version"],
        robot=data["robot"],
        description=data["description"],
        tracking=tracking,
        accel=accel,
        sources=sources,
        kinds=kinds,
        path=path,
        measurements=measurements,
        **values,
    )
