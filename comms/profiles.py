"""Say-channel profiles: the league rules (alphabet, length, hearing model) as frozen data."""

import math
import re
from dataclasses import dataclass, field, fields, replace
from typing import Any, Literal

from comms.errors import ChannelError
from paramkit import Registry
from paramkit.checks import check_fields, in_range, invalid, non_negative, positive

#: SimSpark: every printable ASCII character 0x21-0x7E except the S-expression parentheses.
SIMSPARK_CHARSET: str = "".join(chr(c) for c in range(0x21, 0x7F) if chr(c) not in "()")
#: Standard base64 alphabet (RFC 4648 section 4), the data characters of an `mj` message.
BASE64_ALPHABET: str = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/"
#: `mj`: base64 with mandatory padding.
MJ_CHARSET: str = BASE64_ALPHABET + "="

#: Reasons `check_message` can return (and `Drop.reason` values for illegal messages).
REASON_NOT_A_STRING = "not_a_string"
REASON_TOO_LONG = "too_long"
REASON_ILLEGAL_CHARACTER = "illegal_character"
REASON_BAD_BASE64 = "bad_base64"
REASON_BAD_VOLUME = "bad_volume"


@dataclass(frozen=True)
class HearingCapacity:
    """SimSpark's per-listener hearing budget (AgentState): one counter per sender class.

    Each listener keeps two counters, one for teammates and one for opponents. Both start at
    `maximum`; every cycle each gains `increment` (capped at `maximum`); hearing a message needs
    the counter to be at least `cost` and subtracts `cost`. With the league's numbers (2, 1, 2)
    a listener hears at most one teammate and one opponent message every 2 cycles.
    """

    maximum: int = field(default=2, metadata=non_negative())
    increment: int = field(default=1, metadata=non_negative())
    cost: int = field(default=2, metadata=positive())

    def __post_init__(self) -> None:
        check_fields(self, ChannelError)


