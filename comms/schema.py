"""Declarative message schemas: typed fields packed into bits, bits into a legal say text.

The field types (`Int`, `Bool`, `Enum`, `Fixed`, `Permutation`, `Array`) are defined in
`comms.fields` and importable from here too."""

import functools
import math
import operator
import zlib
from collections import namedtuple
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from comms.codec import BoundCodec, bind_codec, bits_for
from comms.errors import DecodeError, EncodeError, SchemaError
from comms.fields import Array as Array
from comms.fields import Bool as Bool
from comms.fields import Enum as Enum
from comms.fields import Field, _check_name
from comms.fields import Fixed as Fixed
from comms.fields import Int as Int
from comms.fields import Permutation as Permutation
from comms.profiles import ChannelProfile, get_profile

_CACHE_MAX = 4096
_tuple_new = tuple.__new__  # builds a namedtuple from a list without Python-level calls


@functools.cache
def record_class(name: str, names: tuple[str, ...]) -> type:
    """The namedtuple class of a schema's records, one per (name, fields) in a process.

    Built at run time, so pickle could not find it by name: its records pickle (and copy) as
    a call that rebuilds them through this function, in any process."""
    cls = namedtuple(name, names)  # noqa: PYI024 - built at runtime
    cls.__reduce__ = lambda self: (_rebuild_record, (name, names, tuple(self)))
    return cls


def _rebuild_record(name: str, names: tuple[str, ...], values: tuple) -> Any:
    return record_class(name, names)._make(values)


