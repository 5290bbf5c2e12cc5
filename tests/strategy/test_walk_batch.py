"""A team's walk commands computed together equal each agent's ``walk_command``, bit for bit,
and a pending walk request behaves like a computed one."""

import numpy as np
import pytest

from strategy.behaviours.control import ControlRequest, resolve_walks
from strategy.behaviours.navigation import NavigationParams, walk_command
from strategy.behaviours.walk_batch import WalkGoal, walk_commands

PARAMS = (NavigationParams(), NavigationParams(influence_m=3.0, omni_m=0.0, arrive_m=0.0),
          NavigationParams(side_step_left=False),  # the league network's walk
          NavigationParams(side_step_right=False, omni_m=0.6))


def _goals(rng, params, team=11, grid=0.01):
    players = np.round(rng.uniform(-4, 4, (2 * team, 2)) / grid) * grid + 0.0
    goals = []
    for me in range(team):
        position = players[me]
        kind = rng.integers(0, 6)
        if kind == 0:
            target = position.copy()                       # already there
        elif kind == 1:
            target = position + rng.uniform(-0.3, 0.3, 2)  # omnidirectional zone
        elif kind == 2:
            target = players[rng.integers(0, 2 * team)]    # onto another player
        else:
            target = np.round(rng.uniform(-6, 6, 2) / grid) * grid
        avoid = rng.uniform(size=2 * team) < 0.9
        avoid[me] = False
        face = None if rng.uniform() < 0.3 else rng.uniform(-6, 6, 2)
        speed = None if rng.uniform() < 0.5 else float(rng.uniform(0.2, 1.5))
        goals.append(WalkGoal(position, float(rng.uniform(-np.pi, np.pi)), target, players,
                              None if rng.uniform() < 0.15 else avoid, face, speed, params))
    return goals


@pytest.mark.parametrize("params", PARAMS)
def test_batched_commands_equal_one_by_one(params):
    rng = np.random.default_rng(0)
    for _ in range(300):
        goals = _goals(rng, params)
        batched = walk_commands(goals)
        for goal, command in zip(goals, batched, strict=True):
            alone = walk_command(goal.position, goal.heading, goal.target, goal.obstacles(),
                                 params, face=goal.face, speed=goal.speed)
            assert command.dtype == alone.dtype and command.tobytes() == alone.tobytes()


def test_pending_request_computes_its_walk_on_first_read_and_keeps_it():
    goal = _goals(np.random.default_rng(1), PARAMS[0])[3]
    request = ControlRequest.walking(goal, "go_to")
    assert request.pending
    said = request.with_say("hi")
    assert said.pending and said.say == "hi" and said.behaviour == "go_to"
    walk = request.walk
    assert not request.pending and walk.tobytes() == goal.command().tobytes()
    assert request.walk is walk
    action = said.to_action(np.full(3, -9.0), np.full(3, 9.0))
    assert action["walk"].tobytes() == walk.tobytes() and action["say"] == "hi"


def test_resolve_walks_fills_every_pending_request():
    goals = _goals(np.random.default_rng(2), PARAMS[0])
    requests = [ControlRequest.walking(g, "go_to") for g in goals] + [ControlRequest()]
    resolve_walks(requests)
    assert not any(r.pending for r in requests)
    for goal, request in zip(goals, requests[:-1], strict=True):
        assert request.walk.tobytes() == goal.command().tobytes()
    with pytest.raises(AttributeError):
        ControlRequest().not_a_field  # noqa: B018


def test_team_actions_equal_each_request_to_action():
    from strategy.behaviours.control import team_actions

    goals = _goals(np.random.default_rng(3), PARAMS[0])
    low, high = np.array([-0.5, -0.2, -1.0]), np.array([0.8, 0.2, 1.0])
    requests = {f"a{k}": ControlRequest.walking(g, "go_to") for k, g in enumerate(goals)}
    requests["kicker"] = ControlRequest(np.array([2.0, -1.0, 0.3]), kick=(1.5, 0.2), say="x")
    requests["beamer"] = ControlRequest(beam=(-3.0, 1.0, 0.0))
    together = team_actions(requests, low, high)
    for agent, request in requests.items():
        alone = request.to_action(low, high)
        assert list(together[agent]) == list(alone)
        for key, value in alone.items():
            assert np.asarray(together[agent][key]).tobytes() == np.asarray(value).tobytes()


def test_pending_request_copies_and_pickles_still_pending():
    import copy
    import pickle

    goal = _goals(np.random.default_rng(4), PARAMS[0])[5]
    request = ControlRequest.walking(goal, "go_to")
    for clone in (copy.deepcopy(request), pickle.loads(pickle.dumps(request))):
        assert clone.pending and clone.behaviour == "go_to"
        assert clone.walk.tobytes() == goal.command().tobytes()
    assert request.pending


def test_the_kernels_hypot_is_pythons_bit_for_bit():
    # CPython computes math.hypot itself (not the C library's hypot, which numba calls)
    import math

    from strategy.behaviours.walk_kernel import py_hypot

    rng = np.random.default_rng(0)
    legs = rng.normal(size=(100_000, 2)) * 10.0 ** rng.uniform(-8, 8, (100_000, 2))
    special = [0.0, -0.0, 5e-324, 1e-310, -2.2250738585072014e-308, 1e-300, 1e300, 1.7e308,
               math.inf, -math.inf, math.nan, 3.0, 4.0]
    pairs = legs.tolist() + [(x, y) for x in special for y in special]
    got = np.array([py_hypot(x, y) for x, y in pairs])
    expected = np.array([math.hypot(x, y) for x, y in pairs])
    assert got.tobytes() == expected.tobytes()
