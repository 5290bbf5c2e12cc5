"""The say channel model: who hears which message, when, and from which direction."""

import math
import operator
from collections import deque
from collections.abc import Sequence
from itertools import repeat
from typing import Any, NamedTuple

import numpy as np

import portable_math as pm
from comms.errors import ChannelError
from comms.profiles import REASON_BAD_VOLUME, ChannelProfile, HearingCapacity, get_profile

#: Per-listener drop reasons (illegal messages use the reasons of `ChannelProfile.check_message`).
REASON_OUT_OF_RANGE = "out_of_range"  # farther than the profile's hearing range
REASON_CAPACITY = "capacity"  # SimSpark hearing capacity exhausted this cycle
REASON_LOST = "lost"  # `mj`: random loss of a message that was not among the loudest
REASON_MAX_HEARD = "max_heard"  # more messages than the listener's `max_heard` slots
REASON_INAUDIBLE = "inaudible"  # `mj`: said at volume 0 (listener -1: nobody hears it)

_TWO_PI = 2.0 * math.pi
_new = tuple.__new__  # builds a NamedTuple from a tuple without the Python-level __new__
_INT = {int}
# ufunc reductions called directly (ndarray.max/any/sum go through Python wrappers)
_max, _any, _add = np.maximum.reduce, np.logical_or.reduce, np.add.reduce
_REAL = {int, float}


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


def received_volume(
    volume: Any, distance_m: Any, db_per_doubling: float = 6.0, reference_m: float = 1.0
) -> np.ndarray:
    """Volume (percent) at which a message said at `volume` arrives `distance_m` metres away.

    Falls `db_per_doubling` dB (amplitude) per doubling of distance beyond `reference_m`
    (RCSSServerMJ: 6 dB, 1 m, i.e. roughly volume / distance).
    """
    d = np.maximum(np.asarray(distance_m, dtype=np.float64), reference_m)
    return np.asarray(volume, dtype=np.float64) * pm.power(
        10.0, -db_per_doubling * pm.log2(d / reference_m) / 20.0
    )


def loss_probability(
    received: Any,
    max_volume: float = 100.0,
    midpoint_m: float = 50.0,
    db_per_doubling: float = 6.0,
    reference_m: float = 1.0,
) -> np.ndarray:
    """`mj`: probability that a message arriving at volume `received` is lost.

    RCSSServerMJ's distance-based loss p = 0.5 tanh(pi d / midpoint - pi) + 0.5, evaluated at
    the distance from which a max-volume message would arrive this loud (so for volume 100 it
    is the true distance: 25 m 4 %, 40 m 22 %, 50 m 50 %, 60 m 78 %, 75 m 96 %).
    """
    rec = np.asarray(received, dtype=np.float64)
    with np.errstate(divide="ignore"):
        d_eff = reference_m * pm.exp2(-20.0 * pm.log10(rec / max_volume) / db_per_doubling)
    return 0.5 * pm.tanh(math.pi * d_eff / midpoint_m - math.pi) + 0.5


