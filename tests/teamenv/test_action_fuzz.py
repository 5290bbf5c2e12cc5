"""Fuzzing the action parser from the caller's side: every malformed action,
Dict or Box, strict or lenient, gets a ``TeamEnvError`` naming the agent, the field and the value
(strict) or a documented drop (lenient: warned and listed in ``infos[agent]["dropped"]``); no
other exception escapes, and valid actions pass untouched.

Each example is stepped in a strict and a lenient env built alike: the lenient env's first
warning must be the strict env's error, word for word, and a lenient env warns exactly when the
strict env raises. Values are drawn with a label: ``VALID`` (within the space: must step),
``INVALID`` (must raise / be dropped) or ``EITHER`` (junk whose verdict we do not predict: it
must only get one of the two answers).
"""

from __future__ import annotations

import types
import warnings
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import teamenv
from teamenv.actions import DICT_KEYS
from teamenv.box_layout import ACTION_SIZE
from teamenv.errors import ActionError, TeamEnvError, value_repr

VALID, INVALID, EITHER = "valid", "invalid", "either"
TEAM_SIZE = 2



def fuzz(examples: int) -> settings:
    """Deterministic in CI (derandomized, no example database) and no deadline (a shared
    2-core machine); ``examples`` keeps each test's share of CI time to a few seconds."""
    return settings(max_examples=examples, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


_PROBE = teamenv.parallel_env(team_size=TEAM_SIZE)
_SPACE = _PROBE.action_space("left_1")
BOUNDS = {key: (_SPACE[key].low.astype(float), _SPACE[key].high.astype(float))
          for key in ("walk", "kick", "beam")}
SAY = _PROBE.sim.channel.profile
AGENTS = [f"{side}_{k}" for side in ("left", "right") for k in range(1, TEAM_SIZE + 1)]


# -- building blocks -------------------------------------------------------------------------
HUGE_INTS = st.sampled_from([10**400, -(10**400), 2**64, 2**63, -(2**63) - 1])

junk_scalars = st.one_of(
    st.none(), st.booleans(), st.integers(), HUGE_INTS, st.floats(), st.complex_numbers(),
    st.text(max_size=5), st.binary(max_size=5), st.fractions(),
    hnp.scalar_dtypes().flatmap(hnp.from_dtype),
    st.text(max_size=5).map(np.str_), st.binary(max_size=5).map(np.bytes_),
)

array_shapes = hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4)

any_array = st.one_of(
    hnp.arrays(hnp.scalar_dtypes(), array_shapes),
    hnp.arrays(hnp.unicode_string_dtypes(max_len=4), array_shapes),
    hnp.arrays(hnp.byte_string_dtypes(max_len=4), array_shapes),
    hnp.arrays(np.dtype(object), array_shapes, elements=junk_scalars),
)

nested = st.recursive(junk_scalars, lambda inner: st.one_of(
    st.lists(inner, max_size=4), st.tuples(inner, inner, inner),
    st.dictionaries(st.text(max_size=4), inner, max_size=2)), max_leaves=10)

anything = st.one_of(junk_scalars, nested, any_array, st.frozensets(st.integers(), max_size=3))


def vector(key: str) -> st.SearchStrategy[tuple[Any, str]]:
    """Values of a Box(3)/Box(2) field (or of the whole flat Box action), labelled."""
    if key == "box":
        low, high = np.full(ACTION_SIZE, -1.0), np.full(ACTION_SIZE, 1.0)
    else:
        low, high = BOUNDS[key]
    size = len(low)
    inside = st.tuples(*[st.floats(lo, hi) for lo, hi in zip(low, high, strict=True)]).map(list)
    container = st.sampled_from([list, tuple, lambda v: np.array(v, np.float32),
                                 lambda v: np.array(v, np.float64)])
    valid = st.builds(lambda values, wrap: wrap(values), inside, container)

    def replace(values: list, j: int, new: Any, wrap) -> Any:
        values = list(values)
        values[j % size] = new
        return wrap(values)

    slot = st.integers(0, size - 1)
    non_finite = st.builds(replace, inside, slot, st.sampled_from([np.nan, np.inf, -np.inf]),
                           container)
    too_big = st.builds(lambda values, j, d, up, wrap: replace(
        values, j, (high[j] + d) if up else (low[j] - d), wrap),
        inside, slot, st.floats(1e-3, 1e6), st.booleans(), container)
    wrong_shape = st.one_of(
        hnp.arrays(np.float64, array_shapes.filter(lambda s: s != (size,)),
                   elements=st.floats(-0.1, 0.1)),
        st.lists(st.floats(-0.1, 0.1), max_size=size + 2).filter(lambda v: len(v) != size),
        inside.map(lambda v: [[x] for x in v]),  # (size, 1)
        inside.map(lambda v: [v]),  # (1, size)
    )
    not_real = st.one_of(
        st.text(max_size=4), st.binary(max_size=4), st.none(), st.just({}),
        inside.map(lambda v: np.array(v, np.complex128)),  # even with a zero imaginary part
        inside.map(lambda v: [str(x) for x in v]),  # numbers as text
        inside.map(lambda v: np.array(v).astype(str)),
        inside.map(lambda v: [None, *v[1:]]),
        inside.map(lambda v: [10**400, *v[1:]]),  # overflows a float
        inside.map(lambda v: np.array(["2026-01-01"] * len(v), "datetime64[D]")),
    )
    return st.one_of(
        valid.map(lambda v: (v, VALID)),
        st.one_of(non_finite, too_big, wrong_shape, not_real).map(lambda v: (v, INVALID)),
        st.one_of(anything, hnp.arrays(hnp.scalar_dtypes(), st.just((size,)))).map(
            lambda v: (v, EITHER)),
    )