class Schema:
    """A message type: named fields, packed into bits, encoded as one legal say text.

    Args:
        name: identifier of the message type (also seeds the check bits).
        fields: the Field objects, in order (first field in the least significant bits).
        channel: "simspark", "mj" or a ChannelProfile; the budget is checked here, at
            declaration: a schema that cannot fit raises BudgetError.
        codec: "auto" (simspark: base64 if it fits, else base-92 big integer; mj: bytes +
            base64), or "base64" / "baseN" / "bytes+base64".
        packing: "bits" (each field gets ceil(log2(cardinality)) bits at a fixed offset) or
            "radix" (the whole message is one mixed-radix number: ceil(log2(product of
            cardinalities)) bits; tighter, no fixed bit offsets).
        check_bits: CRC bits (of the payload, seeded by the schema name) appended on top;
            a corrupt or foreign text then fails to decode with probability 1 - 2**-check_bits.
        tag, tag_bits: an optional message-type id 0..2**tag_bits-1 in the lowest bits, so
            several schemas can share a channel (see `decode_any`).

    `encode(values)` takes a mapping (or the Record, or keywords) and returns the text;
    `decode(text)` returns a `Record` (a namedtuple of the fields) or raises DecodeError.
    Decoded Records are immutable and cached per text (up to 4096 per schema), and `encode`
    primes that cache, so the 10 teammates decoding a text cost one dictionary lookup each.
    """

    def __init__(
        self,
        name: str,
        fields: Sequence[Field],
        *,
        channel: "str | ChannelProfile" = "simspark",
        codec: str = "auto",
        packing: str = "bits",
        check_bits: int = 0,
        tag: int | None = None,
        tag_bits: int = 0,
    ) -> None:
        self.name: str = _check_name(name, "schema")
        fields = tuple(fields)
        if not fields:
            raise SchemaError(f"schema {name!r}: needs at least one field")
        for f in fields:
            if not isinstance(f, Field):
                raise SchemaError(f"schema {name!r}: {f!r} is not a Field")
        names = [f.name for f in fields]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise SchemaError(f"schema {name!r}: repeated field names {sorted(dup)}")
        if packing not in ("bits", "radix"):
            raise SchemaError(
                f"schema {name!r}: packing must be 'bits' or 'radix', got {packing!r}"
            )
        check_bits = operator.index(check_bits)
        tag_bits = operator.index(tag_bits)
        if not 0 <= check_bits <= 32:
            raise SchemaError(f"schema {name!r}: check_bits must be 0..32, got {check_bits}")
        if (tag is None) != (tag_bits == 0) or tag_bits < 0:
            raise SchemaError(f"schema {name!r}: give both tag and tag_bits > 0, or neither")
        if tag is not None and not 0 <= tag < (1 << tag_bits):
            raise SchemaError(f"schema {name!r}: tag {tag} does not fit in {tag_bits} bits")
        self.fields: tuple[Field, ...] = fields
        self.profile: ChannelProfile = get_profile(channel)
        self.packing: str = packing
        self.check_bits: int = check_bits
        self.tag: int | None = tag
        self.tag_bits: int = tag_bits
        self._codec_request = codec

        # slot sizes: the tag, then the fields
        sizes = [1 << tag_bits] if tag_bits else []
        for f in fields:
            sizes.append(1 << f.bits if packing == "bits" else f.cardinality)
        space = math.prod(sizes)
        self.payload_bits: int = bits_for(space)
        self.bits: int = self.payload_bits + check_bits
        self.codec: BoundCodec = bind_codec(self.profile, codec, self.bits, what=f"schema {name!r}")
        self._space = space
        self._check_pos = 1 << self.payload_bits
        self._payload_mask = self._check_pos - 1
        self._check_mask = (1 << check_bits) - 1
        self._check_seed = zlib.crc32(name.encode())
        self._payload_nbytes = (self.payload_bits + 7) // 8
        weights = []
        w = sizes[0] if tag_bits else 1
        offset = tag_bits
        self._offsets = []
        for f, size in zip(fields, sizes[1:] if tag_bits else sizes, strict=True):
            weights.append(w)
            self._offsets.append(offset)
            w *= size
            offset += f.bits
        self._enc = tuple(zip(fields, weights, strict=True))
        self._dec = tuple(
            (f, size, f.cardinality)
            for f, size in zip(fields, sizes[1:] if tag_bits else sizes, strict=True)
        )
        self._tag_size = sizes[0] if tag_bits else 1
        self._n_fields = len(fields)
        self._names = tuple(names)
        self.Record = record_class(name, tuple(names))
        self._cache: dict[str, Any] = {}

    def __getstate__(self) -> dict[str, Any]:
        # the Record class is built at run time: pickled as its name and fields
        state = self.__dict__.copy()
        state["Record"] = (self.Record.__name__, self.Record._fields)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self.Record = record_class(*state["Record"])

    # ------------------------------------------------------------ properties
    @property
    def chars(self) -> int:
        """Length of every encoded text, in characters."""
        return self.codec.chars

    @property
    def codec_name(self) -> str:
        """Name of the codec in use ("base64", "base92", "bytes+base64")."""
        return self.codec.name

    @property
    def field_names(self) -> tuple[str, ...]:
        """Field names, in order."""
        return self.Record._fields

    @property
    def information_bits(self) -> float:
        """log2 of the number of distinct messages (lower bound for any packing)."""
        return self.tag_bits + sum(math.log2(f.cardinality) for f in self.fields)

    def for_channel(self, channel: "str | ChannelProfile", codec: str = "auto") -> "Schema":
        """The same message type declared for another channel (budget checked again)."""
        return Schema(
            self.name,
            self.fields,
            channel=channel,
            codec=codec,
            packing=self.packing,
            check_bits=self.check_bits,
            tag=self.tag,
            tag_bits=self.tag_bits,
        )

    # ------------------------------------------------------------ encode / decode
    def encode(self, values: Any = None, /, **kwargs: Any) -> str:
        """Encode the field values (a mapping, a Record, or keywords) into a legal say text.

        Raises:
            EncodeError: a missing or unknown field, or a value its field cannot hold.
        """
        if values is None:
            values = kwargs
        elif kwargs:
            raise EncodeError(f"schema {self.name!r}: give a mapping or keywords, not both")
        if type(values) is dict or isinstance(values, Mapping):
            try:
                items = [values[k] for k in self._names]
            except KeyError:
                items = None
            if items is None or len(values) != self._n_fields:
                missing = [k for k in self._names if k not in values]
                extra = [k for k in values if k not in self._names]
                raise EncodeError(
                    f"schema {self.name!r}: missing fields {missing}, unknown fields {extra}"
                )
        elif type(values) is self.Record or getattr(values, "_fields", None) == self._names:
            items = values  # this schema's Record, or any namedtuple with the same fields
        else:
            raise EncodeError(
                f"schema {self.name!r}: values must be a mapping or {self.name}.Record, "
                f"got {type(values).__name__}"
            )
        v = self.tag or 0
        decoded = []
        for (f, w), x in zip(self._enc, items, strict=True):
            raw = f.to_raw(x)
            v += raw * w
            decoded.append(f.canonical(x, raw))
        if self.check_bits:
            v |= self._crc(v) << self.payload_bits
        text = self.codec.encode(v)
        # prime the decode cache: teammates in this process decode this text for free
        cache = self._cache
        if len(cache) >= _CACHE_MAX:
            cache.clear()
        cache[text] = _tuple_new(self.Record, decoded)
        return text

    def _crc(self, payload: int) -> int:
        return (
            zlib.crc32(payload.to_bytes(self._payload_nbytes, "little"), self._check_seed)
            & self._check_mask
        )

    def decode(self, text: str) -> Any:
        """Decode a received text into a Record; never returns garbage silently.

        Raises:
            DecodeError: wrong length or character, a field value out of range, a wrong tag,
                a failed check, or bits set beyond the schema (corrupt or another message type).
        """
        try:
            hit = self._cache.get(text)
        except TypeError:
            raise DecodeError(
                f"schema {self.name!r}: expected a str, got {type(text).__name__}"
            ) from None
        if hit is not None:
            return hit
        try:
            v = self.codec.decode(text)
        except DecodeError as e:
            raise DecodeError(f"schema {self.name!r}: {e}") from None
        if self.check_bits:
            payload = v & self._payload_mask
            if v >> self.payload_bits != self._crc(payload):
                raise DecodeError(
                    f"schema {self.name!r}: check bits of {text!r} do not match "
                    f"(corrupt or another message type)"
                )
            v = payload
        if v >= self._space:
            raise DecodeError(
                f"schema {self.name!r}: {text!r} sets bits beyond the schema "
                f"(corrupt or another message type)"
            )
        if self.tag_bits:
            v, t = divmod(v, self._tag_size)
            if t != self.tag:
                raise DecodeError(
                    f"schema {self.name!r}: tag {t} in {text!r}, expected {self.tag} "
                    f"(another message type)"
                )
        out = []
        for f, size, card in self._dec:
            v, raw = divmod(v, size)
            if raw >= card:
                raise DecodeError(
                    f"schema {self.name!r}: field {f.name!r} raw value {raw} out of range "
                    f"0..{card - 1} in {text!r} (corrupt or another message type)"
                )
            out.append(f.from_raw(raw))
        rec = _tuple_new(self.Record, out)
        cache = self._cache
        if len(cache) >= _CACHE_MAX:
            cache.clear()
        cache[text] = rec
        return rec

    def is_valid(self, text: str) -> bool:
        """True if `text` decodes under this schema."""
        try:
            self.decode(text)
        except DecodeError:
            return False
        return True

    # ------------------------------------------------------------ helpers
    def quantize(self, values: Mapping[str, Any]) -> Any:
        """The Record a receiver gets for `values` (fixed-point fields rounded)."""
        return self.Record._make(f.quantize(values[f.name]) for f in self.fields)

    def random_values(self, rng: np.random.Generator) -> Any:
        """A Record of uniformly random legal values (for property tests)."""
        return self.Record._make(f.random_value(rng) for f in self.fields)

    def extreme_values(self) -> list[Any]:
        """Records with every field at its minimum, at its maximum, and mixed."""
        ext = [f.extreme_values() for f in self.fields]
        recs = [
            self.Record._make(e[0] for e in ext),
            self.Record._make(e[1] for e in ext),
            self.Record._make(e[i % 2] for i, e in enumerate(ext)),
            self.Record._make(e[(i + 1) % 2] for i, e in enumerate(ext)),
        ]
        return recs

    def budget_bits(self) -> int:
        """Capacity (bits) of the chosen codec on this schema's channel."""
        from comms.codec import codec_capacity

        name = self.codec.name
        key = (
            "bytes+base64"
            if name == "bytes+base64"
            else ("base64" if name == "base64" else "baseN")
        )
        return codec_capacity(self.profile, key)

    def layout(self) -> str:
        """A table of the bit layout: offset, width and range of every field."""
        lines = [
            f"schema {self.name!r} on channel {self.profile.name!r}: {self.bits} bits "
            f"({self.information_bits:.1f} bits of information), codec {self.codec.name}, "
            f"{self.chars} chars, budget {self.budget_bits()} bits, packing {self.packing}",
            f"{'offset':>6} {'bits':>5}  {'field':<16} range",
        ]
        if self.tag_bits:
            lines.append(f"{0:>6} {self.tag_bits:>5}  {'(tag)':<16} = {self.tag}")
        if self.packing == "bits":
            for f, off in zip(self.fields, self._offsets, strict=True):
                lines.append(f"{off:>6} {f.bits:>5}  {f.name:<16} {f.describe()}")
        else:
            for f in self.fields:
                lb = math.log2(f.cardinality) if f.cardinality > 1 else 0.0
                lines.append(f"{'radix':>6} {lb:>5.1f}  {f.name:<16} {f.describe()}")
        if self.check_bits:
            lines.append(
                f"{self.payload_bits:>6} {self.check_bits:>5}  {'(check)':<16} CRC-32, low {self.check_bits} bits"
            )
        return "\n".join(lines)

    def __repr__(self) -> str:
        return (
            f"Schema({self.name!r}, {self.bits} bits, {self.codec.name}, {self.chars} chars, "
            f"channel={self.profile.name!r})"
        )


def decode_any(text: str, schemas: Sequence[Schema]) -> tuple[Schema, Any]:
    """Decode `text` with the first schema that accepts it (tags / check bits tell them apart).

    Raises DecodeError listing every schema's complaint if none accepts it.
    """
    errors = []
    for s in schemas:
        try:
            return s, s.decode(text)
        except DecodeError as e:
            errors.append(str(e))
    raise DecodeError(f"no schema accepts {text!r}: " + "; ".join(errors))
