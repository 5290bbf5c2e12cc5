"""The full team decides exactly as recorded before its decision layer went into arrays:
every cycle's actions and chosen behaviours, bit for bit (``tests.strategy.team_decisions``;
a few cycles have a second machine's digest too, see there)."""

from __future__ import annotations

import json

import pytest

from tests.strategy.team_decisions import ALTERNATE, FIXTURE, RUNS, cycle_digests

RECORDED = json.loads(FIXTURE.read_text())
SECOND_MACHINE = json.loads(ALTERNATE.read_text())


@pytest.mark.parametrize("name", sorted(RUNS))
def test_decisions_equal_the_recorded_ones(name):
    now = cycle_digests(RUNS[name])
    recorded = RECORDED[name]
    other = SECOND_MACHINE.get(name, {})
    assert len(now) == len(recorded)
    first = next((k for k, (a, b) in enumerate(zip(now, recorded, strict=True))
                  if a != b and a != other.get(str(k))), None)
    assert first is None, f"{name}: the team's decisions differ from cycle {first} on"


def test_the_second_machine_differs_in_few_cycles():
    # a handful of cycles, never a whole run: the alternates are not a second record
    for name, cycles in SECOND_MACHINE.items():
        assert len(cycles) <= 0.01 * len(RECORDED[name]) or len(cycles) <= 30, (name, cycles)
