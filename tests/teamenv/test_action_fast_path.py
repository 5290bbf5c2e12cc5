"""Vectorized Dict-action parsing (ActionParser._fill_dict_fast) writes exactly what the
per-agent path writes, for every mix of keys and rows; anything unusual goes to the per-agent
path and raises its errors."""

import numpy as np
import pytest

import teamenv
from teamenv.errors import ActionError, MessageError
from teamenv.sim.simulation import Commands


def _same_commands(fast, slow):
    for name in ("walk", "kick_power", "kick_dir", "beam_request", "beam"):
        assert getattr(fast, name).tobytes() == getattr(slow, name).tobytes(), name
    assert fast.say == slow.say


def _agents(env, rows, rng):
    """The env's agents whose actions a test gives: all, the right side's, or shuffled."""
    agents = list(env.agents)
    if rows == "right":
        return agents[11:]
    if rows == "shuffled":
        return [agents[k] for k in rng.permutation(22)]
    return agents


def _both(parser, rows, agents, actions):
    fast, slow = Commands.idle(22), Commands.idle(22)
    assert parser._fill_dict_fast(Commands.idle(22), rows, actions)  # valid: the fast path
    parser.fill(fast, rows, agents, actions, {})
    for row, agent, action in zip(rows, agents, actions, strict=True):
        parser._fill_dict(slow, row, agent, action, {})
    _same_commands(fast, slow)


FLAGS = (True, False, 0, 1, np.True_, np.False_)


@pytest.mark.parametrize("keys", [("walk",), ("walk", "kick"), ("walk", "kick", "say"),
                                  ("say",), ("kick", "say"), (),
                                  ("walk", "kick", "beam", "beam_request", "say"),
                                  ("beam",), ("beam_request", "say")])
@pytest.mark.parametrize("rows", ["all", "right", "shuffled"])
def test_fast_path_writes_what_the_per_agent_path_writes(keys, rows):
    env = teamenv.parallel_env(team_size=11)
    env.reset(seed=0)
    rng = np.random.default_rng(len(keys))
    agents = _agents(env, rows, rng)
    row_of = [env._row[a] for a in agents]
    for _ in range(20):
        actions = []
        for k, _agent in enumerate(agents):
            action = {}
            if "walk" in keys:
                action["walk"] = rng.uniform(env.parser.walk_low, env.parser.walk_high).astype(
                    np.float32 if k % 2 else np.float64)
            if "kick" in keys:
                action["kick"] = [float(rng.random()), float(rng.uniform(-3, 3))]
            if "beam" in keys:
                action["beam"] = rng.uniform(env.parser.beam_low, env.parser.beam_high).astype(
                    np.float32 if k % 3 else np.float64)
            if "beam_request" in keys:
                action["beam_request"] = FLAGS[int(rng.integers(len(FLAGS)))]
            if "say" in keys:
                action["say"] = "" if rng.random() < 0.3 else f"m{k}"
            actions.append(action)
        _both(env.parser, row_of, agents, actions)
        # mixed key sets: the first agent drops a key
        if keys:
            actions[0] = {key: actions[0][key] for key in keys[:-1]}
            _both(env.parser, row_of, agents, actions)


def test_unusual_input_gets_the_per_agent_errors():
    env = teamenv.parallel_env(team_size=2)
    env.reset(seed=0)
    ok = {"walk": np.zeros(3), "say": "hi"}
    for bad, error, words in [
        ({"walk": np.array([np.nan, 0, 0])}, ActionError, "finite"),
        ({"walk": np.array([99.0, 0, 0])}, ActionError, "out of range"),
        ({"walk": np.zeros(4)}, ActionError, "shape"),
        ({"walk": np.zeros(3), "say": "(bad)"}, MessageError, "illegal_character"),
        ({"walk": np.zeros(3), "say": "x" * 21}, MessageError, "too_long"),
        ({"walk": np.zeros(3), "say": 7}, MessageError, "must be a str"),
        ({"walk": np.zeros(3), "jump": 1}, ActionError, "unknown action key"),
        ({"walk": np.zeros(3), "beam": np.array([0.0, np.inf, 0.0])}, ActionError, "finite"),
        ({"walk": np.zeros(3), "beam": np.array([0.0, 99.0, 0.0])}, ActionError, "out of range"),
        ({"walk": np.zeros(3), "beam": "0 0 0"}, ActionError, "real numbers"),
        ({"walk": np.zeros(3), "beam_request": 2}, ActionError, "must be 0 or 1"),
        ({"walk": np.zeros(3), "beam_request": "1"}, ActionError, "must be 0 or 1"),
        ({"walk": np.zeros(3), "beam_request": 1.0}, ActionError, "must be 0 or 1"),
    ]:
        actions = {a: dict(ok) for a in env.agents}
        actions["right_2"] = bad
        with pytest.raises(error, match=words):
            env.step(actions)


def _box_both(parser, rows, agents, actions, monkeypatch):
    from teamenv import actions as actions_module

    fast, slow = Commands.idle(22), Commands.idle(22)
    parser.fill(fast, rows, agents, actions, {})
    with monkeypatch.context() as m:  # the NumPy path: the kernel declines every batch
        m.setattr(actions_module, "_box_kernel", lambda: lambda *args: False)
        parser.fill(slow, rows, agents, actions, {})
    _same_commands(fast, slow)


@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.float16, np.longdouble, np.int64,
                                   np.int8, np.uint16, np.bool_])
@pytest.mark.parametrize("rows", ["all", "right", "shuffled"])
def test_compiled_box_path_writes_what_the_numpy_path_writes(dtype, rows, monkeypatch):
    env = teamenv.parallel_env(team_size=11, action_format="box")
    env.reset(seed=0)
    rng = np.random.default_rng(7)
    agents = _agents(env, rows, rng)
    row_of = [env._row[a] for a in agents]
    edges = np.array([-1.0, -0.0, 0.0, 1.0, -1.0 - 5e-7, 1.0 + 5e-7, 1e-300, -1e-300])
    for _ in range(20):
        box = rng.uniform(-1.0, 1.0, (len(agents), 9))
        picks = rng.random(box.shape) < 0.3
        box[picks] = rng.choice(edges, int(picks.sum()))
        if np.dtype(dtype).kind in "iu":
            box = np.rint(box) if np.dtype(dtype).kind == "i" else np.abs(np.rint(box))
        actions = [row.astype(dtype) for row in box]
        _box_both(env.parser, row_of, agents, actions, monkeypatch)


def test_compiled_box_path_leaves_faults_to_the_numpy_path_that_names_them():
    # (the kernel also never sees dtypes numba does not read: float16, longdouble, bool)
    env = teamenv.parallel_env(team_size=1, action_format="box")
    env.reset(seed=0)
    bad = np.zeros(9)
    bad[4] = np.nan
    with pytest.raises(ActionError, match=r"left_1.*action\[4\].*nan.*must be finite"):
        env.step({"left_1": bad, "right_1": np.zeros(9)})
    env.reset(seed=0)
    bad[4] = 1.5
    with pytest.raises(ActionError, match=r"right_1.*action\[4\].*1\.5"):
        env.step({"left_1": np.zeros(9), "right_1": bad})
