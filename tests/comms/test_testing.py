"""Tests of the helpers for teams' tests (comms.testing) and the pytest plugin."""

import pytest

from comms import messages as m
from comms.schema import Bool, Fixed, Int, Schema
from comms.testing import assert_fits, channel_budget, check_corruption, check_roundtrip

pytest_plugins = ["pytester"]


def test_assert_fits_message_has_layout():
    s = Schema("wide", [Int(f"x{k}", 0, 2**20 - 1) for k in range(5)])  # 100 bits
    assert assert_fits(s, channel="simspark").bits == 100
    with pytest.raises(AssertionError, match="(?s)needs 100 bits.*offset.*x4"):
        assert_fits(s, channel="mj")


def test_budget_table():
    assert channel_budget("simspark") == {"base64": 120, "baseN": 130}
    assert channel_budget("mj") == {"bytes+base64": 80}


def test_roundtrip_helper_catches_a_broken_field():
    class Broken(Fixed):
        def from_raw(self, raw):  # off by one grid step
            return super().from_raw(raw) + self.resolution

    s = Schema("broken", [Broken("x", 0.0, 1.0, 0.1), Bool("b")])
    with pytest.raises(AssertionError, match="field 'x'"):
        check_roundtrip(s, n=10)


def test_corruption_helper_counts():
    counts = check_corruption(m.TEAM_STATE, n=100)
    assert counts["rejected"] >= 95  # 8 check bits


PLUGIN_TEST = """
from comms.messages import ROLE_VECTOR, opponents_schema
from comms.schema import Schema, Int


def test_fits(assert_fits, check_roundtrip, comms_channel):
    assert_fits(ROLE_VECTOR)
    assert check_roundtrip(ROLE_VECTOR, n=20) == 24
    ch = comms_channel(4)
    assert ch.profile.name in ("simspark", "mj") and ch.n_agents == 4


def test_too_big(assert_fits):
    assert_fits(opponents_schema())
"""


@pytest.mark.parametrize("channel,failed", [("simspark", 0), ("mj", 1)])
def test_pytest_plugin(pytester, channel, failed):
    pytester.makeconftest("pytest_plugins = ['comms.pytest_plugin']")
    pytester.makepyfile(test_team=PLUGIN_TEST)
    result = pytester.runpytest_inprocess(
        "-p", "no:teamenv_comms", "-p", "no:cacheprovider", f"--comms-channel={channel}"
    )
    result.assert_outcomes(passed=2 - failed, failed=failed)
