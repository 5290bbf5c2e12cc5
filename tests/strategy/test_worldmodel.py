"""The world model's shared beliefs: rounding at perception gives teammates one belief key,
and ``shared`` computes a team-wide fact once per belief, never across different beliefs."""

from __future__ import annotations

import numpy as np

from strategy.perception.worldmodel import WorldModel, shared

from .scenes import make_env, world


def test_teammates_in_state_mode_share_one_belief_key():
    # beliefs are rounded at perception, so every agent of a team believes the same pitch
    env, obs = make_env(field="mj7v7", team_size=7)
    for _ in range(30):
        obs, *_ = env.step({a: {"walk": np.array([0.5, 0.0, 0.2])} for a in env.agents})
    left = [a for a in env.agents if a.startswith("left")]
    models = [WorldModel.from_observation(obs[a], k, env.field, a) for k, a in enumerate(left)]
    assert len({m.belief_key for m in models}) == 1
    assert all(np.array_equal(m.teammates, models[0].teammates) for m in models)


def test_shared_computes_once_per_belief_and_separately_for_different_ones():
    memo: dict = {}
    calls = []

    def fact(wm):
        calls.append(1)
        return float(wm.ball[0])

    a1 = world(ball=(1.0, 0.0))
    a2 = world(ball=(1.0, 0.0), position=(0.5, 0.5))
    b = world(ball=(2.0, 0.0))
    # hand-built models carry no key: nothing is shared, each keeps its facts to itself
    assert shared(memo, "x", a1, lambda: fact(a1)) == 1.0 and not memo
    assert shared(memo, "x", a1, lambda: fact(a1)) == 1.0 and len(calls) == 1
    assert shared(memo, "x", a2, lambda: fact(a2)) == 1.0 and len(calls) == 2
    keyed = [WorldModel(**{**{k: v for k, v in m.__dict__.items() if not k.startswith("_")},
                           "belief_key": m.ball.tobytes()}) for m in (a1, a2, b)]
    got = [shared(memo, "x", m, lambda m=m: fact(m)) for m in keyed]
    assert got == [1.0, 1.0, 2.0]
    assert len(calls) == 4  # one per unkeyed model, then one per distinct belief


def test_shared_caches_none_results_too():
    memo: dict = {}
    m = WorldModel(**{**world().__dict__, "belief_key": b"k"})
    calls = []
    for _ in range(3):
        assert shared(memo, "none", m, lambda: calls.append(1)) is None
    assert len(calls) == 1
