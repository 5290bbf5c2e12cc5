"""The teamenv formation file format (JSON): read, write and validate.

A formation file is one JSON object (unknown keys are an error)::

    {
      "format": "teamenv.formation",        # required, exactly this string
      "version": 1,                         # required, 1
      "name": "11v11-defend",               # optional label (default: the file's stem)
      "description": "free text",           # optional
      "field": "simspark",                  # the pitch the coordinates are measured on: a preset
                                            #   name or {"length": 30.0, "width": 20.0} (metres)
      "outside": "nearest",                 # optional: "nearest" (default) or "project"
      "roles": [                            # one per player; index i = uniform number i + 1
        {"name": "Goalie", "type": "G"},    #   type: G, DF, MF or FW; the goalie is role 0
        {"name": "CenterBack", "type": "DF"}, ...
      ],
      "samples": [                          # 1 sample (static) or >= 3 not all on one line
        {"ball": [0.0, 0.0],                # metres, team frame (our goal at x = -length/2)
         "players": [[-14.0, 0.0], [-9.0, -2.0], ...]},   # one [x, y] per role, metres
        ...
      ]
    }

Coordinates are in the team frame: our goal at x = -length/2, we attack +x, y to the left.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from strategy.positioning.formation.model import Formation, FormationError, Role
from teamenv.errors import value_repr
from teamenv.field import FIELD_PRESETS, FieldSpec
from teamenv.input_files import read_text

FORMAT_NAME = "teamenv.formation"
FORMAT_VERSION = 1
_TOP_KEYS = {"format", "version", "name", "description", "field", "outside", "roles", "samples"}
_REQUIRED = ("format", "version", "field", "roles", "samples")


def formation_from_dict(
    data: Mapping[str, Any],
    *,
    source: str = "<dict>",
    field: str | FieldSpec | tuple[float, float] | None = None,
    team_size: int | None = None,
) -> Formation:
    """Build a ``Formation`` from a parsed formation file (see the module docstring).

    Args:
        data: the JSON object.
        source: where it came from, for error messages (a path).
        field: if given, scale the formation from its own pitch to this one.
        team_size: if given, the number of roles it must have.

    Raises:
        FormationError: naming the source, the field (JSON path) and the value.
    """
    src = f"formation file {source}"
    if not isinstance(data, Mapping):
        raise FormationError(f"{src}: the top level must be a JSON object, got {type(data).__name__}")
    unknown = sorted(set(data) - _TOP_KEYS)
    if unknown:
        raise FormationError(f"{src}: unknown key(s) {unknown}; allowed: {sorted(_TOP_KEYS)}")
    for key in _REQUIRED:
        if key not in data:
            raise FormationError(f"{src}: missing required key {key!r}")
    if data["format"] != FORMAT_NAME:
        raise FormationError(f"{src}: format must be {FORMAT_NAME!r}, got {value_repr(data['format'])}")
    if data["version"] != FORMAT_VERSION:
        raise FormationError(f"{src}: version must be {FORMAT_VERSION}, got {value_repr(data['version'])}")
    name = data.get("name", Path(source).stem if source != "<dict>" else "formation")
    if not isinstance(name, str):
        raise FormationError(f"{src}: name must be a string, got {value_repr(name)}")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise FormationError(f"{src}: description must be a string, got {value_repr(description)}")
    own_field = _parse_field(data["field"], src)
    roles = _parse_roles(data["roles"], src)
    if team_size is not None and len(roles) != team_size:
        raise FormationError(
            f"{src}: roles: the formation has {len(roles)} players, expected team_size={team_size}"
        )
    ball, players = _parse_samples(data["samples"], len(roles), src)
    outside = data.get("outside", "nearest")
    try:
        formation = Formation(roles, ball, players, field=own_field, name=name,
                              description=description, outside=outside)
    except FormationError as exc:
        raise FormationError(f"{src}: {exc}") from None
    if field is not None:
        formation = formation.scaled_to(field)
    return formation


def read_formation(
    path: str | Path,
    *,
    field: str | FieldSpec | tuple[float, float] | None = None,
    team_size: int | None = None,
) -> Formation:
    """Read a formation file (JSON, this module's format); optionally scale it to ``field``."""
    p = Path(path)
    text = read_text(p, f"formation file {p}", FormationError)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise FormationError(
            f"formation file {p}: not valid JSON (line {exc.lineno}, column {exc.colno}): "
            f"{exc.msg}"
        ) from None
    except (ValueError, RecursionError) as exc:  # e.g. an integer of over 4300 digits
        raise FormationError(f"formation file {p}: not readable JSON: {exc}") from None
    return formation_from_dict(data, source=str(p), field=field, team_size=team_size)


def formation_to_dict(formation: Formation, *, description: str | None = None) -> dict[str, Any]:
    """The formation as a JSON-ready dict in this module's format (coordinates in metres)."""
    length, width = formation.field_size
    field_value: Any = {"length": length, "width": width}
    for preset in FIELD_PRESETS.values():
        if (preset.length, preset.width) == (length, width):
            field_value = preset.name
            break
    desc = description if description is not None else formation.description
    out: dict[str, Any] = {"format": FORMAT_NAME, "version": FORMAT_VERSION,
                           "name": formation.name}
    if desc:
        out["description"] = desc
    out["field"] = field_value
    if formation.outside != "nearest":
        out["outside"] = formation.outside
    out["roles"] = [{"name": r.name, "type": r.type} for r in formation.roles]
    out["samples"] = [
        {"ball": [_r(v) for v in b], "players": [[_r(x), _r(y)] for x, y in p]}
        for b, p in zip(formation.ball_samples, formation.sample_positions, strict=True)
    ]
    return out


def write_formation(formation: Formation, path: str | Path, *, description: str | None = None) -> None:
    """Write the formation to ``path`` as a formation file (one sample per line)."""
    d = formation_to_dict(formation, description=description)
    roles = d.pop("roles")
    samples = d.pop("samples")
    head = json.dumps(d, indent=2)[:-2]  # drop the closing "\n}"

    def block(key: str, items: list[Any]) -> str:
        rows = ",\n    ".join(json.dumps(x, separators=(", ", ": ")) for x in items)
        return f'  "{key}": [\n    {rows}\n  ]'

    body = head + ",\n" + block("roles", roles) + ",\n" + block("samples", samples) + "\n}\n"
    Path(path).write_text(body, encoding="utf-8")


def _r(v: float) -> float:
    """Round to a millimetre for files (keeps them readable and diff-friendly)."""
    return round(float(v), 3) + 0.0


def _parse_field(value: Any, src: str) -> str | tuple[float, float]:
    if isinstance(value, str):
        if value not in FIELD_PRESETS:
            raise FormationError(
                f"{src}: field: unknown preset {value_repr(value)}; choose one of {sorted(FIELD_PRESETS)} "
                f"or give {{'length': ..., 'width': ...}} in metres"
            )
        return value
    if isinstance(value, Mapping):
        extra = sorted(set(value) - {"length", "width"})
        if extra or "length" not in value or "width" not in value:
            raise FormationError(
                f"{src}: field must be a preset name or {{'length': L, 'width': W}}, got {value_repr(value)}"
            )
        length, width = value["length"], value["width"]
        for key, v in (("length", length), ("width", width)):
            if not _is_number(v) or not v > 0:
                raise FormationError(f"{src}: field.{key} must be a positive number, got {value_repr(v)}")
        return (float(length), float(width))
    raise FormationError(f"{src}: field must be a preset name or an object, got {value_repr(value)}")


def _parse_roles(value: Any, src: str) -> list[Role]:
    if not isinstance(value, list) or not value:
        raise FormationError(f"{src}: roles must be a non-empty list, got {value_repr(value)}")
    roles = []
    for i, r in enumerate(value):
        if not isinstance(r, Mapping):
            raise FormationError(f"{src}: roles[{i}] must be an object, got {value_repr(r)}")
        extra = sorted(set(r) - {"name", "type"})
        if extra:
            raise FormationError(f"{src}: roles[{i}]: unknown key(s) {extra}; allowed: name, type")
        for key in ("name", "type"):
            if key not in r:
                raise FormationError(f"{src}: roles[{i}]: missing key {key!r}")
        roles.append(Role(name=r["name"], type=r["type"]))
    return roles


def _parse_samples(value: Any, n: int, src: str) -> tuple[list[list[float]], list[list[list[float]]]]:
    if not isinstance(value, list) or not value:
        raise FormationError(f"{src}: samples must be a non-empty list, got {value_repr(value)}")
    balls, players = [], []
    for i, s in enumerate(value):
        if not isinstance(s, Mapping):
            raise FormationError(f"{src}: samples[{i}] must be an object, got {value_repr(s)}")
        extra = sorted(set(s) - {"ball", "players"})
        if extra:
            raise FormationError(
                f"{src}: samples[{i}]: unknown key(s) {extra}; allowed: ball, players"
            )
        if "ball" not in s or "players" not in s:
            raise FormationError(f"{src}: samples[{i}]: needs both 'ball' and 'players'")
        balls.append(_point(s["ball"], f"samples[{i}].ball", src))
        ps = s["players"]
        if not isinstance(ps, list):
            raise FormationError(f"{src}: samples[{i}].players must be a list, got {value_repr(ps)}")
        if len(ps) != n:
            raise FormationError(
                f"{src}: samples[{i}].players has {len(ps)} positions, expected {n} (one per role)"
            )
        players.append([_point(p, f"samples[{i}].players[{j}]", src) for j, p in enumerate(ps)])
    return balls, players


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _point(value: Any, where: str, src: str) -> list[float]:
    if (not isinstance(value, (list, tuple)) or len(value) != 2
            or not all(_is_number(v) for v in value)):
        raise FormationError(f"{src}: {where} must be [x, y] (finite metres), got {value_repr(value)}")
    return [float(value[0]), float(value[1])]
