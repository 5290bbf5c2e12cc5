"""Team override files: a named JSON config (e.g. an optimizer's best) that specs use by name.

``full@opt1`` in a tournament (``teamenv tournament run full@opt1 chaser``) is the team
``full`` with the config of the override file ``opt1``, looked up as the path ``opt1``, then
``opt1.json``, then ``overrides/opt1.json`` (relative to the working directory). The file::

    {"format": "teamenv-team-override", "version": 1, "team": "full",
     "config": {"pressure_m": 2.7, "kick_goal_weight": 31.4}, "source": {...}}

``source`` says where the config came from (free-form, not read). The tournament's spec parser
reads these files and ``teamenv optimize`` (above the tournaments) writes them, so they live
here. Imports nothing of teamenv but its errors.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from teamenv.errors import ConfigError

OVERRIDE_FORMAT = "teamenv-team-override"
OVERRIDE_VERSION = 1
OVERRIDE_DIR = Path("overrides")  # where a bare name is also looked up, and exports go


def override_path(name: str) -> Path:
    """The file of override ``name``: ``name``, ``name.json`` or ``overrides/name.json``."""
    if not isinstance(name, str) or not name.strip():
        raise ConfigError(f"team override: expected a name or a path, got {name!r}")
    tried = [Path(name), Path(f"{name}.json"), OVERRIDE_DIR / f"{name}.json"]
    for path in tried:
        if path.is_file():
            return path
    raise ConfigError(f"team override {name!r}: no such file (tried "
                      f"{[str(p) for p in tried]} from {str(Path.cwd())!r})")


def load_team_override(name: str, team: str) -> dict[str, Any]:
    """The config of override ``name`` for team ``team`` (the file must name that team)."""
    path = override_path(name)
    try:
        data = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise ConfigError(f"team override {str(path)!r}: not readable JSON ({exc})") from exc
    if not isinstance(data, dict) or data.get("format") != OVERRIDE_FORMAT:
        raise ConfigError(f"team override {str(path)!r}: not a team override file (expected "
                          f"\"format\": \"{OVERRIDE_FORMAT}\")")
    if data.get("version") != OVERRIDE_VERSION:
        raise ConfigError(f"team override {str(path)!r}: version {data.get('version')!r}, this "
                          f"teamenv reads version {OVERRIDE_VERSION}")
    if data.get("team") != team:
        raise ConfigError(f"team override {str(path)!r}: is for team {data.get('team')!r}, "
                          f"not {team!r}")
    config = data.get("config")
    if not isinstance(config, dict):
        raise ConfigError(f"team override {str(path)!r}: \"config\" must be an object, got "
                          f"{config!r}")
    return config


def write_team_override(path: str | Path, team: str, config: Mapping[str, Any],
                        source: Mapping[str, Any] | None = None) -> Path:
    """Write an override file for ``team`` with ``config`` (JSON scalars); returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    data = {"format": OVERRIDE_FORMAT, "version": OVERRIDE_VERSION, "team": team,
            "config": dict(sorted(config.items())), "source": dict(source or {})}
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(data, indent=2) + "\n")
    tmp.replace(path)  # readers never see half a file
    return path
