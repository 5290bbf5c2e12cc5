"""The env's fast paths agree with the plain ones: batch body I/O vs body by body, the
flat observation vs the Dict parts, heard slots vs the channel's delivery."""

import hashlib
import pickle

import numpy as np
import pytest

import teamenv
from teamenv.box_layout import N_PLAY_MODES


def _run(env, steps: int, seed: int = 0) -> str:
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed + 1)
    h = hashlib.sha256(pickle.dumps(obs))
    for t in range(steps):
        actions = {a: {"walk": rng.uniform([-0.5, -0.3, -1.0], [1.0, 0.3, 1.0]),
                       "kick": np.array([rng.random() * (rng.random() < 0.3), 0.0])}
                   for a in env.agents}
        if t % 3 == 0:
            actions[env.agents[t % len(env.agents)]]["say"] = f"m{t}"
        out = env.step(actions)
        h.update(pickle.dumps(out))
        h.update(env.state().tobytes())
        h.update(env.sim.world.impacts.tobytes())
    return h.hexdigest()


def test_batch_body_io_is_used_and_matches_body_by_body():
    fast = teamenv.parallel_env(team_size=4)
    slow = teamenv.parallel_env(team_size=4)
    assert fast.sim.world._batch is not None  # pymunk's batch API lists our bodies in order
    slow.sim.world._batch = None  # the per-body fallback
    assert _run(fast, 300) == _run(slow, 300)
    w_fast, w_slow = fast.sim.world, slow.sim.world
    assert w_fast.player_poses().tobytes() == w_slow.player_poses().tobytes()
    assert w_fast.player_velocities().tobytes() == w_slow.player_velocities().tobytes()
    assert not w_fast.player_poses().flags.writeable


def test_poses_cache_follows_placement():
    env = teamenv.parallel_env(team_size=2)
    env.reset(seed=0)
    world = env.sim.world
    before = world.player_poses()
    world.place_player(1, 3.0, -2.0, 0.5)
    after = world.player_poses()
    assert after is not before
    assert after[1].tolist() == pytest.approx([3.0, -2.0, 0.5])
    assert after[0].tolist() == before[0].tolist()


@pytest.mark.parametrize("team_size", [1, 3, 11])
def test_flat_rows_are_the_dict_parts(team_size):
    dict_env = teamenv.parallel_env(team_size=team_size)
    box_env = teamenv.parallel_env(team_size=team_size, observation_format="box")
    obs_d, _ = dict_env.reset(seed=2)
    obs_b, _ = box_env.reset(seed=2)
    for _ in range(30):
        acts = {a: {"walk": np.array([0.5, 0.0, 0.2])} for a in dict_env.agents}
        obs_d, *_ = dict_env.step(acts)
        obs_b, *_ = box_env.step(acts)
    for agent in dict_env.agents:
        d = obs_d[agent]
        onehot = np.zeros(N_PLAY_MODES, np.float32)
        onehot[d["play_mode"]] = 1.0
        expected = np.concatenate([d["self"], d["ball"], d["teammates"].ravel(),
                                   d["opponents"].ravel(), onehot, d["game"],
                                   d["heard"].ravel()])
        assert obs_b[agent].dtype == np.float32
        assert obs_b[agent].tobytes() == expected.tobytes()
        assert d["teammates"].shape == (team_size, 5) and d["teammates"].flags.c_contiguous
        assert dict_env.observation_space(agent).contains(d)


def test_observations_are_fresh_arrays_each_cycle():
    env = teamenv.parallel_env(team_size=2)
    obs0, _ = env.reset(seed=0)
    kept = obs0["left_1"]["self"].copy()
    obs1, *_ = env.step({a: {"walk": np.array([1.0, 0.0, 0.0])} for a in env.agents})
    assert obs0["left_1"]["self"].tobytes() == kept.tobytes()  # not overwritten
    assert not np.shares_memory(obs0["left_1"]["self"], obs1["left_1"]["self"])


@pytest.mark.parametrize("channel", ["simspark", "mj"])
def test_heard_slots_follow_the_delivery(channel):
    import base64

    env = teamenv.parallel_env(team_size=3, channel=channel)
    env.reset(seed=1)
    sim = env.sim
    n_heard = 0
    for t in range(12):
        acts = {}
        for k, a in enumerate(env.agents):
            text = f"{a[0]}{k}x{t}"
            if channel == "mj":
                text = base64.b64encode(text.encode()).decode()
            acts[a] = {"say": text} if (k + t) % 2 else {}
        obs, *_ = env.step(acts)
        slots = sim.heard_slots
        for i, heard in enumerate(env.last_report.heard):
            ordered = sorted(heard, key=lambda m: 0 if m.is_self else (1 if m.teammate else 2))
            ordered = ordered[:slots]
            n_heard += len(ordered)
            o = obs[env.player_names[i]]
            assert o["heard_text"] == tuple(m.text for m in ordered) + ("",) * (slots - len(ordered))
            expected = np.zeros((slots, 4), np.float32)
            for k, m in enumerate(ordered):
                expected[k] = (1.0, float(m.is_self), float(m.teammate), m.direction)
            assert o["heard"].tobytes() == expected.tobytes()
    assert n_heard > 20
