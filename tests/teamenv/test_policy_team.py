"""The policy team: the MLP file format round-trips, errors are clear, the Dict<->Box
conversions match the env's own Box forms, and self-play passes PettingZoo's API tests."""

from __future__ import annotations

import numpy as np
import pytest
from pettingzoo.test import api_test, parallel_api_test

import teamenv
from teamenv.actions import ActionParser
from teamenv.errors import TeamFault
from teamenv.policy_team import (
    MLP_FORMAT,
    MLPPolicy,
    PolicyFileError,
    box_to_dict_action,
    flatten_observation,
    load_policy,
    save_mlp_policy,
)
from teamenv.sim.simulation import Commands
from tests.teamenv.helpers import idle


def _layers(obs_size: int, hidden: int = 16, seed: int = 0):
    rng = np.random.default_rng(seed)
    return [(rng.normal(0, 0.3, (obs_size, hidden)), rng.normal(0, 0.1, hidden)),
            (rng.normal(0, 0.3, (hidden, 9)), rng.normal(0, 0.1, 9))]


def _obs_size(**opts) -> int:
    env = teamenv.parallel_env(observation_format="box", **opts)
    return env.observation_space(env.possible_agents[0]).shape[0]


def test_file_round_trips(tmp_path):
    size = _obs_size(team_size=2)
    rng = np.random.default_rng(1)
    mean, std = rng.normal(size=size), rng.uniform(0.5, 2.0, size)
    path = save_mlp_policy(tmp_path / "w.npz", _layers(size), activation="relu",
                           obs_mean=mean, obs_std=std, obs_clip=5.0, team_size=2)
    policy = load_policy(path)
    assert (policy.observation_size, policy.team_size, policy.activation) == (size, 2, "relu")
    assert str(np.load(path)["format"]) == MLP_FORMAT
    batch = rng.normal(size=(4, size)).astype(np.float32)
    in_memory = MLPPolicy(_layers(size), activation="relu", obs_mean=mean, obs_std=std,
                          obs_clip=5.0)
    assert np.array_equal(policy(batch), in_memory(batch))
    # by hand: normalise, clip, relu hidden layer, identity output, clip to [-1, 1]
    (w0, b0), (w1, b1) = [(w.astype(np.float32), b.astype(np.float32))
                          for w, b in _layers(size)]
    x = np.clip((batch - mean.astype(np.float32)) / std.astype(np.float32), -5, 5)
    expected = np.clip(np.maximum(x @ w0 + b0, 0) @ w1 + b1, -1, 1)
    assert policy(batch) == pytest.approx(expected, abs=1e-5)


def test_missing_and_malformed_files_are_clear(tmp_path):
    with pytest.raises(PolicyFileError, match="not found"):
        load_policy(tmp_path / "nope.npz")
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    with pytest.raises(PolicyFileError, match="not an .npz"):
        load_policy(tmp_path / "junk.npz")
    np.savez(tmp_path / "other.npz", format=np.array("something-else"))
    with pytest.raises(PolicyFileError, match="format 'something-else'"):
        load_policy(tmp_path / "other.npz")
    np.savez(tmp_path / "short.npz", format=np.array(MLP_FORMAT), n_layers=np.array(2),
             W0=np.zeros((3, 9)), b0=np.zeros(9))
    with pytest.raises(PolicyFileError, match=r"missing \['W1', 'b1'\]"):
        load_policy(tmp_path / "short.npz")
    with pytest.raises(PolicyFileError, match="last layer gives 4 outputs"):
        save_mlp_policy(tmp_path / "x.npz", [(np.zeros((3, 4)), np.zeros(4))])
    with pytest.raises(PolicyFileError, match="W1 has 5 inputs, the layer before gives 4"):
        MLPPolicy([(np.zeros((3, 4)), np.zeros(4)), (np.zeros((5, 9)), np.zeros(9))])
    with pytest.raises(PolicyFileError, match="activation: 'gelu'"):
        MLPPolicy(_layers(3), activation="gelu")
    with pytest.raises(PolicyFileError, match="obs_std: every entry must be > 0"):
        MLPPolicy(_layers(3), obs_std=np.array([1.0, 0.0, 1.0]))


