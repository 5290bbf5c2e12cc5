"""Set plays (seed 000 §6.1): who takes our kick-offs, kick-ins, corner and goal kicks, where
the kick goes, and how the rest of the team keeps the referee's distance at the other side's.

Play modes are team-relative (``_Left`` = ours). The league's rules mirrored here: at the other
side's set play we stay ``set_play_distance`` (2 m) from the ball; at their kick-off we stay in
our half and out of the centre circle; beaming is allowed before kick-off and after a goal.
"""

from __future__ import annotations

import math
from enum import Enum

import numpy as np
from numpy.typing import NDArray

from strategy.behaviours.ball import choose_pass, clear_ball, kick_to, pass_to
from strategy.behaviours.control import ControlRequest
from strategy.behaviours.skills import Skills
from strategy.perception.worldmodel import WorldModel
from teamenv import PlayMode


class Situation(Enum):
    """What the play mode asks of the team."""

    BEAM = "beam"  # before kick-off / after a goal: take kick-off positions
    OUR_KICKOFF = "our_kickoff"
    THEIR_KICKOFF = "their_kickoff"
    OUR_SET_PLAY = "our_set_play"  # kick-in, corner kick, goal kick
    THEIR_SET_PLAY = "their_set_play"
    PLAY_ON = "play_on"
    OVER = "over"


def situation(mode: PlayMode) -> Situation:
    """The situation of team-relative play mode ``mode``."""
    if mode in (PlayMode.BeforeKickOff, PlayMode.Goal_Left, PlayMode.Goal_Right):
        return Situation.BEAM
    if mode == PlayMode.PlayOn:
        return Situation.PLAY_ON
    if mode == PlayMode.GameOver:
        return Situation.OVER
    ours = mode.team == 0
    if mode.kind == "KickOff":
        return Situation.OUR_KICKOFF if ours else Situation.THEIR_KICKOFF
    return Situation.OUR_SET_PLAY if ours else Situation.THEIR_SET_PLAY


def we_kick_off_next(mode: PlayMode, half: int, side: str) -> bool:
    """Before a kick-off: True if our team takes it. The left side kicks off the first half
    and the right side the second (as the league does); after a goal the team that conceded."""
    if mode == PlayMode.Goal_Left:
        return False
    if mode == PlayMode.Goal_Right:
        return True
    return (side == "left") == (half == 1)


#: a player this much (m) beyond touching distance of the ball has not touched it yet
TOUCH_MARGIN_M = 0.15


def set_play_taker(wm: WorldModel, mode: PlayMode, goalie: int | None) -> int:
    """Our player who takes the set play ``mode``: the goalie takes goal kicks (when upright);
    otherwise the upright field player closest to the ball (lowest index on a tie)."""
    d = wm.upright_ball_distances()
    upright = np.isfinite(d)
    if mode.kind == "GoalKick" and goalie is not None and upright[goalie]:
        return goalie
    if goalie is not None and upright.sum() > 1:
        d[goalie] = np.inf
    return int(np.argmin(d))


def take_set_play(wm: WorldModel, skills: Skills, pass_max_m: float,
                  lane_m: float) -> ControlRequest:
    """The taker's kick for our set play: a corner is played into the penalty area, a goal
    kick is cleared, a kick-in or kick-off is passed to a free teammate ahead when there is
    one, else played forward."""
    f = wm.field
    mode = wm.play_mode
    if mode.kind == "CornerKick":
        target = np.array([f.half_length - f.penalty_length - 0.5, 0.0])
        return kick_to(wm, target, skills).named("corner_kick")
    if mode.kind == "GoalKick":
        return clear_ball(wm, skills).named("goal_kick")
    # no longer a pass than the body's mean kick carries
    mate = choose_pass(wm, min_gain_m=0.0, max_distance_m=min(pass_max_m, skills.kick_distance_m),
                       lane_m=lane_m, free_m=1.0)
    if mate is not None:
        return pass_to(wm, mate, skills).named(f"{_name(mode)}_pass")
    forward = np.array([wm.ball[0] + 4.0, wm.ball[1] * 0.5])
    return kick_to(wm, forward, skills).named(f"{_name(mode)}_forward")


def keep_distance(target: NDArray[np.float64], wm: WorldModel, clearance_m: float,
                  kickoff: bool) -> NDArray[np.float64]:
    """``target`` moved to respect the other side's set play: ``clearance_m`` from the ball,
    and at their kick-off also out of the centre circle and in our half."""
    t = np.array(target, dtype=np.float64)
    radius = clearance_m
    if kickoff:
        radius = max(radius, wm.field.center_circle_radius + 0.3)
        t[0] = min(t[0], -0.4)
    gap = t - wm.ball
    dist = math.hypot(gap[0], gap[1])
    if dist < radius:
        if dist < 1e-9:
            gap, dist = np.array([-1.0, 0.0]), 1.0
        t = wm.ball + gap * (radius / dist)
        if kickoff:
            t[0] = min(t[0], -0.4)
    return t


def _name(mode: PlayMode) -> str:
    return {"KickIn": "kick_in", "KickOff": "kick_off"}.get(mode.kind, mode.kind.lower())

