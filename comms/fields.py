"""The typed fields of a message schema: each maps its values to the integers
0..cardinality-1 and back (`to_raw`, `from_raw`); `comms.schema.Schema` packs those integers
into bits and the bits into a say text."""

import keyword
import math
import operator
import re
from collections.abc import Sequence
from typing import Any

import numpy as np

from comms.codec import bits_for
from comms.errors import EncodeError, SchemaError
from comms.permutation import lehmer_rank, lehmer_unrank

_NAME_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]*").fullmatch


def _check_name(name: Any, what: str) -> str:
    if not isinstance(name, str) or not _NAME_RE(name) or keyword.iskeyword(name):
        raise SchemaError(
            f"{what} name {name!r} must be an identifier (letters, digits, _; not a keyword)"
        )
    return name



class Field:
    """A typed message field: maps its values to raw integers 0..cardinality-1 and back."""

    kind = "field"

    def __init__(self, name: str, cardinality: int) -> None:
        self.name: str = _check_name(name, "field")
        if cardinality < 1:
            raise SchemaError(f"field {name!r}: cardinality must be >= 1, got {cardinality}")
        self.cardinality: int = cardinality

    @property
    def bits(self) -> int:
        """Bits this field takes with bit packing: ceil(log2(cardinality))."""
        return bits_for(self.cardinality)

    def to_raw(self, value: Any) -> int:  # pragma: no cover - interface
        raise NotImplementedError

    def from_raw(self, raw: int) -> Any:  # pragma: no cover - interface
        raise NotImplementedError

    def describe(self) -> str:
        """One-line human description of the value range."""
        return self.kind

    def random_value(self, rng: np.random.Generator) -> Any:
        """A uniformly random legal value (for property tests)."""
        return self.from_raw(int(rng.integers(self.cardinality)))

    def extreme_values(self) -> list[Any]:
        """The smallest and largest legal values (raw 0 and cardinality-1)."""
        return [self.from_raw(0), self.from_raw(self.cardinality - 1)]

    def quantize(self, value: Any) -> Any:
        """The value the receiver will get for `value` (identity except for Fixed)."""
        return self.from_raw(self.to_raw(value))

    def canonical(self, value: Any, raw: int) -> Any:
        """What `from_raw(raw)` returns, given the encoded `value` (overridden where cheaper)."""
        return self.from_raw(raw)

    def _bad(self, value: Any, why: str) -> EncodeError:
        return EncodeError(f"field {self.name!r}: value {value!r} {why}")

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}: {self.describe()})"


class Int(Field):
    """A bounded integer lo..hi (inclusive)."""

    kind = "int"

    def __init__(self, name: str, lo: int, hi: int) -> None:
        lo, hi = operator.index(lo), operator.index(hi)
        if hi < lo:
            raise SchemaError(f"field {name!r}: empty range [{lo}, {hi}]")
        super().__init__(name, hi - lo + 1)
        self.lo, self.hi = lo, hi

    def to_raw(self, value: Any) -> int:
        if type(value) is not int:
            if isinstance(value, bool | float) or not isinstance(value, int | np.integer):
                raise self._bad(value, "is not an int")
            value = int(value)
        if not self.lo <= value <= self.hi:
            raise self._bad(value, f"is outside [{self.lo}, {self.hi}]")
        return value - self.lo

    def from_raw(self, raw: int) -> int:
        return self.lo + raw

    def describe(self) -> str:
        return f"int [{self.lo}, {self.hi}]"


class Bool(Field):
    """A flag: False/True (0/1 accepted)."""

    kind = "bool"

    def __init__(self, name: str) -> None:
        super().__init__(name, 2)

    def to_raw(self, value: Any) -> int:
        if value is True or value is False:
            return int(value)
        if isinstance(value, int | np.integer | np.bool_) and value in (0, 1):
            return int(value)
        raise self._bad(value, "is not a bool")

    def from_raw(self, raw: int) -> bool:
        return bool(raw)

    def describe(self) -> str:
        return "bool"


class Enum(Field):
    """One of a fixed tuple of choices (any hashable values, e.g. strings)."""

    kind = "enum"

    def __init__(self, name: str, choices: Sequence[Any]) -> None:
        choices = tuple(choices)
        if not choices:
            raise SchemaError(f"field {name!r}: enum needs at least one choice")
        if len(set(choices)) != len(choices):
            raise SchemaError(f"field {name!r}: enum choices repeat: {choices!r}")
        super().__init__(name, len(choices))
        self.choices = choices
        self._index = {c: i for i, c in enumerate(choices)}

    def to_raw(self, value: Any) -> int:
        try:
            return self._index[value]
        except (KeyError, TypeError):
            raise self._bad(value, f"is not one of {self.choices!r}") from None

    def from_raw(self, raw: int) -> Any:
        return self.choices[raw]

    def describe(self) -> str:
        return f"enum {list(self.choices)!r}"


