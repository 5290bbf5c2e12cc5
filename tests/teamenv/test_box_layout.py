"""The flat (Box) action and observation layouts are written once (teamenv.box_layout), and
what the env, its spaces, the slot names and the policy team do agrees with them."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import teamenv
from teamenv import box_layout
from teamenv.box_layout import (
    ACTION_COLUMNS,
    ACTION_SIZE,
    STATE_PARTS,
    VISION_PARTS,
    StateLayout,
    decode_box_actions,
    flatten_observation,
)
from teamenv.policy_team import box_to_dict_action, box_to_dict_actions
from teamenv.slots import action_slot_names, observation_slot_names

ROOT = Path(__file__).resolve().parents[2]
# Module-level assignments of names that state a part of the layout: box_layout's constants,
# the Box action's old size and a part's width (``*_DIM``).
FACT_NAMES = {name for name in vars(box_layout) if name.isupper()} | {"BOX_SIZE"}
ASSIGNED = re.compile(r"^([A-Z_]+(?:\s*,\s*[A-Z_]+)*)\s*=", re.MULTILINE)

CONFIGS = [
    {"team_size": 3},
    {"team_size": 1, "channel": "mj"},
    {"team_size": 2, "observation_mode": "vision"},
    {"team_size": 2, "observation_mode": "vision", "vision": "mj", "channel": "mj"},
]


def test_the_layout_is_written_in_one_module():
    found = {}
    for path in (ROOT / "teamenv").rglob("*.py"):
        if path.name == "box_layout.py":
            continue
        assigned = {name.strip() for m in ASSIGNED.finditer(path.read_text())
                    for name in m.group(1).split(",")}
        names = sorted(n for n in assigned if n in FACT_NAMES or n.endswith("_DIM"))
        if names:
            found[str(path.relative_to(ROOT))] = names
    assert not found, f"layout facts outside teamenv/box_layout.py: {found}"


@pytest.mark.parametrize("kwargs", CONFIGS)
def test_the_spaces_and_slot_names_have_the_layout_sizes(kwargs):
    env = teamenv.parallel_env(observation_format="box", action_format="box", **kwargs)
    agent = env.possible_agents[0]
    layout = env.sim.vision.layout if env.sim.vision is not None else \
        StateLayout(env.team_size, env.sim.heard_slots)
    assert env.observation_space(agent).shape == (layout.size,)
    assert env.action_space(agent).shape == (ACTION_SIZE,)
    assert len(observation_slot_names(env)) == layout.size
    assert action_slot_names() == ACTION_COLUMNS
    offsets = list(layout.offsets.values())
    assert offsets[0][0] == 0 and offsets[-1][1] == layout.size
    assert all(a[1] == b[0] for a, b in zip(offsets[:-1], offsets[1:], strict=True))  # contiguous, in order
    parts = STATE_PARTS if env.sim.vision is None else VISION_PARTS
    assert tuple(layout.offsets) == parts


@pytest.mark.parametrize("kwargs", CONFIGS)
def test_dict_parts_and_flatten_are_the_two_forms_of_one_row(kwargs):
    envs = {}
    for form in ("dict", "box"):
        envs[form] = teamenv.parallel_env(observation_format=form, **kwargs)
    obs = {form: env.reset(seed=5)[0] for form, env in envs.items()}
    for _ in range(4):  # a vision update and the cycles between
        obs = {form: env.step({a: {"walk": np.array([0.3, 0.0, 0.2])} for a in env.agents})[0]
               for form, env in envs.items()}
    env = envs["box"]
    layout = env.sim.vision.layout if env.sim.vision is not None else \
        StateLayout(env.team_size, env.sim.heard_slots)
    rows = np.stack([obs["box"][a] for a in env.agents])
    parts = layout.dict_parts(rows)
    for k, agent in enumerate(env.agents):
        as_dict = obs["dict"][agent]
        assert np.array_equal(flatten_observation(as_dict), rows[k])
        for key, values in parts.items():
            assert np.array_equal(values[k], as_dict[key]), (agent, key)
        start, stop = layout.offsets["play_mode"]
        assert rows[k, start:stop].argmax() == as_dict["play_mode"]


def test_decoding_maps_the_ends_of_the_box_onto_the_command_ranges():
    low, high = np.array([-0.4, -0.3, -1.0]), np.array([0.8, 0.3, 1.2])
    box = np.array([[-1.0, -1.0, -1.0, -0.5, -1.0, 0.0, -1.0, -1.0, -1.0],
                    [1.0, 1.0, 1.0, 1.0, 1.0, 0.5, 1.0, 1.0, 1.0],
                    [0.5, 0.0, -0.5, 0.25, 0.5, -0.1, 0.0, 0.5, 0.5]])
    d = decode_box_actions(box, low, high, half_length=15.0, half_width=10.0)
    assert np.array_equal(d.walk[0], low) and np.array_equal(d.walk[1], high)
    assert np.allclose(d.walk[2], [0.4, 0.0, -0.5])  # -0.5 is half of walk_low
    assert d.kick_power.tolist() == [0.0, 1.0, 0.25]  # <= 0: no kick
    assert np.allclose(d.kick_direction, [-math.pi, math.pi, math.pi / 2])
    assert d.beam_request.tolist() == [False, True, False]
    assert np.allclose(d.beam, [[-15.0, -10.0, -math.pi], [0.0, 10.0, math.pi],
                                [-7.5, 5.0, math.pi / 2]])


def test_the_policy_teams_batch_conversion_is_the_row_by_row_one():
    env = teamenv.parallel_env(team_size=2)
    low, high = env.parser.walk_low, env.parser.walk_high
    actions = np.random.default_rng(4).uniform(-1.2, 1.2, (20, ACTION_SIZE))  # some clipped
    batch = box_to_dict_actions(actions, low, high, env.field)
    for row, got in zip(actions, batch, strict=True):
        one = box_to_dict_action(row, low, high, env.field)
        assert got.keys() == one.keys()
        for key in got:
            assert np.array_equal(got[key], one[key]), key
