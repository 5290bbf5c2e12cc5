"""The env in the usual subprocess vector envs: Gymnasium's AsyncVectorEnv over the single-agent view and SuperSuit's multiprocess concat_vec_envs_v1 over the ParallelEnv give the in-process results."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

import teamenv


def rollout(vec_env, actions: np.ndarray, seed: int):
    """Observations and rewards of a vector env stepped through ``actions`` after a reset."""
    obs, _ = vec_env.reset(seed=seed)
    observations, rewards = [obs], []
    for action in actions:
        obs, reward, *_ = vec_env.step(action)
        observations.append(obs)
        rewards.append(reward)
    vec_env.close()
    return np.stack(observations), np.stack(rewards)


def player_env():
    return gymnasium.make("teamenv/Player-v0", scenario="one_v_goalie", opponents="chaser",
                          teammates="static", reward={"goal": 1.0, "ball_progress": 0.1})


def test_gymnasium_async_vector_env_steps_the_player_view_like_the_sync_one():
    actions = np.random.default_rng(0).uniform(-1, 1, (40, 2, 9)).astype(np.float32)
    sync = rollout(gymnasium.vector.SyncVectorEnv([player_env] * 2), actions, seed=11)
    subprocesses = rollout(gymnasium.vector.AsyncVectorEnv([player_env] * 2), actions, seed=11)
    np.testing.assert_array_equal(subprocesses[0], sync[0])
    np.testing.assert_array_equal(subprocesses[1], sync[1])
    assert not np.array_equal(sync[0][:, 0], sync[0][:, 1])  # the copies got different seeds


@pytest.mark.rl
def test_supersuit_multiprocess_concat_matches_in_process():
    supersuit = pytest.importorskip("supersuit", reason="needs the rl extra: pip install -e '.[rl]'")

    def vec_env(workers: int):
        env = teamenv.parallel_env(team_size=2, observation_format="box", action_format="box",
                                   max_cycles=100)
        return supersuit.concat_vec_envs_v1(supersuit.pettingzoo_env_to_vec_env_v1(env), 2,
                                            num_cpus=workers)

    # 2 envs x 4 agents = 8 slots, within the first episode: SuperSuit's auto-reset calls
    # reset() without a seed, which the env answers with a fresh, unseeded episode.
    actions = np.random.default_rng(1).uniform(-1, 1, (40, 8, 9)).astype(np.float32)
    in_process = rollout(vec_env(0), actions, seed=5)
    workers = rollout(vec_env(2), actions, seed=5)
    np.testing.assert_array_equal(workers[0], in_process[0])
    np.testing.assert_array_equal(workers[1], in_process[1])