def test_wrong_team_size_or_mode_is_refused(tmp_path):
    path = save_mlp_policy(tmp_path / "w.npz", _layers(_obs_size(team_size=2)), team_size=2)
    with pytest.raises(PolicyFileError, match=r"trained with team_size 2.*team_size 3, state"):
        teamenv.parallel_env(team_size=3, right="policy", right_config={"path": str(path)})
    with pytest.raises(PolicyFileError, match="trained on observation_mode 'state'"):
        teamenv.parallel_env(team_size=2, right="policy", right_config={"path": str(path)},
                             observation_mode="vision")
    with pytest.raises(PolicyFileError, match="exactly one of 'path'"):
        teamenv.parallel_env(team_size=2, right="policy")
    with pytest.raises(PolicyFileError, match="not found"):
        teamenv.parallel_env(team_size=2, right="policy", right_config={"path": "no.npz"})


@pytest.mark.parametrize("opts", [dict(team_size=3), dict(team_size=2, channel="mj"),
                                  dict(team_size=2, observation_mode="vision")],
                         ids=["state", "mj", "vision"])
def test_flattened_dict_observation_is_the_box_observation(opts):
    dict_env = teamenv.parallel_env(**opts)
    box_env = teamenv.parallel_env(observation_format="box", **opts)
    rng = np.random.default_rng(0)
    d_obs, _ = dict_env.reset(seed=7)
    b_obs, _ = box_env.reset(seed=7)
    for _ in range(6):
        for agent in dict_env.agents:
            assert np.array_equal(flatten_observation(d_obs[agent]), b_obs[agent]), agent
        actions = {a: {"walk": rng.uniform(-0.4, 0.4, 3).astype(np.float32),
                       "say": "ab" if "mj" not in opts.values() else ""}
                   for a in dict_env.agents}
        d_obs, *_ = dict_env.step(actions)
        b_obs, *_ = box_env.step(actions if box_env.action_format == "dict" else None)


def test_box_to_dict_action_is_what_the_box_parser_does():
    env = teamenv.parallel_env(team_size=2)
    low, high = env.parser.walk_low, env.parser.walk_high
    box = ActionParser(env.field, low, high, env.sim.channel, "box", True)
    as_dict = ActionParser(env.field, low, high, env.sim.channel, "dict", True)
    rng = np.random.default_rng(3)
    actions = rng.uniform(-1, 1, (50, 9))
    actions[::3, 5] = 0.5  # some beam requests
    actions[::4, :3] = [[-1.0, 1.0, -1.0]]  # the ends of the walk range
    n = len(actions)
    a, b = Commands.idle(n), Commands.idle(n)
    names = [f"left_{k}" for k in range(n)]
    box.fill(a, list(range(n)), names, list(actions), {})
    as_dict.fill(b, list(range(n)), names,
                 [box_to_dict_action(x, low, high, env.field) for x in actions], {})
    for field in ("walk", "kick_power", "kick_dir", "beam_request", "beam"):
        assert np.allclose(getattr(a, field), getattr(b, field), atol=1e-12), field


def test_policy_team_plays_and_a_callable_works_in_process(tmp_path):
    size = _obs_size(team_size=2)
    path = save_mlp_policy(tmp_path / "w.npz", _layers(size))
    from_file = teamenv.parallel_env(team_size=2, right="policy",
                                     right_config={"path": str(path)})
    policy = load_policy(path)
    calls = []

    def in_process(batch):
        calls.append(batch.shape)
        return policy(batch)

    from_fn = teamenv.parallel_env(team_size=2, right="policy",
                                   right_config={"policy": in_process})
    from_file.reset(seed=2)
    from_fn.reset(seed=2)
    for _ in range(80):
        from_file.step(idle(from_file))
        from_fn.step(idle(from_fn))
    assert np.array_equal(from_file.state(), from_fn.state())
    assert calls == [(2, size)] * 80  # one batched call per cycle for the whole team
    # the team's Box actions reach the bodies: full speed ahead, no kick, no beam
    forward = np.array([1.0, 0.0, 0.0, -1.0, 0.0, -1.0, 0.0, 0.0, 0.0])
    walker = teamenv.parallel_env(team_size=2, right="policy", right_config={
        "policy": lambda batch: np.tile(forward, (len(batch), 1))})
    walker.reset(seed=2)
    start_x = walker.sim.world.player_poses()[2:, 0].copy()
    for _ in range(100):
        walker.step(idle(walker))
    walked = start_x - walker.sim.world.player_poses()[2:, 0]  # the right team faces -x
    assert (walked > 0.5).all(), walked


