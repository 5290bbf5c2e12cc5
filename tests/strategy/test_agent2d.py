"""agent2d/HELIOS formation import: JSON, 2021 CSV and legacy text files written here, then read."""

from __future__ import annotations

import json

import numpy as np
import pytest

from strategy.positioning.formation import FormationError, builtin_formation, import_agent2d

NAMES = ["Goalie", "CenterBack", "CenterBack", "SideBack", "SideBack", "DefensiveHalf",
         "DefensiveHalf", "SideHalf", "SideHalf", "Forward", "Forward"]
TYPES = ["G", "DF", "DF", "DF", "DF", "MF", "MF", "MF", "MF", "FW", "FW"]
PAIRS = [0, -1, 2, -1, 4, -1, 6, -1, 8, -1, 10]


def agent2d_data() -> tuple[np.ndarray, np.ndarray]:
    """The built-in 11v11-defend formation in agent2d's coordinates (105 x 68 m, y to the
    right), rounded to agent2d's 0.01 m."""
    f = builtin_formation("11v11-defend", "fifa").mirrored(flip_x=False, flip_y=True)
    return np.round(f.ball_samples, 2), np.round(f.sample_positions, 2)


def write_json(ball, players) -> str:
    return json.dumps({
        "method": "DelaunayTriangulation",
        "role": [{"number": i + 1, "name": n, "type": t, "pair": p}
                 for i, (n, t, p) in enumerate(zip(NAMES, TYPES, PAIRS, strict=True))],
        "data": [
            {"index": k, "ball": {"x": b[0], "y": b[1]},
             **{str(u + 1): {"x": pl[u][0], "y": pl[u][1]} for u in range(11)}}
            for k, (b, pl) in enumerate(zip(ball.tolist(), players.tolist(), strict=True))
        ],
    }, indent=1)


def write_csv(ball, players) -> str:
    lines = [
        "# written by the teamenv tests",
        "Method,DelaunayTriangulation",
        "RoleNumber," + ",".join(str(u) for u in range(1, 12)),
        "RoleName," + ",".join(NAMES),
        "RoleType," + ",".join(TYPES),
        "SymmetryNumber," + ",".join(str(p) for p in PAIRS),
        "Marker," + ",".join("0" for _ in range(11)),
        "SetplayMarker," + ",".join("0" for _ in range(11)),
        "SampleData",
        f"Size,{len(ball)}",
        "idx,ballX,ballY," + ",".join(f"{u}X,{u}Y" for u in range(1, 12)),
    ]
    for k, (b, pl) in enumerate(zip(ball.tolist(), players.tolist(), strict=True)):
        lines.append(",".join([str(k), f"{b[0]:g}", f"{b[1]:g}"]
                              + [f"{v:g}" for xy in pl for v in xy]))
    return "\n".join(lines) + "\n"


def write_legacy(ball, players, version: int) -> str:
    lines = ["# written by the teamenv tests", f"Formation DelaunayTriangulation {version}",
             "Begin Roles"]
    for u in range(11):
        if version == 3:
            lines.append(f"{u + 1} {TYPES[u]} {NAMES[u]} {PAIRS[u]} x x")
        else:
            lines.append(f"{u + 1} {NAMES[u]} {PAIRS[u]}")
    lines += ["End Roles", f"Begin Samples 2 {len(ball)}"]
    for k, (b, pl) in enumerate(zip(ball.tolist(), players.tolist(), strict=True)):
        lines.append(f"----- {k} -----")
        lines.append(f"Ball {b[0]:g} {b[1]:g}")
        lines += [f"{u + 1} {pl[u][0]:g} {pl[u][1]:g}" for u in range(11)]
    lines.append("End Samples")
    return "\n".join(lines) + "\n"


def write_v1(ball, players) -> str:
    lines = ["Formation DelaunayTriangulation",
             " ".join(f"{n} {p}" for n, p in zip(NAMES, PAIRS, strict=True))]
    for b, pl in zip(ball.tolist(), players.tolist(), strict=True):
        lines.append(" ".join(f"{v:g}" for v in [*b, *[c for xy in pl for c in xy]]))
    lines.append("End")
    return "\n".join(lines) + "\n"


WRITERS = {
    "json": write_json,
    "csv": write_csv,
    "v2": lambda b, p: write_legacy(b, p, 2),
    "v3": lambda b, p: write_legacy(b, p, 3),
    "v1": write_v1,
}


