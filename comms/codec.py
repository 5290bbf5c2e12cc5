"""Text codecs: a non-negative integer of a fixed bit width <-> a legal say text."""

import base64
import binascii
import math
import re

from comms.errors import BudgetError, DecodeError, EncodeError, SchemaError
from comms.profiles import BASE64_ALPHABET, ChannelProfile

_B64_RE = re.compile("[A-Za-z0-9+/]*").fullmatch


class BoundCodec:
    """A codec fixed to one bit width: `encode(int) -> str` of exactly `chars` characters.

    Attributes: name (codec name), bits (payload width), chars (text length).
    """

    name: str
    bits: int
    chars: int

    def encode(self, value: int) -> str:  # pragma: no cover - interface
        raise NotImplementedError

    def decode(self, text: str) -> int:  # pragma: no cover - interface
        raise NotImplementedError

    def _check_value(self, value: int) -> None:
        if not 0 <= value < (1 << self.bits):
            raise EncodeError(f"{self.name}: value {value!r} does not fit in {self.bits} bits")

    def _check_text(self, text: object) -> str:
        if not isinstance(text, str):
            raise DecodeError(f"{self.name}: expected a str, got {type(text).__name__}")
        if len(text) != self.chars:
            raise DecodeError(
                f"{self.name}: expected {self.chars} characters, got {len(text)} ({text!r})"
            )
        return text

    def __repr__(self) -> str:
        return f"<{self.name} codec: {self.bits} bits in {self.chars} chars>"


