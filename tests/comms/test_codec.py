"""Tests of the text codecs (base64 bits, base-N big integer, bytes + base64 for mj)."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from comms import MJ, SIMSPARK, BudgetError, DecodeError, EncodeError
from comms.codec import Base64Bits, BaseNBits, BytesBase64, bind_codec, codec_capacity


def test_capacities():
    assert codec_capacity(SIMSPARK, "base64") == 120
    assert codec_capacity(SIMSPARK, "baseN") == 130
    assert codec_capacity(SIMSPARK, "bytes+base64") == 0
    assert codec_capacity(MJ, "bytes+base64") == 80
    assert codec_capacity(MJ, "base64") == 0


def test_auto_choice():
    assert bind_codec(SIMSPARK, "auto", 120).name == "base64"
    assert bind_codec(SIMSPARK, "auto", 121).name == "base92"
    assert bind_codec(SIMSPARK, "auto", 130).chars == 20
    assert bind_codec(MJ, "auto", 80).name == "bytes+base64"
    with pytest.raises(BudgetError, match="131 bits"):
        bind_codec(SIMSPARK, "auto", 131)
    with pytest.raises(BudgetError, match="81 bits"):
        bind_codec(MJ, "auto", 81)


def _codecs():
    out = []
    for bits in (1, 5, 6, 7, 23, 24, 25, 26, 64, 120):
        out.append(Base64Bits(bits))
    for bits in (1, 6, 7, 13, 26, 64, 129, 130):
        out.append(BaseNBits(bits, SIMSPARK.charset))
    for bits in (1, 8, 9, 26, 79, 80):
        out.append(BytesBase64(bits))
    return out


@pytest.mark.parametrize("codec", _codecs(), ids=repr)
def test_bounds_roundtrip_and_legal(codec):
    profile = MJ if codec.name == "bytes+base64" else SIMSPARK
    for v in (0, 1, (1 << codec.bits) - 1, (1 << codec.bits) // 3):
        t = codec.encode(v)
        assert len(t) == codec.chars
        assert profile.check_message(t) is None
        assert codec.decode(t) == v
    with pytest.raises(EncodeError):
        codec.encode(1 << codec.bits)
    with pytest.raises(EncodeError):
        codec.encode(-1)


@settings(max_examples=200, deadline=None)
@given(st.integers(0, (1 << 130) - 1))
def test_base92_random(v):
    c = BaseNBits(130, SIMSPARK.charset)
    assert c.decode(c.encode(v)) == v


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 120), st.data())
def test_base64_random(bits, data):
    c = Base64Bits(bits)
    v = data.draw(st.integers(0, (1 << bits) - 1))
    assert c.decode(c.encode(v)) == v


def test_decode_errors():
    b = Base64Bits(26)  # 5 chars, 4 unused low bits
    with pytest.raises(DecodeError, match="expected 5 characters"):
        b.decode("AAAA")
    with pytest.raises(DecodeError, match="illegal character"):
        b.decode("AA!AA")
    with pytest.raises(DecodeError, match="unused low bits"):
        b.decode("AAAAB")
    with pytest.raises(DecodeError, match="expected a str"):
        b.decode(b"AAAAA")
    n = BaseNBits(26, SIMSPARK.charset)  # 4 chars of 92 > 2**26
    with pytest.raises(DecodeError, match=">= 2\\*\\*26"):
        n.decode("~~~~")
    with pytest.raises(DecodeError, match="illegal character"):
        n.decode("ab(d")
    m = BytesBase64(26)
    with pytest.raises(DecodeError, match="not valid base64"):
        m.decode("AAAAA*==")
    with pytest.raises(DecodeError, match=">= 2\\*\\*26"):
        m.decode("/////w==")
