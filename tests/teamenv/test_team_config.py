"""Every built-in team checks its config with one helper (``teamenv.team_config``): unknown
keys, wrong types and out-of-range values are ConfigErrors naming the team, key and value."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

import teamenv
from teamenv.errors import ConfigError
from teamenv.policy_team import PolicyFileError
from teamenv.team_config import in_range, team_config


@dataclass(frozen=True)
class Options:
    flag: bool = False
    count: int = field(default=1, metadata=in_range(1))
    ratio: float = field(default=0.5, metadata=in_range(0.0, 1.0, low_open=True))
    reach: float | None = field(default=None, metadata=in_range(0.0, low_open=True))
    label: str = "x"
    where: str | Path | None = None


def test_helper_builds_the_dataclass_with_good_values():
    got = team_config("demo", Options, {"flag": True, "count": np.int64(3), "ratio": 1,
                                        "reach": 0.2, "where": Path("a.npz")})
    assert got == Options(flag=True, count=3, ratio=1, reach=0.2, where=Path("a.npz"))
    assert team_config("demo", Options, None) == Options()


@pytest.mark.parametrize(("config", "message"), [
    ({"flag": "false"}, "demo team config: flag must be true or false, got 'false'"),
    ({"flag": 1}, "flag must be true or false, got 1"),
    ({"count": True}, "count must be an integer, got True"),
    ({"count": 2.5}, "count must be an integer, got 2.5"),
    ({"count": 0}, "count must be >= 1, got 0"),
    ({"ratio": 0.0}, r"ratio must be in \(0, 1\], got 0.0"),
    ({"ratio": float("inf")}, "ratio must be a finite number, got inf"),
    ({"ratio": "0.3"}, "ratio must be a finite number, got '0.3'"),
    ({"reach": -1.0}, r"reach must be > 0, got -1.0"),
    ({"reach": "far"}, "reach must be a finite number or null, got 'far'"),
    ({"label": 3}, "label must be a string, got 3"),
    ({"where": 3}, r"where must be a path \(string\) or null, got 3"),
    ({"flga": True}, r"unknown key 'flga' \(did you mean 'flag'\?\); known keys: \['count'"),
    ({"zzz": 1}, r"unknown key 'zzz'; known keys"),
])
def test_helper_errors_name_team_key_and_value(config, message):
    with pytest.raises(ConfigError, match=message):
        team_config("demo", Options, config)


def test_helper_refuses_a_non_mapping_and_keeps_the_error_class():
    with pytest.raises(ConfigError, match="demo team config: expected a mapping"):
        team_config("demo", Options, [("flag", True)])
    with pytest.raises(PolicyFileError, match="unknown key"):
        team_config("demo", Options, {"nope": 1}, error=PolicyFileError)


@pytest.mark.parametrize(("team", "config", "message"), [
    ("chaser", {"all_chase": "maybe"}, "chaser team config: all_chase must be true or false, "
                                       "got 'maybe'"),
    ("chaser", {"all_chase": 7}, "chaser team config: all_chase must be true or false, got 7"),
    ("chaser", {"all_chase": "false"}, "all_chase must be true or false, got 'false'"),
    ("chaser", {"all_chace": True}, r"chaser team config: unknown key 'all_chace' \(did you "
                                    r"mean 'all_chase'\?\)"),
    ("chaser", {"kick_reach": 0}, "chaser team config: kick_reach must be > 0, got 0"),
    ("chaser", {"kick_reach": float("nan")}, "kick_reach must be a finite number or null"),
    ("static", {"depth": 7}, r"static team config: depth must be in \(0, 1\], got 7"),
    ("static", {"depth": "0.4"}, "static team config: depth must be a finite number"),
    ("static", {"deep": 0.4}, r"static team config: unknown key 'deep' \(did you mean 'depth'"),
    ("silent", {"communicate": "false"}, "silent team config: communicate must be true or "
                                         "false, got 'false'"),
    ("silent", {"vote": 1}, "silent team config: vote must be true or false, got 1"),
    ("silent", {"shoot_range": 6}, "silent team config: unknown key 'shoot_range'"),
    ("silent", {"ball_pull": 3.0}, "silent team config: .*ball_pull must be in"),
    ("policy", {"paht": "w.npz"}, r"policy team config: unknown key 'paht' \(did you mean "
                                  r"'path'\?\)"),
    ("policy", {"path": 3}, r"policy team config: path must be a path \(string\) or null"),
    ("policy", {"policy": "not callable"}, "policy team config: policy must be a callable"),
])
def test_builtin_teams_check_their_config(team, config, message):
    with pytest.raises(ConfigError, match=message):
        teamenv.parallel_env(team_size=2, right=team, right_config=config)


def test_builtin_teams_take_their_good_config():
    env = teamenv.parallel_env(team_size=2, left="static", left_config={"depth": 1},
                               right="chaser", right_config={"all_chase": True,
                                                             "kick_reach": 0.3})
    assert env.teams["right"].all_chase is True and env.teams["right"].kick_reach == 0.3
    assert env.teams["left"].config.depth == 1
    env = teamenv.parallel_env(team_size=2, left="silent", left_config={"vote": False})
    assert env.teams["left"].config.communicate is False and env.teams["left"].config.vote is False
    env = teamenv.parallel_env(team_size=2, right="policy",
                               right_config={"policy": lambda batch: np.zeros((len(batch), 9))})
    env.reset(seed=0)
    env.step({a: {} for a in env.agents})
