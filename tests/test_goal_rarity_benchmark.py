"""benchmarks/goal_rarity.py: its counting on synthetic cycles and on a short seeded match."""

from __future__ import annotations

import math
from dataclasses import dataclass

import pytest

from tests.benchmark_scripts import load_benchmark

gr = load_benchmark("goal_rarity")


@dataclass(frozen=True)
class Ev:
    kind: str
    time_s: float
    team: int | None = None
    player: int | None = None
    play_mode: str | None = None


SIGN = (1.0, -1.0)


def cyc(t, ball, kicks=(), touches=(), events=(), mode="PlayOn"):
    return gr.Cycle(kicks=list(kicks), touches=list(touches), events=list(events), ball=ball,
                    mode=mode, time_s=t, attack_sign=SIGN)


def test_synthetic_shot_goal_block_and_possession():
    # 2 a side on a 20 m x ? pitch, goal mouth |y| < 1; players 0, 1 left, 2, 3 right
    c = gr.MatchCounter(half_length=10.0, half_goal_width=1.0, team_size=2,
                        start_ball=(5.0, 0.0, 0.0, 0.0))
    # left's player 0 kicks 6 m straight at the right goal from 5 m: a shot
    c.add(cyc(0.02, (5.2, 0.0, 10.0, 0.0), kicks=[(0, 6.0, 0.0)], touches=[0]))
    x = 5.2
    for k in range(2, 27):
        x += 0.19
        c.add(cyc(0.02 * k, (x, 0.0, 9.0, 0.0)))
    c.add(cyc(0.54, (10.1, 0.0, 5.0, 0.0), events=[Ev("goal", 0.54, 0, 0),
                                                 Ev("play_mode", 0.54, 0, None, "Goal_Left")],
              mode="Goal_Left"))
    # kick-off for the right side: the ball jumps to the centre (not travel)
    c.add(cyc(3.60, (0.0, 0.0, 0.0, 0.0), events=[Ev("play_mode", 3.6, 1, None, "KickOff_Right")],
              mode="KickOff_Right"))
    # right's player 2 kicks 3 m at the left goal 10 m away: on frame, short
    c.add(cyc(3.62, (-0.2, 0.0, -4.0, 0.0), kicks=[(2, 3.0, math.pi)], touches=[2],
              events=[Ev("play_mode", 3.62, None, None, "PlayOn")]))
    c.add(cyc(3.64, (-0.3, 0.0, -4.0, 0.0)))
    # left's player 1 stops it: blocked, possession back to the left
    c.add(cyc(3.66, (-0.35, 0.0, 0.0, 0.0), touches=[1]))
    c.add(cyc(3.68, (-0.35, 0.0, 0.0, 0.0), touches=[1]))  # same contact: one dribble touch
    # right's 3 kicks it sideways, it comes to rest
    c.add(cyc(3.70, (-0.35, -0.2, 0.0, -3.0), kicks=[(3, 2.0, -math.pi / 2)]))
    c.add(cyc(3.72, (-0.35, -0.25, 0.0, 0.0)))
    c.finish()

    left, right = c.side_metrics(0), c.side_metrics(1)
    assert left["kicks"] == 1 and right["kicks"] == 2
    assert left["on_frame_kicks"] == 1 and left["shots"] == 1 and left["on_frame_short"] == 0
    assert right["on_frame_kicks"] == 1 and right["shots"] == 0 and right["on_frame_short"] == 1
    assert left["goals"] == 1 and left["goals_from_shots"] == 1 and left["shots_goal"] == 1
    assert left["opponent_own_goals"] == 0
    assert left["shot_to_goal_s_mean"] == pytest.approx(0.52)
    assert left["shot_distance_mean_m"] == pytest.approx(5.0)
    assert right["kicks_blocked"] == 1 and right["kicks_stopped"] == 1
    assert left["dribble_touches"] == 1
    # possession: left (kick) -> right (kick-off kick) -> left (touch) -> right (kick)
    assert c.possession_changes == 3
    assert left["possession_losses"] == 2 and right["possession_losses"] == 1
    assert left["losses_restart"] == 1 and left["losses_open_play"] == 1
    assert right["losses_open_play"] == 1 and left["lost_in_middle_third"] == 2
    # the jump to the centre spot is not travel; the rest is
    m = c.match_metrics()
    assert m["goals_total"] == 1 and m["kicks_total"] == 3 and m["shots_total"] == 1
    assert 5.0 < m["ball_travel_m"] < 6.0
    assert m["play_on_s"] + m["dead_ball_s"] == pytest.approx(c.cycles * 0.02)


def test_goal_line_crossing_and_thirds():
    c = gr.MatchCounter(half_length=10.0, half_goal_width=1.0, team_size=1)
    assert c.goal_line_crossing((0.0, 0.0), 0.0, 1.0) == pytest.approx((10.0, 0.0))
    assert c.goal_line_crossing((0.0, 0.0), math.pi, 1.0) is None  # away from that goal
    d, y = c.goal_line_crossing((5.0, 0.0), math.atan2(1.0, 5.0), 1.0)
    assert y == pytest.approx(1.0) and d == pytest.approx(math.hypot(5.0, 1.0))
    assert c.third(-8.0, 1.0) == "defensive" and c.third(8.0, 1.0) == "attacking"
    assert c.third(8.0, -1.0) == "defensive" and c.third(0.0, -1.0) == "middle"


def _check_consistent(m):
    for side in ("a", "b"):
        s = m[side]
        assert s["shots"] <= s["on_frame_kicks"] <= s["kicks"]
        assert s["goals_from_shots"] <= s["shots"]
        # a side's goals: from its shots, from the opponents' own goals, or other touches
        assert s["goals_from_shots"] + s["opponent_own_goals"] <= s["goals"]
        assert sum(s[f"kicks_{o}"] for o in gr.OUTCOMES) == s["kicks"]
        assert sum(s[f"shots_{o}"] for o in gr.OUTCOMES) == s["shots"]
        assert s["possession_losses"] == s["losses_open_play"] + s["losses_restart"] == sum(
            s[f"lost_in_{t}_third"] for t in gr.THIRDS)
        assert sum(s[f"ball_in_{t}_third_pct"] for t in gr.THIRDS) == pytest.approx(
            100.0 if m["match"]["play_on_s"] else 0.0)
    a, b, match = m["a"], m["b"], m["match"]
    # every change of possession is one side's loss and the other's gain
    assert a["possession_losses"] + b["possession_losses"] == match["possession_changes"]
    assert a["goals"] + b["goals"] == match["goals_total"]
    assert a["kicks"] + b["kicks"] == match["kicks_total"]


def test_short_seeded_match_is_consistent_and_deterministic():
    job = ("chaser", "static", 5000, False, "mj7v7", 7, 20.0)
    first, again = gr.run_match(job), gr.run_match(job)
    first.pop("wall_s"), again.pop("wall_s")
    assert first == again or repr(first) == repr(again)  # NaN != NaN: compare the text
    _check_consistent(first)
    assert first["a"]["kicks"] >= 1  # the chaser kicks; the static team never does
    assert first["b"]["kicks"] == 0 and first["b"]["shots"] == 0
    m = first["match"]
    assert m["play_on_s"] + m["dead_ball_s"] > 40.0
    summary = gr.summarize([first, again])
    assert summary["a"]["kicks"][0] == first["a"]["kicks"]
