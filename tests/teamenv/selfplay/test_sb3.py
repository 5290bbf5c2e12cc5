"""The league with Stable-Baselines3 PPO (torch on the CPU, tiny step counts): a run killed
with SIGKILL twice — in a rating gauntlet, then after the next generation began — and resumed
ends with the pool, opponents and ratings of an uninterrupted run; the PPO learner continues
bit for bit from a checkpoint; a snapshot acts as the learner's deterministic policy."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stable_baselines3", reason="needs the rl extra: pip install -e '.[rl]'")

from teamenv.policy_team import apply_reflexes  # noqa: E402
from teamenv.selfplay.cli import build_config  # noqa: E402
from teamenv.selfplay.league import run_league  # noqa: E402
from teamenv.selfplay.pfsp import OpponentMix  # noqa: E402
from teamenv.selfplay.sb3_learner import PPOLearner  # noqa: E402
from teamenv.selfplay.snapshots import SnapshotPool  # noqa: E402
from teamenv.selfplay.training_setup import TrainingSetup, kick_gate_m  # noqa: E402
from tests.teamenv.selfplay.test_league import league_contents  # noqa: E402

pytestmark = pytest.mark.rl
ROOT = Path(__file__).resolve().parents[3]
ARGS = ["--generations", "2", "--seed", "3", "--steps", "192", "--builtins", "chaser,static",
        "--team-size", "3", "--episode-seconds", "2", "--rating-half-time", "10",
        "--rating-halves", "1", "--rating-recent", "1", "--bootstrap", "20",
        "--learner-option", "copies=1", "--learner-option", "n_steps=64",
        "--learner-option", "batch_size=64", "--learner-option", "n_epochs=2"]
TINY = {"copies": 1, "n_steps": 64, "batch_size": 64, "n_epochs": 2}


def _cli(run_dir: Path, *extra: str) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}",
               OMP_NUM_THREADS="1")
    return subprocess.Popen([sys.executable, "-m", "teamenv", "selfplay", "run", str(run_dir),
                             *extra, "--backend", "serial"], cwd=ROOT, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            start_new_session=True)


def _query(db: Path, sql: str) -> int:
    try:
        with sqlite3.connect(db, timeout=5) as conn:
            return int(conn.execute(sql).fetchone()[0])
    except sqlite3.OperationalError:  # not created yet
        return 0


def _kill_when(proc: subprocess.Popen, db: Path, sql: str, at_least: int) -> None:
    deadline = time.monotonic() + 300
    try:
        while _query(db, sql) < at_least:
            assert proc.poll() is None, proc.stdout.read().decode()
            assert time.monotonic() < deadline, "the league never got there"
            time.sleep(0.02)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


GEN1_MATCHES = ("SELECT COUNT(*) FROM matches m JOIN tournaments t ON m.tournament_id = t.id "
                "WHERE t.name = 'gen-0001'")
GEN1_RATED = "SELECT COUNT(*) FROM generations WHERE generation = 1 AND rated = 1"


def test_a_run_killed_twice_and_resumed_equals_an_uninterrupted_run(tmp_path):
    killed = tmp_path / "killed"
    _kill_when(_cli(killed, *ARGS), killed / "ratings.sqlite", GEN1_MATCHES, 1)
    stored_at_kill = _query(killed / "ratings.sqlite", GEN1_MATCHES)
    assert 1 <= stored_at_kill < 6  # killed inside generation 1's gauntlet
    assert _query(killed / "league.sqlite", GEN1_RATED) == 0

    _kill_when(_cli(killed, "--resume", "--generations", "2"), killed / "league.sqlite",
               GEN1_RATED, 1)  # killed as generation 2 begins
    assert _query(killed / "league.sqlite",
                  "SELECT COUNT(*) FROM generations WHERE rated = 1") == 2

    resumed = _cli(killed, "--resume", "--generations", "2")
    out, _ = resumed.communicate(timeout=300)
    assert resumed.returncode == 0, out.decode()
    assert "3 generation(s) rated" in out.decode()

    reference = tmp_path / "reference"
    args = __import__("teamenv.cli", fromlist=["build_parser"]).build_parser().parse_args(
        ["selfplay", "run", str(reference), *ARGS])
    config, _ = build_config(args)
    run_league(reference, 2, config, backend="serial", log=None)
    got, want = league_contents(killed), league_contents(reference)
    assert got[0] == want[0]  # snapshots (digests), opponents drawn, training outcomes
    assert got[1] == want[1]  # every team's ratings after every generation
    assert got[2] == want[2]  # every rating match
    assert len(want[2]) == 6 + 6 + 6


def test_the_ppo_learner_continues_bit_for_bit_from_a_checkpoint(tmp_path):
    setup = TrainingSetup(team_size=2, episode_s=1.0)
    mix = OpponentMix(("chaser", "static"), (0.5, 0.5), seed=1)
    first = PPOLearner(setup, seed=0, **TINY)
    first.train(128, mix, seed=10)
    first.save(tmp_path)
    on = first.train(128, mix, seed=11)
    second = PPOLearner(setup, seed=99, **TINY)  # another initial network: load replaces it
    second.load(tmp_path)
    again = second.train(128, mix, seed=11)
    for (w1, b1), (w2, b2) in zip(on.layers, again.layers, strict=True):
        assert np.array_equal(w1, w2) and np.array_equal(b1, b2)
    assert np.array_equal(on.obs_mean, again.obs_mean)
    assert first.last_episodes == second.last_episodes


def test_a_snapshot_acts_as_the_learners_deterministic_policy(tmp_path):
    setup = TrainingSetup(team_size=3, episode_s=1.0)
    learner = PPOLearner(setup, seed=0, **TINY)
    weights = learner.train(192, OpponentMix.single("chaser"), seed=5)
    pool = SnapshotPool(tmp_path, setup)
    pool.write(1, weights)
    spec = pool.spec(1)
    import teamenv

    team = teamenv.parallel_env(team_size=3, left=spec.name,
                                left_config=spec.config_dict).teams["left"]
    batch = learner.batch
    obs = batch.reset()
    for _ in range(4):
        obs, *_ = batch.step(np.zeros((batch.n_slots, batch.action_size)))
    raw = batch._raw.copy()
    expected = apply_reflexes(raw, batch.box_actions(learner.act(obs)), kick_gate_m(), False)
    assert team.team.policy(raw) == pytest.approx(expected, abs=1e-4)
