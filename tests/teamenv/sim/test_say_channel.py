"""The say channel inside the env: next-observation delivery, self echo, slots, capacity, drops."""

import numpy as np

from tests.teamenv.helpers import idle, make_env


def test_message_heard_in_next_observation_with_self_echo_first():
    env = make_env(team_size=3)
    obs, *_ = env.step({**idle(env), "left_2": {"say": "ball@3,4"}})
    assert obs["left_2"]["heard_text"][0] == "ball@3,4"
    assert obs["left_2"]["heard"][0, :2].tolist() == [1.0, 1.0]  # present, from self
    # A teammate hears it in a teammate slot with a direction; an opponent in another slot.
    mate = obs["left_1"]
    assert "ball@3,4" in mate["heard_text"]
    k = mate["heard_text"].index("ball@3,4")
    assert mate["heard"][k, 2] == 1.0 and mate["heard"][k, 1] == 0.0
    assert "ball@3,4" in obs["right_1"]["heard_text"]
    # The cycle after, nobody says anything: the slots are empty again.
    obs, *_ = env.step(idle(env))
    assert obs["left_1"]["heard_text"] == ("",) * len(obs["left_1"]["heard_text"])
    assert not obs["left_1"]["heard"][:, 0].any()


def test_hearing_capacity_one_teammate_message_every_two_cycles():
    env = make_env(team_size=3)
    heard_by_left_1 = []
    for cycle in range(8):
        actions = {**idle(env), "left_2": {"say": f"a{cycle}"}, "left_3": {"say": f"b{cycle}"}}
        obs, _, _, _, infos = env.step(actions)
        texts = [t for t in obs["left_1"]["heard_text"] if t]
        heard_by_left_1.append(len(texts))
    # Capacity 2, +1 per cycle, -2 per message: at most one teammate message every 2 cycles.
    assert sum(heard_by_left_1) == 4
    assert all(a + b <= 1 for a, b in zip(heard_by_left_1, heard_by_left_1[1:], strict=False))


def test_capacity_refills_during_silent_cycles():
    env = make_env(team_size=2)
    env.step({**idle(env), "left_2": {"say": "one"}})
    env.step(idle(env))  # silent: capacity refills from 0 to 1
    obs, *_ = env.step({**idle(env), "left_2": {"say": "two"}})
    assert "two" in obs["left_1"]["heard_text"]


def test_drops_are_reported_in_infos():
    env = make_env(team_size=3)
    env.step({**idle(env), "left_2": {"say": "x"}, "left_3": {"say": "y"}})
    _, _, _, _, infos = env.step({**idle(env), "left_2": {"say": "x2"}, "left_3": {"say": "y2"}})
    reasons = [d["reason"] for a in ("left_2", "left_3") for d in infos[a].get("message_dropped", [])]
    assert "capacity" in reasons


def test_mj_channel_base64_messages():
    import base64

    env = make_env(team_size=2, channel="mj")
    text = base64.b64encode(b"\x01\x02hello").decode()
    obs, *_ = env.step({**idle(env), "left_1": {"say": text}})
    assert text in obs["left_2"]["heard_text"]
    assert env.action_space("left_1")["say"].contains(text)
    assert not env.action_space("left_1")["say"].contains("not base64!")
    np.testing.assert_array_equal(obs["left_1"]["heard"][:, 1], 0.0)  # mj: no self echo
