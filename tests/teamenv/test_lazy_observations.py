"""State-mode Dict observations are built lazily per agent: they equal the eager build
(values, dtypes, shapes, strides) and the mapping behaves as a plain dict."""

import copy
import pickle

import numpy as np

import teamenv
from teamenv.lazy import LazyObservations


def _eager(env):
    """The eager list of every player's observation dict, as observe() built it before."""
    sim, ref = env.sim, env.sim.referee
    return sim.perception.observe(
        sim.world.player_poses(), sim.world.player_velocities(), sim.world.ball_state(),
        sim.fallen(), ref.mode, ref.time_s, ref.half, ref.score, ref.attack_sign,
        sim._heard_info, sim._heard_texts, flat=False)


def _same(a, b):
    assert a.keys() == b.keys() and list(a) == list(b)
    for key in a:
        x, y = a[key], b[key]
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape and x.strides == y.strides
            assert x.tobytes() == y.tobytes() and x.flags.c_contiguous == y.flags.c_contiguous
        else:
            assert type(x) is type(y) and x == y


def test_lazy_observations_equal_the_eager_build():
    env = teamenv.parallel_env(team_size=4)
    obs, _ = env.reset(seed=2)
    rng = np.random.default_rng(2)
    for step in range(40):
        eager = _eager(env)
        assert isinstance(obs, LazyObservations) and isinstance(obs, dict)
        assert list(obs) == env.agents and len(obs) == len(env.agents)
        picked = env.agents[::-1] if step % 2 else env.agents
        for agent in picked:
            _same(obs[agent], eager[env._row[agent]])
            assert obs[agent] is obs[agent]  # built once
        actions = {a: {"walk": rng.uniform(env.parser.walk_low, env.parser.walk_high),
                       "say": f"s{step}"} for a in env.agents}
        obs, *_ = env.step(actions)


def test_lazy_observations_behave_as_a_dict():
    env = teamenv.parallel_env(team_size=3)
    obs, _ = env.reset(seed=5)
    eager = _eager(env)
    for make in (dict, lambda o: {**o}, copy.copy, copy.deepcopy,
                 lambda o: pickle.loads(pickle.dumps(o)), lambda o: dict(o.items())):
        obs, _ = env.reset(seed=5)
        plain = make(obs)
        assert type(plain) is dict and list(plain) == env.agents
        for agent in env.agents:
            _same(plain[agent], eager[env._row[agent]])
    obs, _ = env.reset(seed=5)
    assert obs.get("left_1")["play_mode"] == eager[0]["play_mode"]
    assert obs.get("nobody", 7) == 7 and "left_2" in obs
    values = list(obs.values())
    assert all(isinstance(v, dict) for v in values)
    assert repr(obs).startswith("{'left_1': {'self': array(")


def test_stacked_rows_hold_every_agents_values_until_the_dicts_are_built():
    env = teamenv.parallel_env(team_size=3)
    obs, _ = env.reset(seed=4)
    obs, *_ = env.step({a: {"walk": np.full(3, 0.2, np.float32), "say": "hi"} for a in env.agents})
    block = obs.stacked()
    spans, n = block.spans, block.team_size
    for row, agent in zip(block.values, obs, strict=True):
        d = obs[agent]  # built one by one: the rows stay available
        assert row[:spans[0]].tobytes() == d["self"].tobytes()
        assert row[spans[0]:spans[1]].tobytes() == d["ball"].tobytes()
        players = row[spans[1]:spans[2]].reshape(2 * n, -1)
        assert players[:n].tobytes() == d["teammates"].tobytes()
        assert players[n:].tobytes() == d["opponents"].tobytes()
        assert row[spans[3]:spans[4]].tobytes() == d["game"].tobytes()
        assert row[spans[4]:].reshape(block.heard_shape).tobytes() == d["heard"].tobytes()
    assert block.heard_texts == [obs[a]["heard_text"] for a in obs]
    assert block.play_modes == [obs[a]["play_mode"] for a in obs]
    assert any(any(texts) for texts in block.heard_texts)
    list(obs.values())  # every dict built: a reader may have changed them since
    assert obs.stacked() is None
