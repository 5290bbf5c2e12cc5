"""Named registries: one way to hold the named things a user picks by name and may add to
(vision profiles, say-channel profiles, locomotion profiles).

    VISION_PROFILES = Registry("vision profile", ConfigError)
    VISION_PROFILES.register("simspark", PerceptionConfig())         # a value
    PROFILES.register("t1_mj", factory=lambda: load_file(path))      # made on first use

    VISION_PROFILES.get("mj")    # the value; an unknown name raises the registry's error,
                                 # naming the kind and every registered name
    VISION_PROFILES.names()      # sorted names
    VISION_PROFILES.unregister("mj")
    "mj" in VISION_PROFILES, VISION_PROFILES["mj"], dict(VISION_PROFILES.items())

A name is registered once; ``replace=True`` overrides it on purpose. A factory runs once, on
the first ``get``, and its value is kept (a profile file is read when first asked for, and a
broken one fails then, naming itself, not at import).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Generic, TypeVar

T = TypeVar("T")
_UNSET = object()


class Registry(Generic[T]):
    """Names -> values of one kind (``kind``, e.g. "vision profile"), each given as the value
    or as a factory that makes it on first use. ``error(message)`` is the exception an
    unknown or doubly registered name raises (the owning package's error type)."""

    def __init__(self, kind: str, error: Callable[[str], Exception]) -> None:
        self.kind = kind
        self.error = error
        self._values: dict[str, T] = {}
        self._factories: dict[str, Callable[[], T]] = {}

    def register(self, name: str, value: T = _UNSET, *,  # type: ignore[assignment]
                 factory: Callable[[], T] | None = None, replace: bool = False) -> None:
        """Add ``name``: its ``value``, or a ``factory`` called on the first ``get``."""
        if not isinstance(name, str) or not name:
            raise self.error(f"{self.kind}: a name must be a non-empty string, got {name!r}")
        if (value is _UNSET) == (factory is None):
            raise self.error(f"{self.kind} {name!r}: give a value or a factory, not both or "
                             "neither")
        if name in self and not replace:
            raise self.error(f"{self.kind} {name!r} is registered already (replace=True "
                             "overrides it)")
        self._values.pop(name, None)
        self._factories.pop(name, None)
        if factory is None:
            self._values[name] = value
        else:
            self._factories[name] = factory

    def unregister(self, name: str) -> None:
        """Remove ``name`` (an unknown name raises ``error``)."""
        if name not in self:
            raise self.error(f"unknown {self.kind} {name!r}; choose one of {self.names()}")
        self._values.pop(name, None)
        self._factories.pop(name, None)

    def get(self, name: str) -> T:
        """The value registered as ``name``; an unknown name raises ``error`` listing the
        registered names."""
        try:
            return self._values[name]
        except (KeyError, TypeError):  # TypeError: an unhashable name
            pass
        factory = self._factories.get(name) if isinstance(name, str) else None
        if factory is None:
            raise self.error(f"unknown {self.kind} {name!r}; choose one of {self.names()}")
        value = self._values[name] = factory()
        del self._factories[name]
        return value

    def names(self) -> list[str]:
        """Every registered name, sorted."""
        return sorted({*self._values, *self._factories})

    def keys(self) -> list[str]:
        """The same as ``names()``: ``dict(registry)`` works as for a mapping."""
        return self.names()

    def items(self) -> list[tuple[str, T]]:
        """(name, value) of every name, sorted by name (factories run)."""
        return [(name, self.get(name)) for name in self.names()]

    def __getitem__(self, name: str) -> T:
        return self.get(name)

    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and (name in self._values or name in self._factories)

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def __len__(self) -> int:
        return len(self._values) + len(self._factories)

    def __repr__(self) -> str:
        return f"Registry({self.kind!r}, names={self.names()})"
