"""The built-in formations shipped as JSON files in ``strategy/positioning/formation/data/``."""

from __future__ import annotations

from functools import lru_cache
from importlib import resources

from strategy.positioning.formation.fileformat import formation_from_dict
from strategy.positioning.formation.model import Formation, FormationError
from teamenv.field import FieldSpec

_PACKAGE = "strategy.positioning.formation"


def builtin_formation_names() -> tuple[str, ...]:
    """Names of the built-in formations, e.g. ``"11v11-defend"``, ``"7v7-kickoff-ours"``."""
    files = resources.files(_PACKAGE).joinpath("data").iterdir()
    return tuple(sorted(f.name[:-5] for f in files if f.name.endswith(".json")))


def builtin_formation(name: str, field: str | FieldSpec | None = None) -> Formation:
    """The built-in formation ``name``, scaled to ``field`` (a preset name or ``FieldSpec``).

    11 v 11 formations are written for ``simspark`` and 7 v 7 ones for ``mj7v7``; without
    ``field`` they come on that pitch. Formations are immutable, so the result is cached.
    """
    key = field if field is None or isinstance(field, str) else (field.length, field.width)
    return _load(name, key)


@lru_cache(maxsize=64)
def _load(name: str, field: str | tuple[float, float] | None) -> Formation:
    import json

    names = builtin_formation_names()
    if name not in names:
        raise FormationError(f"builtin formation: unknown name {name!r}; choose one of {names}")
    text = resources.files(_PACKAGE).joinpath("data", f"{name}.json").read_text(encoding="utf-8")
    return formation_from_dict(json.loads(text), source=f"<builtin {name}>", field=field)
