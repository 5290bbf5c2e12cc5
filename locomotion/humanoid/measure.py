"""Measure profile parameters on the humanoid T1 (push/fall thresholds, fall duration) and write them."""

from __future__ import annotations

import json
import math
import platform
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..profile import PROFILE_DIR, load_profile
from .t1 import TORSO_ON_GROUND, TORSO_STANDING_MIN, T1Model, load_t1

__all__ = [
    "DIRECTIONS",
    "analyse_push_grid",
    "measure_push_grid",
    "bisect_threshold_mujoco",
    "fall_duration_from_grid",
    "base_profile",
    "measurements_to_profile",
    "write_measured_profile",
]

DIRECTIONS: dict[str, tuple[float, float]] = {
    "forward": (1.0, 0.0),
    "backward": (-1.0, 0.0),
    "side": (0.0, 1.0),
}
_PARAM_OF = {
    "forward": "push_fall_speed_forward",
    "backward": "push_fall_speed_backward",
    "side": "push_fall_speed_side",
}


def _fall_time(times: np.ndarray, h: np.ndarray) -> float | None:
    """Seconds from the push until the torso is on the ground (height < TORSO_ON_GROUND)."""
    idx = np.flatnonzero(h < TORSO_ON_GROUND)
    return float(times[idx[0]]) if idx.size else None


def measure_push_grid(
    engine: str,
    speeds: Sequence[float],
    directions: Sequence[str] = tuple(DIRECTIONS),
    sim_s: float = 2.0,
    settle_s: float = 0.5,
    t1: T1Model | None = None,
    brax_t1: Any = None,
) -> dict[str, Any]:
    """Push the standing T1 with every speed (m/s) in every direction; one batch per engine.

    Args:
        engine: ``"brax"`` (generalized pipeline, one vmapped batch) or ``"mujoco"`` (native).
        speeds: push speeds (m/s); directions: keys of :data:`DIRECTIONS`.
        sim_s: time simulated after the push (s); settle_s: standing time before it (s).

    Returns:
        raw results: engine, speeds, and per direction the minimum torso height (m) and the
        fall time (s, None if the robot did not reach the ground) of each push.
    """
    t1 = t1 or load_t1()
    speeds = [float(s) for s in speeds]
    pushes = np.array(
        [[s * DIRECTIONS[d][0], s * DIRECTIONS[d][1]] for d in directions for s in speeds]
    )
    if engine == "brax":
        from .brax_sim import BraxT1

        b = brax_t1 or BraxT1(t1)
        times, heights = b.push_rollout(pushes, sim_s=sim_s, settle_s=settle_s)
    elif engine == "mujoco":
        from .mujoco_sim import push_rollout_mujoco

        times, heights = push_rollout_mujoco(t1, pushes, sim_s=sim_s, settle_s=settle_s)
    else:
        raise ValueError(f"engine must be 'brax' or 'mujoco', got {engine!r}")
    out: dict[str, Any] = {
        "engine": engine,
        "speeds": speeds,
        "sim_s": sim_s,
        "settle_s": settle_s,
        "directions": {},
    }
    for k, d in enumerate(directions):
        hs = heights[k * len(speeds) : (k + 1) * len(speeds)]
        out["directions"][d] = {
            "min_height": [round(float(x), 4) for x in hs.min(axis=1)],
            "fall_time": [_fall_time(times, h) for h in hs],
        }
    return out


def analyse_push_grid(grid: dict[str, Any]) -> dict[str, Any]:
    """Thresholds from a push grid: midpoint of the bracket [last standing, first fallen].

    A push counts as a fall when the torso height drops below ``TORSO_STANDING_MIN``. Returns
    per direction ``threshold`` (m/s, None if no push fell or all fell), ``bracket`` and
    ``fall_time`` (s: time to the ground of the weakest push that fell).
    """
    speeds = np.array(grid["speeds"])
    res: dict[str, Any] = {}
    for d, r in grid["directions"].items():
        fell = np.array(r["min_height"]) < TORSO_STANDING_MIN
        order = np.argsort(speeds)
        s_sorted, f_sorted = speeds[order], fell[order]
        standing = s_sorted[~f_sorted]
        falling = s_sorted[f_sorted]
        lo = float(standing.max()) if standing.size else None
        hi = (
            float(falling[falling > (lo if lo is not None else -1)].min())
            if falling.size and (lo is None or (falling > lo).any())
            else None
        )
        thr = 0.5 * (lo + hi) if lo is not None and hi is not None else None
        ft = None
        if hi is not None:
            ft = r["fall_time"][int(np.flatnonzero(speeds == hi)[0])]
        res[d] = {
            "threshold": thr,
            "bracket": [lo, hi],
            "fall_time": ft,
            "monotonic": bool(np.all(np.diff(f_sorted.astype(int)) >= 0)),
        }
    return res


def fall_duration_from_grid(
    grid: dict[str, Any], analysis: dict[str, Any], factor: float = 1.5
) -> float | None:
    """Median over directions of the time to the ground (s) of the grid push nearest to
    ``factor`` x that direction's threshold (a clear fall, not a marginal one)."""
    speeds = np.array(grid["speeds"])
    times = []
    for d, r in analysis.items():
        if r["threshold"] is None:
            continue
        k = int(np.argmin(np.abs(speeds - factor * r["threshold"])))
        t = grid["directions"][d]["fall_time"][k]
        if t is not None:
            times.append(t)
    return float(np.median(times)) if times else None


