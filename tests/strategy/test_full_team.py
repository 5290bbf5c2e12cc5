"""The full team as a plugin: any size and pitch, its config, its messages, decentralization,
determinism, and the observation modes it accepts."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import teamenv
from comms.testing import assert_fits
from strategy.positioning.roles.message import decode_role_vote, role_vote_schema
from strategy.teams.full import FullTeam
from strategy.teams.full_config import FullTeamConfig
from teamenv.errors import ConfigError, TeamLoadError
from teamenv.field import field_preset
from teamenv.match import MatchOptions, play_match
from teamenv.teams import TeamContext, make_team
from tests.strategy import scenes


def context(n: int = 5, field: str = "mj7v7", side: str = "left", channel: str = "simspark",
            observation_mode: str = "state") -> TeamContext:
    return TeamContext(side=side, agents=tuple(f"{side}_{k + 1}" for k in range(n)),
                       team_size=n, field=field_preset(field), cycle_s=0.02, channel=channel,
                       observation_mode=observation_mode, seed=0, body=scenes.BODY)


class Recorder:
    """Wraps a team's ``act`` to keep what it saw and what it answered."""

    def __init__(self, team) -> None:
        self.team, self.seen, self.actions = team, [], []
        self._act = team.act
        team.act = self

    def __call__(self, observations):
        actions = self._act(observations)
        self.seen.append(observations)
        self.actions.append(actions)
        return actions


def same_action(a, b) -> bool:
    if set(a) != set(b):
        return False
    return all(np.array_equal(np.asarray(a[k]), np.asarray(b[k])) if k != "say" else a[k] == b[k]
               for k in a)


# -- any size, any pitch ---------------------------------------------------------------------------
@pytest.mark.parametrize("field", ["simspark", "mj7v7"])
@pytest.mark.parametrize("n", [1, 3, 5, 7, 11])
def test_plays_any_team_size_on_any_pitch(field, n):
    env, _ = scenes.make_env(field=field, team_size=n, left="full", right="chaser",
                             profile_phases=False)
    rec = Recorder(env.teams["left"])
    start = scenes.poses(env)[:n].copy()
    for _ in range(200):
        env.step({})
    assert len(rec.actions) == 200
    assert all(set(a) == set(env.team_agents["left"]) for a in rec.actions)
    for actions in rec.actions:
        for act in actions.values():
            assert np.all(np.isfinite(act["walk"]))
            assert np.all(act["walk"] >= scenes.LOW) and np.all(act["walk"] <= scenes.HIGH)
    end = scenes.poses(env)[:n]
    assert np.any(np.hypot(*(end[:, :2] - start[:, :2]).T) > 0.2), "nobody moved"
    f = env.field
    assert np.all(np.abs(end[:, 0]) <= f.half_length + 1.5)
    assert env.sim.referee.mode != teamenv.PlayMode.BeforeKickOff


# -- config ----------------------------------------------------------------------------------------
def test_config_rejects_unknown_keys_listing_the_known_ones():
    with pytest.raises(ConfigError) as info:
        FullTeamConfig.from_overrides("full", {"kick_goal_weigth": 6.0})
    msg = str(info.value)
    assert "kick_goal_weigth" in msg and "kick_goal_weight" in msg and "pass_max_m" in msg


@pytest.mark.parametrize("key,value", [
    ("kick_goal_weight", -1.0), ("kick_goal_weight", math.nan), ("kick_max_angle_rad", 4.0), ("ball_pull", 1.5), ("pass_max_m", math.inf),
    ("pass_max_m", "9"), ("dribble_speed", True), ("communicate", 1), ("marking", "yes"),
    ("say_every", 0), ("max_markers", 1.5), ("max_markers", -1), ("nav_k_repulse", 0.35),
    ("nav_k_repulse", 0.0), ("formation_attack", "4-4-2"), ("set_play_clearance_m", -2.0),
])
def test_config_rejects_bad_values_naming_field_and_value(key, value):
    with pytest.raises(ConfigError) as info:
        FullTeamConfig.from_overrides("full", {key: value})
    assert key in str(info.value) and repr(value) in str(info.value)


