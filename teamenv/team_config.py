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
import typing
from collections.abc import Mapping
from dataclasses import MISSING, fields, is_dataclass
from typing import Any, TypeVar

from paramkit.checks import field_problem, in_range
from teamenv.errors import ConfigError, value_repr

__all__ = ["in_range", "team_config", "team_config_defaults"]

T = TypeVar("T")


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
        why = field_problem(value, hints[key], known[key].metadata)
        if why is not None:
            raise error(f"{section}: {key} must be {why}, got {value_repr(value)}")
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
