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


def test_batched_sightings_and_reports_equal_each_agent_alone_bit_for_bit():
    """``see_many`` (a whole team's sightings in one call) and the heard-report table give
    every agent exactly - not just closely - what its own ``BallBelief`` and window give."""
    team = TeamSightings(AGENTS, OPPONENTS)
    alone = [BallBelief() for _ in range(AGENTS)]
    windows = [MultiObjectWindow(OPPONENTS) for _ in range(AGENTS)]
    stride = 1 + OPPONENTS
    compared = 0
    for t, frame in _scenario(5):
        ids, points = [], []
        for k, (seen_ball, opp_ids, opp, heard) in enumerate(frame):
            if seen_ball is not None:
                ids.append(k * stride)
                points.append(seen_ball)
                alone[k].see(t, seen_ball)
            ids += [k * stride + 1 + int(j) for j in opp_ids]
            points += list(opp)
            if len(opp_ids):
                windows[k].add(t, opp_ids, opp)
            for xy, age, sender in heard:
                team.hear(t, k, xy, age, sender)
                alone[k].hear(t, xy, age, sender)
        team.see_many(t, np.asarray(ids, dtype=np.int64), np.asarray(points).reshape(-1, 2))
        beliefs = team.ball_beliefs(t)
        positions, known = team.all_opponents(t)
        for k in range(AGENTS):
            mine = alone[k].belief(t)
            assert (beliefs[k].source, beliefs[k].age_s, beliefs[k].confidence,
                    beliefs[k].support) == (mine.source, mine.age_s, mine.confidence,
                                            mine.support)
            if mine.position is not None:
                np.testing.assert_array_equal(beliefs[k].position, mine.position)
                compared += 1
            est = windows[k].estimate(t)
            np.testing.assert_array_equal(known[k], est.known)
            np.testing.assert_array_equal(positions[k][est.known],
                                          est.latest_positions()[est.known])
    assert compared > 300