@dataclass(frozen=True)
class ChannelProfile:
    """Rules of one say channel. Units: metres, cycles, dB, percent of volume.

    Attributes:
        name: profile name (`"simspark"` or `"mj"`).
        max_chars: longest legal `say` text in characters.
        charset: every legal character, as one string.
        max_heard: most messages one listener receives per cycle (slots in the observation).
        payload_bits: the channel's raw capacity in bits for one message (`mj`: 10 bytes = 80;
            `simspark`: 20 characters of 92 symbols = 130, base-92 big-integer packing).
        base64_payload: the text is the padded base64 of at most `payload_bytes` bytes (`mj`).
        payload_bytes: most payload bytes before base64 (`mj` only, else None).
        hearing_range_m: listeners farther than this never hear (`math.inf`: no hard limit).
        self_echo: a speaker hears its own message (not charged against its capacity).
        capacity: SimSpark hearing-capacity model, or None for no capacity limit.
        always_heard: `mj`: this many loudest messages per listener are never lost.
        attenuation_db_per_doubling: `mj`: received volume falls this many dB per doubling of
            distance beyond `reference_distance_m`.
        reference_distance_m: distance (m) under which no attenuation applies.
        loss_midpoint_m: `mj`: a volume-100 message from this far is lost with probability 0.5
            (distance-based loss of RCSSServerMJ: p = 0.5 tanh(pi d / mid - pi) + 0.5).
        max_volume: loudest legal `Utterance.volume` (percent).
        delay_cycles: a message said in cycle t is heard in the observation of cycle t +
            delay_cycles; 1 (the league) means `deliver` returns it at once and the env puts it
            into the next observation; larger values are queued inside the channel.
        arrival_order: order in which one cycle's messages arrive at the listeners (it decides
            which are dropped by the capacity model): `"shuffle"` (a permutation drawn from the
            env's Generator each cycle with 2+ speakers) or `"index"` (ascending speaker index).
        direction_quantum_deg: heard directions are truncated (towards 0) to multiples of this
            many degrees (`mj` reports integer degrees); 0 keeps them exact.
    """

    name: str
    max_chars: int = field(metadata=non_negative())
    charset: str
    max_heard: int = field(metadata=non_negative())
    payload_bits: int = field(metadata=non_negative())
    base64_payload: bool = False
    payload_bytes: int | None = field(default=None, metadata=non_negative())
    hearing_range_m: float = field(default=math.inf, metadata=non_negative(infinite=True))
    self_echo: bool = False
    capacity: HearingCapacity | None = None
    always_heard: int = field(default=0, metadata=non_negative())
    attenuation_db_per_doubling: float = field(default=0.0, metadata=non_negative())
    reference_distance_m: float = field(default=1.0, metadata=positive())
    loss_midpoint_m: float = field(default=math.inf, metadata=positive(infinite=True))
    max_volume: float = field(default=100.0, metadata=positive())
    delay_cycles: int = field(default=1, metadata=in_range(1))
    arrival_order: Literal["shuffle", "index"] = "shuffle"
    direction_quantum_deg: float = field(default=0.0, metadata=non_negative())
    _charset_set: frozenset = field(init=False, repr=False, compare=False)
    _legal_re: Any = field(init=False, repr=False, compare=False)
    _batch_re: Any = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        check_fields(self, ChannelError)
        if self.base64_payload and not self.payload_bytes:
            raise invalid(self, "payload_bytes", "> 0 with base64_payload", ChannelError)
        object.__setattr__(self, "_charset_set", frozenset(self.charset))
        object.__setattr__(
            self, "_legal_re", re.compile("[" + re.escape(self.charset) + "]*").fullmatch
        )
        object.__setattr__(self, "_batch_re", _batch_pattern(self))

    def all_legal(self, texts: Any) -> bool:
        """True when every text of `texts` (a sequence of str) is a legal, non-empty say text,
        i.e. `check_message(t) is None and t != ""` for each: one regular-expression match over
        all of them. False when any is not (or is not a str); `check_message` then says why."""
        batch = self._batch_re
        if batch is None:
            return all(type(t) is str and t and self.check_message(t) is None for t in texts)
        if not texts:
            return True
        try:
            joined = _SEP.join(texts)
        except TypeError:
            return False
        # A text holding the separator itself would split in two: count them.
        return joined.count(_SEP) == len(texts) - 1 and batch(joined + _SEP) is not None

    def check_message(self, text: Any) -> str | None:
        """Return None if `text` is a legal say text under this profile, else the reason.

        Reasons: "not_a_string", "too_long", "illegal_character", "bad_base64" (`mj`: length
        not a multiple of 4 or misplaced padding). The empty string is legal (silence).
        """
        if not isinstance(text, str):
            return REASON_NOT_A_STRING
        if len(text) > self.max_chars:
            return REASON_TOO_LONG
        if self._legal_re(text) is None:
            return REASON_ILLEGAL_CHARACTER
        if self.base64_payload and text:
            if len(text) % 4 or _PADDED_B64(text) is None:
                return REASON_BAD_BASE64
            n_bytes = len(text) // 4 * 3 - (len(text) - len(text.rstrip("=")))
            if n_bytes > self.payload_bytes:
                return REASON_TOO_LONG
        return None


    def heard_text(self, text: str) -> str:
        """The text listeners hear when a legal `text` is said: on `mj` the canonical base64 of
        its bytes (the server decodes a say and re-encodes what it delivers, so "AZjglD==" and
        "AZjglA==" are one message, heard as "AZjglA=="), elsewhere `text` itself."""
        if not self.base64_payload or not text.endswith("="):
            return text  # unpadded base64 uses every bit of its last character
        if text.endswith("=="):
            last, unused = -3, 0b1111
        else:
            last, unused = -2, 0b11
        value = BASE64_ALPHABET.find(text[last])
        if value & unused == 0:
            return text
        return text[:last] + BASE64_ALPHABET[value & ~unused] + text[last + 1:]


_PADDED_B64 = re.compile("[A-Za-z0-9+/]*={0,2}").fullmatch
_SEP = "\n"  # separates the texts of one `all_legal` match (not a legal character there)


