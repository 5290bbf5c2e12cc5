"""Dicts whose values are built on first use, for what ``reset()``/``step()`` return.

Observations and infos are plain ``dict`` subclasses: a caller that never reads an agent's
observation, or the message drops in the infos, does not pay for building them. Once built
(or when used in any way that needs every value) they hold exactly what an eager build
holds; pickled or copied they are plain dicts.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from teamenv.box_layout import StackedState
    from teamenv.sim.perception import ObservationRows


class LazyInfos(dict):
    """The ``infos`` of one step: a real ``dict`` (agent -> info dict) whose ``message_dropped``
    entries are filled in the first time the mapping is used (indexing, iteration, ``items()``,
    comparison, copying, pickling, printing...). Once filled it is exactly the dict an eager
    build gives; a step whose infos nobody reads does not pay for listing hundreds of drops.
    Pickled, it is a plain ``dict``."""

    __slots__ = ("_fill",)

    def __init__(self, base: dict[str, dict], fill: Callable[[dict], None]) -> None:
        dict.__init__(self, base)
        self._fill: Callable[[dict], None] | None = fill

    def _materialize(self) -> None:
        fill = self._fill
        if fill is not None:
            self._fill = None
            fill(self)

    def __reduce__(self):
        self._materialize()
        return (dict, (dict(dict.items(self)),))

    def __reduce_ex__(self, protocol):
        return self.__reduce__()


_UNBUILT = object()  # the value of an agent whose observation is not built yet


class LazyObservations(dict):
    """The observations of one step: a real ``dict`` (agent -> observation dict) whose values
    are built the first time each is looked up (``obs[agent]``, ``get``); any other use of
    the values (``items()``, ``values()``, comparison, copying, pickling, printing...) builds
    them all first. Keys, ``len`` and ``in`` need no build. The values are the dicts an eager
    build gives. Pickled, it is a plain ``dict``."""

    __slots__ = ("_rows", "_row_of")

    def __init__(self, agents: list[str], rows: ObservationRows, row_of: dict[str, int]) -> None:
        dict.__init__(self, dict.fromkeys(agents, _UNBUILT))
        self._rows: ObservationRows | None = rows
        self._row_of = row_of

    def __getitem__(self, agent):
        value = dict.__getitem__(self, agent)
        if value is _UNBUILT:
            value = self._rows[self._row_of[agent]]
            dict.__setitem__(self, agent, value)
        return value

    def get(self, agent, default=None):
        return self[agent] if dict.__contains__(self, agent) else default

    def stacked(self) -> StackedState | None:
        """Every agent's observation as one array of flat rows, in key order
        (``ObservationRows.stacked``), for readers that take them together; None once the
        dicts have been built (they may have been changed since: read them instead)."""
        if self._rows is None:
            return None
        return self._rows.stacked([self._row_of[agent] for agent in dict.__iter__(self)])

    def __iter__(self):
        # Defined here so that dict(obs), {**obs} and dict.update(obs) go through keys() and
        # __getitem__ (CPython copies a dict subclass's storage directly only when it keeps
        # dict's own __iter__).
        return dict.__iter__(self)

    def _materialize(self) -> None:
        if self._rows is not None:
            for agent, value in dict.items(self):
                if value is _UNBUILT:
                    dict.__setitem__(self, agent, self._rows[self._row_of[agent]])
            self._rows = None

    __reduce__ = LazyInfos.__reduce__
    __reduce_ex__ = LazyInfos.__reduce_ex__


def _lazy_method(name: str) -> Callable:
    base = getattr(dict, name)

    def method(self, *args, **kwargs):
        self._materialize()
        return base(self, *args, **kwargs)

    method.__name__ = name
    method.__qualname__ = f"lazy.{name}"
    method.__doc__ = base.__doc__
    return method


for _name in ("__getitem__", "get", "__iter__", "__reversed__", "__len__", "__contains__",
              "keys", "values", "items", "__eq__", "__ne__", "__repr__", "__or__", "__ror__",
              "__ior__", "copy", "pop", "popitem", "setdefault", "update", "__setitem__",
              "__delitem__", "clear", "__sizeof__"):
    setattr(LazyInfos, _name, _lazy_method(_name))
for _name in ("values", "items", "__eq__", "__ne__", "__repr__", "__or__", "__ror__",
              "__ior__", "copy", "pop", "popitem", "setdefault", "update", "__sizeof__"):
    setattr(LazyObservations, _name, _lazy_method(_name))
del _name
LazyInfos.__hash__ = None  # type: ignore[assignment]
LazyObservations.__hash__ = None  # type: ignore[assignment]
