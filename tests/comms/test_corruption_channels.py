"""What a corrupted text is, on both channels: the channel and `check_corruption` agree.

On `mj` a say text is the padded base64 of its bytes; the server decodes it and delivers the
canonical spelling, so a text that differs from the sender's only in the unused low bits of
its last character ("AZjglD==" for "AZjglA==") is the same message, not a corrupted one.
"""

import itertools

import numpy as np
import pytest

from comms.channel import make_channel
from comms.profiles import get_profile
from comms.schema import Array, Bool, Enum, Fixed, Int, Permutation, Schema
from comms.testing import check_corruption


def tutorial_schema(channel: str, check_bits: int) -> Schema:
    """A user's schema as in the message-budget tutorial: ball x/y, an enum and a flag."""
    return Schema("ball_call", [Fixed("ball_x", -28.0, 28.0, 0.05),
                                Fixed("ball_y", -19.0, 19.0, 0.05),
                                Enum("intent", ["hold", "pass", "shoot", "clear"]),
                                Bool("has_ball")], channel=channel, check_bits=check_bits)


def every_field_schema(channel: str, check_bits: int) -> Schema:
    return Schema("every_field", [Int("n", -3, 40), Bool("b"), Enum("e", ["a", "b", "c"]),
                                  Fixed("f", -1.0, 1.0, 0.1), Permutation("p", 4),
                                  Array("xs", Int("x", 0, 5), 3)],
                  channel=channel, check_bits=check_bits)


def test_the_reported_text_is_the_same_message_on_mj():
    mj = get_profile("mj")
    assert mj.check_message("AZjglD==") is None        # legal: the server accepts it
    assert mj.heard_text("AZjglD==") == "AZjglA=="     # ... and delivers its bytes' spelling
    assert mj.heard_text("AZjglA==") == "AZjglA=="
    assert mj.heard_text("AZjg") == "AZjg"             # no padding: every bit is used
    assert mj.heard_text("AZj/") == "AZj/"
    assert mj.heard_text("AZf=") == "AZc="             # one pad: the last 2 bits are unused
    assert get_profile("simspark").heard_text("AZjglD==") == "AZjglD=="


@pytest.mark.parametrize("channel, check_bits, make", list(itertools.product(
    ["simspark", "mj"], [0, 4, 8, 16], [tutorial_schema, every_field_schema])))
def test_check_corruption_passes_correct_schemas(channel, check_bits, make):
    schema = make(channel, check_bits)
    counts = check_corruption(schema, n=600, seed=11)
    assert sum(counts.values()) == 600
    if check_bits >= 8:
        assert counts["accepted"] <= 600 * 2 ** -check_bits * 4 + 3


def test_mj_corruptions_of_the_unused_bits_are_counted_intact():
    # the tutorial's schema is 2 x 10 + 2 + 1 (+ 4 check) bits = 4 bytes: "xxxxxx==" texts,
    # whose last data character has 4 unused bits: some corruptions only touch those
    counts = check_corruption(tutorial_schema("mj", 4), n=2000, seed=1)
    assert counts["intact"] > 0
    assert check_corruption(tutorial_schema("simspark", 4), n=2000, seed=1)["intact"] == 0


def test_the_mj_channel_delivers_the_canonical_spelling():
    mj = get_profile("mj")
    channel = make_channel(mj, 2, [0, 0])
    positions = np.array([[0.0, 0.0], [1.0, 0.0]])
    headings = np.zeros(2)
    rng = np.random.default_rng(0)
    for deliver in (lambda: channel.deliver_texts(["AZjglD==", ""], positions, headings, rng),
                    lambda: channel.deliver([(0, "AZjglD==", 100.0)], positions, headings, rng)):
        heard = deliver().heard[1]
        assert [h.text for h in heard] == ["AZjglA=="]
    schema = tutorial_schema("mj", 4)
    text = schema.encode(schema.random_values(np.random.default_rng(2)))
    assert mj.heard_text(text) == text                 # our own encoder is canonical
