"""What one cycle of the say channel delivers: the utterances that go in (`Utterance`), what
each listener hears (`Heard`), what is lost on the way (`Drop`), and the `Delivery` that holds
both, built lazily from arrays (`comms.channel.Channel` makes them)."""

from itertools import repeat
from typing import Any, NamedTuple

import numpy as np

_new = tuple.__new__  # builds a NamedTuple from a tuple without the Python-level __new__
# ufunc reduction called directly (ndarray.any goes through a Python wrapper)
_any = np.logical_or.reduce


class Utterance(NamedTuple):
    """One `say` of one agent in one cycle.

    speaker: agent index (0..n_agents-1); text: the say text ("" = silent);
    volume: percent 0-100, used by `mj` only.
    """

    speaker: int
    text: str
    volume: float = 100.0


class Heard(NamedTuple):
    """One message as one listener hears it.

    speaker: agent index (for infos and tests; agents are not shown it);
    direction: rad, direction of the speaker relative to the listener's heading, in [-pi, pi)
    (0 for self); is_self: the listener's own message; teammate: the speaker is on the
    listener's team (True for self).
    """

    speaker: int
    text: str
    direction: float
    is_self: bool
    teammate: bool


class Drop(NamedTuple):
    """A message that did not reach a listener; listener is -1 when nobody hears it."""

    speaker: int
    listener: int
    reason: str


class Delivery:
    """What every listener hears from one cycle's utterances.

    `heard[i]`: list of Heard for listener i, at most `max_heard`, self first (built on first
    access from `pairs`).
    `dropped`: list of Drop (built on first access, so a caller that ignores it pays nothing).
    `pairs`: the same as arrays, or None (a delivery nobody spoke into): a tuple
    `(listener, speaker, text, direction, is_self, teammate)` over every (listener, message)
    heard, sorted by listener and, within a listener, in `heard[i]` order: `listener`,
    `speaker` (agent index) int arrays, `text` an object array of str, `direction` a float
    array, `is_self` and `teammate` bool arrays. `heard` is built from exactly these values.
    `grouped`: True when each listener's pairs come as its own message, then teammates',
    then opponents' (`simspark`-like profiles; `mj` orders them by loudness).
    """

    __slots__ = ("_heard", "_dropped", "_pending", "pairs", "_n", "grouped")

    def __init__(
        self,
        heard: list[list[Heard]] | None,
        dropped: list[Drop] | None = None,
        pending: Any = None,
        pairs: tuple | None = None,
        n_agents: int = 0,
        grouped: bool = False,
    ) -> None:
        self._heard = heard
        self.grouped = grouped
        self._dropped = dropped if dropped is not None else []
        self._pending = pending
        self.pairs = pairs
        self._n = n_agents

    @property
    def heard(self) -> list[list[Heard]]:
        """Per listener, the list of Heard (at most `max_heard`, self first)."""
        if self._heard is None:
            out: list[list[Heard]] = [[] for _ in range(self._n)]
            li, speaker, text, direction, me, mate = self.pairs
            for lst_i, spk, t, a, s, m in zip(
                li.tolist(),
                speaker.tolist(),
                text.tolist(),
                direction.tolist(),
                me.tolist(),
                mate.tolist(),
                strict=True,
            ):
                out[lst_i].append(_new(Heard, (spk, t, a, s, m)))
            self._heard = out
        return self._heard

    @property
    def dropped(self) -> list[Drop]:
        """Every drop of the cycle: illegal messages first, then per-listener drops."""
        if self._pending is not None:
            speaker_ids, chunks = self._pending
            self._pending = None
            out = self._dropped
            make = Drop._make
            for mask, reason in chunks:
                si, li = np.nonzero(mask)
                out.extend(map(make, zip(speaker_ids[si].tolist(), li.tolist(), repeat(reason))))
        return self._dropped

    def drop_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The drops of `dropped`, in its order, as arrays (without building Drop objects):
        speaker and listener (-1: nobody) int arrays, reason an object array of str."""
        if self._pending is None:
            drops = self._dropped
            return (
                np.array([d.speaker for d in drops], dtype=np.intp),
                np.array([d.listener for d in drops], dtype=np.intp),
                np.array([d.reason for d in drops], dtype=object),
            )
        speaker_ids, chunks = self._pending
        illegal = self._dropped
        speakers = [np.array([d.speaker for d in illegal], dtype=np.intp)]
        listeners = [np.full(len(illegal), -1, dtype=np.intp)]
        reasons = [np.array([d.reason for d in illegal], dtype=object)]
        for mask, reason in chunks:
            si, li = mask.nonzero()
            speakers.append(speaker_ids[si])
            listeners.append(li)
            reasons.append(np.full(len(li), reason, dtype=object))
        return np.concatenate(speakers), np.concatenate(listeners), np.concatenate(reasons)

    def has_drops(self) -> bool:
        """True when any message was dropped this cycle (cheap: builds no Drop)."""
        if self._dropped:
            return True
        pending = self._pending
        return pending is not None and any(_any(mask, axis=None) for mask, _ in pending[1])

    def drop_counts(self) -> dict[str, int]:
        """Number of drops per reason, without building the Drop list (cheap, for infos)."""
        counts: dict[str, int] = {}
        for d in self._dropped:
            counts[d.reason] = counts.get(d.reason, 0) + 1
        if self._pending is not None:
            for mask, reason in self._pending[1]:
                counts[reason] = counts.get(reason, 0) + int(np.count_nonzero(mask))
        return counts

    def __repr__(self) -> str:
        n = sum(len(h) for h in self.heard)
        return f"Delivery(listeners={len(self.heard)}, heard={n}, dropped={len(self.dropped)})"
