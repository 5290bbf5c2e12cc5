"""Tests of profile loading: every shipped profile validates, bad files give clear errors."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest

from locomotion import ProfileError, load_profile, profile_from_dict, shipped_profiles
from locomotion.profile import PARAMETERS, PROFILE_DIR


def _raw(name: str = "t1_mj") -> dict:
    return json.loads((PROFILE_DIR / f"{name}.json").read_text())


def test_required_profiles_are_shipped() -> None:
    assert {"t1_mj", "nao_simspark"} <= set(shipped_profiles())


@pytest.mark.parametrize("name", shipped_profiles())
def test_every_shipped_profile_loads(name: str) -> None:
    p = load_profile(name)
    assert p.name == name and p.version >= 1
    assert set(p.sources) == set(PARAMETERS)
    assert all(s.strip() for s in p.sources.values())
    assert p.command_low.shape == (3,) and np.all(p.command_low < p.command_high)
    assert p.kick_reach > p.body_radius > 0 and p.mass > 0
    assert 0 < p.kick_direction_std < 1


def test_load_by_path(tmp_path: Path) -> None:
    f = tmp_path / "mine.json"
    f.write_text(json.dumps(_raw()))
    assert load_profile(f).name == "t1_mj"
    assert load_profile(str(f)).path == str(f)


def test_t1_command_space_allows_commands_beyond_envelope() -> None:
    p = load_profile("t1_mj")
    assert p.command_high[0] >= 1.5 > p.envelope_vx_forward


def test_unknown_name() -> None:
    with pytest.raises(ProfileError, match="no such shipped profile.*t1_mj"):
        load_profile("robocop")


def test_not_json(tmp_path: Path) -> None:
    f = tmp_path / "bad.json"
    f.write_text("{not json")
    with pytest.raises(ProfileError, match="not valid JSON"):
        load_profile(f)


def _mutate(fn) -> dict:
    d = copy.deepcopy(_raw())
    fn(d)
    return d


@pytest.mark.parametrize(
    ("mutation", "pattern"),
    [
        (lambda d: d["parameters"].pop("mass"), r"parameters\.mass.*missing"),
        (
            lambda d: d["parameters"].__setitem__("wings", {"value": 1}),
            r"parameters\.wings.*unknown",
        ),
        (lambda d: d.__setitem__("colour", "red"), r"'colour'.*unknown key"),
        (lambda d: d.pop("version"), r"'version'.*missing"),
        (lambda d: d.__setitem__("version", 0), r"'version' = 0.*positive integer"),
        (lambda d: d.__setitem__("format", "other/9"), r"'format'"),
        (
            lambda d: d["parameters"]["step_period"].__setitem__("value", -0.3),
            r"parameters\.step_period' = -0\.3.*out of range",
        ),
        (
            lambda d: d["parameters"]["mass"].__setitem__("value", "heavy"),
            r"parameters\.mass' = 'heavy'.*number",
        ),
        (lambda d: d["parameters"]["mass"].__setitem__("value", float("nan")), r"finite"),
        (lambda d: d["parameters"]["mass"].__setitem__("source", " "), r"mass\.source.*source"),
        (lambda d: d["parameters"]["mass"].pop("source"), r"mass\.source.*missing"),
        (lambda d: d["parameters"]["mass"].__setitem__("kind", "guessed"), r"mass\.kind"),
        (lambda d: d["parameters"]["mass"].__setitem__("unit", "lb"), r"mass\.unit' = 'lb'"),
        (lambda d: d["parameters"]["command_low"].__setitem__("value", [1, 2]), r"list of 3"),
        (
            lambda d: d["parameters"]["tracking_vx"].__setitem__("value", [[0, 0], [0, 1]]),
            r"strictly increasing",
        ),
        (
            lambda d: d["parameters"]["tracking_vx"].__setitem__("value", [[0.5, 0.5], [1, 1]]),
            r"span commanded 0",
        ),
        (
            lambda d: d["parameters"]["envelope_vx_forward"].__setitem__("value", 1.0),
            r"tracking_vx.*achieves more than",
        ),
        (
            lambda d: d["parameters"]["kick_prep_time"].__setitem__("value", 5.0),
            r"kick_prep_time.*longer than",
        ),
    ],
)
def test_bad_profiles_give_clear_errors(mutation, pattern: str) -> None:
    with pytest.raises(ProfileError, match=pattern) as info:
        profile_from_dict(_mutate(mutation), label="test")
    assert isinstance(info.value, ValueError)


def test_error_names_field_and_value(tmp_path: Path) -> None:
    d = _raw()
    d["parameters"]["getup_duration"]["value"] = 1e9
    f = tmp_path / "x.json"
    f.write_text(json.dumps(d))
    with pytest.raises(ProfileError) as info:
        load_profile(f)
    assert info.value.field == "parameters.getup_duration" and info.value.value == 1e9
    assert str(f) in str(info.value)


def test_profile_is_immutable() -> None:
    p = load_profile("t1_mj")
    with pytest.raises(ValueError):
        p.command_high[0] = 9.0
    with pytest.raises(AttributeError):
        p.mass = 1.0  # type: ignore[misc]


def test_a_profile_without_kick_max_angle_kicks_in_any_direction() -> None:
    d = _raw()
    d["parameters"].pop("kick_max_angle")
    p = profile_from_dict(d)
    assert p.kick_max_angle == pytest.approx(np.pi)
    assert p.kinds["kick_max_angle"] == "hand-entered"
    assert "not in this profile" in p.sources["kick_max_angle"]


def test_kick_max_angle_out_of_range_is_named() -> None:
    d = _raw()
    d["parameters"]["kick_max_angle"]["value"] = 4.0
    with pytest.raises(ProfileError, match=r"parameters\.kick_max_angle' = 4\.0.*out of range"):
        profile_from_dict(d)


def test_the_league_t1_kicks_only_near_its_heading() -> None:
    # measured (benchmarks/league_kick_angle.py): the league kick walks round the ball badly
    league = load_profile("t1_league")
    assert league.kinds["kick_max_angle"] == "measured"
    assert 0.0 < league.kick_max_angle < 1.5
    assert load_profile("t1_mj").kick_max_angle == pytest.approx(np.pi)
