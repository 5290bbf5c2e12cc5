"""The infos of a step are built lazily (message drops listed on first use): once used they
equal, key order included, the dict an eager build gives, and behave as a plain dict."""

import copy
import json
import pickle

import numpy as np

import teamenv
from teamenv.env import SIDES
from teamenv.lazy import LazyInfos
from teamenv.sim.playmode import PlayMode


def eager_infos(env, agents, report, dropped):
    """The eager build of infos as the env did it before it was made lazy."""
    infos = {a: {} for a in agents}
    names = env.player_names
    for agent, problems in dropped.items():
        if agent in infos:
            infos[agent]["dropped"] = problems
    for i in report.beams_refused:
        if names[i] in infos:
            infos[names[i]]["beam_refused"] = PlayMode(env.sim.referee.mode).name
    for drop in report.dropped:
        speaker = names[drop.speaker] if 0 <= drop.speaker < len(names) else None
        if speaker in infos:
            infos[speaker].setdefault("message_dropped", []).append(
                {"listener": names[drop.listener] if drop.listener >= 0 else None,
                 "reason": drop.reason})
    for event in report.referee:
        if event.kind == "goal":
            for a in agents:
                infos[a]["goal"] = SIDES[event.team]
    return infos


def _talking_actions(env, rng):
    return {a: {"walk": rng.uniform(env.parser.walk_low, env.parser.walk_high),
                "say": "m" + str(int(rng.integers(0, 1000))),
                "beam_request": 1}
            for a in env.agents}


def test_lazy_infos_equal_the_eager_build():
    for channel in ("simspark", "mj"):
        env = teamenv.parallel_env(team_size=5, channel=channel, strict=False)
        env.reset(seed=3)
        rng = np.random.default_rng(3)
        lazy_seen = 0
        for _ in range(30):
            actions = _talking_actions(env, rng)
            if channel == "mj":  # base64 texts
                for a in actions:
                    actions[a]["say"] = "QUJD"
            agents = list(env.agents)
            _, _, _, _, infos = env.step(actions)
            lazy_seen += isinstance(infos, LazyInfos)
            eager = eager_infos(env, agents, env.last_report, {})
            assert isinstance(infos, dict)
            assert repr(infos) == repr(eager)  # same values, same key order
            assert infos == eager and list(infos) == agents
        assert lazy_seen > 0


def test_lazy_infos_behave_as_a_dict():
    env = teamenv.parallel_env(team_size=5)
    env.reset(seed=1)
    rng = np.random.default_rng(1)
    for _ in range(5):
        _, _, _, _, infos = env.step(_talking_actions(env, rng))
    assert isinstance(infos, LazyInfos)
    eager = eager_infos(env, list(env.agents), env.last_report, {})
    plain = pickle.loads(pickle.dumps(infos))
    assert type(plain) is dict and plain == eager
    assert copy.deepcopy(infos) == eager and dict(infos) == eager and {**infos} == eager
    assert json.loads(json.dumps(infos)) == eager
    # any use fills it, so even dict's own C methods see the full content afterwards
    _, _, _, _, infos = env.step(_talking_actions(env, rng))
    eager = eager_infos(env, list(env.agents), env.last_report, {})
    assert len(infos) == len(eager)
    assert dict.__repr__(infos) == repr(eager)
    _, _, _, _, infos = env.step(_talking_actions(env, rng))
    eager = eager_infos(env, list(env.agents), env.last_report, {})
    assert sorted(infos.items()) == sorted(eager.items())


def test_message_drops_go_before_the_goal_key():
    """An eager build lists dropped, beam_refused, message_dropped, goal in this order."""
    from types import SimpleNamespace

    from comms.channel import Delivery, Drop
    from teamenv.infos import add_message_drops

    names = ["left_1", "left_2", "right_1", "right_2"]
    base = {a: {"goal": "left"} for a in names}
    base["left_1"] = {"dropped": ["x"], "goal": "left"}
    drops = [Drop(0, -1, "too_long"), Drop(0, 2, "capacity"), Drop(3, 1, "capacity")]
    report = SimpleNamespace(delivery=Delivery([[] for _ in names], drops))
    infos = LazyInfos(base, lambda b: add_message_drops(b, names, report))
    assert list(infos["left_1"]) == ["dropped", "message_dropped", "goal"]
    assert infos["left_1"]["message_dropped"] == [
        {"listener": None, "reason": "too_long"}, {"listener": "right_1", "reason": "capacity"}]
    assert list(infos["right_2"]) == ["message_dropped", "goal"]
    assert list(infos["left_2"]) == ["goal"]
