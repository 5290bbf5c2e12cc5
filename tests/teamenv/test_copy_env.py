"""The env pickles and deep-copies (as SuperSuit and vector-env wrappers do), before and after
reset; a copy's next episode is a fresh env's, bit for bit."""

import copy
import pickle

import cloudpickle
import pytest

import teamenv
from teamenv.config import RulesConfig
from tests.teamenv.helpers import episode_digest

COPIES = {"pickle": lambda env: pickle.loads(pickle.dumps(env)),
          "cloudpickle": lambda env: cloudpickle.loads(cloudpickle.dumps(env)),
          "deepcopy": copy.deepcopy}


def _make(**kw):
    return teamenv.parallel_env(left="chaser", right="chaser", team_size=5,
                                rules=RulesConfig(half_time_s=6.0), **kw)


@pytest.mark.parametrize("how", sorted(COPIES))
def test_copy_before_and_after_reset_plays_like_a_fresh_env(how):
    fresh = episode_digest(_make(), 9)
    assert episode_digest(COPIES[how](_make()), 9) == fresh          # never reset
    used = _make()
    used.reset(seed=1)
    for _ in range(150):
        used.step({})
    clone = COPIES[how](used)                                   # mid-episode
    assert episode_digest(clone, 9) == fresh
    assert episode_digest(used, 9) == fresh                           # the original is unharmed


def test_mid_episode_copies_continue_alike():
    # pymunk does not copy its contact cache, so a copy may part from the original in the
    # last bits; copies of one state continue exactly alike
    env = _make(observation_format="box", action_format="box")
    env.reset(seed=2)
    for _ in range(100):
        env.step({})
    a, b = copy.deepcopy(env), pickle.loads(pickle.dumps(env))
    for _ in range(200):
        a.step({})
        b.step({})
    assert a.state().tobytes() == b.state().tobytes()


def test_vision_match_with_talking_teams_copies():
    # the full team keeps decoded team messages (records of a schema built at run time)
    env = teamenv.parallel_env(left="full", right="chaser", team_size=5,
                               observation_mode="vision", rules=RulesConfig(half_time_s=6.0))
    env.reset(seed=4)
    for _ in range(60):
        env.step({})
    for how in COPIES.values():
        assert episode_digest(how(env), 9) == episode_digest(
            teamenv.parallel_env(left="full", right="chaser", team_size=5,
                                 observation_mode="vision",
                                 rules=RulesConfig(half_time_s=6.0)), 9)
