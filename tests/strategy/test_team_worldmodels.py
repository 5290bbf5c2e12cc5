"""The team's world models computed in one pass equal each agent's own, bit for bit."""

import numpy as np
import pytest

import teamenv
from strategy.geometry import BallRoll
from strategy.perception.team_worldmodels import team_world_models
from strategy.perception.worldmodel import WorldModel, WorldModelError

FIELDS = ("me", "position", "heading", "velocity", "fallen", "ball", "ball_velocity",
          "teammates", "teammates_present", "teammates_fallen", "opponents",
          "opponents_present", "opponents_fallen", "play_mode", "time_s", "half", "score",
          "heard", "field", "belief_key", "ball_age_s", "pose_spread_m")


def _same(a: WorldModel, b: WorldModel) -> None:
    for name in FIELDS:
        x, y = getattr(a, name), getattr(b, name)
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape, name
            assert x.tobytes() == y.tobytes(), name  # bitwise, -0.0 and NaN included
        else:
            assert type(x) is type(y) and x == y, name
    assert a.obstacles().tobytes() == b.obstacles().tobytes()
    assert a.ball_rest().tobytes() == b.ball_rest().tobytes()


@pytest.mark.parametrize("resolution", [0.01, None])
def test_batched_world_models_equal_one_by_one(resolution):
    env = teamenv.parallel_env(field="mj7v7", team_size=7, right="chaser")
    obs, _ = env.reset(seed=5)
    rng = np.random.default_rng(5)
    left = [a for a in env.agents if a.startswith("left")]
    index = {a: k for k, a in enumerate(left)}
    roll = BallRoll()
    low, high = env.parser.walk_low, env.parser.walk_high
    for _ in range(400):
        mine = {a: obs[a] for a in left}
        batched = team_world_models(mine, index, env.field, roll, resolution,
                                    ball_rest=resolution is not None)
        assert list(batched) == left
        for agent in left:
            alone = WorldModel.from_observation(mine[agent], index[agent], env.field, agent,
                                                roll, resolution)
            _same(batched[agent], alone)
        actions = {a: {"walk": rng.uniform(low, high).astype(np.float32),
                       "kick": np.array([rng.uniform() * (rng.uniform() < 0.3),
                                         rng.uniform(-3, 3)], dtype=np.float32),
                       "say": "ab"} for a in left}
        obs, *_ = env.step(actions)


@pytest.mark.parametrize("resolution", [0.01, None])
def test_world_models_from_the_envs_stacked_rows_equal_those_from_the_dicts(resolution):
    # a team hosted by the env gets its observations as LazyObservations, whose stacked
    # rows team_world_models reads without building the per-agent dicts
    env = teamenv.parallel_env(team_size=5, left="chaser", right="chaser")
    env.reset(seed=3)
    roll = BallRoll()
    for _ in range(300):
        for side in ("left", "right"):
            hosted = env.team_host.observations[side]
            assert hosted.stacked() is not None
            index = {a: k for k, a in enumerate(hosted)}
            from_rows = team_world_models(hosted, index, env.field, roll, resolution,
                                          ball_rest=True)
            dicts = {a: hosted[a] for a in hosted}
            from_dicts = team_world_models(dicts, index, env.field, roll, resolution,
                                           ball_rest=True)
            assert list(from_rows) == list(from_dicts)
            for agent in from_rows:
                _same(from_rows[agent], from_dicts[agent])
        env.step({})


def test_irregular_observation_gets_the_per_agent_error():
    env = teamenv.parallel_env(team_size=3)
    obs, _ = env.reset(seed=1)
    left = [a for a in env.agents if a.startswith("left")]
    mine = {a: dict(obs[a]) for a in left}
    mine[left[1]]["self"] = np.array([np.nan] * 7, dtype=np.float32)
    with pytest.raises(WorldModelError, match=left[1]):
        team_world_models(mine, {a: k for k, a in enumerate(left)}, env.field)
    del mine[left[1]]["ball"]
    with pytest.raises(WorldModelError, match=left[1]):
        team_world_models(mine, {a: k for k, a in enumerate(left)}, env.field)