@pytest.mark.parametrize("form", sorted(WRITERS))
def test_import_each_form_from_a_file(tmp_path, form):
    ball, players = agent2d_data()
    path = tmp_path / f"defense-formation.{'json' if form == 'json' else 'conf'}"
    path.write_text(WRITERS[form](ball, players))
    f = import_agent2d(path, field="simspark")
    assert f.name == "defense-formation"
    assert f.n_players == 11 and f.n_samples == len(ball)
    assert f.field_size == (30.0, 20.0)
    types = [r.type for r in f.roles]
    if form in ("json", "csv", "v3"):
        assert types == TYPES
    else:  # inferred from the uniform number and the name
        assert types == ["G", "DF", "DF", "DF", "DF", "MF", "MF", "MF", "MF", "FW", "FW"]
    assert [r.name for r in f.roles] == NAMES
    # back on simspark, y flipped back: the original built-in (to agent2d's 0.01 m rounding)
    ref = builtin_formation("11v11-defend")
    np.testing.assert_allclose(f.ball_samples, ref.ball_samples, atol=0.01)
    np.testing.assert_allclose(f.sample_positions, ref.sample_positions, atol=0.01)
    for b in ([3.0, 2.0], [-12.0, -7.5], [14.0, 9.0]):
        np.testing.assert_allclose(f.home_positions(b), ref.home_positions(b), atol=0.02)


def test_import_from_text_scaling_flip_and_select():
    ball, players = agent2d_data()
    text = write_csv(ball, players)
    raw = import_agent2d(text, field="fifa", flip_y=False)
    np.testing.assert_allclose(raw.sample_positions, players, atol=1e-9)  # 105 x 68, as written
    seven = import_agent2d(text, field="mj7v7", select=[1, 2, 3, 6, 7, 10, 11], name="mini")
    assert seven.n_players == 7 and seven.name == "mini"
    assert seven.field_size == (55.0, 36.0)
    np.testing.assert_allclose(seven.sample_positions[:, 1],
                               players[:, 1] * [55 / 105, -36 / 68], atol=1e-9)


def test_agent2d_ball_samples_beyond_the_lines_are_accepted():
    ball, players = agent2d_data()
    ball[0] = [54.5, -36.0]  # as agent2d's own files do (2 m beyond the lines)
    f = import_agent2d(write_json(ball, players))
    assert f.ball_samples[0] == pytest.approx([54.5 * 30 / 105, 36.0 * 20 / 68])


@pytest.mark.parametrize(
    ("mutate", "message"),
    [
        (lambda t: t.replace("DelaunayTriangulation", "KNN"), "method 'KNN' is not supported"),
        (lambda t: t.replace("Begin Roles", "Begin Rolls"), "expected 'Begin Roles'"),
        (lambda t: t.replace("\n7 DefensiveHalf 6", "\n8 DefensiveHalf 6"), "uniform number 7"),
        (lambda t: t.replace("----- 3 -----", "----- 4 -----"), r"expected '----- 3 -----'"),
        (lambda t: t.replace("Ball ", "Bal ", 1), "expected 'Ball x y'"),
        (lambda t: t.replace("Formation DelaunayTriangulation 2", "Formation DelaunayTriangulation 7"),
         "format version 7"),
    ],
)
def test_legacy_errors_name_the_line(mutate, message):
    ball, players = agent2d_data()
    with pytest.raises(FormationError, match=message):
        import_agent2d(mutate(write_legacy(ball, players, 2)))


def test_csv_and_json_errors():
    ball, players = agent2d_data()
    csv = write_csv(ball, players)
    short_row = "\n".join(ln.rsplit(",", 1)[0] if ln.startswith("1,") else ln
                          for ln in csv.splitlines())
    with pytest.raises(FormationError, match=r"line 13: a sample row has 24 values, expected 25"):
        import_agent2d(short_row)
    with pytest.raises(FormationError, match="Size says"):
        import_agent2d(csv.replace(f"Size,{len(ball)}", f"Size,{len(ball) + 1}"))
    with pytest.raises(FormationError, match="RoleType"):
        import_agent2d(csv.replace("RoleType,G,", "RoleType,GK,"))
    doc = json.loads(write_json(ball, players))
    del doc["role"][4]
    with pytest.raises(FormationError, match=r"uniform numbers \[5\] have no role"):
        import_agent2d(json.dumps(doc))
    doc = json.loads(write_json(ball, players))
    doc["data"][2]["7"] = {"x": 1.0}
    with pytest.raises(FormationError, match=r"data\[2\]\.7 must be"):
        import_agent2d(json.dumps(doc))
    with pytest.raises(FormationError, match="unknown format"):
        import_agent2d("hello world\nsecond line\n")
    with pytest.raises(FormationError, match="select"):
        import_agent2d(csv, select=[0, 1])


def test_duplicate_samples_in_an_agent2d_file_are_reported():
    ball, players = agent2d_data()
    ball[5] = ball[3]
    with pytest.raises(FormationError, match=r"samples\[5\]\.ball .* duplicates samples\[3\]"):
        import_agent2d(write_json(ball, players))
