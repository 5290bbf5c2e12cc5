"""A replay in the compact form the page reads: a JSON header and two binary blobs.

Each blob is per-cycle arrays back to back, little-endian, each starting on an 8-byte
boundary; the header lists each array's ``name``, ``group``, ``dtype`` (a JavaScript
typed-array name), ``shape`` and byte ``offset`` in its group's blob. Group ``core`` (positions,
ball, play mode, score, time: ~8.6 MB for a full 11 v 11 match of 30,000 cycles) is all the
page needs to play; group ``overlays`` (falls, messages, beliefs, roles: ~4 MB without extras,
~18 MB with them) follows while it plays. Positions stay float32 (as recorded), so what the
page draws is exactly what the replay holds. Everything else (field geometry, teams, score,
kicks, goals, the view cone) is in the header.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from teamenv.field import field_preset
from teamenv.replay import Replay
from teamenv.sim.playmode import PlayMode

#: numpy dtype -> the JavaScript typed array the page views it with.
_JS_TYPES = {np.dtype(np.float32): "Float32Array", np.dtype(np.int8): "Int8Array",
             np.dtype(np.uint8): "Uint8Array", np.dtype(np.int16): "Int16Array",
             np.dtype(np.uint16): "Uint16Array", np.dtype(np.int32): "Int32Array",
             np.dtype(np.uint32): "Uint32Array"}

#: Per-cycle arrays sent when the replay has them: (group, the dtype they travel as). float16
#: and float64 become float32: JavaScript has no float16 view everywhere, and float32 is enough.
_CYCLE_ARRAYS = {
    "players": ("core", np.float32), "ball": ("core", np.float32),
    "play_mode": ("core", np.int8), "score": ("core", np.int16), "time_s": ("core", np.float32),
    "attack_sign": ("overlays", np.int8), "fallen": ("overlays", np.uint8),
    "say_bytes": ("overlays", np.uint8), "heard_from": ("overlays", np.uint32),
    "belief_pose": ("overlays", np.float32), "belief_ball": ("overlays", np.float32),
    "role": ("overlays", np.int8),
}
GROUPS = ("core", "overlays")
#: Per-event arrays (kicks, goals) sent in the header as lists.
_EVENT_ARRAYS = ("kick_cycle", "kick_player", "goal_cycle", "goal_team", "goal_player")


def replay_arrays(replay: Replay) -> dict[str, tuple[str, np.ndarray]]:
    """The per-cycle arrays of ``replay`` that the page uses: name -> (group, array in its
    travel dtype)."""
    out = {}
    for name, (group, dtype) in _CYCLE_ARRAYS.items():
        value = getattr(replay, name, None)
        if value is not None:
            out[name] = (group, np.ascontiguousarray(value, dtype=dtype))
    return out


def encode_replay(replay: Replay, match_id: int) -> tuple[dict[str, Any], dict[str, bytes]]:
    """(header, {group: blob}) of ``replay``: see the module docstring."""
    layout = []
    chunks: dict[str, list[bytes]] = {group: [] for group in GROUPS}
    sizes = dict.fromkeys(GROUPS, 0)
    for name, (group, array) in replay_arrays(replay).items():
        data = array.astype(array.dtype.newbyteorder("<"), copy=False).tobytes()
        layout.append({"name": name, "group": group, "dtype": _JS_TYPES[array.dtype],
                       "shape": list(array.shape), "offset": sizes[group]})
        pad = -len(data) % 8
        chunks[group].append(data + b"\0" * pad)
        sizes[group] += len(data) + pad
    header = replay_header(replay, match_id)
    header["arrays"] = layout
    header["bytes"] = sizes
    return header, {group: b"".join(parts) for group, parts in chunks.items()}


def replay_header(replay: Replay, match_id: int) -> dict[str, Any]:
    """What the page needs besides the arrays: field, teams, result, overlays available."""
    meta = replay.metadata
    field = field_preset(meta["field"])
    options = meta.get("options") or {}
    events = {name: np.asarray(getattr(replay, name)).tolist() for name in _EVENT_ARRAYS
              if getattr(replay, name, None) is not None}
    return {
        "id": match_id,
        "cycles": len(replay),
        "cycle_s": float(meta.get("cycle_s", 0.02)),
        "team_size": replay.team_size,
        "left": meta.get("left"), "right": meta.get("right"), "seed": meta.get("seed"),
        "options": options,
        "result": meta.get("result"),
        "field": {"name": field.name, "length": field.length, "width": field.width,
                  "goal_width": field.goal_width, "goal_depth": field.goal_depth,
                  "penalty_length": field.penalty_length, "penalty_width": field.penalty_width,
                  "center_circle_radius": field.center_circle_radius},
        "play_modes": [mode.name for mode in sorted(PlayMode)],
        "view_cone": view_cone(options),
        "events": events,
    }


def view_cone(options: dict[str, Any]) -> dict[str, Any] | None:
    """The agents' field of view in a vision-mode match (half angle in radians), else None."""
    if options.get("observation_mode") != "vision":
        return None
    from teamenv.config import VISION_PROFILES

    profile = options.get("vision") or "simspark"
    if profile not in VISION_PROFILES:
        return None
    fov_deg = VISION_PROFILES[profile].fov_horizontal_deg
    return {"profile": profile, "fov_deg": fov_deg, "half_angle": math.radians(fov_deg) / 2.0}
