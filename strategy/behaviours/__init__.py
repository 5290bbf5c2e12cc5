"""Behaviours: what an agent can do, from high to low level (seed 000 §2.4).

Each behaviour is a function of the agent's ``WorldModel`` and its ``Skills`` that returns a
``ControlRequest``; behaviours use one another (``shoot`` uses ``kick_to``, which uses
``approach_ball``, which uses ``go_to``, which uses potential-field navigation). The direct
ones (``walk_to``, ``kick_toward``) return raw walk and kick arrays, for the simple teams.
"""

from strategy.behaviours.ball import (
    approach_ball,
    choose_pass,
    clear_ball,
    dribble,
    kick_to,
    pass_to,
    shoot,
    shot_target,
)
from strategy.behaviours.direct import kick_toward, walk_to
from strategy.behaviours.goalie import goalie_clear, goalie_position, goalie_target
from strategy.behaviours.motion import beam_to, face_ball, go_to, hold_position, keep_clear
from strategy.behaviours.skills import Skills

__all__ = [
    "Skills", "approach_ball", "beam_to", "choose_pass", "clear_ball", "dribble", "face_ball",
    "go_to", "goalie_clear", "goalie_position", "goalie_target", "hold_position", "keep_clear",
    "kick_to", "kick_toward", "pass_to", "shoot", "shot_target", "walk_to",
]
