"""agent2d `Static` formations (before-kick-off.conf and the other set-up line-ups): imported in
every on-disk form as single-sample formations that hold their positions whatever the ball does."""

from __future__ import annotations

import json

import numpy as np
import pytest

from strategy.positioning.formation import FormationError, import_agent2d

NAMES = ["Goalie", "CenterBack", "CenterBack", "SideBack", "SideBack", "DefensiveHalf",
         "OffensiveHalf", "OffensiveHalf", "SideForward", "SideForward", "CenterForward"]
# agent2d's before-kick-off.conf (helios-base), metres on 105 x 68, y to the right of the attack
XY = [(-49, 0), (-25, -5), (-25, 5), (-25, -10), (-25, 10), (-25, 0), (-15, -5), (-15, 5),
      (-15, -10), (-15, 10), (-15, 0)]

CSV = "\n".join([
    "Method,Static",
    "RoleNumber," + ",".join(str(u) for u in range(1, 12)),
    "RoleName," + ",".join(NAMES),
    "#PositionIdx," + ",".join(f"{u}X,{u}Y" for u in range(1, 12)),
    "Position," + ",".join(f"{x:g},{y:g}" for x, y in XY),
]) + "\n"

LEGACY = "\n".join([
    "Formation Static",
    "# ---------------------------------------------------------",
    "# move positions when playmode is BeforeKickOff or AfterGoal.",
    *[f"{u + 1} {NAMES[u]}  {x:g}  {y:g}" for u, (x, y) in enumerate(XY)],
    "# ---------------------------------------------------------",
]) + "\n"

JSON = json.dumps({
    "method": "Static",
    "role": [{"number": u + 1, "name": n, "type": "G" if u == 0 else "MF", "pair": 0}
             for u, n in enumerate(NAMES)],
    "data": [{"index": 0, "ball": {"x": 0.0, "y": 0.0},
              **{str(u + 1): {"x": x, "y": y} for u, (x, y) in enumerate(XY)}}],
})


def expected_on(length: float, width: float) -> np.ndarray:
    """XY scaled from 105 x 68 m and y negated (our y points left of the attack)."""
    return np.array([(x * length / 105.0, -y * width / 68.0) for x, y in XY])


@pytest.mark.parametrize("text", [CSV, LEGACY, JSON], ids=["csv", "legacy", "json"])
def test_static_formation_holds_its_positions_whatever_the_ball(tmp_path, text):
    path = tmp_path / "before-kick-off.conf"
    path.write_text(text)
    f = import_agent2d(path, field="simspark")
    assert f.is_static and f.n_samples == 1 and f.name == "before-kick-off"
    assert [r.name for r in f.roles] == NAMES and f.roles[0].type == "G"
    home = f.home_positions((0.0, 0.0))
    np.testing.assert_allclose(home, expected_on(30.0, 20.0), atol=1e-12)
    rng = np.random.default_rng(0)
    for ball in rng.uniform((-15, -10), (15, 10), size=(20, 2)):
        np.testing.assert_array_equal(f.home_positions(ball), home)
    many = f.home_positions_many(rng.uniform((-15, -10), (15, 10), size=(7, 2)))
    np.testing.assert_array_equal(many, np.broadcast_to(home, many.shape))


def test_static_select_and_fields():
    f = import_agent2d(CSV, field="mj7v7", select=[1, 6, 11], flip_y=False)
    assert [r.name for r in f.roles] == ["Goalie", "DefensiveHalf", "CenterForward"]
    np.testing.assert_allclose(f.home_positions((3.0, 4.0)),
                               [[-49 * 55 / 105, 0.0], [-25 * 55 / 105, 0.0], [-15 * 55 / 105, 0.0]])


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (CSV.replace("Position,", "Positions,"), "unknown row 'Positions' in a Static formation"),
        ("\n".join(ln for ln in CSV.splitlines() if not ln.startswith("Position")),
         "no 'Position' row"),
        (CSV.rsplit(",", 1)[0] + "\n", r"line 5: the Position row has 21 values, expected 22"),
        (CSV.replace(",-49,", ",minus49,"), r"line 5: 'minus49' is not a number"),
        (CSV.replace("RoleName,Goalie,", "RoleName,"), "RoleName has 10 names"),
        (LEGACY.replace("\n11 CenterForward", "\n# 11 CenterForward"),
         "needs 11 rows 'unum name x y', got 10"),
        (LEGACY.replace("\n7 OffensiveHalf", "\n8 OffensiveHalf"), r"expected '7 name x y'"),
        (LEGACY.replace("Formation Static", "Formation Static 2"), "takes no version"),
        (JSON.replace('"index": 0', '"index": 0, "extra": 1').replace(
            '"data": [', '"data": [{"ball": {"x": 1, "y": 1}}, '), "data has 2 entries"),
        (CSV.replace("Method,Static", "Method,UvA"), "method 'UvA' is not supported"),
    ],
)
def test_static_errors_name_the_problem(text, message):
    with pytest.raises(FormationError, match=message):
        import_agent2d(text)
