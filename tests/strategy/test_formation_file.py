"""The teamenv formation file format (JSON), its validation errors, and the built-in formations."""

from __future__ import annotations

import json

import numpy as np
import pytest

from strategy.positioning.formation import (
    FormationError,
    builtin_formation,
    builtin_formation_names,
    formation_from_dict,
    formation_to_dict,
    read_formation,
    write_formation,
)
from strategy.positioning.formation.design import build_builtins
from teamenv.field import field_preset
from tests.strategy.helpers import grid_formation


def _doc(**changes):
    doc = {
        "format": "teamenv.formation",
        "version": 1,
        "name": "tiny",
        "field": "simspark",
        "roles": [{"name": "Goalie", "type": "G"}, {"name": "Back", "type": "DF"}],
        "samples": [
            {"ball": [0.0, 0.0], "players": [[-14.0, 0.0], [-5.0, 0.0]]},
            {"ball": [10.0, 0.0], "players": [[-13.5, 0.0], [0.0, 0.0]]},
            {"ball": [0.0, 8.0], "players": [[-14.0, 0.5], [-5.0, 3.0]]},
        ],
    }
    doc.update(changes)
    return doc


def test_round_trip_through_a_file(tmp_path):
    f = grid_formation(n=5)
    path = tmp_path / "grid.json"
    write_formation(f, path, description="a test formation")
    g = read_formation(path)
    assert g.name == "grid" and g.description == "a test formation"
    assert [r.name for r in g.roles] == [r.name for r in f.roles]
    # files keep millimetres
    np.testing.assert_allclose(g.sample_positions, f.sample_positions, atol=5e-4)
    np.testing.assert_allclose(g.ball_samples, f.ball_samples, atol=5e-4)
    assert json.loads(path.read_text())["format"] == "teamenv.formation"


def test_minimal_document_and_scaling():
    f = formation_from_dict(_doc())
    np.testing.assert_allclose(f.home_positions([5.0, 0.0]), [[-13.75, 0.0], [-2.5, 0.0]])
    g = formation_from_dict(_doc(), field="fifa")
    np.testing.assert_allclose(g.home_positions([5.0 * 3.5, 0.0]),
                               [[-13.75 * 3.5, 0.0], [-2.5 * 3.5, 0.0]])
    h = formation_from_dict(_doc(field={"length": 30.0, "width": 20.0}))
    assert h.field_size == (30.0, 20.0)
    assert formation_to_dict(h)["field"] == "simspark"


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"format": "agent2d"}, "format must be 'teamenv.formation'"),
        ({"version": 2}, "version must be 1"),
        ({"colour": "red"}, r"unknown key\(s\) \['colour'\]"),
        ({"field": "moon"}, "field: unknown preset 'moon'"),
        ({"field": {"length": -3, "width": 20}}, "field.length must be a positive number"),
        ({"roles": []}, "roles must be a non-empty list"),
        ({"roles": [{"name": "G", "type": "G"}, {"name": "B"}]}, r"roles\[1\]: missing key 'type'"),
        ({"roles": [{"name": "G", "type": "G", "pair": 0}, {"name": "B", "type": "DF"}]},
         r"roles\[0\]: unknown key"),
        ({"samples": []}, "samples must be a non-empty list"),
        ({"outside": "clamp"}, "outside must be one of"),
    ],
)
def test_bad_documents_name_the_field(changes, message):
    with pytest.raises(FormationError, match=message):
        formation_from_dict(_doc(**changes), source="bad.json")


def test_bad_samples_name_the_sample():
    doc = _doc()
    doc["samples"][1]["players"].append([0.0, 0.0])
    with pytest.raises(FormationError, match=r"samples\[1\]\.players has 3 positions, expected 2"):
        formation_from_dict(doc)
    doc = _doc()
    doc["samples"][2]["players"][1] = [1.0, "x"]
    with pytest.raises(FormationError, match=r"samples\[2\]\.players\[1\] must be \[x, y\]"):
        formation_from_dict(doc)
    doc = _doc()
    doc["samples"][2]["ball"] = [10.0, 0.0]
    with pytest.raises(FormationError, match=r"samples\[2\]\.ball .* duplicates samples\[1\]"):
        formation_from_dict(doc)
    doc = _doc()
    doc["samples"][0]["players"][0] = [-40.0, 0.0]
    with pytest.raises(FormationError, match=r"samples\[0\]\.players\[0\] = \(-40\.0, 0\.0\) is off"):
        formation_from_dict(doc)
    doc = _doc()
    doc["samples"][1]["ball"] = [0.0, 4.0]  # on the line through the other two
    with pytest.raises(FormationError, match="degenerate"):
        formation_from_dict(doc)


def test_team_size_mismatch_and_file_errors(tmp_path):
    with pytest.raises(FormationError, match="2 players, expected team_size=11"):
        formation_from_dict(_doc(), team_size=11)
    bad = tmp_path / "broken.json"
    bad.write_text('{"format": "teamenv.formation",')
    with pytest.raises(FormationError, match=r"broken\.json: not valid JSON \(line 1"):
        read_formation(bad)
    with pytest.raises(FormationError, match="cannot be read"):
        read_formation(tmp_path / "missing.json")


# ------------------------------------------------------------------------------ built-ins
def test_builtin_names():
    names = builtin_formation_names()
    for size in ("11v11", "7v7"):
        for kind in ("attack", "defend", "kickoff-ours", "kickoff-theirs", "setplay-ours",
                     "setplay-theirs"):
            assert f"{size}-{kind}" in names
    with pytest.raises(FormationError, match="unknown name"):
        builtin_formation("4-4-2")


@pytest.mark.parametrize("name", builtin_formation_names())
def test_builtins_load_match_their_generator_and_scale(name):
    f = builtin_formation(name)
    assert f.n_players == (11 if name.startswith("11") else 7)
    assert f.goalie_index == 0
    generated = build_builtins()[name]
    np.testing.assert_allclose(f.sample_positions, generated.sample_positions, atol=5e-4)
    for preset in ("simspark", "mj7v7", "fifa"):
        g = builtin_formation(name, preset)
        spec = field_preset(preset)
        home = g.home_positions([spec.half_length * 0.3, -spec.half_width * 0.2])
        assert (np.abs(home[:, 0]) <= spec.half_length + 1e-9).all()
        assert (np.abs(home[:, 1]) <= spec.half_width + 1e-9).all()


@pytest.mark.parametrize("name", [n for n in builtin_formation_names() if "kickoff" in n])
def test_kickoff_lineups_are_in_our_half_and_outside_the_circle(name):
    for preset in ("simspark", "mj7v7", "fifa"):
        spec = field_preset(preset)
        home = builtin_formation(name, preset).home_positions([0.0, 0.0])
        assert (home[:, 0] <= 0).all()
        dist = np.hypot(home[:, 0], home[:, 1])
        outside = dist >= spec.center_circle_radius
        if name.endswith("theirs"):
            assert outside.all()
        else:
            assert outside.sum() >= len(home) - 1  # our kicker may stand at the ball


def test_setplay_theirs_keeps_away_from_the_ball_at_samples():
    f = builtin_formation("11v11-setplay-theirs")
    for b, p in zip(f.ball_samples, f.sample_positions, strict=True):
        assert (np.hypot(*(p - b).T) >= 2.0 - 1e-3).all()