def say_values(profile) -> st.SearchStrategy[tuple[Any, str]]:
    """``say`` values labelled by the channel profile's own rules (comms is tested on its own)."""
    legal = st.text(alphabet=profile.charset, max_size=profile.max_chars)
    texts = st.one_of(legal, legal.map(np.str_), st.text(max_size=profile.max_chars + 3),
                      st.text(alphabet=profile.charset, min_size=profile.max_chars + 1,
                              max_size=profile.max_chars + 4))

    def label_text(text: str) -> tuple[Any, str]:
        return text, VALID if profile.check_message(text) is None else INVALID

    not_str = st.one_of(
        hnp.arrays(hnp.unicode_string_dtypes(max_len=4), hnp.array_shapes(min_dims=0)),
        st.binary(max_size=4), st.integers(), st.booleans(), st.just([]), st.lists(legal, max_size=3),
        st.floats(), hnp.scalar_dtypes().flatmap(hnp.from_dtype),
    )
    return st.one_of(texts.map(label_text), st.just((None, VALID)),
                     not_str.map(lambda v: (v, INVALID)))


beam_requests = st.one_of(
    st.sampled_from([0, 1, True, False, np.int8(1), np.uint64(0), np.int64(1), np.bool_(True)]
                    ).map(lambda v: (v, VALID)),
    st.one_of(st.integers().filter(lambda v: v not in (0, 1)), st.floats(), st.text(max_size=3),
              st.none(), st.just(np.array(1)), st.just(np.array([1])), HUGE_INTS).map(
        lambda v: (v, INVALID)),
)

unknown_keys = st.one_of(st.text(max_size=6).filter(lambda k: k not in DICT_KEYS),
                         st.integers(), st.none(), st.binary(max_size=3), st.tuples(st.text(max_size=3)))


def combine(labels: list[str]) -> str:
    if INVALID in labels:
        return INVALID
    return VALID if all(label == VALID for label in labels) else EITHER


@st.composite
def dict_actions(draw, profile=SAY) -> tuple[Any, str]:
    """A per-agent Dict action: some known keys (each valid, invalid or junk), maybe an unknown
    key, maybe not a dict at all."""
    if draw(st.integers(0, 9)) == 0:
        return draw(anything.filter(lambda v: not isinstance(v, dict))), INVALID
    fields = {"walk": vector("walk"), "kick": vector("kick"), "beam": vector("beam"),
              "beam_request": beam_requests, "say": say_values(profile)}
    action, labels = {}, []
    for key in draw(st.lists(st.sampled_from(DICT_KEYS), unique=True, max_size=5)):
        action[key], label = draw(fields[key])
        labels.append(label)
    if draw(st.integers(0, 5)) == 0:
        action[draw(unknown_keys)] = draw(anything)
        labels.append(INVALID)
    if draw(st.booleans()):  # a Mapping that is no dict takes the per-agent path
        action = types.MappingProxyType(action)
    return action, combine(labels)


def box_actions() -> st.SearchStrategy[tuple[Any, str]]:
    return st.one_of(vector("box"), st.one_of(st.none(), st.text(max_size=3),
                                              st.dictionaries(st.text(max_size=3), st.integers(),
                                                              max_size=2)).map(
        lambda v: (v, INVALID)))


# -- the envs and the oracle ------------------------------------------------------------------
@pytest.fixture(scope="module")
def envs():
    """One strict and one lenient env per configuration, reused by every example."""
    cache: dict[tuple, tuple] = {}

    def get(action_format: str, observation_mode: str = "state", channel: str = "simspark"):
        key = (action_format, observation_mode, channel)
        if key not in cache:
            pair = []
            for strict in (True, False):
                env = teamenv.parallel_env(team_size=TEAM_SIZE, action_format=action_format,
                                           observation_mode=observation_mode, channel=channel,
                                           strict=strict, rules={"half_time_s": 1e6})
                env.reset(seed=0)
                pair.append(env)
            cache[key] = tuple(pair)
        return cache[key]

    return get


