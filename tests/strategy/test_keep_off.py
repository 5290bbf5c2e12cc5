"""Teammates do not walk into one spot: ``go_to`` stops beside a teammate that already holds
the target (``keep_off_teammates``), by hand-built scenes and in the env."""

from __future__ import annotations

import math

import numpy as np

from strategy.behaviours.motion import KEEP_OFF_MARGIN_M, go_to, keep_off_teammates
from strategy.perception.worldmodel import WorldModel
from teamenv.sim.playmode import PlayMode
from tests.strategy import scenes

SK = scenes.skills()
CLEAR = 2.0 * SK.body.body_radius + KEEP_OFF_MARGIN_M


def test_a_teammate_on_the_target_keeps_it_and_the_walker_stops_beside_it():
    wm = scenes.world(position=(0.0, 0.0), teammates=[(3.0, 0.0)])
    got = keep_off_teammates(wm, np.array([3.0, 0.0]), CLEAR)
    np.testing.assert_allclose(got, [3.0 - CLEAR, 0.0])
    request = go_to(wm, (3.0, 0.0), SK)
    np.testing.assert_allclose(request.goal.target, [3.0 - CLEAR, 0.0])


def test_the_nearer_player_keeps_its_target_and_the_far_teammate_does_not_matter():
    # I am nearer the target than the teammate by it: I keep it
    wm = scenes.world(position=(3.1, 0.0), teammates=[(3.0, 0.4)])
    np.testing.assert_array_equal(keep_off_teammates(wm, np.array([3.0, 0.0]), CLEAR),
                                  [3.0, 0.0])
    # a teammate farther than the clearance from the target changes nothing
    wm = scenes.world(position=(0.0, 0.0), teammates=[(3.0, CLEAR + 0.05)])
    np.testing.assert_array_equal(keep_off_teammates(wm, np.array([3.0, 0.0]), CLEAR),
                                  [3.0, 0.0])
    # an opponent on the spot is contested, not avoided (ball fights)
    wm = scenes.world(position=(0.0, 0.0), opponents=[(3.0, 0.0)])
    np.testing.assert_array_equal(keep_off_teammates(wm, np.array([3.0, 0.0]), CLEAR),
                                  [3.0, 0.0])


def _two_walk_to_one_spot(avoid: bool, cycles: int = 400) -> tuple[float, int]:
    """Left players 1 and 2 walk to (5, 0) from different distances; the closest they come
    after the first has arrived, and how many of them fell."""
    env, _ = scenes.make_env(team_size=2)
    scenes.place(env, {0: (0.0, 2.0, 0.0), 1: (-2.0, -2.5, 0.0)}, ball=(-8.0, 8.0),
                 mode=PlayMode.PlayOn)
    obs, *_ = env.step(scenes.idle_actions(env))
    target = np.array([5.0, 0.0])
    closest, falls = math.inf, 0
    for _ in range(cycles):
        actions = {}
        for k, agent in enumerate(("left_1", "left_2")):
            wm = WorldModel.from_observation(obs[agent], k, SK.field)
            request = go_to(wm, target, SK, avoid=avoid)
            actions[agent] = request.to_action(scenes.LOW, scenes.HIGH)
        obs, *_ = env.step({**actions, "right_1": {}, "right_2": {}})
        p = scenes.poses(env)
        closest = min(closest, float(np.hypot(*(p[0, :2] - p[1, :2]))))
        falls += int(obs["left_1"]["self"][6] > 0) + int(obs["left_2"]["self"][6] > 0)
    env.close()
    return closest, falls


def test_two_teammates_sent_to_one_spot_stop_apart_in_the_env():
    closest, falls = _two_walk_to_one_spot(avoid=True)
    assert closest >= 2.0 * SK.body.body_radius + 0.05  # never in contact
    assert falls == 0
    # the control: walking straight there, they run into each other
    straight, _ = _two_walk_to_one_spot(avoid=False)
    assert straight < 2.0 * SK.body.body_radius + 0.01