def _batch_pattern(profile: "ChannelProfile") -> Any:
    """The `fullmatch` of a pattern matching "text\n" repeated, for legal non-empty texts of
    `profile` (None when "\n" is a legal character: `all_legal` then checks text by text)."""
    if _SEP in profile.charset:
        return None
    if not profile.base64_payload:
        if profile.max_chars < 1:
            return re.compile(re.escape(_SEP) + "{0}").fullmatch  # only the empty batch
        one = "[" + re.escape(profile.charset) + f"]{{1,{profile.max_chars}}}"
    else:
        # Padded base64 of 1..payload_bytes bytes, at most max_chars characters, using only
        # characters of the charset: g full groups of 4, then a full, "xxx=" or "xx==" group.
        data = "".join(c for c in BASE64_ALPHABET if c in profile.charset)
        d = "[" + re.escape(data) + "]"
        pad_ok = "=" in profile.charset
        alts = []
        for g in range(profile.max_chars // 4):
            lead = d + f"{{{4 * g}}}" if g else ""
            if 4 * (g + 1) > profile.max_chars:
                break
            if 3 * g + 3 <= profile.payload_bytes:
                alts.append(lead + d + "{4}")
            if pad_ok and 3 * g + 2 <= profile.payload_bytes:
                alts.append(lead + d + "{3}=")
            if pad_ok and 3 * g + 1 <= profile.payload_bytes:
                alts.append(lead + d + "{2}==")
        if not alts:
            return re.compile(re.escape(_SEP) + "{0}").fullmatch
        one = "(?:" + "|".join(alts) + ")"
    return re.compile("(?:" + one + re.escape(_SEP) + ")*").fullmatch

SIMSPARK = ChannelProfile(
    name="simspark",
    max_chars=20,
    charset=SIMSPARK_CHARSET,
    max_heard=3,  # self, one teammate, one opponent (the capacity model allows no more)
    payload_bits=int(20 * math.log2(len(SIMSPARK_CHARSET))),  # 130
    hearing_range_m=50.0,
    self_echo=True,
    capacity=HearingCapacity(maximum=2, increment=1, cost=2),
)

MJ = ChannelProfile(
    name="mj",
    max_chars=16,  # base64 of 10 bytes, padded: 4 * ceil(10 / 3)
    charset=MJ_CHARSET,
    # The server itself has no cap; observations need a fixed number of slots. 3 loudest
    # (never lost) + up to 5 more survivors of the random loss, loudest first.
    max_heard=8,
    payload_bits=80,
    base64_payload=True,
    payload_bytes=10,
    self_echo=False,  # RCSSServerMJ: "the sending agent will not receive its own message"
    always_heard=3,
    attenuation_db_per_doubling=6.0,
    reference_distance_m=1.0,
    loss_midpoint_m=50.0,
    direction_quantum_deg=1.0,
)

#: The channel profiles by name (a ``paramkit.Registry``, as the vision and locomotion profiles):
#: ``PROFILES.register("mine", replace(SIMSPARK, name="mine", max_chars=10))`` adds one that
#: ``get_profile``, ``make_channel`` and the env's ``channel=`` then accept.
PROFILES: Registry[ChannelProfile] = Registry("channel profile", ChannelError)
PROFILES.register(SIMSPARK.name, SIMSPARK)
PROFILES.register(MJ.name, MJ)

_OVERRIDABLE = frozenset(f.name for f in fields(ChannelProfile) if f.init) - {"name"}


def get_profile(name: "str | ChannelProfile", **overrides: Any) -> ChannelProfile:
    """Return the named profile (or the given one), with `overrides` applied.

    Raises ChannelError for an unknown name or an unknown override key.
    """
    profile = name if isinstance(name, ChannelProfile) else PROFILES.get(name)
    if overrides:
        unknown = set(overrides) - _OVERRIDABLE
        if unknown:
            raise ChannelError(
                f"unknown channel option(s) {sorted(unknown)} for profile {profile.name!r}; "
                f"known: {sorted(_OVERRIDABLE)}"
            )
        profile = replace(profile, **overrides)
    return profile
