"""The built-in teams in vision mode: they play, localize, talk within the budget, agree."""

from __future__ import annotations

import numpy as np
import pytest

import teamenv
from strategy.perception.team_message import decode_team_report, team_message_schema
from tests.teamenv.helpers import episode_digest


def _env(left="full", right="chaser", cycles=600, **kwargs):
    options = dict(field="mj7v7", team_size=4, left=left, right=right, max_cycles=cycles,
                   observation_mode="vision", rules={"half_time_s": 30.0},
                   profile_phases=False)
    options.update(kwargs)
    return teamenv.parallel_env(**options)


def _true_team_frame(env, side):
    """(N, 3) true poses of ``side``'s players in its team frame."""
    poses = env.sim.world.player_poses()
    n = env.team_size
    rows = poses[:n] if side == "left" else poses[n:]
    if env.sim.referee.attack_sign[0 if side == "left" else 1] > 0:
        return rows.copy()
    out = rows.copy()
    out[:, :2] *= -1
    out[:, 2] = (out[:, 2] + 2 * np.pi) % (2 * np.pi) - np.pi
    return out


@pytest.mark.parametrize("team", ["full", "silent", "chaser", "static"])
def test_every_builtin_team_plays_in_vision_mode(team):
    env = _env(left=team, right="static", cycles=300)
    env.reset(seed=3)
    while not env.episode_over:
        env.step({})
    assert env.sim.cycle == 300


def test_full_team_localizes_its_players_during_a_match():
    env = _env(cycles=900)
    env.reset(seed=5)
    errors = []
    while not env.episode_over:
        env.step({})
        if env.sim.cycle > 300 and env.sim.cycle % 10 == 0:
            truth = _true_team_frame(env, "left")
            for k, player in enumerate(env.teams["left"].players.values()):
                wm = player.last_world_model
                errors.append(np.hypot(*(wm.position - truth[k, :2])))
    errors = np.array(errors)
    assert np.sqrt(np.mean(errors ** 2)) < 0.5, np.percentile(errors, [50, 95, 100])


def test_full_team_messages_fit_and_follow_the_talk_schedule():
    env = _env(cycles=200)
    env.reset(seed=2)
    team = env.teams["left"]
    schema = team_message_schema(4, env.field, "simspark")
    speakers = []
    while not env.episode_over:
        env.step({})
        said = [(p.me, p.last_request.say) for p in team.players.values() if p.last_request.say]
        assert len(said) <= 1  # one speaker per cycle at most
        for me, text in said:
            assert len(text) <= 20
            report = decode_team_report(schema, text)
            assert report is not None and report.sender == me
            speakers.append((env.sim.cycle - 1, me))
    assert {me for _, me in speakers} == {0, 1, 2, 3}
    assert all(cycle % 2 == 0 and (cycle // 2) % 4 == me for cycle, me in speakers)


def test_silent_team_says_nothing_in_vision_mode():
    env = _env(left="silent", cycles=100)
    env.reset(seed=2)
    while not env.episode_over:
        env.step({})
        assert not any(p.last_request.say for p in env.teams["left"].players.values())


@pytest.mark.slow
def test_voting_makes_the_team_agree_more_than_each_agent_alone():
    # every agent starts in its own kick-off slot (the beam), so agents alone disagree only
    # once play has moved them and their beliefs drift apart: the noisier camera of the
    # server's next vision, four matches pooled (at this commit agents alone never disagreed
    # in seeds 1 and 2, and in 9 % of PlayOn cycles in seeds 3 and 4; voting: never)
    share = {}
    for vote in (True, False):
        same = []
        for seed in (1, 2, 3, 4):
            env = _env(cycles=1000, left_config={"vote": vote}, team_size=7,
                       vision="mj_noisy")
            env.reset(seed=seed)
            players = list(env.teams["left"].players.values())
            while not env.episode_over:
                env.step({})
                if env.sim.referee.mode.name == "PlayOn":
                    v = [p.last_decision.team_vector for p in players]
                    same.append(all(np.array_equal(v[0], x) for x in v[1:]))
        share[vote] = float(np.mean(same))
    assert share[True] > 0.95
    assert share[True] > share[False] + 0.02


def _trajectory_hash(seed):
    return episode_digest(_env(cycles=300), seed)


def test_same_seed_same_vision_match_bit_for_bit():
    assert _trajectory_hash(4) == _trajectory_hash(4)
    assert _trajectory_hash(4) != _trajectory_hash(5)


def test_a_vision_teams_beliefs_are_positioned_in_one_pass(monkeypatch):
    # every agent believes something else: the formation lookups and role assignments of a
    # cycle's distinct beliefs run together (PositioningAgent._assign_all), not one by one
    from strategy.positioning.agent import PositioningAgent

    sizes = []
    assign_all = PositioningAgent._assign_all

    def recorded(self, formation, views):
        sizes.append(len(views))
        return assign_all(self, formation, views)

    monkeypatch.setattr(PositioningAgent, "_assign_all", recorded)
    env = _env(cycles=120)
    env.reset(seed=3)
    while not env.episode_over:
        env.step({})
    assert sizes and max(sizes) == env.team_size
    assert sum(s > 1 for s in sizes) > len(sizes) // 2