def _good(env) -> dict[str, Any]:
    """Valid actions for every agent, in the common shape (the vectorized fast path)."""
    if env.action_format == "box":
        return {a: np.full(ACTION_SIZE, 0.1, np.float32) for a in env.agents}
    say = "b2s=" if env.channel_name == "mj" else "ok"  # base64 of b"ok" on the mj channel
    return {a: {"walk": np.array([0.2, 0.0, 0.1], np.float32), "say": say} for a in env.agents}


def _step_strict(env, actions) -> str | None:
    """The strict env's error message, or None when the step went through (no warning)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            env.step(actions)
        except TeamEnvError as exc:
            assert isinstance(exc, ActionError), repr(exc)
            return str(exc)
    assert not caught, [str(w.message) for w in caught]
    return None


def _step_lenient(env, actions) -> tuple[list[str], dict]:
    """The lenient env's warnings (each a RuntimeWarning) and infos."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        infos = env.step(actions)[4]
    for w in caught:
        assert w.category is RuntimeWarning, (w.category, str(w.message))
    return [str(w.message) for w in caught], infos


def check(pair, actions: dict, label: str, named) -> None:
    """Step ``actions`` in the strict and the lenient env of ``pair`` and check the answers:
    ``named(message)`` says whether an error names the right agent, field and value."""
    strict, lenient = pair
    error = _step_strict(strict, actions)
    warned, infos = _step_lenient(lenient, actions)
    if label == VALID:
        assert error is None, error
    elif label == INVALID:
        assert error is not None, "an invalid action went through in strict mode"
    if error is None:
        assert not warned, warned
        assert not any("dropped" in info for info in infos.values())
        return
    assert named(error), error
    # The lenient env reports what the strict env raised, first, in the same words, and lists
    # every warning about one of its agents in that agent's infos.
    assert warned and warned[0] == error, (warned, error)
    for message in warned:
        owners = [a for a in lenient.agents if message.startswith(f"agent {a!r}: ")]
        for agent in owners:
            assert message in infos[agent]["dropped"], (message, infos[agent])
    listed = [m for info in infos.values() for m in info.get("dropped", [])]
    assert all(m in warned for m in listed), (listed, warned)
    assert np.isfinite(lenient.state()).all()


def _names_dict_field(victim: str, action: Any):
    """An error about ``victim``'s Dict action names one of its fields and that field's value."""
    candidates = [f"agent {victim!r}: action = {value_repr(action)}: "]
    if isinstance(action, types.MappingProxyType | dict):
        for key, value in action.items():
            field = key if key in DICT_KEYS else value_repr(key)
            candidates.append(f"agent {victim!r}: {field} = {value_repr(value)}: ")
    return lambda message: any(message.startswith(c) for c in candidates)


def _names_box_field(victim: str, action: Any):
    whole = f"agent {victim!r}: action = {value_repr(action)}: "
    slots = tuple(f"agent {victim!r}: action[{j}] = " for j in range(ACTION_SIZE))
    return lambda message: message.startswith(whole) or message.startswith(slots)


# -- the fuzz tests ---------------------------------------------------------------------------
@pytest.mark.parametrize("observation_mode", ["state", "vision"])
@fuzz(120)
@given(victim=st.sampled_from(AGENTS), drawn=dict_actions())
def test_dict_action_of_one_agent(envs, observation_mode, victim, drawn):
    pair = envs("dict", observation_mode)
    action, label = drawn
    actions = {**_good(pair[0]), victim: action}
    check(pair, actions, label, _names_dict_field(victim, action))


@fuzz(100)
@given(victim=st.sampled_from(AGENTS), drawn=dict_actions(profile=teamenv.parallel_env(
    team_size=TEAM_SIZE, channel="mj").sim.channel.profile))
def test_dict_action_on_the_mj_channel(envs, victim, drawn):
    pair = envs("dict", "state", "mj")
    action, label = drawn
    check(pair, {**_good(pair[0]), victim: action}, label, _names_dict_field(victim, action))


@fuzz(300)
@given(victim=st.sampled_from(AGENTS), drawn=box_actions())
def test_box_action_of_one_agent(envs, victim, drawn):
    pair = envs("box")
    action, label = drawn
    check(pair, {**_good(pair[0]), victim: action}, label, _names_box_field(victim, action))


