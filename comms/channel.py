"""The say channel model: who hears which message, when, and from which direction.

What a cycle delivers (`Utterance`, `Heard`, `Drop`, `Delivery`) is in `comms.delivery`; the
hearing models as single-value formulas in `comms.hearing`."""

import functools
import math
import operator
from collections import deque
from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

import portable_math as pm
from comms.delivery import Delivery, Drop, Utterance
from comms.errors import ChannelError
from comms.profiles import REASON_BAD_VOLUME, ChannelProfile, get_profile

#: Per-listener drop reasons (illegal messages use the reasons of `ChannelProfile.check_message`).
REASON_OUT_OF_RANGE = "out_of_range"  # farther than the profile's hearing range
REASON_CAPACITY = "capacity"  # SimSpark hearing capacity exhausted this cycle
REASON_LOST = "lost"  # `mj`: random loss of a message that was not among the loudest
REASON_MAX_HEARD = "max_heard"  # more messages than the listener's `max_heard` slots
REASON_INAUDIBLE = "inaudible"  # `mj`: said at volume 0 (listener -1: nobody hears it)

_TWO_PI = 2.0 * math.pi
_new = tuple.__new__  # builds a NamedTuple from a tuple without the Python-level __new__
_INT = {int}
# a ufunc reduction called directly (ndarray.max goes through a Python wrapper)
_max = np.maximum.reduce
_REAL = {int, float}


@functools.cache
def _capacity_kernel():
    """The compiled `simspark` hearing kernel, imported on the first delivery: importing numba
    takes a few tenths of a second that `import comms` should not pay."""
    from comms.capacity_kernel import hear_by_capacity

    return hear_by_capacity


