"""Search spaces: the bounds, scale and choices of a team config's fields, declared beside them.

A team declares what an optimizer may vary in its config dataclass's field metadata::

    from teamenv.search_space import Choice, Range, search

    @dataclass(frozen=True)
    class MyTeamConfig:
        pressure_m: float = field(default=2.0, metadata=search(Range(0.5, 5.0)))
        kick_goal_weight: float = field(default=25.0, metadata=search(Range(2, 200, "log")))
        max_markers: int = field(default=2, metadata=search(Range(0, 4, integer=True)))
        formation_attack: str = field(default="attack", metadata=search(Choice(("attack", "defend"))))

The optimizer works in the unit cube: each parameter maps to one coordinate in [0, 1] (linear
or logarithmic in the value; a choice of n options splits [0, 1] into n equal bins), so one
CMA-ES step size fits every parameter. Decoded floats are rounded to ``digits`` significant
digits so a candidate's config (and its tournament label) stays short and exact.

Part of the plugin API in teamenv's core (like ``teamenv.team_config``): a team's config
module imports it, and ``teamenv optimize`` reads what it declared. It imports numpy and
teamenv's errors only.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, fields, is_dataclass
from typing import Any

import numpy as np

from paramkit.checks import check_fields, in_range, invalid, one_of
from teamenv.errors import ConfigError

SEARCH_KEY = "search"  # the dataclass field-metadata key of a declared domain
SCALES = ("linear", "log")
Scalar = bool | int | float | str


class SearchSpaceError(ConfigError):
    """A search space is malformed: bad bounds, unknown or undeclared field, bad choice."""


@dataclass(frozen=True)
class Range:
    """A numeric domain ``[low, high]``; ``scale="log"`` searches the logarithm (low > 0);
    ``integer`` rounds decoded values to ints; floats keep ``digits`` significant digits."""

    low: float
    high: float
    scale: str = field(default="linear", metadata=one_of(*SCALES))
    integer: bool = False
    digits: int = field(default=4, metadata=in_range(1, 15))

    def __post_init__(self) -> None:
        check_fields(self, SearchSpaceError)
        if not self.low < self.high:
            raise invalid(self, "low", f"< high ({self.high!r})", SearchSpaceError)
        if self.scale == "log" and self.low <= 0:
            raise invalid(self, "low", "> 0 on a log scale", SearchSpaceError)
        if self.integer and math.floor(self.high) < math.ceil(self.low):
            raise invalid(self, "integer", f"False: there is no integer in [{self.low!r}, "
                          f"{self.high!r}]", SearchSpaceError)

    def to_json(self) -> dict[str, Any]:
        return {"kind": "range", "low": self.low, "high": self.high, "scale": self.scale,
                "integer": self.integer, "digits": self.digits}

    def describe(self) -> str:
        return f"[{self.low:g}, {self.high:g}]" + (" log" if self.scale == "log" else "") + \
            (" int" if self.integer else "")


@dataclass(frozen=True)
class Choice:
    """A categorical domain: one of ``options`` (distinct bools, ints, floats or strings)."""

    options: tuple[Scalar, ...]

    def __post_init__(self) -> None:
        if isinstance(self.options, (str, bytes)) or not isinstance(self.options, Iterable):
            raise SearchSpaceError(f"Choice: options must be a sequence, got {self.options!r}")
        options = tuple(self.options)
        object.__setattr__(self, "options", options)
        if len(options) < 2:
            raise SearchSpaceError(f"Choice: needs at least two options, got {list(options)}")
        for option in options:
            if not isinstance(option, (bool, int, float, str)):
                raise SearchSpaceError(f"Choice: option {option!r} is not a bool, int, float "
                                       "or string")
        keys = [(type(o), o) for o in options]
        if len(set(keys)) != len(keys):
            raise SearchSpaceError(f"Choice: options must be distinct, got {list(options)}")

    def to_json(self) -> dict[str, Any]:
        return {"kind": "choice", "options": list(self.options)}

    def describe(self) -> str:
        return "{" + ", ".join(map(str, self.options)) + "}"

    def index(self, value: Any) -> int | None:
        for k, option in enumerate(self.options):
            if type(option) is type(value) and option == value:
                return k
        return None


Domain = Range | Choice


def search(domain: Domain) -> dict[str, Domain]:
    """Field metadata declaring ``domain``: ``field(default=..., metadata=search(Range(...)))``."""
    if not isinstance(domain, (Range, Choice)):
        raise SearchSpaceError(f"search(): expected a Range or a Choice, got {domain!r}")
    return {SEARCH_KEY: domain}


def domain_from_json(data: Mapping[str, Any]) -> Domain:
    """Rebuild a domain written by ``to_json``."""
    if data.get("kind") == "range":
        return Range(data["low"], data["high"], data["scale"], data["integer"], data["digits"])
    if data.get("kind") == "choice":
        return Choice(tuple(data["options"]))
    raise SearchSpaceError(f"search space: unknown domain {dict(data)!r}")


@dataclass(frozen=True)
class Parameter:
    """One searched config field: its name, domain and default (the search's start)."""

    name: str
    domain: Domain
    default: Any

    def encode(self, value: Any) -> float:
        """The unit coordinate of ``value`` (a Range clips values outside it to its ends)."""
        d = self.domain
        if isinstance(d, Choice):
            k = d.index(value)
            if k is None:
                raise SearchSpaceError(f"search space: {self.name}={value!r} is not one of "
                                       f"its options {list(d.options)}")
            return (k + 0.5) / len(d.options)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or \
                not math.isfinite(value):
            raise SearchSpaceError(f"search space: {self.name}={value!r} is not a finite number")
        v = min(max(float(value), d.low), d.high)
        if d.scale == "log":
            return (math.log(v) - math.log(d.low)) / (math.log(d.high) - math.log(d.low))
        return (v - d.low) / (d.high - d.low)

    def decode(self, u: float) -> Scalar:
        """The value at unit coordinate ``u`` (clipped to [0, 1])."""
        u = min(max(float(u), 0.0), 1.0)
        d = self.domain
        if isinstance(d, Choice):
            return d.options[min(int(u * len(d.options)), len(d.options) - 1)]
        if d.scale == "log":
            value = math.exp(math.log(d.low) + u * (math.log(d.high) - math.log(d.low)))
        else:
            value = d.low + u * (d.high - d.low)
        if d.integer:
            return int(min(max(round(value), math.ceil(d.low)), math.floor(d.high)))
        return min(max(float(f"{value:.{d.digits}g}"), d.low), d.high)


@dataclass(frozen=True)
class SearchSpace:
    """The searched parameters, in order; a candidate is a vector in [0, 1]^dimension."""

    parameters: tuple[Parameter, ...]

    def __post_init__(self) -> None:
        if not self.parameters:
            raise SearchSpaceError("search space: no parameters to search")
        names = [p.name for p in self.parameters]
        dupes = sorted({n for n in names if names.count(n) > 1})
        if dupes:
            raise SearchSpaceError(f"search space: parameters {dupes} given more than once")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    @property
    def dimension(self) -> int:
        return len(self.parameters)

    def encode(self, config: Mapping[str, Any]) -> np.ndarray:
        """The unit vector of ``config`` (every searched name must be in it)."""
        missing = [p.name for p in self.parameters if p.name not in config]
        if missing:
            raise SearchSpaceError(f"search space: config has no value for {missing}")
        return np.array([p.encode(config[p.name]) for p in self.parameters])

    def decode(self, x: Sequence[float] | np.ndarray) -> dict[str, Scalar]:
        """The config overrides of unit vector ``x``."""
        x = np.asarray(x, dtype=np.float64)
        if x.shape != (self.dimension,):
            raise SearchSpaceError(f"search space: expected a vector of {self.dimension} "
                                   f"coordinates, got shape {x.shape}")
        return {p.name: p.decode(u) for p, u in zip(self.parameters, x, strict=True)}

    def start(self) -> np.ndarray:
        """The unit vector of the defaults: where the search starts."""
        return np.array([p.encode(p.default) for p in self.parameters])

    def to_json(self) -> list[dict[str, Any]]:
        return [{"name": p.name, "default": p.default, "domain": p.domain.to_json()}
                for p in self.parameters]

    @classmethod
    def from_json(cls, data: Sequence[Mapping[str, Any]]) -> SearchSpace:
        return cls(tuple(Parameter(d["name"], domain_from_json(d["domain"]), d["default"])
                         for d in data))

    def describe(self) -> str:
        return "\n".join(f"  {p.name:28s} {p.domain.describe():32s} default {p.default!r}"
                         for p in self.parameters)


def declared_domains(config: Any) -> dict[str, Domain]:
    """``{field name: domain}`` of a config dataclass (class or instance) whose fields declare
    one with ``search(...)``; raises when a declaration is not a Range or Choice."""
    if not is_dataclass(config):
        raise SearchSpaceError(f"search space: {config!r} is not a dataclass config")
    out: dict[str, Domain] = {}
    for f in fields(config):
        if SEARCH_KEY in f.metadata:
            domain = f.metadata[SEARCH_KEY]
            if not isinstance(domain, (Range, Choice)):
                raise SearchSpaceError(f"search space: field {f.name!r} declares {domain!r}, "
                                       "not a Range or a Choice")
            out[f.name] = domain
    return out


def build_search_space(config: Any, *, only: Sequence[str] | None = None,
                       bounds: Mapping[str, Domain] | None = None,
                       section: str = "config") -> SearchSpace:
    """The search space of a config dataclass *instance* (its values are the start).

    ``only``: search these fields (default: every declared one); ``bounds``: domains that
    replace (or add to) the declared ones. An unknown field, a field with neither a
    declaration nor a bound, or a domain that does not fit the field's value is an error
    naming the field.
    """
    declared = declared_domains(config)
    known = [f.name for f in fields(config)]
    integer_fields = {f.name for f in fields(config) if f.type in (int, "int")}
    bounds = dict(bounds or {})
    for name in list(bounds) + list(only or ()):
        if name not in known:
            raise SearchSpaceError(f"{section}: unknown field {name!r}; searchable fields are "
                                   f"{sorted(declared)} (others: {sorted(set(known) - set(declared))})")
    if only is not None and len(set(only)) != len(only):
        raise SearchSpaceError(f"{section}: a parameter is named twice in {list(only)}")
    names = list(only) if only is not None else \
        [n for n in known if n in declared or n in bounds]
    parameters = []
    for name in names:
        domain = bounds.get(name, declared.get(name))
        if domain is None:
            raise SearchSpaceError(f"{section}: field {name!r} declares no search range; give "
                                   f"one (--bounds {name}=LOW:HIGH) or pick from {sorted(declared)}")
        default = getattr(config, name)
        _check_fits(section, name, domain, default, name in integer_fields)
        parameters.append(Parameter(name, domain, default))
    return SearchSpace(tuple(parameters))


def _check_fits(section: str, name: str, domain: Domain, default: Any, integer: bool) -> None:
    if isinstance(domain, Choice):
        if domain.index(default) is None:
            raise SearchSpaceError(f"{section}: {name}'s value {default!r} is not one of its "
                                   f"options {list(domain.options)}")
        return
    if isinstance(default, bool) or not isinstance(default, (int, float)):
        raise SearchSpaceError(f"{section}: {name} is {default!r}, not a number: give it a "
                               "Choice, not a Range")
    if integer and not domain.integer:
        raise SearchSpaceError(f"{section}: {name} is an integer field; its Range needs "
                               "integer=True (':int' on the command line)")


def parse_bounds(text: str) -> tuple[str, Domain]:
    """Parse a command-line domain: ``name=LOW:HIGH[:log][:int]`` or ``name=a|b|c``
    (choice values are parsed as bool, int, float or string)."""
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not sep or not name or not spec:
        raise SearchSpaceError(f"--bounds {text!r}: expected NAME=LOW:HIGH[:log][:int] or "
                               "NAME=a|b|c")
    if "|" in spec:
        return name, Choice(tuple(_choice_value(v.strip()) for v in spec.split("|")))
    parts = [p.strip() for p in spec.split(":")]
    flags = parts[2:]
    unknown = [f for f in flags if f not in ("log", "linear", "int")]
    if len(parts) < 2 or unknown:
        raise SearchSpaceError(f"--bounds {text!r}: expected NAME=LOW:HIGH[:log][:int]"
                               + (f" (unknown flag(s) {unknown})" if unknown else ""))
    try:
        low, high = float(parts[0]), float(parts[1])
    except ValueError:
        raise SearchSpaceError(f"--bounds {text!r}: LOW and HIGH must be numbers") from None
    try:
        return name, Range(low, high, "log" if "log" in flags else "linear",
                           integer="int" in flags)
    except SearchSpaceError as exc:
        raise SearchSpaceError(f"--bounds {text!r}: {exc}") from None


def _choice_value(raw: str) -> Scalar:
    low = raw.lower()
    if low in ("true", "false"):
        return low == "true"
    for kind in (int, float):
        try:
            return kind(raw)
        except ValueError:
            pass
    return raw
