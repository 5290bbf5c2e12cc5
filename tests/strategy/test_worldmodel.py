"""The world model's shared beliefs: rounding at perception gives teammates one belief key,
and ``shared`` computes a team-wide fact once per belief, never across different beliefs."""

from __future__ import annotations

import numpy as np

from strategy.geometry import BallRoll
from strategy.perception.worldmodel import WorldModel, ball_controls, prime_team_facts, shared

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


def test_who_controls_the_ball():
    # our nearest upright player against theirs, with 0.3 m of margin; or the ball in their
    # half with nobody of theirs within 3 m
    assert world(position=(0.0, 0.0), ball=(-1.0, 0.0), opponents=[(-2.5, 0.0)]).we_control_ball()
    assert not world(position=(0.0, 0.0), ball=(-1.0, 0.0),
                     opponents=[(-2.2, 0.0)]).we_control_ball()
    assert world(position=(-9.0, 0.0), ball=(1.0, 0.0), opponents=[(4.5, 0.0)]).we_control_ball()
    assert not world(position=(-9.0, 0.0), ball=(1.0, 0.0),
                     opponents=[(3.5, 0.0)]).we_control_ball()
    alone = world(position=(0.0, 0.0), ball=(-1.0, 0.0), fallen_mates=[0], opponents=[(-5, 0)])
    assert not alone.we_control_ball()  # our only player is down


def test_team_facts_in_one_pass_equal_each_agents_own():
    """``prime_team_facts`` (a vision team's agents, each with its own belief) gives every
    model the control and rest point that model computes alone, bit for bit."""
    rng = np.random.default_rng(4)
    for roll in (BallRoll(), BallRoll(0.0, 0.5)):
        for _ in range(60):
            models = [world(position=tuple(rng.normal(size=2) * 5), me=0, ball=tuple(ball),
                            ball_velocity=tuple(rng.normal(size=2) * rng.choice([0.0, 0.5, 4.0])),
                            teammates=[tuple(p) for p in rng.normal(size=(3, 2)) * 8],
                            opponents=[tuple(p) for p in rng.normal(size=(4, 2)) * 8],
                            fallen_mates=[int(k) for k in np.flatnonzero(rng.random(4) < 0.3)])
                      for ball in rng.normal(size=(5, 2)) * 6]
            models = [WorldModel(**{**{k: v for k, v in m.__dict__.items()
                                       if not k.startswith("_")}, "roll": roll})
                      for m in models]
            alone = [(m.we_control_ball(), m.ball_rest().tobytes()) for m in models]
            fresh = [WorldModel(**{k: v for k, v in m.__dict__.items() if not k.startswith("_")})
                     for m in models]
            prime_team_facts(fresh)
            assert [(m.__dict__["_control"], m.__dict__["_ball_rest"].tobytes())
                    for m in fresh] == alone
            assert ball_controls(fresh) == [c for c, _ in alone]