class _Routing(NamedTuple):
    """One cycle's legal messages on their way to the listeners (`Channel._route`).

    speakers, texts: in arrival order; illegal: the drops of illegal messages; chunks: the
    per-listener drops so far, (mask over (speaker slot, listener), reason); rel: listener ->
    speaker offsets, (S, N) each; dist: their lengths; headings: the listeners'; in_range: None
    when everyone is within hearing range.
    """

    speakers: np.ndarray
    texts: np.ndarray
    illegal: list[Drop]
    chunks: list[tuple[np.ndarray, str]]
    rel: tuple[np.ndarray, np.ndarray]
    dist: np.ndarray
    headings: np.ndarray
    in_range: np.ndarray | None


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
        """Who hears which of this cycle's legal messages: the arrival order and the hearing
        range here, then the profile's hearing model: `_hear_by_loudness` where the volume
        falls with distance (`mj`), else `_hear_by_capacity` (`simspark`)."""
        prof = self.profile
        n = self.n_agents
        n_spk = len(speakers)
        spk = np.asarray(speakers, dtype=np.intp)
        text_arr = np.array(texts, dtype=object)
        by_volume = prof.attenuation_db_per_doubling > 0.0
        if n_spk > 1:
            if prof.arrival_order == "shuffle":
                perm = rng.permutation(n_spk)
            else:  # ascending speaker index (speakers are distinct)
                perm = np.argsort(spk, kind="stable")
            spk = spk[perm]
            text_arr = text_arr[perm]
            if by_volume:
                volumes = [volumes[k] for k in perm.tolist()]
        pos = np.asarray(positions, dtype=np.float64)
        hd = np.asarray(headings, dtype=np.float64)
        if pos.shape != (n, 2) or hd.shape != (n,):
            raise ChannelError(
                f"positions must be ({n}, 2) and headings ({n},), got {pos.shape} and {hd.shape}"
            )
        if not by_volume:
            return self._hear_by_capacity(spk, text_arr, illegal, np.ascontiguousarray(pos), hd)
        x, y = pos[:, 0], pos[:, 1]
        rel = (x[spk][:, None] - x, y[spk][:, None] - y)  # listener -> speaker, (S, N) each
        dist = np.hypot(*rel)
        chunks: list[tuple[np.ndarray, str]] = []
        if _max(dist, axis=None) <= prof.hearing_range_m:  # everyone (False for NaN)
            in_range = None
        else:
            in_range = dist <= prof.hearing_range_m
            if not in_range.all():
                chunks.append((~in_range, REASON_OUT_OF_RANGE))
        routing = _Routing(spk, text_arr, illegal, chunks, rel, dist, hd, in_range)
        return self._hear_by_loudness(routing, volumes, rng)

    def _hear_by_loudness(
        self, routing: _Routing, volumes: list[float], rng: np.random.Generator
    ) -> Delivery:
        """`mj`: loudest-first ranking, random loss of the quieter ones. Ranked by the
        equivalent distance d_eff (the distance from which a max-volume message arrives as
        loud), which orders like the received volume and feeds the loss model."""
        prof = self.profile
        n = self.n_agents
        dist, chunks = routing.dist, routing.chunks
        # Rows of the speakers: [self, same team, teammate (not self), opponent] x (S, N).
        masks = self._masks[:, routing.speakers]
        is_self = masks[0]
        audible = ~is_self if routing.in_range is None else routing.in_range & ~is_self
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
        if not prof.self_echo:
            # fast path: walk each listener's column in loudness order
            ranked = np.take_along_axis(survive, order, axis=0)
            kept = ranked & (np.cumsum(ranked, axis=0) <= prof.max_heard)
            if not np.array_equal(kept, ranked):
                r, c = np.nonzero(ranked & ~kept)
                over = np.zeros_like(survive)
                over[order[r, c], c] = True
                chunks.append((over, REASON_MAX_HEARD))
            li, r = np.nonzero(kept.T)
            return self._assemble_pairs(routing, masks, order[r, li], li)
        # A speaker that hears itself: its own message first, then the others by loudness.
        heard = survive | is_self
        sort_key = np.where(is_self, -1, rank + 1)
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
        return self._assemble_pairs(routing, masks, si, li)

    def _hear_by_capacity(self, speakers: np.ndarray, texts: np.ndarray, illegal: list[Drop],
                          positions: np.ndarray, headings: np.ndarray) -> Delivery:
        """`simspark`: within range, then per-listener hearing capacity in arrival order, per
        sender class (teammates, opponents); per listener its own message, then teammates',
        then opponents', at most `max_heard`; ranges, slots and directions in one compiled
        loop (`comms.capacity_kernel`)."""
        prof = self.profile
        cap = prof.capacity
        n = self.n_agents
        size = n * prof.max_heard
        pair_ids = np.empty((2, size), dtype=np.intp)
        pair_flags = np.empty((2, size), dtype=bool)
        directions = np.empty(size)
        # messages out of range, over capacity, over max_heard: (speaker slot, listener)
        masks = np.zeros((3, len(speakers), n), dtype=bool)
        count, any_out, any_over_capacity, any_over_max = _capacity_kernel()(
            speakers, self.teams, positions, headings, float(prof.hearing_range_m), self._cap,
            0 if cap is None else int(cap.cost), bool(prof.self_echo), int(prof.max_heard),
            float(prof.direction_quantum_deg), pair_ids, pair_flags, directions, masks[0],
            masks[1:])
        chunks = []
        if any_out:
            chunks.append((masks[0], REASON_OUT_OF_RANGE))
        if any_over_capacity:
            chunks.append((masks[1], REASON_CAPACITY))
        if any_over_max:
            chunks.append((masks[2], REASON_MAX_HEARD))
        si = pair_ids[1, :count]
        pairs = (pair_ids[0, :count], speakers[si], texts[si], directions[:count],
                 pair_flags[0, :count], pair_flags[1, :count])
        return Delivery(None, illegal, (speakers, chunks), pairs, n, True)

    def _assemble_pairs(
        self, routing: _Routing, masks: np.ndarray, si: np.ndarray, li: np.ndarray
    ) -> Delivery:
        """Build the Delivery from the (speaker slot, listener) pairs `_hear_by_loudness`
        picked, sorted per listener: whether each is the listener's own message, from its
        team, and the direction it is heard from."""
        rel_x, rel_y = routing.rel[0][si, li], routing.rel[1][si, li]
        pair_self = masks[0][si, li]
        ang = pm.arctan2(rel_y, rel_x) - routing.headings[li]
        ang = (ang + math.pi) % _TWO_PI - math.pi
        q = self.profile.direction_quantum_deg
        if q > 0.0:
            ang = np.trunc(ang * (180.0 / math.pi / q)) * (q * math.pi / 180.0)
        ang[pair_self] = 0.0
        spk = routing.speakers
        pairs = (li, spk[si], routing.texts[si], ang, pair_self, masks[1][si, li])
        return Delivery(None, routing.illegal, (spk, routing.chunks), pairs, self.n_agents)


def make_channel(
    profile: "str | ChannelProfile", n_agents: int, teams: Any, **overrides: Any
) -> Channel:
    """Build a Channel for `n_agents` agents; `teams` holds 0 (left) or 1 (right) per agent.

    `profile` is "simspark", "mj" or a ChannelProfile; keyword overrides replace profile
    fields (e.g. `max_heard=21`, `arrival_order="index"`); an unknown key is a ChannelError.
    """
    return Channel(get_profile(profile, **overrides), n_agents, teams)
