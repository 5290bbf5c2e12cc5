"""Potential-based shaping: the discounted shaping of an episode telescopes to
gamma^T Phi(s_T) - Phi(s_0) (the property that leaves optimal policies unchanged), per team,
across the half-time side change, with Phi = 0 at GameOver."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import teamenv
from teamenv.errors import ConfigError
from teamenv.shaping import BallToGoalPotential, PotentialShaping


def test_ball_to_goal_potential_runs_from_minus_one_to_zero():
    phi = BallToGoalPotential("simspark")
    half = phi.field.half_length
    state = np.zeros(10)
    state[0] = half  # the ball in the right goal's mouth
    assert phi(state, (1.0, -1.0)) == pytest.approx([0.0, -1.0])
    state[0] = 0.0
    assert phi(state, (1.0, -1.0)) == pytest.approx([-0.5, -0.5])
    assert phi(state, (-1.0, 1.0)) == pytest.approx([-0.5, -0.5])


def _attack_direction(state, attack_sign):
    """A potential that is nothing but the side's attack direction: it changes only when the
    sides change at half time, where a shaping that read the previous state with the new
    directions would lose the step."""
    return np.array([0.25 * attack_sign[0] + 0.5, 0.25 * attack_sign[1] + 0.5])


@pytest.mark.parametrize("halves,potential", [(1, BallToGoalPotential("simspark")),
                                              (2, BallToGoalPotential("simspark")),
                                              (2, _attack_direction)])
def test_discounted_shaping_telescopes_over_a_whole_match(halves, potential):
    gamma = 0.97
    shaping = PotentialShaping(potential, gamma, weight=2.0)
    # reward={} zeroes the goal reward: what the agents get is the shaping alone
    env = teamenv.parallel_env(team_size=2, right="chaser", reward={}, reward_fn=shaping,
                               rules={"half_time_s": 1.5, "halves": halves,
                                      "change_sides_at_half_time": True})
    obs, _ = env.reset(seed=5)
    phi_start = potential(env.state(), tuple(env.sim.referee.attack_sign))
    rng = np.random.default_rng(0)
    total, discount, cycles = 0.0, 1.0, 0
    signs = set()
    while env.agents:
        actions = {a: {"walk": rng.uniform(-0.3, 0.3, 3), "kick": np.array([1.0, 0.0])}
                   for a in env.agents}
        obs, rewards, terms, truncs, _ = env.step(actions)
        assert rewards["left_1"] == rewards["left_2"]  # team-shared
        total += discount * rewards["left_1"]
        discount *= gamma
        cycles += 1
        signs.add(tuple(env.sim.referee.attack_sign))
    assert terms["left_1"] and env.sim.referee.mode.name == "GameOver"
    assert len(signs) == halves  # the second half has the sides swapped
    # Phi(s_T) = 0 at GameOver: the sum is -weight * Phi(s_0) whatever happened in between
    assert total == pytest.approx(-2.0 * phi_start[0], rel=1e-9, abs=1e-9)
    assert cycles >= round(1.5 * halves / 0.02)  # plus the kick-off waits


def test_shaping_adds_to_the_reward_terms_and_each_team_gets_its_own():
    potential = BallToGoalPotential("simspark")
    plain = teamenv.parallel_env(team_size=1, reward={"goal": 1.0, "ball_progress": 1.0})
    shaped = teamenv.parallel_env(team_size=1, reward={"goal": 1.0, "ball_progress": 1.0},
                                  reward_fn=PotentialShaping(potential, 1.0))
    for env in (plain, shaped):
        env.reset(seed=1)
    kick = {"left_1": {"kick": np.array([1.0, 0.0])}, "right_1": {}}
    for _ in range(120):
        before = shaped.state()
        sign = tuple(shaped.sim.referee.attack_sign)
        _, base, *_ = plain.step(kick)
        _, got, *_ = shaped.step(kick)
        phi = potential(shaped.state(), sign) - potential(before, sign)
        assert got["left_1"] == pytest.approx(base["left_1"] + phi[0], abs=1e-12)
        assert got["right_1"] == pytest.approx(base["right_1"] + phi[1], abs=1e-12)


def test_bad_options_are_clear_and_the_shaping_pickles():
    potential = BallToGoalPotential()
    with pytest.raises(ConfigError, match="gamma must be in"):
        PotentialShaping(potential, 1.5)
    with pytest.raises(ConfigError, match="weight must be a finite number"):
        PotentialShaping(potential, 0.9, weight=float("nan"))
    with pytest.raises(ConfigError, match="potential must be callable"):
        PotentialShaping(3, 0.9)
    shaping = PotentialShaping(potential, 0.9)
    env = teamenv.parallel_env(team_size=1, reward_fn=shaping)
    env.reset(seed=0)
    env.step({"left_1": {}, "right_1": {}})
    copy = pickle.loads(pickle.dumps(shaping))
    assert copy._last_state is None and copy.gamma == 0.9


def test_team_to_ball_counts_the_nearest_player_and_potentials_add_up():
    from teamenv.shaping import TeamToBallPotential, WeightedPotentials

    env = teamenv.parallel_env(team_size=3)
    env.reset(seed=2)
    state = env.state()
    players = state[4:4 + 6 * 7].reshape(6, 7)[:, :2]
    dist = np.hypot(players[:, 0] - state[0], players[:, 1] - state[1])
    phi = TeamToBallPotential("simspark")(state, (1.0, -1.0))
    assert phi == pytest.approx(-np.array([dist[:3].min(), dist[3:].min()]) / 30.0)
    both = WeightedPotentials({"ball_to_goal": 1.0, "team_to_ball": 0.5})
    assert both(state, (1.0, -1.0)) == pytest.approx(
        BallToGoalPotential()(state, (1.0, -1.0)) + 0.5 * phi)
    with pytest.raises(ConfigError, match="unknown potential"):
        WeightedPotentials({"possession": 1.0})