class Fixed(Field):
    """A fixed-point float on the grid lo, lo+resolution, ... covering [lo, hi].

    If hi is not on the grid it is raised to the next grid point (`field.hi` shows it).

    Encoding rounds to the nearest grid point (error <= resolution / 2). Values outside
    [lo, hi] raise EncodeError, or are clipped when `clip=True`. NaN always raises.
    """

    kind = "fixed"

    def __init__(
        self, name: str, lo: float, hi: float, resolution: float, clip: bool = False
    ) -> None:
        lo, hi, resolution = float(lo), float(hi), float(resolution)
        if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
            raise SchemaError(f"field {name!r}: need finite lo < hi, got [{lo}, {hi}]")
        if not (math.isfinite(resolution) and resolution > 0):
            raise SchemaError(f"field {name!r}: resolution must be > 0, got {resolution}")
        steps = math.ceil((hi - lo) / resolution - 1e-9)
        super().__init__(name, steps + 1)
        hi = round(lo + steps * resolution, 12)  # hi rounded up onto the grid
        self.lo, self.hi, self.resolution, self.clip = lo, hi, resolution, clip
        self._steps = steps
        self._tol = 1e-9 * max(1.0, abs(lo), abs(hi))

    def to_raw(self, value: Any) -> int:
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise self._bad(value, "is not a number") from None
        if not self.lo - self._tol <= v <= self.hi + self._tol:
            if v != v:
                raise self._bad(value, "is NaN")
            if not self.clip:
                raise self._bad(value, f"is outside [{self.lo}, {self.hi}] (use clip=True)")
            v = self.lo if v < self.lo else self.hi
        k = round((v - self.lo) / self.resolution)
        return 0 if k < 0 else (self._steps if k > self._steps else k)

    def from_raw(self, raw: int) -> float:
        return round(self.lo + raw * self.resolution, 12)

    def describe(self) -> str:
        return f"fixed [{self.lo:g}, {self.hi:g}] step {self.resolution:g}"

    def random_value(self, rng: np.random.Generator) -> float:
        return float(rng.uniform(self.lo, self.hi))

    def extreme_values(self) -> list[float]:
        return [self.lo, self.hi]


class Permutation(Field):
    """A permutation of start..start+n-1 (e.g. a role vector), sent as its Lehmer rank.

    Decodes to a tuple. n = 11 takes 26 bits (log2 11! = 25.25).
    """

    kind = "perm"

    def __init__(self, name: str, n: int, start: int = 0) -> None:
        n = operator.index(n)
        if not 1 <= n <= 34:
            raise SchemaError(f"field {name!r}: permutation size must be 1..34, got {n}")
        super().__init__(name, math.factorial(n))
        self.n, self.start = n, operator.index(start)

    def to_raw(self, value: Any) -> int:
        try:
            if len(value) != self.n:
                raise self._bad(value, f"has length {len(value)}, expected {self.n}")
        except TypeError:
            raise self._bad(value, "is not a sequence") from None
        try:
            return lehmer_rank(value, self.start)
        except EncodeError as e:
            raise EncodeError(f"field {self.name!r}: {e}") from None

    def from_raw(self, raw: int) -> tuple[int, ...]:
        return tuple(lehmer_unrank(raw, self.n, self.start))

    def canonical(self, value: Any, raw: int) -> tuple[int, ...]:
        # `value` was just validated as a permutation: it is its own decoding
        return tuple(map(int, value))

    def describe(self) -> str:
        return f"permutation of {self.start}..{self.start + self.n - 1}"

    def random_value(self, rng: np.random.Generator) -> tuple[int, ...]:
        return tuple(int(x) + self.start for x in rng.permutation(self.n))


class Array(Field):
    """`count` values of one element field, mixed-radix packed (decodes to a tuple)."""

    kind = "array"

    def __init__(self, name: str, element: Field, count: int) -> None:
        count = operator.index(count)
        if count < 1:
            raise SchemaError(f"field {name!r}: array count must be >= 1, got {count}")
        if not isinstance(element, Field):
            raise SchemaError(f"field {name!r}: element must be a Field, got {element!r}")
        super().__init__(name, element.cardinality**count)
        self.element, self.count = element, count

    def to_raw(self, value: Any) -> int:
        try:
            n = len(value)
        except TypeError:
            raise self._bad(value, "is not a sequence") from None
        if n != self.count:
            raise self._bad(value, f"has length {n}, expected {self.count}")
        el = self.element
        card = el.cardinality
        raw = 0
        for i in range(self.count - 1, -1, -1):
            try:
                raw = raw * card + el.to_raw(value[i])
            except EncodeError as e:
                raise EncodeError(f"field {self.name!r}[{i}]: {e}") from None
        return raw

    def from_raw(self, raw: int) -> tuple[Any, ...]:
        el = self.element
        card = el.cardinality
        out = []
        for _ in range(self.count):
            raw, r = divmod(raw, card)
            out.append(el.from_raw(r))
        return tuple(out)

    def describe(self) -> str:
        return f"{self.count} x {self.element.describe()}"

    def random_value(self, rng: np.random.Generator) -> tuple[Any, ...]:
        return tuple(self.element.random_value(rng) for _ in range(self.count))

    def extreme_values(self) -> list[tuple[Any, ...]]:
        lo, hi = self.element.extreme_values()
        return [(lo,) * self.count, (hi,) * self.count]

    def quantize(self, value: Any) -> tuple[Any, ...]:
        return tuple(self.element.quantize(v) for v in value)
