"""Search spaces: declarations beside config fields, unit-cube encoding, and clear errors for
bad bounds, unknown or undeclared fields."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pytest

from teamenv.match import MatchOptions
from teamenv.optimize.team_space import team_search_space
from teamenv.search_space import (
    Choice,
    Range,
    SearchSpaceError,
    build_search_space,
    parse_bounds,
    search,
)


@dataclass(frozen=True)
class ToyConfig:
    speed: float = field(default=1.0, metadata=search(Range(0.5, 2.0)))
    weight: float = field(default=10.0, metadata=search(Range(1.0, 100.0, "log")))
    count: int = field(default=2, metadata=search(Range(0, 5, integer=True)))
    shape: str = field(default="wide", metadata=search(Choice(("narrow", "wide", "deep"))))
    flag: bool = True
    label: str = "x"


def test_declared_fields_in_order_and_start_decodes_to_the_defaults():
    space = build_search_space(ToyConfig())
    assert space.names == ("speed", "weight", "count", "shape")
    assert space.decode(space.start()) == {"speed": 1.0, "weight": 10.0, "count": 2,
                                           "shape": "wide"}
    assert space.start()[1] == pytest.approx(0.5)  # log scale: 10 is half-way from 1 to 100


def test_decode_clips_rounds_and_maps_choices_to_bins():
    space = build_search_space(ToyConfig())
    low = space.decode(np.array([-3.0, -1.0, 0.0, 0.0]))
    high = space.decode(np.array([7.0, 2.0, 1.0, 1.0]))
    assert low == {"speed": 0.5, "weight": 1.0, "count": 0, "shape": "narrow"}
    assert high == {"speed": 2.0, "weight": 100.0, "count": 5, "shape": "deep"}
    mid = space.decode(np.array([1 / 3, 0.25, 0.5, 0.5]))
    assert mid["speed"] == 1.0 and mid["weight"] == pytest.approx(math.sqrt(10), rel=1e-3)
    assert isinstance(mid["count"], int) and mid["shape"] == "wide"
    assert space.decode(space.encode(mid)) == mid


def test_only_and_bounds_select_and_replace_domains():
    space = build_search_space(ToyConfig(), only=["count", "flag"],
                               bounds={"flag": Choice((True, False))})
    assert space.names == ("count", "flag")
    assert space.decode([0.0, 0.9]) == {"count": 0, "flag": False}


@pytest.mark.parametrize("kwargs, message", [
    ({"only": ["sped"]}, "unknown field 'sped'"),
    ({"bounds": {"nope": Range(0, 1)}}, "unknown field 'nope'"),
    ({"only": ["label"]}, "field 'label' declares no search range"),
    ({"only": ["speed", "speed"]}, "named twice"),
    ({"bounds": {"flag": Range(0, 1)}}, "flag is True, not a number"),
    ({"bounds": {"count": Range(0, 4)}}, "integer field"),
    ({"bounds": {"shape": Choice(("a", "b"))}}, "shape's value 'wide' is not one of"),
])
def test_bad_fields_and_domains_name_the_field(kwargs, message):
    with pytest.raises(SearchSpaceError, match=message):
        build_search_space(ToyConfig(), **kwargs)


@pytest.mark.parametrize("make, message", [
    (lambda: Range(2.0, 1.0), "low must be < high"),
    (lambda: Range(1.0, 1.0), "low must be < high"),
    (lambda: Range(0.0, 1.0, "log"), "low must be > 0 on a log scale"),
    (lambda: Range(0.0, float("inf")), "high must be a finite number"),
    (lambda: Range(0.0, 1.0, "cubic"), "scale must be one of"),
    (lambda: Range(0.2, 0.8, integer=True), "no integer in"),
    (lambda: Choice(("only",)), "at least two options"),
    (lambda: Choice(("a", "a")), "distinct"),
    (lambda: search((0, 1)), "expected a Range or a Choice"),
])
def test_bad_domains_are_clear_errors(make, message):
    with pytest.raises(SearchSpaceError, match=message):
        make()


def test_parse_bounds():
    assert parse_bounds("pressure_m=1:4") == ("pressure_m", Range(1.0, 4.0))
    assert parse_bounds("w=0.1:10:log") == ("w", Range(0.1, 10.0, "log"))
    assert parse_bounds("n=0:3:int") == ("n", Range(0.0, 3.0, integer=True))
    assert parse_bounds("marking=true|false") == ("marking", Choice((True, False)))
    for text, message in [("pressure_m", "expected NAME="), ("p=1", "expected NAME="),
                          ("p=a:b", "must be numbers"), ("p=1:2:cube", "unknown flag"),
                          ("p=3:1", "low must be < high")]:
        with pytest.raises(SearchSpaceError, match=message):
            parse_bounds(text)


OPTIONS = MatchOptions(team_size=3, half_time_s=5.0, halves=1)


def test_full_team_declares_its_space_and_every_end_is_a_valid_config():
    """Every declared domain of the full team keeps its default inside and its ends valid
    (team_search_space builds the config at each end of each range)."""
    space = team_search_space("full", {}, OPTIONS)
    assert {"kick_goal_weight", "pressure_m", "formation_attack", "max_markers"} <= \
        set(space.names)
    assert "communicate" not in space.names  # another team, not a parameter to tune
    from strategy.teams.full_config import FullTeamConfig

    defaults = FullTeamConfig()
    assert space.decode(space.start()) == {n: getattr(defaults, n) for n in space.names}


def test_team_bounds_the_team_rejects_are_caught_before_any_match():
    with pytest.raises(SearchSpaceError, match="ball_pull=2.0, which the team rejects"):
        team_search_space("full", {}, OPTIONS, only=["ball_pull", "pressure_m"],
                          bounds=["ball_pull=0:2"])
    with pytest.raises(SearchSpaceError, match="unknown field 'presure_m'"):
        team_search_space("full", {}, OPTIONS, only=["presure_m"])
    # chaser's config is a checked dataclass now (teamenv.team_config), with nothing marked
    # for search
    with pytest.raises(SearchSpaceError, match="no parameters to search"):
        team_search_space("chaser", {}, OPTIONS)
