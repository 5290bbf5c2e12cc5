"""The committed trained policies (``examples/policies/<scenario>.npz``, written by
``examples/train_scenario_policy.py``) play as the torch-free ``policy`` team: each loads, it
replays its committed evaluation bit for bit on the first evaluation seeds, and on those seeds
it does at least as well as the ball-chasing team in its seat.

``one_v_goalie`` (100 evaluation seeds in the report): the policy and the chaser score 15 goals
each, random actions 1. On the first 16 seeds: 3, 3 and 0 (on the first 8: 1, 2 and 0, which is
why the test plays 16). The two attackers' outcomes are strongly correlated seed by seed: both
shoot at once and the kick's noise comes from the same draws of the episode's generator.

``keep_away``: the report's numbers are in ``docs/rl_training.md``; the test plays the first
``KEEP_AWAY_SEEDS`` evaluation seeds, where the policy lasts the 20 s more often than the
chaser does (on the first 16, 13 times against 3 in the committed report; the test once
played 40, 31 against 9, which cost CI about a minute for no sharper check).
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
GOALIE_SEEDS = evaluation_seeds(16)
KEEP_AWAY_SEEDS = evaluation_seeds(16)


def ends(scenario: str, left: str, left_config: dict | None, seeds) -> list[str]:
    """The end reason of one ``scenario`` episode per seed, right = chaser."""
    env = teamenv.parallel_env(scenario=scenario, left=left, left_config=left_config,
                               right="chaser")
    out = []
    for seed in seeds:
        env.reset(seed=seed)
        while env.end_reason is None:
            env.step({})
        out.append(env.end_reason)
    return out


def policy_path(scenario: str) -> dict:
    return {"path": str(POLICIES / f"{scenario}.npz")}


def report(scenario: str) -> dict:
    return json.loads((POLICIES / f"{scenario}.json").read_text())


class RandomActions:
    """Uniform random Box actions from a generator of its own."""

    def __init__(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)

    def __call__(self, obs_batch: np.ndarray) -> np.ndarray:
        return self.rng.uniform(-1.0, 1.0, (len(obs_batch), 9))


@pytest.mark.parametrize("scenario", ["one_v_goalie", "keep_away"])
def test_the_committed_policy_file_is_small_and_loads_without_torch(scenario):
    path = POLICIES / f"{scenario}.npz"
    assert path.stat().st_size < 100_000
    policy = load_policy(path)
    assert policy.observation_mode == "state" and policy.team_size == 1
    actions = policy(np.zeros((2, policy.observation_size), np.float32))
    assert actions.shape == (2, 9) and (np.abs(actions) <= 1.0).all()
    assert (actions[:, 5:] == 0.0).all()  # never a beam
    if scenario == "one_v_goalie":  # a full-power kick requested every cycle, no gate
        assert (actions[:, 3] == 1.0).all() and policy.kick_gate_m is None
    else:  # the reflexes: walk at the ball, kick within the gate, 5-cycle decisions
        assert policy.walk_to_ball and policy.kick_gate_m == pytest.approx(0.315)
        assert policy.action_repeat == 5


@pytest.fixture(scope="module")
def goalie_learned() -> list[str]:
    return ends("one_v_goalie", "policy", policy_path("one_v_goalie"), GOALIE_SEEDS)


def test_one_v_goalie_replays_its_committed_evaluation(goalie_learned):
    committed = report("one_v_goalie")
    assert committed["evaluation_seeds"][0] == GOALIE_SEEDS[0]
    assert goalie_learned == committed["learned"]["end_per_seed"][:len(GOALIE_SEEDS)]
    assert ends("one_v_goalie", "chaser", None, GOALIE_SEEDS) == \
        committed["baselines"]["chaser"]["end_per_seed"][:len(GOALIE_SEEDS)]


def test_one_v_goalie_scores_at_least_as_often_as_the_chaser_and_more_than_random(
        goalie_learned):
    chaser = ends("one_v_goalie", "chaser", None, GOALIE_SEEDS).count("goal")
    random = ends("one_v_goalie", "policy", {"policy": RandomActions(0)},
                  GOALIE_SEEDS).count("goal")
    goals = goalie_learned.count("goal")
    assert goals >= chaser, (goals, chaser)
    assert goals > random, (goals, random)


def test_keep_away_replays_its_evaluation_and_outlasts_the_chaser():
    committed = report("keep_away")
    assert committed["evaluation_seeds"][0] == KEEP_AWAY_SEEDS[0]
    learned = ends("keep_away", "policy", policy_path("keep_away"), KEEP_AWAY_SEEDS)
    chaser = ends("keep_away", "chaser", None, KEEP_AWAY_SEEDS)
    assert learned == committed["learned"]["end_per_seed"][:len(KEEP_AWAY_SEEDS)]
    assert chaser == committed["baselines"]["chaser"]["end_per_seed"][:len(KEEP_AWAY_SEEDS)]
    assert learned.count("time_limit") > chaser.count("time_limit"), (learned, chaser)
