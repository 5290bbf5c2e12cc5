"""Team specs for tournaments: ``name`` or ``module:Class`` with ``:key=value,...`` overrides.

A spec names a team plugin (a registered entry-point name such as ``chaser``, or
``package.module:ClassName``) and optional keyword overrides for its constructor::

    chaser
    chaser:all_chase=true
    formation:cfg=defensive
    my_pkg.teams:MyTeam:depth=0.4,name='left wing'
    full@opt1        (the config of the team override file opt1, e.g. from ``teamenv optimize``)
    full@opt1:pressure_m=3

Override values are parsed as bool (``true``/``false``), ``none``, int, finite float, or else
string; quote a value (``'1'``) to keep it a string. Commas cannot appear inside values.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from teamenv.errors import ConfigError, TeamLoadError
from teamenv.tournament.errors import TeamSpecError, TournamentConfigError
from teamenv.tournament.overrides import load_team_override

_KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_OVERRIDE_START = re.compile(r"[A-Za-z_][A-Za-z0-9_]*=")
_INT = re.compile(r"[+-]?\d+")
Scalar = bool | int | float | str | None


@dataclass(frozen=True)
class TeamSpec:
    """A team plugin name plus constructor overrides (sorted ``(key, value)`` pairs).

    ``label`` is the canonical text of the spec and the team's identity in a tournament.
    """

    name: str
    config: tuple[tuple[str, Scalar], ...] = ()

    @classmethod
    def of(cls, name: str, config: Mapping[str, Scalar] | None = None) -> TeamSpec:
        """Build a spec from a name and a mapping of overrides (values must be scalars)."""
        items = dict(config or {})
        for key, value in items.items():
            if not isinstance(key, str) or not _KEY.fullmatch(key):
                raise TeamSpecError(f"team spec {name!r}: override key {key!r} is not an identifier")
            if value is not None and not isinstance(value, (bool, int, float, str)):
                raise TeamSpecError(f"team spec {name!r}: override {key}={value!r} must be a "
                                    "bool, int, float, str or None")
        return cls(name, tuple(sorted(items.items())))

    @property
    def config_dict(self) -> dict[str, Scalar]:
        return dict(self.config)

    @property
    def label(self) -> str:
        """Canonical text, e.g. ``chaser:all_chase=true``; parse_team_spec(label) == self."""
        if not self.config:
            return self.name
        return f"{self.name}:" + ",".join(f"{k}={_format_value(v)}" for k, v in self.config)

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "config": self.config_dict}

    def __str__(self) -> str:
        return self.label


def parse_team_spec(spec: str | TeamSpec) -> TeamSpec:
    """Parse ``name[:key=value,...]`` (or ``module:Class[:key=value,...]``) into a TeamSpec.

    Raises TeamSpecError naming the spec and the offending part.
    """
    if isinstance(spec, TeamSpec):
        return spec
    if not isinstance(spec, str) or not spec.strip():
        raise TeamSpecError(f"team spec: expected 'name' or 'name:key=value,...', got {spec!r}")
    text = spec.strip()
    name, overrides = text, ""
    for pos, char in enumerate(text):
        if char == ":" and _OVERRIDE_START.match(text, pos + 1):
            name, overrides = text[:pos], text[pos + 1:]
            break
    if not name or name.endswith(":") or name.startswith(":"):
        raise TeamSpecError(f"team spec {spec!r}: missing team name before the overrides")
    if "=" in name:
        raise TeamSpecError(f"team spec {spec!r}: overrides must look like "
                            "'name:key=value,key2=value2'")
    config: dict[str, Scalar] = {}
    inline: set[str] = set()
    if "@" in name:  # name@file: the config of a team override file (overrides.py)
        name, _, file = name.partition("@")
        try:
            config.update(load_team_override(file, name))
        except ConfigError as exc:
            raise TeamSpecError(f"team spec {spec!r}: {exc}") from exc
    if overrides:
        for item in overrides.split(","):
            key, sep, raw = item.partition("=")
            key = key.strip()
            if not sep or not _KEY.fullmatch(key):
                raise TeamSpecError(f"team spec {spec!r}: override {item!r} is not 'key=value'")
            if key in inline:
                raise TeamSpecError(f"team spec {spec!r}: override key {key!r} given twice")
            config[key] = parse_value(raw.strip())
            inline.add(key)
    return TeamSpec.of(name, config)


def parse_value(raw: str) -> Scalar:
    """Parse one override value: bool, none, int, finite float, quoted or bare string."""
    low = raw.lower()
    if low in ("true", "false"):
        return low == "true"
    if low in ("none", "null"):
        return None
    if len(raw) >= 2 and raw[0] == raw[-1] and raw[0] in "'\"":
        return raw[1:-1]
    if _INT.fullmatch(raw):
        return int(raw)
    try:
        value = float(raw)
    except ValueError:
        return raw
    return value if math.isfinite(value) else raw


def _format_value(value: Scalar) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "none"
    if isinstance(value, str):
        if parse_value(value) != value or value != value.strip() or "," in value:
            return json.dumps(value) if "'" in value else f"'{value}'"
        return value
    return repr(value)


def validate_specs(specs: Iterable[TeamSpec], options: Any) -> dict[str, str]:
    """Check the match options and build every team once; return ``{label: version}``.

    Each team is constructed exactly as a match would (``SoccerParallelEnv`` with the team on
    the left side, which calls ``make_team`` with the match's TeamContext), so an unknown team,
    an unknown override key or a value the team rejects fails here, before anything runs.
    """
    from teamenv.env import SoccerParallelEnv
    from teamenv.match import MatchOptions
    from teamenv.teams import team_version

    if not isinstance(options, MatchOptions):
        raise TournamentConfigError(f"match options: expected MatchOptions, got {options!r}")
    try:
        kwargs = options.env_kwargs()
        SoccerParallelEnv(**kwargs).close()
    except (ConfigError, ValueError, TypeError) as exc:
        raise TournamentConfigError(f"match options {options}: {exc}") from exc
    versions: dict[str, str] = {}
    for spec in specs:
        try:
            env = SoccerParallelEnv(left=spec.name, left_config=spec.config_dict, **kwargs)
        except TeamLoadError as exc:
            raise TeamSpecError(f"team spec {spec.label!r}: {exc}") from exc
        except Exception as exc:  # the team's constructor rejected its config
            raise TeamSpecError(f"team spec {spec.label!r}: constructing {spec.name!r} with "
                                f"{spec.config_dict!r} failed: {type(exc).__name__}: {exc}") from exc
        env.close()
        versions[spec.label] = team_version(spec.name)
    return versions
