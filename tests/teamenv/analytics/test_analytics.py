"""Match statistics on a hand-built replay with known answers (tests/teamenv/analytics_replays.py)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from teamenv.analytics.events import match_events
from teamenv.analytics.stats import MatchStats, match_stats, popcount32
from teamenv.analytics.xg import XGModel
from tests.teamenv.analytics_replays import N, T, story_replay


@pytest.fixture
def replay(tmp_path):
    return story_replay(tmp_path)


def test_kicks_passes_shots_and_how_they_ended(replay):
    ev = match_events(replay)
    kicks = {k.row: k for k in ev.kicks}
    assert sorted(kicks) == [10, 40, 70]
    first_pass, shot, kick_in = kicks[10], kicks[40], kicks[70]
    assert first_pass.is_pass and first_pass.completed
    assert (first_pass.outcome, first_pass.receiver, first_pass.end_row) == ("teammate", 1, 20)
    assert shot.on_frame and shot.shot and not shot.is_pass
    assert (shot.team, shot.outcome, shot.end_row, shot.blockers) == (1, "goal", 45, 0)
    assert shot.goal_distance == pytest.approx(5.0)
    assert shot.goal_angle == pytest.approx(2 * math.atan(1.05 / 5.0))
    assert shot.travel_m == pytest.approx(2.0)  # rows 41-44 at 0.5 m; the goal row is a placement
    assert (kick_in.outcome, kick_in.end_row, kick_in.completed) == ("stopped", 90, False)
    assert [k.row for k in ev.shots] == [40] and [k.row for k in ev.passes] == [10, 70]


def test_possession_and_its_changes(replay):
    ev = match_events(replay)
    assert (ev.possession[:10] == -1).all()
    assert (ev.possession[10:30] == 0).all() and (ev.possession[30:] == 1).all()
    assert ev.change_row.tolist() == [30]
    assert ev.change_loser.tolist() == [0]
    assert ev.change_third.tolist() == [1]  # the middle third
    assert ev.change_restart.tolist() == [False]


def test_set_plays_taken_and_their_outcome(replay):
    plays = [(p.kind, p.team, p.row, p.restart_row, p.taken, p.outcome)
             for p in match_events(replay).set_plays]
    assert plays == [("KickOff", 0, 1, 5, False, "lost"), ("KickOff", 0, 50, 55, False, "lost"),
                     ("KickIn", 1, 60, 70, True, "kept")]


def test_match_stats_per_team(replay):
    s = match_stats(replay)
    left, right = s.left, s.right
    assert (left.team, right.team, s.score, s.cycles) == ("lefty", "righty", (0, 1), T - 1)
    assert (left.goals, right.goals, left.own_goals, right.own_goals) == (0, 1, 0, 0)
    # play on: rows 5-44, 55-59, 70-99 = 75 rows; left has it on rows 10-29, right on 50
    assert left.possession_pct == pytest.approx(100 * 20 / 75)
    assert right.possession_pct == pytest.approx(100 * 50 / 75)
    assert s.play_on_s == pytest.approx(75 * 0.02)
    assert (left.passes_attempted, left.passes_completed, left.pass_completion_pct) == (1, 1, 100)
    assert (right.passes_attempted, right.passes_completed) == (1, 0)
    assert (left.shots, right.shots, right.attempts_on_frame) == (0, 1, 1)
    expected_xg = XGModel.load().probability(np.array([[5.0, 2 * math.atan(1.05 / 5), 0]]))[0]
    assert right.xg == pytest.approx(expected_xg) and left.xg == 0.0
    assert s.shots[0]["outcome"] == "goal" and s.shots[0]["unum"] == 2
    assert (left.possession_lost, left.lost_in_third["middle"], right.possession_lost) == (1, 1, 0)
    assert right.ball_progress_m == pytest.approx(2.5, abs=1e-5) and left.ball_progress_m == 0
    # territory: every row counts; the ball is at x = -10 (rows 30-39), rolls -10.5 .. -12.5
    # (40-44), and stands at x = 5 from row 60 on; left attacks +x
    ball_x_sum = 10 * -10.0 + sum(-10.5 - 0.5 * k for k in range(5)) + 5.0 * (T - 60)
    assert left.territory_m == pytest.approx(ball_x_sum / T, abs=1e-5)
    assert right.territory_m == pytest.approx(-left.territory_m)
    assert left.third_pct == pytest.approx({"defensive": 20.0, "middle": 80.0, "attacking": 0})
    assert right.third_pct == pytest.approx({"defensive": 0, "middle": 80.0, "attacking": 20.0})
    assert left.falls == 1 and right.falls == 0 and left.players[0].falls == 1
    assert left.distance_walked_m == pytest.approx(0.79, abs=1e-4)  # the 6.6 m beam left out
    assert (left.messages_sent, left.message_bytes, left.messages_dropped) == (1, 10, 1)
    assert (left.messages_heard_team, left.messages_heard_opponents) == (1, 0)
    assert (right.messages_sent, right.messages_heard_opponents) == (0, 1)
    assert right.set_plays["KickIn"] == {"awarded": 1, "taken": 1, "goal": 0, "shot": 0,
                                         "kept": 1, "lost": 0}
    assert left.set_plays["KickOff"]["awarded"] == 2 and left.set_plays["KickOff"]["taken"] == 0
    assert s.pass_network == {"left": [[1, 2, 1]], "right": []}
    assert left.role_agreement_pct is None and not s.has_extras


def test_json_form_is_stable_and_round_trips(replay):
    s = match_stats(replay)
    data = json.loads(json.dumps(s.to_json()))
    assert data["schema"] == "teamenv.match_stats/1"
    assert set(data["teams"]) == {"left", "right"}
    assert {"goals", "xg", "possession_pct", "passes_attempted", "set_plays",
            "players"} <= set(data["teams"]["left"])
    assert MatchStats.from_json(data).to_json() == data
    assert "left" in s.summary() or "lefty" in s.summary()


def test_role_agreement_from_extras(tmp_path):
    vectors = np.zeros((T, 2 * N, N), np.int8)
    vectors[:] = [0, 1]
    vectors[20:30, 1] = [1, 0]  # left_2 disagrees for 10 play-on rows
    roles = np.tile(np.array([0, 1, 0, 1], np.int8), (T, 1))
    roles[:, 2:] = -1  # the right side gives only vectors
    extras = {"belief_pose": np.zeros((T, 2 * N, 3), np.float16),
              "belief_ball": np.zeros((T, 2 * N, 2), np.float16), "role": roles,
              "role_vector": vectors}
    s = match_stats(story_replay(tmp_path, extras))
    assert s.has_extras
    assert s.left.role_agreement_pct == pytest.approx(100 * 65 / 75)
    assert s.right.role_agreement_pct == pytest.approx(100.0)


def test_popcount():
    values = np.array([0, 1, 3, 0xFFFFFFFF, 0x80000001], np.uint32)
    assert popcount32(values).tolist() == [0, 1, 2, 32, 2]