def bisect_threshold_mujoco(
    direction: str,
    lo: float = 0.0,
    hi: float = 2.0,
    tol: float = 0.005,
    sim_s: float = 2.5,
    t1: T1Model | None = None,
) -> dict[str, float]:
    """Push threshold (m/s) in one direction by bisection in native MuJoCo (fast engine).

    Also returns the time to the ground (s) of a push of 1.5 x the threshold.
    """
    from .mujoco_sim import push_rollout_mujoco

    t1 = t1 or load_t1()
    dvec = np.array(DIRECTIONS[direction])

    def falls(s: float) -> bool:
        _, h = push_rollout_mujoco(t1, (s * dvec)[None], sim_s=sim_s)
        return bool(h.min() < TORSO_STANDING_MIN)

    if falls(lo) or not falls(hi):
        raise ValueError(f"no threshold in [{lo}, {hi}] m/s for direction {direction!r}")
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if falls(mid) else (mid, hi)
    thr = 0.5 * (lo + hi)
    times, h = push_rollout_mujoco(t1, (1.5 * thr * dvec)[None], sim_s=sim_s)
    return {"threshold": thr, "bracket": [lo, hi], "fall_time_1.5x": _fall_time(times, h[0])}


def _versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    from importlib import metadata

    for mod in ("mujoco", "jax", "brax", "rcsssmj", "numpy"):
        try:
            out[mod] = metadata.version(mod)
        except metadata.PackageNotFoundError:
            out[mod] = "not installed"
    return out


def measurements_to_profile(
    base: dict[str, Any],
    analysis: dict[str, Any],
    engine: str,
    command: str,
    fall_duration: float | None = None,
    raw: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """A new profile dict: ``base`` with the measured numbers written in.

    Measured push thresholds (and ``fall_duration`` if given) replace the base values with
    ``kind = "measured-humanoid"`` and a source naming the engine, versions and command. A base
    parameter whose ``note`` contains ``"overrides measurement"`` is a deliberate hand-entered
    override and is kept (the measurement is still recorded under ``measurements``).
    """
    prof = json.loads(json.dumps(base))
    params = prof["parameters"]
    versions = _versions()
    vtext = ", ".join(f"{k} {v}" for k, v in versions.items())
    written = []

    def put(name: str, value: float, unit: str, what: str) -> None:
        entry = params[name]
        if "overrides measurement" in str(entry.get("note", "")):
            return
        params[name] = {
            "value": round(float(value), 4),
            "unit": unit,
            "kind": "measured-humanoid",
            "source": f"locomotion.humanoid.measure: {what}; T1 from rcsssmj under joint PD, "
            f"engine {engine} ({vtext}); command: {command}",
            "note": f"replaces {entry['value']!r} ({entry['kind']}: {entry['source']})"[:400],
        }
        written.append(name)

    for d, r in analysis.items():
        if r["threshold"] is not None and d in _PARAM_OF:
            put(
                _PARAM_OF[d],
                r["threshold"],
                "m/s",
                f"push speed that topples the standing T1, {d}, bracket {r['bracket']} m/s",
            )
    if fall_duration is not None and math.isfinite(fall_duration):
        put(
            "fall_duration",
            fall_duration,
            "s",
            "time from the push to the torso on the ground "
            f"(torso origin below {TORSO_ON_GROUND} m)",
        )
    meas = dict(prof.get("measurements", {}))
    meas[f"humanoid_{engine}"] = {
        "analysis": analysis,
        "written": written,
        "versions": versions,
        "command": command,
        "raw": raw or {},
    }
    prof["measurements"] = meas
    return prof


def write_measured_profile(profile: dict[str, Any], path: str | Path) -> Path:
    """Write a profile dict as JSON (one parameter per line) and check it loads and validates."""
    path = Path(path)
    lines = ["{"]
    keys = [k for k in ("format", "version", "name", "robot", "description") if k in profile]
    for k in keys:
        lines.append(f"  {json.dumps(k)}: {json.dumps(profile[k])},")
    lines.append('  "parameters": {')
    items = list(profile["parameters"].items())
    for i, (k, v) in enumerate(items):
        lines.append(f"    {json.dumps(k)}: {json.dumps(v)}" + ("," if i < len(items) - 1 else ""))
    lines.append("  }" + ("," if "measurements" in profile else ""))
    if "measurements" in profile:
        lines.append(
            '  "measurements": '
            + json.dumps(profile["measurements"], indent=2).replace("\n", "\n  ")
        )
    lines.append("}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    load_profile(path)  # validates; raises ProfileError naming the field otherwise
    return path


def base_profile(name: str = "t1_mj") -> dict[str, Any]:
    """The shipped profile ``name`` as a plain dict (to be updated with measurements)."""
    return json.loads((PROFILE_DIR / f"{name}.json").read_text(encoding="utf-8"))