def test_config_accepts_good_overrides_and_is_frozen():
    c = FullTeamConfig.from_overrides("full", {"kick_goal_weight": 6, "communicate": False,
                                               "formation_attack": "7v7-attack"})
    assert c.kick_goal_weight == 6 and c.communicate is False
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.kick_goal_weight = 1.0  # type: ignore[misc]
    from teamenv.capabilities import body_capabilities

    league = body_capabilities("t1_league")
    assert c.navigation_params(league).k_repulse == c.nav_k_repulse < 0
    assert c.navigation_params(league).side_step_left  # "both" by default
    one_sided = FullTeamConfig(nav_side_steps="body").navigation_params(league)
    assert (one_sided.side_step_left, one_sided.side_step_right) == (False, True)
    assert FullTeamConfig(marking=False).marking_params() is None


@pytest.mark.parametrize("config", [{"bogus": 1}, {"pass_max_m": -3.0}, {"say_every": 0}])
def test_make_team_and_env_report_bad_config(config):
    with pytest.raises((ConfigError, TeamLoadError)) as info:
        make_team("full", context(), config)
    assert next(iter(config)) in str(info.value)
    with pytest.raises((ConfigError, TeamLoadError)):
        teamenv.parallel_env(field="mj7v7", team_size=3, left="full", left_config=config)


def test_registered_entry_points():
    assert isinstance(make_team("full", context()), FullTeam)
    silent = make_team("silent", context())
    assert isinstance(silent, FullTeam) and silent.config.communicate is False


@pytest.mark.parametrize("name", ["full", "silent"])
def test_rejects_unknown_observation_modes_clearly(name):
    with pytest.raises(ConfigError, match="'state' or 'vision'") as info:
        make_team(name, context(observation_mode="radar"))
    assert "radar" in str(info.value)


@pytest.mark.parametrize("name", ["full", "silent", "chaser", "static"])
def test_vision_mode_without_a_perception_config_is_a_clear_error(name):
    with pytest.raises(ConfigError, match="vision"):
        make_team(name, context(observation_mode="vision"))


# -- messages --------------------------------------------------------------------------------------
def says(rec) -> list[tuple[str, str]]:
    return [(agent, act["say"]) for actions in rec.actions for agent, act in actions.items()
            if act.get("say")]


def test_silent_says_nothing():
    env, _ = scenes.make_env(field="mj7v7", team_size=5, left="silent", right="full",
                             profile_phases=False)
    rec = Recorder(env.teams["left"])
    other = Recorder(env.teams["right"])
    for _ in range(100):
        env.step({})
    assert says(rec) == []
    assert says(other), "the full team on the other side should talk (control)"


@pytest.mark.parametrize("channel", ["simspark", "mj"])
@pytest.mark.parametrize("n", [5, 11])
def test_full_says_role_votes_that_fit_the_channel(channel, n):
    field = "simspark" if n == 11 else "mj7v7"
    env, _ = scenes.make_env(field=field, team_size=n, left="full", right="static",
                             channel=channel, profile_phases=False)
    assert_fits(role_vote_schema(n, channel), channel)
    rec = Recorder(env.teams["left"])
    drops = []
    for _ in range(60):
        env.step({})
        drops += [d.reason for d in env.last_report.dropped
                  if d.speaker < n and d.reason in ("too_long", "illegal_character")]
    said = says(rec)
    assert {agent for agent, _ in said} == set(env.team_agents["left"])  # everybody votes
    profile = env.sim.channel.profile
    for agent, text in said:
        assert profile.check_message(text) is None, (agent, text)
        vote = decode_role_vote(text, n, channel)
        assert vote is not None, f"{agent} said {text!r}, not a role vote"
        sender, vector = vote
        assert sender == int(agent.split("_")[1]) - 1
        assert sorted(vector.tolist()) == list(range(n))
    assert not drops
    # they are heard: some agent's observation carries a teammate's vote
    heard = [t for obs in rec.seen[-1].values() for t in obs["heard_text"][1:] if t]
    assert any(decode_role_vote(t, n, channel) is not None for t in heard)


# -- decentralization ------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def recorded():
    """The left team's observations and actions of 150 cycles of full v chaser, 5 v 5."""
    env, _ = scenes.make_env(field="mj7v7", team_size=5, left="full", right="chaser", seed=4,
                             profile_phases=False)
    rec = Recorder(env.teams["left"])
    for _ in range(150):
        env.step({})
    return env, rec


