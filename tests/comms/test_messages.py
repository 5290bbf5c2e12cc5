"""Tests of the shipped message types (role vector, team state, marking, opponents)."""

import numpy as np
import pytest

from comms import messages as m
from comms.testing import assert_fits, check_roundtrip


def test_role_vector_26_bits():
    s = m.ROLE_VECTOR
    assert s.bits == 26 and s.codec_name == "base64" and s.chars == 5
    assert s.bits < m.SOURCE_ROLE_VECTOR_BITS[0]
    roles = [3, 7, 1, 0, 10, 2, 9, 5, 4, 8, 6]
    text = s.encode({"roles": roles})
    assert s.decode(text).roles == tuple(roles)
    assert m.role_vector_schema(11) is s  # cached
    mj = m.role_vector_schema(11, channel="mj")
    assert mj.decode(mj.encode(roles=roles)).roles == tuple(roles)
    assert m.role_vector_schema(11, start=1).decode(
        m.role_vector_schema(11, start=1).encode(roles=[r + 1 for r in roles])
    ).roles == tuple(r + 1 for r in roles)


@pytest.mark.parametrize("n", [1, 2, 5, 7, 11])
def test_role_vector_sizes_roundtrip(n):
    for channel in ("simspark", "mj"):
        check_roundtrip(m.role_vector_schema(n, channel=channel), n=50)


@pytest.mark.parametrize(
    "schema",
    [m.ROLE_VECTOR, m.BALL, m.SELF_STATE, m.MARKING, m.TEAM_STATE, m.opponents_schema()],
    ids=lambda s: s.name,
)
def test_shipped_messages_roundtrip(schema):
    check_roundtrip(schema, n=100)


def test_team_state_fits_both_channels():
    assert m.TEAM_STATE.bits == 74
    assert_fits(m.TEAM_STATE, channel="mj")
    mj = m.team_state_schema(11, channel="mj")
    check_roundtrip(mj, n=100)


def test_opponents_only_fit_base92():
    s = m.opponents_schema()
    assert s.bits == 125 and s.codec_name == "base92" and s.chars == 20
    with pytest.raises(AssertionError, match="holds 120 bits"):
        assert_fits(s, channel="simspark", codec="base64")
    with pytest.raises(AssertionError, match="'mj'"):
        assert_fits(s, channel="mj")


def test_ball_clip_and_age():
    rec = m.BALL.decode(m.BALL.encode(ball_x=40.0, ball_y=-3.04, ball_age=9.0))
    assert rec.ball_x == 16.0 and rec.ball_y == -3.0 and rec.ball_age == 3.1


def test_marking():
    marks = (0, 3, 4, 11, 0, 0, 1, 2, 5, 6, 7)
    assert m.MARKING.decode(m.MARKING.encode(marks=marks)).marks == marks
    assert m.MARKING.bits == 40


def test_catalogue_rows():
    rows = {r["name"]: r for r in m.catalogue()}
    assert rows["role_vector_11"]["bits"] == 26
    assert rows["opponents_11"]["fits_mj"] is False
    assert all(r["bits"] <= 130 for r in rows.values())
    assert np.isclose(rows["role_vector_11"]["information"], 25.3)
