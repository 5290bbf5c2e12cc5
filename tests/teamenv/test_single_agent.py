"""The single-agent Gymnasium views: Gymnasium's checkers, gymnasium.make, determinism, and
that the caller's actions reach the right players."""

from __future__ import annotations

import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils import passive_env_checker
from gymnasium.utils.env_checker import check_env

import teamenv
from teamenv.errors import ConfigError
from teamenv.registration import MAX_EPISODE_STEPS
from teamenv.single_agent import PlayerEnv, TeamEnv

#: check_env's remarks on the env's unbounded observation Boxes (documented: positions,
#: velocities and times have no finite bound); anything else it says fails the test.
_UNBOUNDED = ("minimum value is -infinity", "maximum value is infinity")

VIEWS = [
    (PlayerEnv, dict(scenario="one_v_one")),
    (PlayerEnv, dict(agent="right_2", team_size=2, teammates="chaser", opponents="static",
                     max_cycles=300)),
    (TeamEnv, dict(scenario="counter_3v2", reward={"ball_progress": 1.0})),
    (TeamEnv, dict(side="right", team_size=2, max_cycles=300, observation_mode="vision")),
]


def _ids(view):
    cls, opts = view
    return cls.__name__ + "-" + "-".join(f"{k}={v}" for k, v in opts.items())


def _checked(fn, *args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn(*args, **kwargs)
    other = [str(w.message) for w in caught if not any(s in str(w.message) for s in _UNBOUNDED)]
    assert not other, other
    return out


@pytest.mark.parametrize("view", VIEWS, ids=_ids)
def test_gymnasium_env_checker_passes(view):
    cls, opts = view
    env = cls(**opts)
    _checked(check_env, env, skip_render_check=True)
    passive_env_checker.check_observation_space(env.observation_space)
    passive_env_checker.check_action_space(env.action_space)
    _checked(passive_env_checker.env_reset_passive_checker, env, seed=3)
    for _ in range(20):
        _checked(passive_env_checker.env_step_passive_checker, env, env.action_space.sample())


def test_gymnasium_make_registers_both_views():
    for env_id, cls in (("teamenv/Player-v0", PlayerEnv), ("teamenv/Team-v0", TeamEnv)):
        assert env_id in gymnasium.registry
        env = gymnasium.make(env_id, scenario="one_v_one")
        assert isinstance(env.unwrapped, cls)
        assert env.spec.max_episode_steps == MAX_EPISODE_STEPS
        obs, _ = env.reset(seed=0)
        assert env.observation_space.contains(obs)
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs) and isinstance(reward, float)
    env = gymnasium.make("teamenv/Player-v0", scenario="one_v_one")
    assert env.unwrapped.env.scenario.name == "one_v_one"
    assert env.unwrapped.env.teams["right"].__class__.__name__ == "ChaserTeam"
    teamenv.registration.register_envs()  # a second registration changes nothing


def _trajectory(env, seed, steps=60):
    env.action_space.seed(seed)
    obs, _ = env.reset(seed=seed)
    out = [obs]
    for _ in range(steps):
        obs, reward, term, trunc, _ = env.step(env.action_space.sample())
        out.append(np.append(obs, reward))
        if term or trunc:
            break
    return np.concatenate(out)


@pytest.mark.parametrize("cls", [PlayerEnv, TeamEnv])
def test_deterministic_under_reset_seed(cls):
    a = _trajectory(cls(scenario="counter_3v2", reward="possession"), 5)
    b = _trajectory(cls(scenario="counter_3v2", reward="possession"), 5)
    c = _trajectory(cls(scenario="counter_3v2", reward="possession"), 6)
    assert np.array_equal(a, b)
    assert not np.array_equal(a[:len(c)], c[:len(a)])
    # a reset without a seed after a seeded one is deterministic too
    env1, env2 = cls(scenario="one_v_one"), cls(scenario="one_v_one")
    env1.reset(seed=9)
    env2.reset(seed=9)
    assert np.array_equal(env1.reset()[0], env2.reset()[0])


