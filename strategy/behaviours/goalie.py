"""Goalie behaviours: stand between the ball and the goal centre, and clear the ball out of
the penalty area."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from strategy.behaviours.ball import clear_ball
from strategy.behaviours.control import ControlRequest
from strategy.behaviours.motion import hold_position
from strategy.behaviours.skills import Skills
from strategy.perception.worldmodel import WorldModel


def goalie_target(wm: WorldModel, line_m: float) -> NDArray[np.float64]:
    """On the segment from our goal centre to the ball, ``line_m`` out from the goal line,
    never wider than the goal posts (less a body width)."""
    f = wm.field
    goal = wm.own_goal
    dx, dy = wm.ball[0] - goal[0], wm.ball[1] - goal[1]
    # Where the goal-to-ball line crosses x = goal + line_m (a ball beside the goal: the post).
    y = dy * line_m / dx if dx > line_m else math.copysign(f.half_goal_width, dy)
    limit = max(0.0, f.half_goal_width - 0.2)
    return np.array([goal[0] + line_m, min(limit, max(-limit, y))])


def goalie_position(wm: WorldModel, skills: Skills, line_m: float) -> ControlRequest:
    """Hold the goalie's spot (``goalie_target``), facing the ball."""
    return hold_position(wm, goalie_target(wm, line_m), skills, behaviour="goalie_position")


def goalie_clear(wm: WorldModel, skills: Skills) -> ControlRequest:
    """Go to the ball and kick it away from the goal (the clear behaviour, named for the
    goalie)."""
    return clear_ball(wm, skills).named("goalie_clear")
