"""Bad input: clear errors naming agent, field and value (strict), documented drops (lenient)."""

import warnings

import numpy as np
import pytest

import teamenv
from teamenv.errors import ActionError, ConfigError, MessageError, TeamLoadError
from tests.teamenv.helpers import idle, make_env

GOOD = {"walk": np.array([0.3, 0.0, 0.1], np.float32)}


def test_unknown_agent():
    env = make_env()
    with pytest.raises(ActionError, match="left_9"):
        env.step({**idle(env), "left_9": GOOD})


def test_action_for_team_driven_agent_is_rejected():
    env = make_env(right="static")
    with pytest.raises(ActionError, match="right_1.*team plugin"):
        env.step({**idle(env), "right_1": GOOD})


def test_missing_agent():
    env = make_env()
    actions = idle(env)
    del actions["right_2"]
    with pytest.raises(ActionError, match="right_2.*no action"):
        env.step(actions)


@pytest.mark.parametrize("field,value,pattern", [
    ("walk", [0.1, 0.2], "walk.*shape"),
    ("walk", [np.nan, 0, 0], "walk.*finite"),
    ("walk", [np.inf, 0, 0], "walk.*finite"),
    ("walk", [9.0, 0, 0], "walk.*out of range"),
    ("walk", "fast", "walk"),
    ("kick", [1.5, 0.0], "kick.*out of range"),
    ("kick", [0.5, 7.0], "kick.*out of range"),
    ("beam", [1.0, 0.0, 0.0], "beam.*out of range"),
    ("beam_request", 2, "beam_request"),
    ("dance", 1, "unknown action key"),
])
def test_bad_dict_fields_name_agent_field_value(field, value, pattern):
    env = make_env()
    with pytest.raises(ActionError, match=f"left_2.*{pattern}"):
        env.step({**idle(env), "left_2": {field: value}})


@pytest.mark.parametrize("text,reason", [
    ("x" * 21, "too_long"),
    ("hi(there)", "illegal_character"),
    ("caf\u00e9", "illegal_character"),
    ("two words", "illegal_character"),
])
def test_bad_messages(text, reason):
    env = make_env()
    with pytest.raises(MessageError, match=f"right_1.*say.*{reason}"):
        env.step({**idle(env), "right_1": {"say": text}})


def test_bad_box_actions():
    env = make_env(action_format="box")
    zero = {a: np.zeros(9, np.float32) for a in env.agents}
    with pytest.raises(ActionError, match="left_1.*shape"):
        env.step({**zero, "left_1": np.zeros(4)})
    bad = np.zeros(9)
    bad[2] = np.nan
    with pytest.raises(ActionError, match="left_1.*action\\[2\\].*finite"):
        env.step({**zero, "left_1": bad})
    bad = np.zeros(9)
    bad[0] = 1.5
    with pytest.raises(ActionError, match="left_1.*action\\[0\\].*\\[-1, 1\\]"):
        env.step({**zero, "left_1": bad})


def test_lenient_mode_drops_and_reports():
    env = make_env(strict=False)
    before = env.sim.world.player_poses().copy()
    actions = idle(env)
    actions["left_1"] = {"walk": [np.nan, 0, 0], "say": "bad(msg)"}
    actions["left_2"] = {"walk": [9.0, 0, 0]}
    del actions["right_1"]
    actions["nobody"] = GOOD
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        obs, rewards, terms, truncs, infos = env.step(actions)
    assert len(caught) >= 4
    assert any("finite" in m for m in infos["left_1"]["dropped"])
    assert any("illegal_character" in m for m in infos["left_1"]["dropped"])
    assert any("out of range" in m for m in infos["left_2"]["dropped"])
    assert any("no action" in m for m in infos["right_1"]["dropped"])
    # The NaN walk was dropped, not applied: no NaN reached the world.
    assert np.isfinite(env.sim.world.player_poses()).all()
    assert np.isfinite(env.state()).all()
    del before


def test_unknown_config_keys_and_values():
    with pytest.raises(ConfigError, match="rules.*unknown key.*half_tme"):
        teamenv.parallel_env(rules={"half_tme": 10})
    with pytest.raises(ConfigError, match="physics.*unknown key"):
        teamenv.parallel_env(physics={"gravity": 9.8})
    with pytest.raises(ConfigError, match="RulesConfig.half_time_s.*-1"):
        teamenv.parallel_env(rules={"half_time_s": -1})
    with pytest.raises(ConfigError, match="field.*unknown preset.*'moon'"):
        teamenv.parallel_env(field="moon")
    with pytest.raises(ConfigError, match="team_size.*12"):
        teamenv.parallel_env(team_size=12)
    with pytest.raises(ConfigError, match="action_format"):
        teamenv.parallel_env(action_format="tuple")
    with pytest.raises(ConfigError, match="channel"):
        teamenv.parallel_env(channel="radio")
    with pytest.raises(ConfigError, match="locomotion_profile"):
        teamenv.parallel_env(locomotion_profile="no_such_robot")
    with pytest.raises(TypeError, match="colour"):
        teamenv.parallel_env(colour="red")


def test_unknown_team():
    with pytest.raises(TeamLoadError, match="'nope'.*registered teams"):
        teamenv.parallel_env(left="nope")
    with pytest.raises(TeamLoadError, match="no_such_module"):
        teamenv.parallel_env(left="no_such_module:Team")
    with pytest.raises(ConfigError, match="static team config: unknown key 'nonsense'"):
        teamenv.parallel_env(left="static", left_config={"nonsense": 1})


def test_spaces_for_unknown_agent():
    env = make_env()
    with pytest.raises(ActionError, match="left_7"):
        env.action_space("left_7")


@pytest.mark.parametrize("text", [0, b"", False, []])
def test_falsy_non_text_say_is_rejected_also_when_every_agent_talks(text):
    # the batched path for many agents must reject what the per-agent path rejects
    env = make_env()
    actions = {agent: {"walk": GOOD["walk"], "say": "ok"} for agent in env.agents}
    actions["right_1"] = {"walk": GOOD["walk"], "say": text}
    with pytest.raises(MessageError, match="right_1.*say.*must be a str"):
        env.step(actions)
    mixed = {agent: {"say": "ok"} for agent in env.agents}  # keys differ from agent to agent
    mixed["left_1"] = {"walk": GOOD["walk"]}
    mixed["right_1"] = {"say": text}
    with pytest.raises(MessageError, match="right_1.*say.*must be a str"):
        env.step(mixed)
