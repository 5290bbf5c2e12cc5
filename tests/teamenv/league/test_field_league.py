"""``mj7v7`` (and ``fifa``) are the league server's own fields and rules: our presets, the
``mj`` landmark table and the rules' team size and half time read against the installed
rcsssmj (its field specs, its ``ssim`` rule book, and the vision markers its simulation puts
in the world)."""

from __future__ import annotations

import numpy as np
import pytest

from teamenv.config import RulesConfig
from teamenv.field import field_preset
from teamenv.landmarks import MJ_MARKS_LEFT, MJ_MARKS_RIGHT, landmarks

pytest.importorskip("rcsssmj")
pytest.importorskip("mujoco")

from rcsssmj.games.soccer.sim.soccer_sim import SoccerSimulation  # noqa: E402
from rcsssmj.games.soccer.soccer_fields import create_soccer_field  # noqa: E402
from rcsssmj.games.soccer.soccer_rules import create_soccer_rule_book  # noqa: E402


def server_markers(field_version: str) -> dict[str, np.ndarray]:
    """The vision markers rcsssmj's soccer simulation adds to its world for a field."""
    sim = SoccerSimulation(field=create_soccer_field(field_version))
    spec = sim._create_world()
    assert spec is not None
    return {site.name.removesuffix("-vismarker"): np.array(site.pos, dtype=float)
            for site in spec.sites if site.name.endswith("-vismarker")}


@pytest.mark.parametrize(("preset", "version"), [("mj7v7", "fifa7vs7"), ("fifa", "fifa")])
def test_field_preset_is_the_servers_field(preset, version):
    ours, theirs = field_preset(preset), create_soccer_field(version)
    length, width, _ = theirs.field_dim
    depth, goal_width, goal_height = theirs.goal_dim
    assert (ours.length, ours.width) == (length, width)
    assert (ours.goal_depth, ours.goal_width, ours.goal_height) == (depth, goal_width,
                                                                    goal_height)
    assert ours.goal_post_radius == theirs.goal_post_radius
    assert (ours.penalty_length, ours.penalty_width) == tuple(theirs.penalty_area_dim)
    assert (ours.goal_area_length, ours.goal_area_width) == tuple(theirs.goalie_area_dim)
    assert ours.center_circle_radius == theirs.center_circle_radius
    assert ours.penalty_spot_distance == theirs.penalty_spot_distance


def test_mj7v7_is_the_ssim_rule_books_field_team_size_and_half():
    rules = create_soccer_rule_book("ssim")
    assert rules.default_field_version.value == "fifa7vs7"
    assert field_preset("mj7v7").default_team_size == rules.max_team_size == 7
    assert RulesConfig().half_time_s == rules.half_time == 300


@pytest.mark.parametrize(("preset", "version"), [("mj7v7", "fifa7vs7"), ("fifa", "fifa")])
def test_mj_landmarks_are_the_servers_vision_markers(preset, version):
    marks = server_markers(version)
    marks.pop("B")  # the ball's marker
    table = landmarks(field_preset(preset), "mj")
    assert sorted(MJ_MARKS_LEFT[m] for m in marks) == sorted(table.names)
    for mark, xyz in marks.items():
        # the left team's frame is the world; the right team's is the world turned by pi
        for names, sign in ((MJ_MARKS_LEFT, 1.0), (MJ_MARKS_RIGHT, -1.0)):
            want = np.array([sign * xyz[0], sign * xyz[1], xyz[2]])
            np.testing.assert_allclose(table.xyz[table.index(names[mark])], want, atol=1e-9,
                                       err_msg=f"{mark} = {names[mark]}")
