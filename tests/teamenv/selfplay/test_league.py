"""The self-play league without torch (a stand-in learner): a run resumed generation by
generation equals an uninterrupted one, the rating store round-trips, configurations are
checked, the training env is reproducible, snapshots act as the learner did, and the
command line answers bad input with one line."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from teamenv.cli import main as teamenv_main
from teamenv.errors import ConfigError
from teamenv.policy_team import apply_reflexes
from teamenv.selfplay.batch_env import TeamBatchEnv, training_seed
from teamenv.selfplay.config import LeagueConfig
from teamenv.selfplay.league import League, run_league
from teamenv.selfplay.league_store import LEAGUE_DB, LeagueStore
from teamenv.selfplay.learner import PolicyWeights
from teamenv.selfplay.pfsp import OpponentMix
from teamenv.selfplay.rating import RATINGS_DB, RatingSetup
from teamenv.selfplay.snapshots import SnapshotPool, policy_digest
from teamenv.selfplay.training_setup import TrainingSetup, kick_gate_m
from teamenv.tournament import ResultStore
from teamenv.tournament.ratings import compute_ratings
from teamenv.tournament.store import MatchRecord

SETUP = TrainingSetup(team_size=2, episode_s=1.0)
CONFIG = LeagueConfig(
    seed=4, steps_per_generation=48, builtins=("chaser", "static"), training=SETUP,
    rating=RatingSetup(half_time_s=10.0, halves=1, recent=1, n_bootstrap=20),
    learner="tests.teamenv.selfplay.noise_learner:NoiseLearner")


def league_contents(run_dir):
    """Everything a rerun must reproduce: generation records, ratings, rating matches."""
    with LeagueStore(run_dir / LEAGUE_DB) as store:
        records = [r.comparable() for r in store.generations()]
        ratings = [store.ratings(r["generation"]) for r in records]
    matches = []
    with ResultStore(run_dir / RATINGS_DB) as results:
        for name in results.tournament_names():
            tid, _ = results.get_tournament(name)
            for m in results.matches(tid):
                row = m.comparable()
                for key in ("left_team", "right_team", "pairing", "match_key",
                            "left_version", "right_version"):
                    row.pop(key)  # labels hold the run directory's path
                matches.append((name, m.left_team.rsplit("/", 1)[-1],
                                m.right_team.rsplit("/", 1)[-1], row))
    return records, ratings, matches


def test_a_run_resumed_generation_by_generation_equals_an_uninterrupted_one(tmp_path):
    whole, steps = tmp_path / "whole", tmp_path / "steps"
    summary = run_league(whole, 2, CONFIG, backend="serial", log=None)
    assert (summary.rated, summary.trained_now) == (3, 3)
    run_league(steps, 0, CONFIG, backend="serial", log=None)
    for generations in (1, 2):  # a new process each time would load the same files
        run_league(steps, generations, None, resume=True, backend="serial", log=None)
    got, want = league_contents(steps), league_contents(whole)
    assert got == want
    records, ratings, matches = want
    assert [r["snapshot"] for r in records] == ["gen-0000", "gen-0001", "gen-0002"]
    assert len(matches) == 6 + 6 + 6  # round robin of 3, then gauntlets of 3 pairings; x2 sides
    # generation 2 drew from the built-ins and both earlier snapshots, as PFSP weighted them
    opponents = records[2]["opponents"]
    assert [o["team"] for o in opponents] == ["chaser", "static", "gen-0000", "gen-0001"]
    assert sum(o["probability"] for o in opponents) == pytest.approx(1.0)
    episodes = records[2]["training"]["episodes"]
    assert sum(row["episodes"] for row in episodes.values()) >= 1
    assert set(ratings[2].bradley_terry) == {"chaser", "static", "gen-0000", "gen-0001",
                                             "gen-0002"}
    # the stored snapshots are the recorded ones
    pool = SnapshotPool(whole, SETUP)
    assert [policy_digest(pool.path(g)) for g in range(3)] == [r["digest"] for r in records]


def test_the_rating_store_round_trips(tmp_path):
    rows = [("chaser", "static", 2, 0), ("static", "gen-0000", 0, 0),
            ("gen-0000", "chaser", 0, 1), ("chaser", "gen-0000", 1, 1)]
    records = [MatchRecord(id=k, idx=k, round=0, pairing="", seed=k, swapped=False,
                           match_key="", left_team=a, right_team=b, left_score=x,
                           right_score=y, left_official=x, right_official=y,
                           forfeit_side=None, forfeit_reason=None, forfeit_detail=None,
                           forfeit_time_s=None, cycles=1, wall_s=0.0, left_version="",
                           right_version="", left_team_time_s=0.0, right_team_time_s=0.0,
                           replay_path=None, finished_utc="")
               for k, (a, b, x, y) in enumerate(rows)]
    ratings = compute_ratings(records, n_bootstrap=50, seed=3)
    path = tmp_path / LEAGUE_DB
    with LeagueStore(path) as store:
        store.set_config(CONFIG.to_json())
        store.record_trained(0, "gen-0000", "abc", [], {"steps": 0}, 1.5)
        assert store.ratings(0) is None and store.last_rated() == -1
        store.record_rated(0, ratings, 2.5)
    with LeagueStore(path) as store:  # reopened: what a resumed run reads
        back = store.ratings(0)
        assert back == ratings
        assert list(back.bradley_terry) == list(ratings.bradley_terry)  # best first
        assert store.last_rated() == 0
        assert LeagueConfig.from_json(store.config()) == CONFIG
        with pytest.raises(ConfigError, match="never recorded as trained"):
            store.record_rated(1, ratings, 0.0)


def test_configurations_are_checked_on_resume(tmp_path):
    run_league(tmp_path, 0, CONFIG, backend="serial", log=None)
    with pytest.raises(ConfigError, match="holds a league already"):
        League(tmp_path, CONFIG)
    changed = dataclasses.replace(CONFIG, pfsp="variance")
    with pytest.raises(ConfigError, match=r"'pfsp': \('hard', 'variance'\)"):
        League(tmp_path, changed, resume=True)
    with pytest.raises(ConfigError, match="nothing to resume"):
        League(tmp_path / "empty", resume=True)
    assert not (tmp_path / "empty").exists()
    # a snapshot that changed after it was recorded would mix two networks in its ratings
    with LeagueStore(tmp_path / LEAGUE_DB) as store:
        store.record_trained(1, "gen-0001", "not-the-digest", [], {"steps": 1}, 0.0)
    SnapshotPool(tmp_path, SETUP).write(1, PolicyWeights.of(
        [(np.zeros((53, 5)), np.zeros(5))]))
    with pytest.raises(ConfigError, match="differs from the one generation 1 recorded"):
        run_league(tmp_path, 1, None, resume=True, backend="serial", log=None)


def test_the_training_env_is_reproducible_and_reports_finished_episodes():
    mix = OpponentMix(("chaser", "static"), (0.5, 0.5), seed=11)
    setup = TrainingSetup(team_size=2, episode_s=0.5)
    runs = []
    for _ in range(2):
        env = TeamBatchEnv(setup, mix, copies=2, seed=5)
        rng = np.random.default_rng(0)
        obs = env.reset()
        assert obs.shape == (4, env.observation_size) and obs.dtype == np.float32
        trace = [obs]
        ends = []
        for _ in range(12):  # 0.5 s = 25 cycles = 5 decisions: episodes end and restart
            obs, rewards, dones, infos = env.step(
                rng.uniform(env.action_low, env.action_high, (4, env.action_size)))
            trace += [obs, rewards, dones]
            for slot in np.flatnonzero(dones):
                ends.append(slot)
                info = infos[slot]
                assert info["TimeLimit.truncated"] is True
                assert info["terminal_observation"].shape == (env.observation_size,)
                assert info["episode"]["l"] == 5
        runs.append((trace, env.episodes))
        assert sorted(set(ends)) == [0, 1, 2, 3]
    (trace_a, episodes_a), (trace_b, episodes_b) = runs
    assert all(np.array_equal(a, b) for a, b in zip(trace_a, trace_b, strict=True))
    assert episodes_a == episodes_b
    for e in episodes_a:  # each episode's opponent and seed are the mix's pure functions
        assert e.opponent == mix.draw(e.copy, e.episode).label
        assert e.seed == training_seed(5, e.copy, e.episode)
        assert 0 <= e.seed < 100_000  # tuning seeds only


def test_a_snapshot_acts_as_the_training_env_does(tmp_path):
    setup = TrainingSetup(team_size=3)
    env = TeamBatchEnv(setup, OpponentMix.single("chaser"), copies=1, seed=2)
    obs = env.reset()
    rng = np.random.default_rng(1)
    for _ in range(6):
        obs, *_ = env.step(rng.uniform(env.action_low, env.action_high, (3, env.action_size)))
    raw = env._raw.copy()
    layers = [(rng.normal(0, 0.3, (env.observation_size, 16)), rng.normal(0, 0.1, 16)),
              (rng.normal(0, 0.3, (16, env.action_size)), rng.normal(0, 0.1, 5))]
    mean, std = rng.normal(size=env.observation_size), rng.uniform(0.5, 2, env.observation_size)
    weights = PolicyWeights.of(layers, obs_mean=mean, obs_std=std, obs_clip=5.0)
    pool = SnapshotPool(tmp_path, setup)
    pool.write(0, weights)
    spec = pool.spec(0)
    import teamenv

    team = teamenv.parallel_env(team_size=3, left=spec.name,
                                left_config=spec.config_dict).teams["left"]
    x = np.clip((obs.astype(np.float32) - mean.astype(np.float32)) / std.astype(np.float32),
                -5, 5)
    (w0, b0), (w1, b1) = weights.layers
    outputs = np.tanh(x @ w0 + b0) @ w1 + b1
    expected = apply_reflexes(raw, env.box_actions(outputs), kick_gate_m(), False)
    assert team.team.policy(raw) == pytest.approx(expected, abs=1e-5)
    assert team.team.action_repeat == setup.actions.action_repeat


@pytest.mark.parametrize("argv,message", [
    (["run", "{dir}", "--pfsp", "greedy"], "pfsp: weighting 'greedy' is not one of"),
    (["run", "{dir}", "--team-size", "12"], "team_size must be an int in 1..11"),
    (["run", "{dir}", "--builtins", "nosuchteam"], "nosuchteam"),
    (["run", "{dir}", "--shaping", "ball_to_goal=x"], "--shaping: expected NAME=WEIGHT"),
    (["run", "{dir}", "--learner", "no.such.module:Learner"], "cannot load it"),
    (["run", "{dir}", "--resume"], "nothing to resume"),
    (["ratings", "{dir}"], "holds no league"),
    (["run", "{dir}", "--generations", "-1"], "expected a whole number >= 0"),
    (["run", "{dir}", "--steps", "many"], "expected a whole number, got 'many'"),
    (["run", "{dir}", "--option-team", "chaser"], "'chaser': the team plays no options"),
    (["run", "{dir}", "--option-team", "nosuchteam"], "unknown team 'nosuchteam'"),
    (["run", "{dir}", "--option-team", "full_options", "--observation", "box"],
     "reads egocentric observations"),
])
def test_bad_command_line_input_gives_one_clear_line(tmp_path, capsys, argv, message):
    argv = ["selfplay", *(a.format(dir=tmp_path / "run") for a in argv)]
    try:
        status = teamenv_main(argv)
    except SystemExit as exc:  # argparse's own errors
        status = exc.code
    err = capsys.readouterr().err
    assert status == 2
    assert not (tmp_path / "run").exists()  # refused before anything was written
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "error:" in lines[0] and message in lines[0], lines[0]
