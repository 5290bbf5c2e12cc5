"""Helpers for teams' own unit tests: budget checks, round-trip and corruption property checks."""

from typing import Any

import numpy as np

from comms.errors import BudgetError, DecodeError
from comms.profiles import ChannelProfile, get_profile
from comms.schema import Fixed, Schema


def assert_fits(
    schema: Schema, channel: "str | ChannelProfile" = "simspark", codec: str = "auto"
) -> Schema:
    """Assert that `schema` fits `channel` (with `codec`); return it declared for that channel.

    Fails with the schema's bit layout in the message, e.g.
    `assert_fits(MY_MSG, channel="mj")`.
    """
    try:
        declared = schema.for_channel(channel, codec)
    except BudgetError as e:
        raise AssertionError(f"{e}\n{schema.layout()}") from None
    return declared


def _close(field: Any, a: Any, b: Any) -> bool:
    if isinstance(field, Fixed):
        return abs(float(a) - float(b)) <= field.resolution / 2 + 1e-9 * max(1.0, abs(float(a)))
    return a == b


def check_roundtrip(
    schema: Schema, n: int = 200, seed: int = 0, rng: np.random.Generator | None = None
) -> int:
    """Property check: every value survives encode -> decode, and every text is legal.

    Checks the extreme values of every field and `n` random values: the text has exactly
    `schema.chars` legal characters of the schema's channel, decodes to the quantized values
    (fixed-point fields within resolution / 2 of the input) and re-encodes to the same text.
    Returns the number of values checked; raises AssertionError naming the failing value.
    """
    rng = rng if rng is not None else np.random.default_rng(seed)
    values = list(schema.extreme_values()) + [schema.random_values(rng) for _ in range(n)]
    profile = schema.profile
    for v in values:
        text = schema.encode(v)
        reason = profile.check_message(text)
        assert reason is None, f"{schema.name}: {v} encodes to {text!r}, illegal: {reason}"
        assert len(text) == schema.chars, f"{schema.name}: {text!r} is not {schema.chars} chars"
        got = schema.decode(text)
        for f, a, b in zip(schema.fields, v, got, strict=True):
            assert _close(f, a, b), f"{schema.name}: field {f.name!r} sent {a!r}, got {b!r}"
        assert schema.encode(got) == text, f"{schema.name}: {got} re-encodes differently"
    return len(values)


def check_corruption(
    schema: Schema, n: int = 200, seed: int = 0, rng: np.random.Generator | None = None
) -> dict[str, int]:
    """Property check: a corrupted text decodes to a legal message or raises DecodeError.

    Each of `n` random messages gets one character replaced by another legal character of the
    channel (or is truncated / extended), and goes through what the channel does to a said
    text: an illegal text is dropped whole (counted "rejected"), a legal one is heard as
    `profile.heard_text(text)` (on `mj` the canonical base64 of its bytes). Returns counts
    {"rejected": .., "accepted": .., "intact": ..}: "intact" ones are heard as the original
    text (on `mj` a change of the last character's unused bits leaves the bytes as they
    were); "accepted" ones decode to a legal message that re-encodes to exactly what was
    heard (so a different message - add `check_bits` to the schema to reject most of those).
    """
    rng = rng if rng is not None else np.random.default_rng(seed)
    profile = schema.profile
    charset = profile.charset
    counts = {"rejected": 0, "accepted": 0, "intact": 0}
    for k in range(n):
        text = schema.encode(schema.random_values(rng))
        mode = k % 4
        if mode == 0:
            bad = text[:-1]
        elif mode == 1:
            bad = text + charset[int(rng.integers(len(charset)))]
        else:
            i = int(rng.integers(len(text)))
            c = text[i]
            while c == text[i]:
                c = charset[int(rng.integers(len(charset)))]
            bad = text[:i] + c + text[i + 1 :]
        if profile.check_message(bad) is not None:
            counts["rejected"] += 1  # the channel drops it whole
            continue
        heard = profile.heard_text(bad)
        if heard == text:
            counts["intact"] += 1
            continue
        try:
            got = schema.decode(heard)
        except DecodeError:
            counts["rejected"] += 1
            continue
        assert schema.encode(got) == heard, (
            f"{schema.name}: {bad!r} (heard as {heard!r}) decoded to garbage {got}")
        counts["accepted"] += 1
    return counts


def field_strategy(field: Any) -> Any:
    """A hypothesis strategy of legal values for one field (needs `hypothesis`)."""
    from hypothesis import strategies as st

    from comms.schema import Array, Bool, Enum, Int, Permutation

    if isinstance(field, Int):
        return st.integers(field.lo, field.hi)
    if isinstance(field, Bool):
        return st.booleans()
    if isinstance(field, Enum):
        return st.sampled_from(field.choices)
    if isinstance(field, Fixed):
        return st.floats(field.lo, field.hi, allow_nan=False)
    if isinstance(field, Permutation):
        return st.permutations(range(field.start, field.start + field.n))
    if isinstance(field, Array):
        el = field_strategy(field.element)
        return st.lists(el, min_size=field.count, max_size=field.count)
    return st.integers(0, field.cardinality - 1).map(field.from_raw)


def hypothesis_values(schema: Schema) -> Any:
    """A hypothesis strategy of value dicts for `schema`: `@given(hypothesis_values(MSG))`.

    Needs the `hypothesis` package (the project's `dev` extra).
    """
    try:
        from hypothesis import strategies as st
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("hypothesis_values needs hypothesis (the 'dev' extra)") from e
    return st.fixed_dictionaries({f.name: field_strategy(f) for f in schema.fields})


def layout(schema: Schema) -> str:
    """The schema's bit layout table (same as `schema.layout()`)."""
    return schema.layout()


def channel_budget(channel: "str | ChannelProfile" = "simspark") -> dict[str, int]:
    """Bits one message can carry on `channel`, per codec."""
    from comms.codec import CODEC_NAMES, codec_capacity

    profile = get_profile(channel)
    return {c: codec_capacity(profile, c) for c in CODEC_NAMES[1:] if codec_capacity(profile, c)}
