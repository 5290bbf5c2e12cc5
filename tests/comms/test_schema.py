"""Tests of declarative schemas: every field type, budgets at declaration, decode validation."""

import math

import numpy as np
import pytest
from hypothesis import given, settings

from comms import BudgetError, DecodeError, EncodeError, SchemaError
from comms.schema import Array, Bool, Enum, Fixed, Int, Permutation, Schema, decode_any
from comms.testing import check_corruption, check_roundtrip, hypothesis_values

FIELDS = [
    Int("i", -5, 300),
    Int("one", 7, 7),
    Bool("b"),
    Enum("e", ["kickoff", "goal_kick", "corner", 3]),
    Fixed("f", -15.0, 15.0, 0.1),
    Fixed("g", 0.0, 1.0, 0.3),  # off-grid hi
    Permutation("p", 11),
    Permutation("p1", 4, start=1),
    Array("a", Int("x", 0, 11), 5),
]
ALL = Schema("all_types", FIELDS)
ALL_RADIX = Schema("all_types", FIELDS, packing="radix", check_bits=8)
ALL_MJ = Schema("all_mj", FIELDS[:6] + FIELDS[7:], channel="mj")
ALL_TAGGED = Schema("all_tag", FIELDS, codec="baseN", tag=5, tag_bits=3, check_bits=4)
SCHEMAS = [ALL, ALL_RADIX, ALL_MJ, ALL_TAGGED]


@pytest.mark.parametrize("schema", SCHEMAS, ids=repr)
def test_roundtrip_bounds_and_random(schema):
    assert check_roundtrip(schema, n=300, seed=1) == 304


@pytest.mark.parametrize("field", FIELDS, ids=repr)
def test_each_field_alone_at_bounds(field):
    s = Schema("one_field", [field])
    for v in field.extreme_values():
        assert s.decode(s.encode({field.name: v}))[0] == field.quantize(v)
    check_roundtrip(s, n=50)


@settings(max_examples=150, deadline=None)
@given(hypothesis_values(ALL))
def test_hypothesis_roundtrip(values):
    for s in (ALL, ALL_RADIX, ALL_TAGGED):
        got = s.decode(s.encode(values))
        for f in s.fields:
            if isinstance(f, Fixed):
                assert abs(getattr(got, f.name) - values[f.name]) <= f.resolution / 2 + 1e-9
            else:
                sent = values[f.name]
                assert getattr(got, f.name) == (tuple(sent) if isinstance(sent, list) else sent)


def test_sizes():
    assert Schema("r", [Permutation("p", 11)]).bits == 26
    assert ALL.bits == sum(f.bits for f in FIELDS)
    assert ALL_RADIX.bits == math.ceil(sum(math.log2(f.cardinality) for f in FIELDS)) + 8
    assert ALL_RADIX.bits - 8 < ALL.bits
    assert ALL_TAGGED.bits == ALL.bits + 3 + 4
    assert Fixed("g", 0.0, 1.0, 0.3).cardinality == 5  # 0, .3, .6, .9, 1.2


def test_budget_fails_at_declaration():
    big = [Int(f"x{k}", 0, 2**20 - 1) for k in range(7)]  # 140 bits
    with pytest.raises(BudgetError, match="needs 140 bits.*'simspark'"):
        Schema("too_big", big)
    with pytest.raises(BudgetError):
        Schema("too_big", big[:6] + [Int("y", 0, 2**10)], codec="base64")  # 131 > 120
    assert Schema("ok", big[:6] + [Int("y", 0, 2**9)]).codec_name == "base92"  # 130
    with pytest.raises(BudgetError, match="'mj'"):
        Schema("too_big_mj", big[:4] + [Int("y", 0, 2**1)], channel="mj")  # 82 > 80
    assert isinstance(BudgetError("x"), ValueError)


def test_declaration_errors():
    with pytest.raises(SchemaError, match="repeated"):
        Schema("s", [Bool("a"), Bool("a")])
    with pytest.raises(SchemaError, match="identifier"):
        Schema("s", [Bool("not ok")])
    with pytest.raises(SchemaError, match="identifier"):
        Bool("class")
    with pytest.raises(SchemaError, match="empty range"):
        Int("a", 3, 2)
    with pytest.raises(SchemaError, match="resolution"):
        Fixed("a", 0, 1, 0)
    with pytest.raises(SchemaError, match="repeat"):
        Enum("a", ["x", "x"])
    with pytest.raises(SchemaError, match="packing"):
        Schema("s", [Bool("a")], packing="zip")
    with pytest.raises(SchemaError, match="tag"):
        Schema("s", [Bool("a")], tag=4, tag_bits=2)
    with pytest.raises(SchemaError, match="codec"):
        Schema("s", [Bool("a")], codec="rot13")


