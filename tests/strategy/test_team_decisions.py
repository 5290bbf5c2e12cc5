"""The full team decides exactly as recorded before its decision layer went into arrays:
every cycle's actions and chosen behaviours, bit for bit (``tests.strategy.team_decisions``)."""

from __future__ import annotations

import json

import pytest

from tests.strategy.team_decisions import FIXTURE, RUNS, cycle_digests

RECORDED = json.loads(FIXTURE.read_text())


@pytest.mark.parametrize("name", sorted(RUNS))
def test_decisions_equal_the_recorded_ones(name):
    now = cycle_digests(RUNS[name])
    recorded = RECORDED[name]
    assert len(now) == len(recorded)
    first = next((k for k, (a, b) in enumerate(zip(now, recorded, strict=True)) if a != b), None)
    assert first is None, f"{name}: the team's decisions differ from cycle {first} on"
