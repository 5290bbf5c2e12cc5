"""agent2d role type ``Unknown`` (librcsc's ``RoleType::Unknown``, what HELIOS's Static files
such as before-kick-off.conf give every role) is read in every form; the type is then inferred
from the uniform number and the role's name, as for files without types."""

from __future__ import annotations

import json

import pytest

from strategy.positioning.formation import FormationError, import_agent2d
from tests.strategy.test_agent2d import (
    NAMES,
    PAIRS,
    TYPES,
    agent2d_data,
    write_csv,
    write_json,
    write_legacy,
)

# HELIOS-style before-kick-off.conf in today's JSON form: every role "Unknown", side "C"
KICKOFF_NAMES = ["Goalie", "CenterBack", "CenterBack", "SideBack", "SideBack", "OffensiveHalf",
                 "DefensiveHalf", "DefensiveHalf", "SideHalf", "SideHalf", "CenterForward"]
KICKOFF_XY = [(-49.0, 0.0), (-12.5, -5.0), (-12.5, 5.0), (-11.6, -15.8), (-11.6, 15.8),
              (-25.0, 0.0), (-10.0, -10.8), (-10.0, 10.8), (-0.5, -23.8), (-0.5, 23.8),
              (-0.385, 0.0)]
KICKOFF_JSON = json.dumps({
    "version": "", "method": "Static",
    "role": [{"number": u + 1, "name": n, "type": "Unknown", "side": "C", "pair": 0}
             for u, n in enumerate(KICKOFF_NAMES)],
    "data": [{"index": 0, "ball": {"x": 0.0, "y": 0.0},
              **{str(u + 1): {"x": x, "y": y} for u, (x, y) in enumerate(KICKOFF_XY)}}],
}, indent=2)
INFERRED_KICKOFF = ["G", "DF", "DF", "DF", "DF", "MF", "MF", "MF", "MF", "MF", "FW"]
# the types _infer_type gives the test_agent2d names
INFERRED = ["G", "DF", "DF", "DF", "DF", "MF", "MF", "MF", "MF", "FW", "FW"]
UNKNOWN_AT = (0, 3, 6, 9)  # goalie, a back, a half, a forward
MIXED = ["Unknown" if i in UNKNOWN_AT else t for i, t in enumerate(TYPES)]


def test_helios_static_json_with_unknown_types(tmp_path):
    path = tmp_path / "before-kick-off.conf"
    path.write_text(KICKOFF_JSON)
    f = import_agent2d(path, field="fifa", flip_y=False)
    assert [r.type for r in f.roles] == INFERRED_KICKOFF
    assert [r.name for r in f.roles] == KICKOFF_NAMES
    assert f.n_samples == 1
    assert f.home_positions([20.0, 10.0])[0].tolist() == [-49.0, 0.0]


def _mixed_json(ball, players) -> str:
    doc = json.loads(write_json(ball, players))
    for role, t in zip(doc["role"], MIXED, strict=True):
        role["type"] = t
    return json.dumps(doc)


def _mixed_csv(ball, players) -> str:
    return write_csv(ball, players).replace("RoleType," + ",".join(TYPES),
                                            "RoleType," + ",".join(MIXED))


def _mixed_v3(ball, players) -> str:
    text = write_legacy(ball, players, 3)
    for u in UNKNOWN_AT:
        text = text.replace(f"\n{u + 1} {TYPES[u]} {NAMES[u]} {PAIRS[u]} x x\n",
                            f"\n{u + 1} Unknown {NAMES[u]} {PAIRS[u]} x x\n")
    assert text.count(" Unknown ") == len(UNKNOWN_AT)
    return text


@pytest.mark.parametrize("writer", [_mixed_json, _mixed_csv, _mixed_v3],
                         ids=["json", "csv", "v3"])
def test_unknown_type_in_every_form_is_inferred(writer):
    ball, players = agent2d_data()
    f = import_agent2d(writer(ball, players), field="simspark")
    assert [r.type for r in f.roles] == INFERRED
    assert f.n_samples == len(ball)


def test_csv_static_with_a_role_type_row_of_unknowns():
    text = "\n".join([
        "Method,Static",
        "RoleNumber," + ",".join(str(u) for u in range(1, 12)),
        "RoleName," + ",".join(KICKOFF_NAMES),
        "RoleType," + ",".join(["Unknown"] * 11),
        "Position," + ",".join(f"{x:g},{y:g}" for x, y in KICKOFF_XY),
    ]) + "\n"
    f = import_agent2d(text, field="fifa")
    assert [r.type for r in f.roles] == INFERRED_KICKOFF


@pytest.mark.parametrize("bad", ["XX", "unknown", "Goalie", 3])
def test_other_role_types_are_refused_with_the_word(bad):
    ball, players = agent2d_data()
    doc = json.loads(write_json(ball, players))
    doc["role"][4]["type"] = bad
    with pytest.raises(FormationError, match=r"role\[4\]\.type: role type .* is not one of "
                                             r"G, DF, MF, FW, Unknown"):
        import_agent2d(json.dumps(doc))