@pytest.mark.parametrize("action_format", ["dict", "box"])
@fuzz(80)
@given(data=st.data())
def test_whole_action_dicts(envs, action_format, data):
    """Any set of agents (some missing, some unknown) with any actions: the error or the first
    warning names an agent that was unknown, missing or given a bad action."""
    pair = envs(action_format)
    draw_action = dict_actions() if action_format == "dict" else box_actions()
    actions, labels, suspects = {}, [], []
    for agent in AGENTS:
        if data.draw(st.integers(0, 6), label=f"{agent} given") == 0:
            labels.append(INVALID)  # missing
            suspects.append(agent)
            continue
        actions[agent], label = data.draw(draw_action, label=agent)
        labels.append(label)
        if label != VALID:
            suspects.append(agent)
    for key in data.draw(st.lists(st.one_of(unknown_keys, st.sampled_from(
            ["left_9", "right_0", "left_1 ", "LEFT_1", "left"]), st.floats()), max_size=2)):
        if key not in actions:
            actions[key] = data.draw(anything)
            labels.append(INVALID)
            suspects.append(key)

    def named(message: str) -> bool:
        return any(message.startswith((f"agent {value_repr(s)}: ",
                                       f"unknown agent {value_repr(s)} ")) for s in suspects)

    check(pair, actions, combine(labels), named)


@fuzz(60)
@given(actions=anything.filter(lambda v: not isinstance(v, dict)))
def test_actions_that_are_not_a_dict(envs, actions):
    for env in envs("dict"):
        with pytest.raises(ActionError, match="expected a dict keyed by agent name"):
            env.step(actions)


@fuzz(60)
@given(victim=st.sampled_from(AGENTS), drawn=dict_actions())
def test_aec_form(victim, drawn):
    """The AEC form (PettingZoo's conversion) hands the actions to the same parser."""
    action, label = drawn
    aec = teamenv.env(team_size=TEAM_SIZE)
    aec.reset(seed=0)
    try:
        for agent in aec.agent_iter(len(AGENTS)):
            aec.step(action if agent == victim else {"walk": [0.1, 0.0, 0.0]})
    except TeamEnvError as exc:
        assert label != VALID, exc
        assert _names_dict_field(victim, action)(str(exc)), exc
    else:
        assert label != INVALID, "an invalid action went through the AEC form"


def test_numpy_array_say_names_the_agent():
    """The issue's case: array-minded RL code passes ``say`` as a numpy array."""
    env = teamenv.parallel_env(team_size=TEAM_SIZE)
    env.reset(seed=0)
    actions = {a: {"walk": np.zeros(3), "say": "ok"} for a in env.agents}
    actions["right_2"]["say"] = np.array(["hi", "yo"])
    with pytest.raises(ActionError, match=r"agent 'right_2': say = array\(\['hi', 'yo'\].*str"):
        env.step(actions)


def test_lenient_box_reports_every_bad_agent():
    """Each agent whose Box action has a NaN or an out-of-range entry gets its own drop."""
    env = teamenv.parallel_env(team_size=TEAM_SIZE, action_format="box", strict=False)
    env.reset(seed=0)
    actions = {a: np.zeros(ACTION_SIZE) for a in env.agents}
    actions["left_1"][2] = np.nan
    actions["right_2"][4] = np.nan
    actions["left_2"][0] = 3.0
    actions["right_1"][1] = -3.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        infos = env.step(actions)[4]
    assert infos["left_1"]["dropped"] == ["agent 'left_1': action[2] = nan: must be finite"]
    assert infos["right_2"]["dropped"] == ["agent 'right_2': action[4] = nan: must be finite"]
    assert infos["left_2"]["dropped"] == [
        "agent 'left_2': action[0] = 3.0: must be in [-1, 1]; clipped in lenient mode"]
    assert infos["right_1"]["dropped"] == [
        "agent 'right_1': action[1] = -3.0: must be in [-1, 1]; clipped in lenient mode"]


@pytest.mark.parametrize("value,words", [
    (np.array([1 + 0j, 0, 0]), "complex"),
    (["0.1", "0", "0"], "numbers"),
    ([10**400, 0, 0], "finite"),
    ([10**5000, 0, 0], "finite"),  # its repr would raise: Python's int -> str limit
    (np.array([[0.1], [0.0], [0.0]]), "shape"),
])
def test_walk_that_numpy_would_coerce_is_rejected(value, words):
    """Values numpy would turn into floats (dropping an imaginary part, parsing text,
    reshaping (3, 1)) are not numbers of the walk's shape: an error, on both parsing paths."""
    env = teamenv.parallel_env(team_size=TEAM_SIZE)
    env.reset(seed=0)
    for others in ({}, {"walk": np.zeros(3)}):  # per-agent path / vectorized path
        actions = {a: dict(others) for a in env.agents}
        actions["left_2"] = {"walk": value}
        with pytest.raises(ActionError, match=f"agent 'left_2': walk = .*{words}"):
            env.step(actions)
