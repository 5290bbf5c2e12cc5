"""Batched team filtering gives each agent exactly what its own filters would give it."""

from __future__ import annotations

import numpy as np

from strategy.perception.ball_belief import BallBelief
from strategy.perception.filtering import MultiObjectWindow
from strategy.perception.team_sightings import TeamSightings

AGENTS, OPPONENTS = 3, 4


def _scenario(seed: int):
    """Per cycle and agent: ball sighting (or None), opponent ids and positions, heard
    reports; the agents see different, noisy things."""
    rng = np.random.default_rng(seed)
    ball = np.array([0.0, 0.0])
    for cycle in range(240):
        t = cycle * 0.02
        ball = ball + np.array([0.02, 0.01])
        frame = []
        for k in range(AGENTS):
            seen_ball = None
            if cycle % 3 == 0 and rng.random() < 0.6:
                seen_ball = ball + rng.normal(0, 0.1, 2)
                if rng.random() < 0.1:
                    seen_ball = rng.uniform(-10, 10, 2)  # an outlier
            ids = np.flatnonzero(rng.random(OPPONENTS) < 0.5) if cycle % 3 == 0 else \
                np.zeros(0, dtype=np.int64)
            opp = np.array([[2.0 * j, -1.0] for j in ids]).reshape(-1, 2) + \
                rng.normal(0, 0.1, (len(ids), 2))
            heard = []
            if cycle % 2 == 0 and rng.random() < 0.7:
                sender = int(rng.integers(AGENTS))
                if sender != k:
                    heard.append((ball + rng.normal(0, 0.3, 2), float(rng.uniform(0, 0.5)),
                                  sender))
            frame.append((seen_ball, ids, opp, heard))
        yield t, frame


def test_team_batch_equals_each_agent_alone():
    team = TeamSightings(AGENTS, OPPONENTS)
    alone = [BallBelief() for _ in range(AGENTS)]
    windows = [MultiObjectWindow(OPPONENTS) for _ in range(AGENTS)]
    compared = 0
    for t, frame in _scenario(3):
        for k, (seen_ball, ids, opp, heard) in enumerate(frame):
            team.see(t, k, seen_ball, ids, opp)
            if seen_ball is not None:
                alone[k].see(t, seen_ball)
            if len(ids):
                windows[k].add(t, ids, opp)
            for xy, age, sender in heard:
                team.hear(t, k, xy, age, sender)
                alone[k].hear(t, xy, age, sender)
        beliefs = team.ball_beliefs(t)
        for k in range(AGENTS):
            mine = alone[k].belief(t)
            assert beliefs[k].source == mine.source
            if mine.position is None:
                assert beliefs[k].position is None
            else:
                np.testing.assert_allclose(beliefs[k].position, mine.position, atol=1e-12)
                compared += 1
            positions, known = team.opponents(t, k)
            est = windows[k].estimate(t)
            np.testing.assert_array_equal(known, est.known)
            np.testing.assert_allclose(positions[known], est.latest_positions()[known],
                                       atol=1e-12)
    assert compared > 300


def test_clearing_the_ball_forgets_it_for_everyone():
    team = TeamSightings(2, 1)
    for c in range(6):
        team.see(c * 0.02, 0, np.array([1.0, 1.0]), [0], [[3.0, 3.0]])
        team.hear(c * 0.02, 1, np.array([1.0, 1.0]), 0.0, 0)
    assert all(b.position is not None for b in team.ball_beliefs(0.1))
    team.clear_ball()
    assert all(b.position is None for b in team.ball_beliefs(0.12))
    assert team.opponents(0.12, 0)[1][0]  # opponents are kept
