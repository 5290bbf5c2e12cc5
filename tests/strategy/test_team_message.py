"""The vision-mode team message: fits both channels, round-trips, rejects foreign texts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from comms.profiles import get_profile
from strategy.perception.team_message import (
    BALL_AGE_MAX_CYCLES,
    HEADING_STEPS,
    decode_team_report,
    encode_team_report,
    team_message_schema,
)
from strategy.positioning.roles.message import encode_role_vote
from teamenv.field import field_preset

CASES = [("simspark", 11), ("mj7v7", 7), ("fifa", 11), ("mj7v7", 11), ("simspark", 3)]


@pytest.mark.parametrize("channel", ["simspark", "mj"])
@pytest.mark.parametrize("field_name,n", CASES)
def test_every_report_fits_the_channel(field_name, n, channel):
    schema = team_message_schema(n, field_preset(field_name), channel)
    f = field_preset(field_name)
    # the extremes: far corner, every field at its largest
    text = encode_team_report(schema, n - 1, np.arange(n)[::-1], np.array([f.half_length + 5,
                              -f.half_width - 5]), math.pi - 1e-9, True,
                              np.array([-f.half_length - 5, f.half_width + 5]), 10_000)
    profile = get_profile(channel)
    if channel == "simspark":
        assert len(text) <= profile.max_chars
        assert set(text) <= set(profile.charset)
    else:
        import base64

        assert len(base64.b64decode(text)) <= 10
    report = decode_team_report(schema, text)
    assert report is not None
    assert report.ball_age_cycles == BALL_AGE_MAX_CYCLES  # saturates, never wraps


@settings(max_examples=60, deadline=None)
@given(x=st.floats(-15, 15), y=st.floats(-10, 10), heading=st.floats(-math.pi, math.pi),
       bx=st.floats(-15, 15), by=st.floats(-10, 10), age=st.integers(0, 200),
       seed=st.integers(0, 2**32 - 1), known=st.booleans(), fallen=st.booleans())
def test_round_trip_within_the_resolution(x, y, heading, bx, by, age, seed, known, fallen):
    field = field_preset("simspark")
    schema = team_message_schema(11, field, "simspark")
    res = next(f for f in schema.fields if f.name == "x").resolution
    roles = np.random.default_rng(seed).permutation(11)
    ball = np.array([bx, by]) if known else None
    report = decode_team_report(schema, encode_team_report(
        schema, 4, roles, np.array([x, y]), heading, fallen, ball, age))
    assert report is not None and report.sender == 4 and report.fallen == fallen
    np.testing.assert_array_equal(report.roles, roles)
    assert np.all(np.abs(report.position - (x, y)) <= res / 2 + 1e-9)
    err = (report.heading - heading + math.pi) % (2 * math.pi) - math.pi
    assert abs(err) <= math.pi / HEADING_STEPS + 1e-9
    assert (report.ball is None) == (not known)
    if known:
        assert np.all(np.abs(report.ball - (bx, by)) <= res / 2 + 1e-9)
    assert report.ball_age_cycles == age


def test_foreign_and_corrupt_texts_are_rejected():
    field = field_preset("mj7v7")
    schema = team_message_schema(7, field, "simspark")
    text = encode_team_report(schema, 2, np.arange(7), np.zeros(2), 0.0, False, None, 0)
    assert decode_team_report(schema, "") is None
    assert decode_team_report(schema, encode_role_vote(2, np.arange(7), 7)) is None
    corrupt = sum(decode_team_report(schema, text[:k] + ("A" if text[k] != "A" else "B") +
                                      text[k + 1:]) is None for k in range(len(text)))
    assert corrupt >= len(text) - 1  # 8 check bits: a one-character change is caught
