"""pytest plugin: fixtures for teams to test their say messages against the league channels."""

from collections.abc import Callable
from typing import Any

import pytest

from comms import testing as _testing
from comms.channel import Channel, make_channel


def pytest_addoption(parser: Any) -> None:
    """Add `--comms-channel` (default channel of the fixtures: simspark)."""
    group = parser.getgroup("comms", "teamenv say-channel checks")
    group.addoption(
        "--comms-channel",
        default="simspark",
        choices=["simspark", "mj"],
        help="channel profile the comms fixtures check against (default: simspark)",
    )


@pytest.fixture
def comms_channel_name(request: Any) -> str:
    """Name of the channel selected with --comms-channel."""
    return request.config.getoption("--comms-channel")


@pytest.fixture
def assert_fits(comms_channel_name: str) -> Callable[..., Any]:
    """`assert_fits(schema, channel=None)`: fail with the bit layout if it does not fit."""

    def _assert_fits(schema: Any, channel: str | None = None, codec: str = "auto") -> Any:
        return _testing.assert_fits(schema, channel or comms_channel_name, codec)

    return _assert_fits


@pytest.fixture
def check_roundtrip(comms_channel_name: str) -> Callable[..., int]:
    """`check_roundtrip(schema, n=200, seed=0)` on the selected channel; returns count."""

    def _check(schema: Any, n: int = 200, seed: int = 0) -> int:
        declared = _testing.assert_fits(schema, comms_channel_name)
        return _testing.check_roundtrip(declared, n=n, seed=seed)

    return _check


@pytest.fixture
def comms_channel(comms_channel_name: str) -> Callable[..., Channel]:
    """Factory: `comms_channel(n_agents=22, teams=None)` -> a fresh Channel."""

    def _make(n_agents: int = 22, teams: Any = None, **overrides: Any) -> Channel:
        if teams is None:
            teams = [0] * (n_agents // 2) + [1] * (n_agents - n_agents // 2)
        return make_channel(comms_channel_name, n_agents, teams, **overrides)

    return _make
