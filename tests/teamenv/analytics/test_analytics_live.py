"""Statistics from a recorded replay agree with benchmarks/goal_rarity.py's live count of the
same seeded match (the two read the same definitions: one from the env, one from the file)."""

from __future__ import annotations

import numpy as np
import pytest

import teamenv
from teamenv.analytics.stats import match_stats
from teamenv.config import RulesConfig
from teamenv.replay import ReplayRecorder, load_replay
from tests.benchmark_scripts import load_benchmark

gr = load_benchmark("goal_rarity")


@pytest.mark.parametrize("seed", [11])
def test_replay_statistics_equal_the_live_count(tmp_path, seed):
    env = teamenv.parallel_env(left="full", right="chaser", field="mj7v7", team_size=3,
                               rules=RulesConfig(half_time_s=20.0), profile_phases=False)
    recorder = ReplayRecorder(env)
    env.reset(seed=seed)
    recorder.record()
    counter = gr.MatchCounter(env.field.half_length, env.field.half_goal_width, env.team_size,
                              start_ball=env.sim.world.ball_state(), cycle_s=env.physics.cycle_s)
    while not env.episode_over:
        env.step({})
        recorder.record()
        counter.add(gr.cycle_from_env(env))
    counter.finish()
    path = recorder.save(tmp_path / "m.npz", {"left": "full", "right": "chaser", "seed": seed})
    stats = match_stats(load_replay(path))
    assert sum(t.kicks for t in stats.teams) >= 3  # the match has something to count
    for side, team in enumerate(stats.teams):
        live = counter.side_metrics(side)
        assert team.kicks == live["kicks"]
        assert team.attempts_on_frame == live["on_frame_kicks"]
        assert team.shots == live["shots"]
        assert team.goals == live["goals"]
        assert team.possession_lost == live["possession_losses"]
        assert team.possession_pct == pytest.approx(live["possession_pct"])
        for outcome in ("blocked", "teammate", "self", "goal", "out", "stopped"):
            assert team.kick_outcomes[outcome] == live[f"kicks_{outcome}"], outcome
        assert team.third_pct["middle"] == pytest.approx(live["ball_in_middle_third_pct"])
    assert stats.possession_changes == counter.possession_changes


def test_extras_record_the_full_teams_beliefs_and_roles(tmp_path):
    from teamenv.match import play_match

    path = tmp_path / "x.npz"
    play_match("full", "chaser", 5, {"field": "mj7v7", "team_size": 3, "half_time_s": 2.0},
               replay_path=path, replay_extras=True)
    replay = load_replay(path)
    assert replay.has_extras
    left = slice(0, 3)
    # state mode: each full agent believes the truth (stored as float16 errors from it)
    poses = replay.belief_pose[:-1, left]  # row t: the belief acted on in step t + 1
    assert abs(poses[..., :2] - replay.players[:-1, left, :2]).max() < 0.05
    assert abs(replay.belief_ball[:-1, left] - replay.ball[:-1, None, :2]).max() < 0.05
    assert (replay.role_vector[:-1, left] >= 0).all() and (replay.role[:-1, left] >= 0).all()
    assert (replay.role[-1] == -1).all()  # nobody acted on the last row
    # the chaser has no annotations() hook: unknown
    assert (replay.role[:, 3:] == -1).all() and np.isnan(replay.belief_pose[:, 3:]).all()
    stats = match_stats(replay)
    assert stats.left.role_agreement_pct == 100.0 and stats.right.role_agreement_pct is None
