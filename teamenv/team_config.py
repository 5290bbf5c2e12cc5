"""Checking a team's config: the one helper the built-in teams share.

A team declares its options as a frozen dataclass (name, type annotation, default, optional
``in_range(...)`` metadata) and builds it with :func:`team_config`. Unknown keys (with the
closest known one suggested), values of the wrong type (``"false"`` for a bool, ``7`` for a
bool, a string for a number, NaN) and values out of range are errors naming the team, the key
and the value — never Python's ``__init__() got an unexpected keyword argument``, never a
silent ``bool("false") == True``.
"""

from __future__ import annotations

import difflib
import math
import numbers
import os
import types
import typing
from collections.abc import Callable, Mapping
from dataclasses import MISSING, fields, is_dataclass
from pathlib import Path
from typing import Any, TypeVar

from teamenv.errors import ConfigError, value_repr

T = TypeVar("T")

#: Field metadata key of :func:`in_range`.
RANGE_KEY = "teamenv.team_config.range"


def in_range(low: float | None = None, high: float | None = None, *, low_open: bool = False,
             high_open: bool = False) -> dict[str, Any]:
    """Field metadata: a number must lie between ``low`` and ``high`` (None: unbounded;
    ``*_open``: that end excluded)."""
    return {RANGE_KEY: (low, high, low_open, high_open)}


def team_config(team: str, cls: type[T], config: Mapping[str, Any] | None,
                error: type[ConfigError] = ConfigError) -> T:
    """``cls`` (a dataclass of the team's options) from the team's ``config``.

    Every key must be a field of ``cls``; every value must be of the field's annotated type
    (``bool`` only True/False; ``int`` a whole number, not a bool; ``float`` a finite number,
    not a bool; ``str``; ``Path`` a str or path; ``Callable`` anything callable; ``X | None``
    also None) and within its ``in_range`` metadata. Errors are ``error`` (a ConfigError)
    whose message starts with ``"<team> team config: "``; an error the dataclass's own
    ``__post_init__`` raises gets the same prefix."""
    if not is_dataclass(cls):
        raise TypeError(f"team_config: {cls!r} is not a dataclass")
    section = f"{team} team config"
    if config is None:
        config = {}
    if not isinstance(config, Mapping):
        raise error(f"{section}: expected a mapping of option names to values, got "
                    f"{value_repr(config)}")
    known = {f.name: f for f in fields(cls)}
    hints = typing.get_type_hints(cls)
    for key in config:
        if key not in known:
            close = difflib.get_close_matches(str(key), list(known), n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise error(f"{section}: unknown key {value_repr(key)}{hint}; known keys: "
                        f"{sorted(known) if known else 'none (this team takes no options)'}")
    for key, value in config.items():
        _check_value(section, key, value, hints[key], known[key].metadata, error)
    try:
        return cls(**dict(config))
    except ConfigError as exc:
        text = str(exc)
        raise error(text if text.startswith(section) else f"{section}: {text}") from None


def team_config_defaults(cls: type) -> dict[str, Any]:
    """The options of ``cls`` with their defaults (for help texts and docs)."""
    out = {}
    for f in fields(cls):
        if f.default is not MISSING:
            out[f.name] = f.default
        elif f.default_factory is not MISSING:
            out[f.name] = f.default_factory()
    return out


def _check_value(section: str, key: str, value: Any, hint: Any, metadata: Mapping[str, Any],
                 error: type[ConfigError]) -> None:
    allowed = _alternatives(hint)
    if value is None and type(None) in allowed:
        return
    kinds = [a for a in allowed if a is not type(None)]
    if Path in kinds and str in kinds:  # "a path" says it: a str or os.PathLike
        kinds.remove(str)
    if not any(_is_kind(value, kind) for kind in kinds):
        what = " or ".join(_describe(kind) for kind in kinds)
        if type(None) in allowed:
            what += " or null"
        raise error(f"{section}: {key} must be {what}, got {value_repr(value)}")
    bounds = metadata.get(RANGE_KEY)
    if bounds is not None and isinstance(value, numbers.Real):
        low, high, low_open, high_open = bounds
        below = low is not None and (value <= low if low_open else value < low)
        above = high is not None and (value >= high if high_open else value > high)
        if below or above:
            if high is None:
                wanted = f"{'>' if low_open else '>='} {low:g}"
            elif low is None:
                wanted = f"{'<' if high_open else '<='} {high:g}"
            else:
                wanted = (f"in {'(' if low_open else '['}{low:g}, {high:g}"
                          f"{')' if high_open else ']'}")
            raise error(f"{section}: {key} must be {wanted}, got {value_repr(value)}")


def _alternatives(hint: Any) -> tuple[Any, ...]:
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        return typing.get_args(hint)
    return (hint,)


def _is_kind(value: Any, kind: Any) -> bool:
    if kind is bool:
        return isinstance(value, bool)
    if kind is int:
        return isinstance(value, numbers.Integral) and not isinstance(value, bool)
    if kind is float:
        return (isinstance(value, numbers.Real) and not isinstance(value, bool)
                and math.isfinite(value))
    if kind is str:
        return isinstance(value, str)
    if kind is Path:
        return isinstance(value, (str, os.PathLike))
    if kind is Any:
        return True
    if typing.get_origin(kind) is Callable or kind is Callable:
        return callable(value)
    return isinstance(value, kind) if isinstance(kind, type) else True


def _describe(kind: Any) -> str:
    if kind is bool:
        return "true or false"
    if kind is int:
        return "an integer"
    if kind is float:
        return "a finite number"
    if kind is str:
        return "a string"
    if kind is Path:
        return "a path (string)"
    if typing.get_origin(kind) is Callable or kind is Callable:
        return "a callable"
    return getattr(kind, "__name__", str(kind))
