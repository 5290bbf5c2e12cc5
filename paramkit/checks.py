"""Checks of a parameter dataclass's fields: what each field's type annotation implies, plus the
range or choices its metadata declares; one message format, whichever package's error type.

A dataclass states each rule next to the field's default and calls ``check_fields`` from
``__post_init__`` with its own package's error type::

    @dataclass(frozen=True)
    class RulesConfig:
        half_time_s: float = field(default=300.0, metadata=in_range(0.0, low_open=True))
        halves: int = field(default=2, metadata=one_of(1, 2))

        def __post_init__(self) -> None:
            check_fields(self, ConfigError)

``RulesConfig(half_time_s=-1)`` then raises
``ConfigError("RulesConfig.half_time_s must be > 0, got -1")``: the dataclass, the field, the
rule and the value.

What an annotation implies (``field_problem``):

- ``bool``: True or False (not 0, 1 or "false");
- ``int``: a whole number (numpy's too), not a bool;
- ``float``: a real number (numpy's too), not a bool, finite unless the field's ``in_range``
  says ``infinite=True`` (NaN never);
- ``str``; ``Path``: a str or path; ``Callable``: anything callable;
- ``tuple[float, float]``, ``tuple[int, ...]``: a tuple (or list) of that many, each entry
  checked and bounded as its type;
- ``Literal["a", "b"]``: one of those values;
- ``X | None``: also None;
- another class: an instance of it; ``Any`` and other generics: anything.

The metadata: ``in_range(low, high, ...)`` bounds a number (each entry of a tuple;
``positive()`` and ``non_negative()`` are its two commonest cases); ``one_of(*choices)`` lists
the values allowed. Rules between fields (``low < high``) stay in
the dataclass's ``__post_init__`` and raise ``invalid(obj, name, rule, error)``, the same
message.
"""

from __future__ import annotations

import math
import numbers
import os
import re
import types
import typing
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any, Literal

#: Field metadata keys of ``in_range`` and ``one_of``.
RANGE_KEY = "paramkit.range"
CHOICES_KEY = "paramkit.choices"

_NONE = type(None)
_LINE_BREAK = re.compile(r"\n\s*")


@dataclass(frozen=True)
class Bounds:
    """A number's allowed interval: ``low``/``high`` (None: unbounded), ``*_open`` (that end
    excluded), ``infinite`` (±inf allowed where the interval holds it; NaN never)."""

    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    infinite: bool = False

    def admits(self, x: float) -> bool:
        if self.low is not None and (x <= self.low if self.low_open else x < self.low):
            return False
        return self.high is None or (x < self.high if self.high_open else x <= self.high)

    def describe(self) -> str:
        """The rule in words: ``> 0``, ``<= 1``, ``in (0, 1]``."""
        if self.high is None and self.low is None:
            return "a number"
        if self.high is None:
            return f"{'>' if self.low_open else '>='} {self.low:g}"
        if self.low is None:
            return f"{'<' if self.high_open else '<='} {self.high:g}"
        return (f"in {'(' if self.low_open else '['}{self.low:g}, {self.high:g}"
                f"{')' if self.high_open else ']'}")


def in_range(low: float | None = None, high: float | None = None, *, low_open: bool = False,
             high_open: bool = False, infinite: bool = False) -> dict[str, Any]:
    """Field metadata: a number must lie between ``low`` and ``high`` (None: unbounded;
    ``*_open``: that end excluded; ``infinite``: ±inf allowed within them)."""
    return {RANGE_KEY: Bounds(low, high, low_open, high_open, infinite)}


def positive(*, infinite: bool = False) -> dict[str, Any]:
    """Field metadata: a number > 0 (``in_range(0, low_open=True)``)."""
    return in_range(0.0, low_open=True, infinite=infinite)


def non_negative(*, infinite: bool = False) -> dict[str, Any]:
    """Field metadata: a number >= 0 (``in_range(0)``)."""
    return in_range(0.0, infinite=infinite)


def one_of(*choices: Any) -> dict[str, Any]:
    """Field metadata: the value must be one of ``choices``."""
    return {CHOICES_KEY: tuple(choices)}


def value_repr(value: Any, limit: int = 80) -> str:
    """``repr(value)`` cut to ``limit`` characters, for error messages about the caller's input.

    Never raises: the value is whatever the caller passed, and a message about it must not
    fail in its turn (``repr`` of an int of more than 4,300 digits raises ValueError; a
    third-party object's ``__repr__`` may raise anything)."""
    if isinstance(value, int) and value.bit_length() > 1024:
        return f"<int of {value.bit_length()} bits>"
    try:
        # On one line (a 2-D numpy array's repr breaks rows): a message is one line.
        text = _LINE_BREAK.sub(" ", repr(value))
    except Exception:  # any failure of a foreign __repr__: name the type instead
        return f"<{type(value).__name__} object>"
    return text if len(text) <= limit else text[:limit - 3] + "..."


def check_fields(obj: Any, error: Callable[[str], Exception], *,
                 default: Mapping[str, Any] | None = None) -> None:
    """Check every ``__init__`` field of the dataclass instance ``obj`` against its annotation
    and metadata (module docstring); raise ``error(message)`` for the first that fails, the
    message ``"<Class>.<field> must be <rule>, got <value>"``. ``default`` (e.g.
    ``non_negative()``) is the range of every number field that declares none."""
    for name, hint, metadata in _field_rules(type(obj)):
        if default is not None and RANGE_KEY not in metadata:
            metadata = {**metadata, **default}
        value = getattr(obj, name)
        why = field_problem(value, hint, metadata)
        if why is not None:
            raise invalid(obj, name, why, error)