def test_encode_errors_name_field_and_value():
    s = Schema("s", [Int("age", 0, 31), Fixed("x", -1, 1, 0.1), Permutation("p", 3)])
    good = {"age": 3, "x": 0.5, "p": (2, 0, 1)}
    s.encode(good)
    cases = [
        ({"age": 32}, "'age'.*32.*outside"),
        ({"age": 2.0}, "'age'.*not an int"),
        ({"x": 1.2}, "'x'.*1.2.*outside"),
        ({"x": float("nan")}, "'x'.*NaN"),
        ({"x": "a"}, "'x'.*not a number"),
        ({"p": (0, 0, 1)}, "'p'.*not a permutation"),
        ({"p": (0, 1)}, "'p'.*length 2"),
    ]
    for patch, pattern in cases:
        with pytest.raises(EncodeError, match=pattern):
            s.encode({**good, **patch})
    with pytest.raises(EncodeError, match="missing fields \\['p'\\]"):
        s.encode({"age": 3, "x": 0.5})
    with pytest.raises(EncodeError, match="unknown fields \\['zz'\\]"):
        s.encode({**good, "zz": 1})
    assert isinstance(EncodeError("x"), ValueError)
    clipped = Schema("c", [Fixed("x", -1, 1, 0.1, clip=True)])
    assert clipped.decode(clipped.encode(x=7.0)).x == 1.0


def test_encode_accepts_record_keywords_numpy():
    s = Schema("s", [Int("a", 0, 9), Bool("b"), Permutation("p", 3)])
    t = s.encode(a=np.int64(4), b=np.bool_(True), p=np.array([2, 1, 0]))
    rec = s.decode(t)
    assert rec == (4, True, (2, 1, 0)) and rec.a == 4
    assert s.encode(rec) == t
    assert s.for_channel("mj").decode(s.for_channel("mj").encode(rec)) == rec


def test_decode_rejects_corrupt():
    s = Schema("s", [Int("a", 0, 4)])  # 3 bits, values 5..7 invalid -> 1 base64 char
    texts = {s.encode(a=k) for k in range(5)}
    for c in "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/!(":
        if c in texts:
            continue
        with pytest.raises(DecodeError):
            s.decode(c)
    with pytest.raises(DecodeError, match="field 'a' raw value 5"):
        s.decode("o")  # 0b101000 -> a raw 5
    with pytest.raises(DecodeError, match="expected a str"):
        s.decode(None)
    # every corruption of a checked message is either rejected or a legal message
    for schema in SCHEMAS:
        counts = check_corruption(schema, n=200, seed=3)
        assert sum(counts.values()) == 200
    counts = check_corruption(ALL_RADIX, n=400, seed=4)
    assert counts["rejected"] >= 390  # 8 check bits


def test_tags_and_decode_any():
    a = Schema("msg_a", [Int("x", 0, 100)], tag=0, tag_bits=2)
    b = Schema("msg_b", [Int("x", 0, 100)], tag=1, tag_bits=2)
    ta, tb = a.encode(x=5), b.encode(x=5)
    assert ta != tb
    assert decode_any(tb, [a, b]) == (b, b.Record(5))
    with pytest.raises(DecodeError, match="tag 1"):
        a.decode(tb)
    with pytest.raises(DecodeError, match="no schema accepts"):
        decode_any("~~", [a, b])
    assert a.is_valid(ta) and not a.is_valid(tb)


def test_layout():
    text = ALL_TAGGED.layout()
    assert "offset" in text and "(tag)" in text and "(check)" in text and "base92" in text
    for f in FIELDS:
        assert f.name in text
    assert "radix" in ALL_RADIX.layout()
    assert repr(ALL).startswith("Schema('all_types'")


def test_decode_cache_returns_equal_immutable():
    s = Schema("s", [Permutation("p", 5)])
    t = s.encode(p=[4, 3, 2, 1, 0])
    assert s.decode(t) is s.decode(t)
    assert isinstance(s.decode(t).p, tuple)


def test_too_big_schema_fails_at_import(tmp_path, monkeypatch):
    (tmp_path / "team_msgs_too_big.py").write_text(
        "from comms.schema import Int, Schema\n"
        "MSG = Schema('huge', [Int(f'x{k}', 0, 2**30) for k in range(5)], channel='mj')\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(BudgetError, match="schema 'huge' needs 155 bits"):
        __import__("team_msgs_too_big")


@pytest.mark.parametrize("schema", SCHEMAS, ids=repr)
def test_encode_primed_cache_equals_cold_decode(schema):
    rng = np.random.default_rng(11)
    values = list(schema.extreme_values()) + [schema.random_values(rng) for _ in range(200)]
    values.append(
        {
            **schema.random_values(rng)._asdict(),
            "p": np.array([int(x) for x in rng.permutation(11)]),
            "b": np.bool_(True),
            "i": np.int16(-5),
        }
    )
    for v in values:
        if isinstance(v, dict) and "p" not in schema.field_names:
            continue
        text = schema.encode(v)
        primed = schema.decode(text)
        schema._cache.clear()
        cold = schema.decode(text)
        assert primed == cold
        assert [type(x) for x in primed] == [type(x) for x in cold]