def hearing_capacity_trace(
    arrivals: Sequence[int], capacity: HearingCapacity | None = None
) -> list[int]:
    """How many messages of one sender class (teammates or opponents) one listener hears.

    `arrivals[t]`: messages of that class arriving in cycle t (within range). Returns the
    number heard in each cycle. Same rule as the channel: the counter starts at `maximum`,
    gains `increment` at the start of every cycle (capped), and each message heard needs and
    costs `cost`; messages beyond that are dropped in arrival order. Default: the league's
    HearingCapacity(maximum=2, increment=1, cost=2).
    """
    if capacity is None:
        capacity = HearingCapacity()
    cap = capacity.maximum
    out = []
    for a in arrivals:
        cap = min(cap + capacity.increment, capacity.maximum)
        k = min(int(a), cap // capacity.cost)
        cap -= k * capacity.cost
        out.append(k)
    return out


class Channel:
    """A say channel for `n_agents` agents in two teams (stateful: capacities, delay queue).

    Call `deliver` once per cycle with that cycle's utterances; it returns what each listener
    hears in the observation that follows (the league's one-cycle delay). Randomness (arrival
    order, `mj` loss) comes only from the Generator passed to `deliver`.
    """

    def __init__(self, profile: ChannelProfile, n_agents: int, teams: Any) -> None:
        n_agents = operator.index(n_agents)
        if n_agents < 1:
            raise ChannelError(f"n_agents must be >= 1, got {n_agents}")
        teams_arr = np.asarray(teams)
        if teams_arr.shape != (n_agents,):
            raise ChannelError(
                f"teams must have shape ({n_agents},) (one team id per agent), "
                f"got shape {teams_arr.shape}"
            )
        if not np.isin(teams_arr, (0, 1)).all():
            raise ChannelError(f"teams must hold 0 (left) or 1 (right), got {teams_arr.tolist()}")
        self.profile: ChannelProfile = profile
        self.n_agents: int = n_agents
        self.teams: np.ndarray = teams_arr.astype(np.int8)
        self.teams.setflags(write=False)
        self._arange = np.arange(n_agents)
        # Row s of these: speaker s against every listener.
        self._is_self = np.eye(n_agents, dtype=bool)
        self._not_self = ~self._is_self
        self._same = self.teams[:, None] == self.teams[None, :]
        # [self, same team, teammate, opponent] x [speaker, listener]
        self._masks = np.stack((self._is_self, self._same, self._same & self._not_self,
                                ~self._same))
        self._cap = np.zeros((2, n_agents), dtype=np.int64)
        self._queue: deque[Delivery] = deque()
        self.reset()

    def reset(self) -> None:
        """Refill every hearing capacity and forget queued (delayed) messages."""
        cap = self.profile.capacity
        self._cap[:] = cap.maximum if cap is not None else 0
        self._queue.clear()

    def check_message(self, text: Any) -> str | None:
        """None if `text` is a legal say text, else the reason ("too_long", ...)."""
        return self.profile.check_message(text)

    @property
    def capacities(self) -> np.ndarray:
        """Copy of the hearing counters, shape (2, n): row 0 teammates, row 1 opponents."""
        return self._cap.copy()

    # ------------------------------------------------------------------ delivery
    def deliver(
        self,
        utterances: Sequence[Utterance],
        positions: Any,
        headings: Any,
        rng: np.random.Generator,
    ) -> Delivery:
        """Route one cycle's utterances to the listeners.

        Args:
            utterances: this cycle's Utterance objects (at most one per speaker; empty text =
                silent and ignored).
            positions: (n, 2) agent positions in metres, any common frame.
            headings: (n,) agent headings in radians, same frame.
            rng: the env's numpy Generator (arrival order, random loss).

        Returns:
            Delivery for the observation that follows this cycle.

        Raises:
            ChannelError: bad speaker index, a speaker twice, or bad array shapes.
        """
        prof = self.profile
        n = self.n_agents
        cap = prof.capacity
        if cap is not None and cap.increment:
            np.minimum(self._cap + cap.increment, cap.maximum, out=self._cap)
        speakers: list[int] = []
        texts: list[str] = []
        volumes: list[float] = []
        illegal: list[Drop] = []
        fast = False
        if utterances:
            fast = self._well_formed(utterances)
        if fast:
            speakers, texts, volumes = map(list, zip(*utterances, strict=True))
        elif utterances:
            seen = bytearray(n)
            check = prof.check_message
            fast_ok = None if prof.base64_payload else prof._legal_re  # simple alphabets only
            max_chars = prof.max_chars
            uses_volume = prof.attenuation_db_per_doubling > 0.0
            max_volume = prof.max_volume
            for s, text, volume in utterances:
                if type(s) is not int:
                    try:
                        s = operator.index(s)
                    except TypeError:
                        raise ChannelError(f"speaker must be an int, got {s!r}") from None
                if not 0 <= s < n:
                    raise ChannelError(f"speaker index {s} out of range 0..{n - 1}")
                if seen[s]:
                    raise ChannelError(f"speaker {s} has more than one utterance this cycle")
                seen[s] = 1
                if text == "":
                    continue
                if (
                    fast_ok is not None
                    and type(text) is str
                    and len(text) <= max_chars
                    and fast_ok(text) is not None
                ):
                    reason = None
                else:
                    reason = check(text)
                if reason is None and uses_volume:
                    if not isinstance(volume, int | float | np.number) or not (
                        0.0 <= volume <= max_volume  # also rejects NaN
                    ):
                        reason = REASON_BAD_VOLUME
                    elif volume == 0.0:
                        reason = REASON_INAUDIBLE
                if reason is not None:
                    illegal.append(Drop(s, -1, reason))
                    continue
                speakers.append(s)
                texts.append(text)
                volumes.append(volume)
        return self._finish(speakers, texts, volumes, illegal, positions, headings, rng)

    def deliver_texts(
        self,
        texts: Sequence[str],
        positions: Any,
        headings: Any,
        rng: np.random.Generator,
    ) -> Delivery:
        """`deliver` for one text per agent, in agent order ("" = silent), said at volume 100:
        the same Delivery (and channel state, and draws from `rng`) as
        `deliver([Utterance(i, t) for i, t in enumerate(texts) if t], ...)`, with less work
        when every text is legal (anything else goes through `deliver` itself)."""
        prof = self.profile
        n = self.n_agents
        spoken = [t for t in texts if t]
        if (
            len(texts) != n
            or not spoken
            or not prof.all_legal(spoken)
            or (prof.attenuation_db_per_doubling > 0.0 and not 0.0 < 100.0 <= prof.max_volume)
        ):
            return self.deliver(
                [_new(Utterance, (i, t, 100.0)) for i, t in enumerate(texts) if t],
                positions, headings, rng,
            )
        cap = prof.capacity
        if cap is not None and cap.increment:
            np.minimum(self._cap + cap.increment, cap.maximum, out=self._cap)
        if len(spoken) == n:
            speakers = list(range(n))
        else:
            speakers = [i for i, t in enumerate(texts) if t]
        volumes = [100.0] * len(speakers)
        return self._finish(speakers, spoken, volumes, [], positions, headings, rng)

    def _finish(
        self,
        speakers: list[int],
        texts: list[str],
        volumes: list[float],
        illegal: list[Drop],
        positions: Any,
        headings: Any,
        rng: np.random.Generator,
    ) -> Delivery:
        prof = self.profile
        n = self.n_agents
        if prof.base64_payload:  # listeners hear the server's spelling of the bytes
            heard_text = prof.heard_text
            texts = [heard_text(t) for t in texts]
        if not speakers:
            delivery = Delivery([[] for _ in range(n)], illegal)
        else:
            delivery = self._route(speakers, texts, volumes, illegal, positions, headings, rng)
        if prof.delay_cycles == 1:
            return delivery
        self._queue.append(delivery)
        if len(self._queue) >= prof.delay_cycles:
            return self._queue.popleft()
        return Delivery([[] for _ in range(n)])

    def _well_formed(self, utterances: Sequence[Utterance]) -> bool:
        """True when every utterance is legal, at once (the usual case): distinct int speakers
        in range, non-empty legal texts and (volume profiles) a volume in (0, max_volume].
        False sends `deliver` through its checks one by one, which name the fault."""
        prof = self.profile
        try:
            speakers, texts, volumes = zip(*utterances, strict=True)
        except (TypeError, ValueError):
            return False
        if set(map(type, speakers)) != _INT or len(set(speakers)) != len(speakers):
            return False
        if min(speakers) < 0 or max(speakers) >= self.n_agents:
            return False
        if prof.attenuation_db_per_doubling > 0.0:
            if not set(map(type, volumes)) <= _REAL:
                return False
            max_volume = prof.max_volume
            if not all(0.0 < v <= max_volume for v in volumes):
                return False
        return prof.all_legal(texts)

    def _route(
        self,
        speakers: list[int],
        texts: list[str],
        volumes: list[float],
        illegal: list[Drop],
        positions: Any,
        headings: Any,
        rng: np.random.Generator,
    ) -> Delivery:
        prof = self.profile
        n = self.n_agents
        n_spk = len(speakers)
        spk = np.asarray(speakers, dtype=np.intp)
        text_arr = np.array(texts, dtype=object)
        if n_spk > 1:
            if prof.arrival_order == "shuffle":
                perm = rng.permutation(n_spk)
            else:  # ascending speaker index (speakers are distinct)
                perm = np.argsort(spk, kind="stable")
            spk = spk[perm]
            text_arr = text_arr[perm]
            if prof.attenuation_db_per_doubling > 0.0:
                volumes = [volumes[k] for k in perm.tolist()]
        pos = np.asarray(positions, dtype=np.float64)
        hd = np.asarray(headings, dtype=np.float64)
        if pos.shape != (n, 2) or hd.shape != (n,):
            raise ChannelError(
                f"positions must be ({n}, 2) and headings ({n},), got {pos.shape} and {hd.shape}"
            )
        x, y = pos[:, 0], pos[:, 1]
        rel = (x[spk][:, None] - x, y[spk][:, None] - y)  # listener -> speaker, (S, N) each
        dist = np.hypot(*rel)
        # Rows of the speakers: [self, same team, teammate (not self), opponent] x (S, N).
        masks = self._masks[:, spk]
        is_self, same = masks[0], masks[1]
        chunks: list[tuple[np.ndarray, str]] = []
        everyone = _max(dist, axis=None) <= prof.hearing_range_m  # (False for NaN)
        if everyone:
            in_range = audible = None  # audible: all but self (built below if needed)
            by_class = masks[2:]  # teammates, opponents: all audible
        else:
            in_range = dist <= prof.hearing_range_m
            audible = in_range & ~is_self
            by_class = None
            if not in_range.all():
                chunks.append((~in_range, REASON_OUT_OF_RANGE))

        if prof.attenuation_db_per_doubling > 0.0:
            # mj: loudest-first ranking, random loss of the quieter ones. Ranked by the
            # equivalent distance d_eff (the distance from which a max-volume message arrives
            # as loud), which orders like the received volume and feeds the loss model.
            if audible is None:
                audible = ~is_self
            att = prof.attenuation_db_per_doubling
            ref = prof.reference_distance_m
            doublings = pm.log2(np.maximum(dist, ref) * (1.0 / ref))
            vol_term = (20.0 / att) * pm.log10(np.asarray(volumes) * (1.0 / prof.max_volume))
            d_eff = ref * pm.exp2(doublings - vol_term[:, None])
            order = np.argsort(np.where(audible, d_eff, np.inf), axis=0, kind="stable")
            rank = np.argsort(order, axis=0)  # inverse permutation, column by column
            loud = audible & (rank < prof.always_heard)
            if math.isfinite(prof.loss_midpoint_m):
                p_loss = 0.5 * pm.tanh(d_eff * (math.pi / prof.loss_midpoint_m) - math.pi) + 0.5
                survive = audible & (loud | (rng.random(dist.shape) >= p_loss))
            else:
                survive = audible
            lost = audible & ~survive
            if lost.any():
                chunks.append((lost, REASON_LOST))
            heard = survive
            sort_key = rank + 1
            if not prof.self_echo:
                # fast path: walk each listener's column in loudness order
                ranked = np.take_along_axis(survive, order, axis=0)
                kept = ranked & (np.cumsum(ranked, axis=0) <= prof.max_heard)
                if not np.array_equal(kept, ranked):
                    r, c = np.nonzero(ranked & ~kept)
                    over = np.zeros_like(heard)
                    over[order[r, c], c] = True
                    chunks.append((over, REASON_MAX_HEARD))
                li, r = np.nonzero(kept.T)
                return self._assemble(
                    text_arr, illegal, spk, chunks, rel, hd, is_self, same, order[r, li], li
                )
        else:
            # simspark: range, then per-listener capacity in arrival order, per sender class
            # (axis 0: teammates, opponents).
            cap = prof.capacity
            if by_class is None:
                by_class = in_range & masks[2:]  # (2, S, N)
            if cap is not None:
                ok = by_class & (by_class.cumsum(axis=1) <= (self._cap // cap.cost)[:, None])
                self._cap -= cap.cost * _add(ok, axis=1)
                over = by_class ^ ok  # ok is within by_class: the ones over capacity
                by_class = ok
                if _any(over, axis=None):
                    chunks.append((over[0] | over[1], REASON_CAPACITY))
            # Per listener: own message, then teammates', then opponents', each in arrival
            # order: the transposed (3S, N) stack of those masks lists them in that order.
            blocks = np.concatenate(
                (is_self[None], by_class) if prof.self_echo else by_class
            ).reshape(-1, n)
            li, si = blocks.T.nonzero()
            if li.size:
                si %= n_spk
                counts = np.bincount(li, minlength=n)
                if _max(counts) > prof.max_heard:
                    within = np.arange(li.size) - (np.cumsum(counts) - counts)[li]
                    keep = within < prof.max_heard
                    over = np.zeros_like(is_self)
                    over[si[~keep], li[~keep]] = True
                    chunks.append((over, REASON_MAX_HEARD))
                    li = li[keep]
                    si = si[keep]
            return self._assemble(
                text_arr, illegal, spk, chunks, rel, hd, is_self, same, si, li, True
            )
        if prof.self_echo:
            heard = heard | is_self
        sort_key = np.where(is_self, -1, sort_key)

        li, si = np.nonzero(heard.T)
        if li.size:
            order = np.lexsort((sort_key[si, li], li))
            li = li[order]
            si = si[order]
            counts = np.bincount(li, minlength=n)
            within = np.arange(li.size) - (np.cumsum(counts) - counts)[li]
            keep = within < prof.max_heard
            if not keep.all():
                over = np.zeros_like(heard)
                over[si[~keep], li[~keep]] = True
                chunks.append((over, REASON_MAX_HEARD))
                li = li[keep]
                si = si[keep]
        return self._assemble(text_arr, illegal, spk, chunks, rel, hd, is_self, same, si, li)

    def _assemble(
        self,
        texts: np.ndarray,
        illegal: list[Drop],
        spk: np.ndarray,
        chunks: list,
        rel: tuple[np.ndarray, np.ndarray],
        hd: np.ndarray,
        is_self: np.ndarray,
        same: np.ndarray,
        si: np.ndarray,
        li: np.ndarray,
        grouped: bool = False,
    ) -> Delivery:
        """Build the Heard lists from (speaker slot, listener) pairs sorted per listener."""
        ang = pm.arctan2(rel[1][si, li], rel[0][si, li]) - hd[li]
        ang = (ang + math.pi) % _TWO_PI - math.pi
        q = self.profile.direction_quantum_deg
        if q > 0.0:
            ang = np.trunc(ang * (180.0 / math.pi / q)) * (q * math.pi / 180.0)
        pair_self = is_self[si, li]
        ang[pair_self] = 0.0
        pairs = (
            li,
            spk[si],
            texts[si],
            ang,
            pair_self,
            same[si, li],
        )
        return Delivery(None, illegal, (spk, chunks), pairs, self.n_agents, grouped)


def make_channel(
    profile: "str | ChannelProfile", n_agents: int, teams: Any, **overrides: Any
) -> Channel:
    """Build a Channel for `n_agents` agents; `teams` holds 0 (left) or 1 (right) per agent.

    `profile` is "simspark", "mj" or a ChannelProfile; keyword overrides replace profile
    fields (e.g. `max_heard=21`, `arrival_order="index"`); an unknown key is a ChannelError.
    """
    return Channel(get_profile(profile, **overrides), n_agents, teams)