def fresh_team(env):
    return make_team("full", context(env.team_size, "mj7v7"))


def test_a_player_acts_on_its_own_observation_only(recorded):
    env, rec = recorded
    team = fresh_team(env)
    team.reset(0)
    agents = env.team_agents["left"]
    for obs, actions in zip(rec.seen, rec.actions, strict=True):
        # each agent alone, in reverse order: same actions as in the match
        for agent in reversed(agents):
            got = team.act({agent: obs[agent]})[agent]
            assert same_action(got, actions[agent]), agent


@pytest.mark.parametrize("victim", [0, 2])
def test_perturbing_another_agents_observation_changes_nothing_else(recorded, victim):
    env, rec = recorded
    agents = env.team_agents["left"]
    rng = np.random.default_rng(victim)
    a, b = fresh_team(env), fresh_team(env)
    a.reset(0)
    b.reset(0)
    changed = 0
    for obs in rec.seen:
        bad = dict(obs)
        o = dict(obs[agents[victim]])
        o["ball"] = (np.asarray(o["ball"]) + rng.normal(0, 3, 4)).astype(np.float32)
        o["self"] = np.asarray(o["self"]).copy()
        o["self"][:2] = rng.uniform(-10, 10, 2)
        o["heard_text"] = ("",) * len(o["heard_text"])
        bad[agents[victim]] = o
        out_a, out_b = a.act(obs), b.act(bad)
        for k, agent in enumerate(agents):
            if k == victim:
                changed += not same_action(out_a[agent], out_b[agent])
            else:
                assert same_action(out_a[agent], out_b[agent]), (agent, out_a[agent],
                                                                 out_b[agent])
    assert changed > 0, "the perturbation did not even change the victim's own actions"


# -- determinism ----------------------------------------------------------------------------------
def run_match(seed: int, cycles: int = 400):
    env, _ = scenes.make_env(field="mj7v7", team_size=5, left="full", right="chaser",
                             seed=seed, profile_phases=False)
    for _ in range(cycles):
        env.step({})
    return env.sim.referee.score.copy(), env.state().copy()


def test_same_seed_same_match():
    (s1, x1), (s2, x2) = run_match(7), run_match(7)
    assert s1 == s2
    np.testing.assert_array_equal(x1, x2)
    _, x3 = run_match(8)
    assert not np.array_equal(x1, x3)  # the seed matters (control)


def test_same_seed_same_match_result():
    opts = MatchOptions(field="mj7v7", team_size=3, half_time_s=6.0, halves=1)
    r1 = play_match("full", "chaser", seed=2, options=opts, stall_timeout_s=None)
    r2 = play_match("full", "chaser", seed=2, options=opts, stall_timeout_s=None)
    assert r1.forfeit is None and r2.forfeit is None
    assert (r1.score, r1.goals, r1.cycles) == (r2.score, r2.goals, r2.cycles)
    assert r1.cycles >= 300


# -- talking in state mode ---------------------------------------------------------------------
def states_of_match(left: str, seed: int, **config) -> list[np.ndarray]:
    env = teamenv.parallel_env(left=left, right="chaser", field="simspark", team_size=5,
                               left_config=config, rules={"half_time_s": 15.0},
                               profile_phases=False)
    env.reset(seed=seed)
    states = []
    while not env.episode_over:
        env.step({})
        states.append(env.state().copy())
    return states


def test_in_state_mode_the_full_team_plays_exactly_as_its_silent_twin():
    """State-mode beliefs are exact and shared, so the vote (counting only vectors heard since
    the own vector last changed) always agrees with each agent's own vector, and the channel
    draws from its own generator: talking changes nothing on the pitch, cycle for cycle."""
    full, silent = states_of_match("full", 5), states_of_match("silent", 5)
    assert len(full) == len(silent)
    assert all(np.array_equal(a, b) for a, b in zip(full, silent, strict=True))
    # control: counting every vector within the age limit (the old rule) does change the match
    stale = states_of_match("full", 5, vote_since_own_change=False)
    assert any(not np.array_equal(a, b) for a, b in zip(full, stale, strict=False))
