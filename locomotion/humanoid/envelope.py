"""Measure the walking envelope of the T1 under the LIPM walker (commanded -> achieved velocity)
and write it as a profile (kind ``measured-humanoid``)."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .t1 import T1Model, load_t1
from .walker import WalkParams, walk_brax, walk_mujoco

__all__ = [
    "achieved_velocity",
    "measure_command",
    "measure_envelope",
    "envelope_to_profile",
    "DEFAULT_COMMANDS",
]

# the sweep of benchmarks/locomotion_envelope_t1.py: (vx m/s, vy m/s, w rad/s), body frame
DEFAULT_COMMANDS: tuple[tuple[float, float, float], ...] = (
    *((v, 0.0, 0.0) for v in (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8)),
    *((-v, 0.0, 0.0) for v in (0.1, 0.2, 0.3, 0.4)),
    *((0.0, v, 0.0) for v in (0.05, 0.1, 0.15, 0.2, 0.25)),
    *((0.0, -v, 0.0) for v in (0.1, 0.2)),
    *((0.0, 0.0, w) for w in (0.25, 0.5, 0.75, 1.0, 1.5)),
    *((0.0, 0.0, -w) for w in (0.5, 1.0)),
    (0.3, 0.0, 0.3),
    (0.5, 0.0, 0.5),
)


def achieved_velocity(times: np.ndarray, poses: np.ndarray, start: float) -> np.ndarray:
    """Mean body-frame velocity (vx m/s, vy m/s, w rad/s) from ``start`` (s) to the end:
    each world displacement between samples is rotated into the body frame of its start."""
    k = int(np.searchsorted(times, start))
    if len(times) - k < 2:
        return np.full(3, np.nan)
    yaw = np.unwrap(poses[k:, 2])
    d = np.diff(poses[k:, :2], axis=0)
    c, s = np.cos(yaw[:-1]), np.sin(yaw[:-1])
    span = float(times[-1] - times[k])
    return np.array(
        [
            float(np.sum(c * d[:, 0] + s * d[:, 1])) / span,
            float(np.sum(-s * d[:, 0] + c * d[:, 1])) / span,
            float(yaw[-1] - yaw[0]) / span,
        ]
    )


def measure_command(
    t1: T1Model,
    cmd: Sequence[float],
    seconds: float = 15.0,
    params: WalkParams | None = None,
    engine: str = "mujoco",
    brax_t1: Any = None,
    skip_s: float | None = None,
) -> dict[str, Any]:
    """Walk one constant command for ``seconds``; achieved velocity over the second half
    (or after ``skip_s``), whether and when it fell."""
    params = params or WalkParams()
    fn = lambda t, pose: cmd  # noqa: E731
    if engine == "mujoco":
        times, poses, fell = walk_mujoco(t1, fn, seconds, params)
    elif engine == "brax":
        times, poses, fell = walk_brax(t1, fn, seconds, params, brax_t1=brax_t1)
    else:
        raise ValueError(f"engine must be 'mujoco' or 'brax', got {engine!r}")
    start = seconds / 2 if skip_s is None else skip_s
    v = achieved_velocity(times, poses, start) if not fell else np.full(3, np.nan)
    return {
        "command": [float(c) for c in cmd],
        "achieved": [None if not math.isfinite(x) else round(float(x), 4) for x in v],
        "fell": bool(fell),
        "time": round(float(times[-1]), 3),
        "distance": round(float(np.hypot(*(poses[-1, :2] - poses[0, :2]))), 4),
        "turned": round(float(np.unwrap(poses[:, 2])[-1] - poses[0, 2]), 4),
    }


def measure_envelope(
    commands: Sequence[Sequence[float]] = DEFAULT_COMMANDS,
    seconds: float = 15.0,
    params: WalkParams | None = None,
    t1: T1Model | None = None,
) -> dict[str, Any]:
    """Every command in native MuJoCo; raw rows plus the parameters and duration."""
    t1 = t1 or load_t1()
    params = params or WalkParams()
    rows = [measure_command(t1, c, seconds, params) for c in commands]
    return {"engine": "mujoco", "seconds": seconds, "walker": params.as_dict(), "rows": rows}


def _axis_points(rows: list[dict], axis: int) -> list[list[float]]:
    """[commanded, achieved] on one axis from the runs that command only that axis and stood."""
    pts = {0.0: 0.0}
    for r in rows:
        c = r["command"]
        if r["fell"] or any(c[k] != 0 for k in range(3) if k != axis) or c[axis] == 0:
            continue
        pts[float(c[axis])] = float(r["achieved"][axis])
    return [[c, pts[c]] for c in sorted(pts)]


def _monotone(points: list[list[float]]) -> list[list[float]]:
    """Keep the longest prefix/suffix around 0 whose achieved values rise with the command
    (the profile validator requires monotone tracking curves)."""
    zero = next(i for i, p in enumerate(points) if p[0] == 0.0)
    out = [points[zero]]
    for p in points[zero + 1 :]:
        if p[1] <= out[-1][1]:
            break
        out.append(p)
    lo = [points[zero]]
    for p in reversed(points[:zero]):
        if p[1] >= lo[-1][1]:
            break
        lo.append(p)
    return list(reversed(lo[1:])) + out


def envelope_to_profile(
    base: dict[str, Any], envelope: dict[str, Any], command: str, name: str = "t1_lipm"
) -> dict[str, Any]:
    """A new profile: ``base`` with tracking curves, envelope, acceleration and step period of
    the walker written in (kind ``measured-humanoid``); push/fall numbers etc. stay as in
    ``base``. A base parameter whose note says "overrides measurement" is kept."""
    from .measure import _versions

    prof = json.loads(json.dumps(base))
    prof["name"] = name
    prof["version"] = 1
    prof["robot"] = "Booster T1 (rcsssmj 0.2.1 MJCF) under the teamenv LIPM walker"
    prof["description"] = (
        "The league's T1 walked by locomotion.humanoid.walker (3D-LIPM/ZMP preview control, "
        "capture-point foot placement, leg IK, joint PD) in native MuJoCo. Walk numbers "
        "measured by locomotion.humanoid.envelope (kind measured-humanoid); everything else "
        f"as in {base['name']}."
    )
    params = prof["parameters"]
    rows = envelope["rows"]
    vtext = ", ".join(f"{k} {v}" for k, v in _versions().items())
    src = (
        f"locomotion.humanoid.envelope: T1 walked by the LIPM walker in native MuJoCo, "
        f"{envelope['seconds']} s runs, achieved = mean body-frame velocity over the second "
        f"half ({vtext}); command: {command}"
    )
    written: list[str] = []

    def put(key: str, value: Any, unit: str, what: str) -> None:
        old = params.get(key, {})
        if "overrides measurement" in str(old.get("note", "")):
            return
        params[key] = {
            "value": value,
            "unit": unit,
            "kind": "measured-humanoid",
            "source": f"{src}; {what}"[:600],
            "note": f"replaces {old.get('value')!r} ({old.get('kind')}) of {base['name']}"[:300],
        }
        written.append(key)

    curves = []
    for axis, key, unit in (
        (0, "tracking_vx", "m/s"),
        (1, "tracking_vy", "m/s"),
        (2, "tracking_turn", "rad/s"),
    ):
        pts = _monotone(_axis_points(rows, axis))
        pts = [[round(c, 4), round(a, 4)] for c, a in pts]
        if axis == 2 and not any(c < 0 for c, _ in pts):  # mirror turning if only one side ran
            pts = [[-c, -a] for c, a in reversed(pts) if c > 0] + pts
        if axis == 1 and not any(c < 0 for c, _ in pts):
            pts = [[-c, -a] for c, a in reversed(pts) if c > 0] + pts
        curves.append(pts)
        fell = sorted(
            r["command"][axis]
            for r in rows
            if r["fell"] and all(r["command"][k] == 0 for k in range(3) if k != axis)
        )
        put(key, pts, unit, f"commanded -> achieved; fell at {fell}")
    vx, vy, vt = curves
    put("envelope_vx_forward", max(a for _, a in vx), "m/s", "fastest forward speed without a fall")
    put(
        "envelope_vx_backward",
        max(-min(a for _, a in vx), 1e-3),
        "m/s",
        "fastest backward speed without a fall",
    )
    put(
        "envelope_vy",
        max(max(abs(a) for _, a in vy), 1e-3),
        "m/s",
        "fastest side speed without a fall",
    )
    put(
        "envelope_turn",
        max(max(abs(a) for _, a in vt), 1e-3),
        "rad/s",
        "fastest turn without a fall",
    )
    w = envelope["walker"]
    put("step_period", w["step_period"], "s", "the walker's step period (WalkParams.step_period)")
    put("accel_vx", w["accel_x"], "m/s^2", "the walker's command slew limit (WalkParams.accel_x)")
    put("accel_vy", w["accel_y"], "m/s^2", "the walker's command slew limit (WalkParams.accel_y)")
    put(
        "accel_turn",
        w["accel_turn"],
        "rad/s^2",
        "the walker's command slew limit (WalkParams.accel_turn)",
    )
    lo, hi = list(params["command_low"]["value"]), list(params["command_high"]["value"])
    params["command_low"]["value"] = [min(lo[k], min(c for c, _ in curves[k])) for k in range(3)]
    params["command_high"]["value"] = [max(hi[k], max(c for c, _ in curves[k])) for k in range(3)]
    for key in ("command_low", "command_high"):
        params[key]["source"] = (
            f"as {base['name']} (the command space; commands beyond the tracking curve "
            "saturate in the 2D model, while the walker itself fell there: see "
            "measurements.walk_envelope_mujoco)"
        )
    meas = dict(prof.get("measurements", {}))
    meas["walk_envelope_mujoco"] = {
        "written": written,
        "command": command,
        "versions": _versions(),
        **envelope,
    }
    prof["measurements"] = meas
    return prof