class Base64Bits(BoundCodec):
    """6 bits per character over the RFC 4648 base64 alphabet, no padding (source docs' way).

    `bits` bits take ceil(bits / 6) characters; 20 characters carry 120 bits. Unused low-order
    bits of the last character must be zero on decode.
    """

    def __init__(self, bits: int) -> None:
        self.name = "base64"
        self.bits = bits
        self.chars = -(-bits // 6)
        self._quads = -(-self.chars // 4)  # whole 4-char / 3-byte groups
        self._shift = self._quads * 24 - bits  # zero bits appended below the value
        self._nbytes = self._quads * 3
        self._pad = "A" * (self._quads * 4 - self.chars)

    def encode(self, value: int) -> str:
        if value < 0 or value >> self.bits:
            self._check_value(value)
        raw = (value << self._shift).to_bytes(self._nbytes, "big")
        return base64.b64encode(raw).decode("ascii")[: self.chars]

    def decode(self, text: str) -> int:
        text = self._check_text(text)
        if _B64_RE(text) is None:
            bad = next(c for c in text if c not in BASE64_ALPHABET)
            raise DecodeError(f"base64: illegal character {bad!r} in {text!r}")
        v = int.from_bytes(base64.b64decode(text + self._pad), "big")
        if v & ((1 << self._shift) - 1):
            raise DecodeError(f"base64: unused low bits of {text!r} are not zero (corrupt)")
        return v >> self._shift


class BaseNBits(BoundCodec):
    """Big-integer packing: the value written in base N over an alphabet of N characters.

    `bits` bits take the smallest k with N**k >= 2**bits characters (92 symbols: 20 characters
    carry 130 bits). Values >= 2**bits are rejected on decode.
    """

    def __init__(self, bits: int, alphabet: str) -> None:
        self.name = f"base{len(alphabet)}"
        self.bits = bits
        self.alphabet = alphabet
        n = len(alphabet)
        k = 0
        while n**k < (1 << bits):
            k += 1
        self.chars = k
        self._n = n
        self._index = {c: i for i, c in enumerate(alphabet)}
        # two digits at a time through a table of N*N two-character strings
        self._pairs = [a + b for a in alphabet for b in alphabet]
        self._n2 = n * n

    def encode(self, value: int) -> str:
        if value < 0 or value >> self.bits:
            self._check_value(value)
        pairs = self._pairs
        n2 = self._n2
        parts = []
        k = self.chars
        while k >= 2:
            value, r = divmod(value, n2)
            parts.append(pairs[r])
            k -= 2
        if k:
            value, r = divmod(value, self._n)
            parts.append(self.alphabet[r])
        return "".join(reversed(parts))

    def decode(self, text: str) -> int:
        text = self._check_text(text)
        index = self._index
        n = self._n
        v = 0
        try:
            for c in text:
                v = v * n + index[c]
        except KeyError as e:
            raise DecodeError(f"{self.name}: illegal character {e.args[0]!r} in {text!r}") from None
        if v >> self.bits:
            raise DecodeError(
                f"{self.name}: {text!r} holds a value >= 2**{self.bits} (corrupt or foreign)"
            )
        return v


class BytesBase64(BoundCodec):
    """`mj`: the value as ceil(bits / 8) big-endian bytes, then padded base64 (RFC 4648)."""

    def __init__(self, bits: int) -> None:
        self.name = "bytes+base64"
        self.bits = bits
        self.nbytes = -(-bits // 8)
        self.chars = 4 * -(-self.nbytes // 3)

    def encode(self, value: int) -> str:
        if value < 0 or value >> self.bits:
            self._check_value(value)
        return base64.b64encode(value.to_bytes(self.nbytes, "big")).decode("ascii")

    def decode(self, text: str) -> int:
        text = self._check_text(text)
        try:
            raw = base64.b64decode(text, validate=True)
        except (binascii.Error, ValueError) as e:
            raise DecodeError(f"bytes+base64: {text!r} is not valid base64 ({e})") from None
        if len(raw) != self.nbytes:
            raise DecodeError(f"bytes+base64: expected {self.nbytes} bytes, got {len(raw)}")
        v = int.from_bytes(raw, "big")
        if v >> self.bits:
            raise DecodeError(
                f"bytes+base64: {text!r} holds a value >= 2**{self.bits} (corrupt or foreign)"
            )
        return v


CODEC_NAMES = ("auto", "base64", "baseN", "bytes+base64")


def codec_capacity(profile: ChannelProfile, codec: str) -> int:
    """Most bits a message can carry on `profile` with `codec` ("base64", "baseN",
    "bytes+base64"); 0 if the codec cannot be used on that channel."""
    if profile.base64_payload:
        return 8 * profile.payload_bytes if codec == "bytes+base64" else 0
    if codec == "base64":
        return 6 * profile.max_chars if set(BASE64_ALPHABET) <= set(profile.charset) else 0
    if codec == "baseN":
        return (len(profile.charset) ** profile.max_chars).bit_length() - 1
    return 0


def bind_codec(profile: ChannelProfile, codec: str, bits: int, what: str = "message") -> BoundCodec:
    """Choose and bind a codec for a `bits`-bit payload on `profile`.

    codec "auto": `mj` -> bytes+base64; `simspark` -> base64 if the payload fits in 6 bits per
    character (what the source documents do), else the base-N big integer over all legal
    characters. Raises BudgetError (naming `what`, the bits and the budget) if it cannot fit.
    """
    if codec not in CODEC_NAMES:
        raise SchemaError(f"{what}: unknown codec {codec!r}; known: {CODEC_NAMES}")
    if codec == "auto":
        if profile.base64_payload:
            codec = "bytes+base64"
        elif bits <= codec_capacity(profile, "base64"):
            codec = "base64"
        else:
            codec = "baseN"
    capacity = codec_capacity(profile, codec)
    if bits > capacity:
        others = {c: codec_capacity(profile, c) for c in CODEC_NAMES[1:]}
        raise BudgetError(
            f"{what} needs {bits} bits but channel {profile.name!r} with codec {codec!r} "
            f"holds {capacity} bits (capacities: {others})"
        )
    if codec == "base64":
        return Base64Bits(bits)
    if codec == "baseN":
        return BaseNBits(bits, profile.charset)
    return BytesBase64(bits)


def bits_for(cardinality: int) -> int:
    """Bits to hold one of `cardinality` values: ceil(log2(cardinality))."""
    return (cardinality - 1).bit_length() if cardinality > 1 else 0


def log2_cardinality(cardinality: int) -> float:
    """Information content in bits of one of `cardinality` equally likely values."""
    return math.log2(cardinality) if cardinality > 0 else 0.0