def invalid(obj: Any, name: str, rule: str, error: Callable[[str], Exception]) -> Exception:
    """The error for field ``name`` of ``obj`` breaking ``rule`` (e.g. ``"< high (2.0)"``), in
    ``check_fields``'s words; for the rules a dataclass checks between its fields."""
    return error(f"{type(obj).__name__}.{name} must be {rule}, got "
                 f"{value_repr(getattr(obj, name))}")


def field_problem(value: Any, hint: Any, metadata: Mapping[str, Any] | None = None) -> str | None:
    """None when ``value`` fits the annotation ``hint`` and the field ``metadata``
    (``in_range``, ``one_of``), else the rule it breaks in words (``"an integer"``,
    ``">= 1"``, ``"true or false"``)."""
    metadata = metadata or {}
    bounds: Bounds | None = metadata.get(RANGE_KEY)
    choices = metadata.get(CHOICES_KEY)
    allowed = _alternatives(hint)
    if value is None and _NONE in allowed:
        return None
    kinds = [kind for kind in allowed if kind is not _NONE]
    if Path in kinds and str in kinds:  # "a path" says it: a str or os.PathLike
        kinds.remove(str)
    infinite = bounds is not None and bounds.infinite
    kind = next((k for k in kinds if _is_kind(value, k, infinite)), None)
    if kind is None:
        what = " or ".join(_describe(k, infinite) for k in kinds)
        return what + " or null" if _NONE in allowed else what
    if choices is not None and not any(_same(value, c) for c in choices):
        return f"one of {list(choices)}"
    if bounds is not None:
        entries = value if typing.get_origin(kind) is tuple else (value,)
        for entry in entries:
            if isinstance(entry, numbers.Real) and not isinstance(entry, bool) and \
                    not bounds.admits(entry):
                if entries is value:
                    return f"{_count(kind)}numbers, each {bounds.describe()}"
                return bounds.describe()
    return None


# -- annotations -------------------------------------------------------------------------------
_RULES: dict[type, tuple[tuple[str, Any, Mapping[str, Any]], ...]] = {}


def _field_rules(cls: type) -> tuple[tuple[str, Any, Mapping[str, Any]], ...]:
    """(name, resolved annotation, metadata) of ``cls``'s init fields, worked out once."""
    rules = _RULES.get(cls)
    if rules is None:
        hints = typing.get_type_hints(cls)
        rules = _RULES[cls] = tuple((f.name, hints[f.name], f.metadata)
                                    for f in fields(cls) if f.init)
    return rules


def _alternatives(hint: Any) -> tuple[Any, ...]:
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        return typing.get_args(hint)
    return (hint,)


def _same(value: Any, choice: Any) -> bool:
    """``value == choice`` of the same kind (1 is not True, 1.0 is not "1")."""
    if isinstance(choice, bool) or isinstance(value, bool):
        return type(value) is type(choice) and value == choice
    try:
        return bool(value == choice)
    except Exception:  # an array compares element-wise: not a choice
        return False


def _is_real(value: Any, infinite: bool) -> bool:
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        return False
    try:
        return math.isfinite(value) or (infinite and not math.isnan(value))
    except OverflowError:  # an int too large for a float
        return False


def _is_kind(value: Any, kind: Any, infinite: bool) -> bool:
    if kind is bool:
        return isinstance(value, bool)
    if kind is int:
        return isinstance(value, numbers.Integral) and not isinstance(value, bool)
    if kind is float:
        return _is_real(value, infinite)
    if kind is str:
        return isinstance(value, str)
    if kind is Path:
        return isinstance(value, (str, os.PathLike))
    if kind is Any:
        return True
    origin = typing.get_origin(kind)
    if origin is Literal:
        return any(_same(value, c) for c in typing.get_args(kind))
    if origin is tuple:
        args = typing.get_args(kind)
        if not isinstance(value, (tuple, list)):
            return False
        if len(args) == 2 and args[1] is Ellipsis:
            return all(_is_kind(v, args[0], infinite) for v in value)
        return len(value) == len(args) and all(
            _is_kind(v, a, infinite) for v, a in zip(value, args, strict=True))
    if origin is Callable or kind is Callable:
        return callable(value)
    if isinstance(origin, type):
        return isinstance(value, origin)
    return isinstance(value, kind) if isinstance(kind, type) else True


def _count(kind: Any) -> str:
    """``"3 "`` for ``tuple[float, float, float]``, ``""`` for ``tuple[float, ...]``."""
    args = typing.get_args(kind)
    return "" if len(args) == 2 and args[1] is Ellipsis else f"{len(args)} "


def _describe(kind: Any, infinite: bool = False) -> str:
    if kind is bool:
        return "true or false"
    if kind is int:
        return "an integer"
    if kind is float:
        return "a number (not NaN)" if infinite else "a finite number"
    if kind is str:
        return "a string"
    if kind is Path:
        return "a path (string)"
    origin = typing.get_origin(kind)
    if origin is Literal:
        return f"one of {list(typing.get_args(kind))}"
    if origin is tuple:
        args = typing.get_args(kind)
        if len(set(args) - {Ellipsis}) == 1 and args[0] in (int, float):
            plural = "integers" if args[0] is int else \
                ("numbers (not NaN)" if infinite else "finite numbers")
            return f"{_count(kind)}{plural}"
        return f"a tuple of {len(args)}"
    if origin is Callable or kind is Callable:
        return "a callable"
    return getattr(kind, "__name__", str(kind))