def test_a_policy_returning_garbage_is_a_team_fault():
    env = teamenv.parallel_env(team_size=2, right="policy",
                               right_config={"policy": lambda batch: np.zeros((1, 9))})
    env.reset(seed=0)
    with pytest.raises(TeamFault, match=r"returned \(1, 9\).*expected \(2, 9\)"):
        env.step(idle(env))


def test_self_play_and_policy_opponent_pass_pettingzoo_api(tmp_path):
    path = save_mlp_policy(tmp_path / "w.npz", _layers(_obs_size(team_size=1)))
    for opts in (dict(team_size=1, scenario="one_v_one"),
                 dict(team_size=1, right="policy", right_config={"path": str(path)}),
                 dict(scenario="one_v_one", right="policy", right_config={"path": str(path)},
                      observation_format="box", action_format="box")):
        parallel_api_test(teamenv.parallel_env(max_cycles=100, **opts), num_cycles=120)
        api_test(teamenv.env(max_cycles=40, **opts), num_cycles=50)


def _ball_at(obs_size: int, rel_xy) -> np.ndarray:
    """State-mode Box rows with the ball at ``rel_xy`` (body frame) and zeros elsewhere."""
    obs = np.zeros((len(rel_xy), obs_size), np.float32)
    obs[:, 7:9] = rel_xy  # ball.rel_x, ball.rel_y (teamenv.slots)
    return obs


def test_kick_gate_walk_to_ball_and_action_repeat_round_trip_and_act(tmp_path):
    size = _obs_size(team_size=1)
    # a network that always asks for a full-power kick straight ahead and walks backwards
    out_bias = np.array([-1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    layers = [(np.zeros((size, 4)), np.zeros(4)), (np.zeros((4, 9)), out_bias)]
    path = save_mlp_policy(tmp_path / "g.npz", layers, kick_gate_m=0.3, walk_to_ball=True,
                           action_repeat=5)
    policy = load_policy(path)
    assert (policy.kick_gate_m, policy.walk_to_ball, policy.action_repeat) == (0.3, True, 5)
    obs = _ball_at(size, [[0.2, 0.0], [3.0, 0.0], [0.0, 3.0], [-3.0, 0.1]])
    acts = policy(obs)
    assert acts[0, 3] == 1.0 and (acts[1:, 3] == 0.0).all()  # kick only within the gate
    assert (acts[0, :3] == 0.0).all()  # stands for the kick
    assert acts[1, 0] == 1.0 and acts[1, 2] == 0.0  # ball ahead: full speed, no turn
    assert acts[2, 2] == 1.0 and acts[2, 0] == pytest.approx(0.2)  # ball to the left: turn
    assert acts[3, 2] > 0.9  # ball behind, a little to the left: turn left
    assert np.array_equal(policy.network_actions(obs), np.tile(out_bias, (4, 1)))
    # the gate alone leaves the network's walk as it is
    gated = load_policy(save_mlp_policy(tmp_path / "k.npz", layers, kick_gate_m=0.3))
    assert np.array_equal(gated(obs)[:, :3], np.tile(out_bias[:3], (4, 1)))
    assert (gated(obs)[1:, 3] == 0.0).all() and gated.action_repeat == 1
    for bad, match in (({"walk_to_ball": True}, "needs kick_gate_m"),
                       ({"kick_gate_m": -1.0}, "kick_gate_m"),
                       ({"kick_gate_m": 0.3, "action_repeat": 0}, "action_repeat"),
                       ({"kick_gate_m": 0.3, "observation_mode": "vision"}, "only for")):
        with pytest.raises(PolicyFileError, match=match):
            MLPPolicy(layers, **bad)


def test_the_policy_team_runs_the_network_every_action_repeat_cycles(tmp_path):
    size = _obs_size(team_size=1)
    layers = [(np.zeros((size, 4)), np.zeros(4)), (np.zeros((4, 9)), np.zeros(9))]
    policy = MLPPolicy(layers, kick_gate_m=0.3, walk_to_ball=True, action_repeat=3)
    calls = []
    network = policy.network_actions
    policy.network_actions = lambda batch: calls.append(len(calls)) or network(batch)
    env = teamenv.parallel_env(scenario="keep_away", right="policy",
                               right_config={"policy": policy}, left="chaser")
    for seed in (0, 1):
        env.reset(seed=seed)
        for _ in range(7):
            env.step({})
        assert len(calls) == 3 * (seed + 1)  # cycles 0, 3, 6 of each episode