def test_player_env_drives_one_player_and_the_team_the_others():
    env = PlayerEnv(agent="left_2", team_size=3, teammates="chaser", opponents="static",
                    max_cycles=400)
    obs, _ = env.reset(seed=1)
    sim = env.env.sim
    assert env.env.agents == ["left_2"]
    start = sim.world.player_poses().copy()
    turn_left = np.array([0.0, 0.0, 1.0, -1, 0, -1, 0, 0, 0], np.float32)
    for _ in range(200):
        obs, *_ = env.step(turn_left)
    poses = sim.world.player_poses()
    # the caller's player turned on the spot (its team's chaser actions were ignored) ...
    assert np.hypot(*(poses[1, :2] - start[1, :2])) < 0.3
    assert abs(poses[1, 2] - start[1, 2]) > 1.0
    # ... while the chaser team ran its other players (the one nearest the ball chases it)
    assert max(np.hypot(*(poses[k, :2] - start[k, :2])) for k in (0, 2)) > 1.0
    assert obs[2] == pytest.approx(poses[1, 2], abs=1e-5)  # own heading, team frame


def test_team_env_layout():
    env = TeamEnv(team_size=3, opponents="static", max_cycles=200)
    obs, info = env.reset(seed=0)
    inner = env.env
    assert env.agents == ["left_1", "left_2", "left_3"]
    size = inner.observation_space("left_1").shape[0]
    assert obs.shape == (3 * size,) and env.action_space.shape == (27,)
    direct = inner.sim.observations(flat=True)
    for k, agent in enumerate(env.agents):
        assert np.array_equal(obs[k * size:(k + 1) * size], direct[inner.player_names.index(agent)])
    start = inner.sim.world.player_poses().copy()
    action = np.tile(np.array([0, 0, 0, -1, 0, -1, 0, 0, 0], np.float32), 3)
    action[9 * 2 + 2] = 1.0  # only left_3 turns
    for _ in range(60):
        obs, reward, *_ = env.step(action)
    turned = np.abs(inner.sim.world.player_poses()[:3, 2] - start[:3, 2])
    assert turned[2] > 0.5 and turned[:2].max() < 1e-6
    with pytest.raises(ConfigError, match=r"expected \(27,\)"):
        env.step(np.zeros(9))


def test_team_env_leaves_benched_players_out_and_ends_with_a_reason():
    env = TeamEnv(scenario="empty_goal", team_size=2, opponents="chaser")
    obs, _ = env.reset(seed=0)
    assert env.agents == ["left_1"]
    assert env.action_space.shape == (9,)
    idle = np.array([0, 0, 0, -1, 0, -1, 0, 0, 0], np.float32)
    while True:
        obs, reward, term, trunc, info = env.step(idle)
        if term or trunc:
            break
    assert trunc and info["end"] == "time_limit"


def test_view_errors_are_clear():
    with pytest.raises(ConfigError, match=r"\['right'\] are set by the view"):
        PlayerEnv(right="chaser")
    with pytest.raises(ConfigError, match="agent must be 'left_<k>'"):
        PlayerEnv(agent="keeper")
    with pytest.raises(ConfigError, match="benched by scenario 'empty_goal'"):
        PlayerEnv(agent="right_1", scenario="empty_goal")
    with pytest.raises(ConfigError, match="unknown agent 'left_4'"):
        PlayerEnv(agent="left_4", team_size=3)
    with pytest.raises(ConfigError, match="side must be"):
        TeamEnv(side="both")
    env = PlayerEnv(scenario="empty_goal", max_cycles=1)
    env.reset(seed=0)
    env.step(env.action_space.sample())
    with pytest.raises(ConfigError, match="call reset"):
        env.step(env.action_space.sample())
