"""Decision layer (seed 000 §2.4): the field player's and the goalie's decision makers and the
set plays, choosing among behaviours from the belief and the positioning decision.

Its parameters (``DecisionParams``) live here; never imports ``strategy.teams``.
"""

from strategy.decision.field_player import FieldPlayerDecisionMaker
from strategy.decision.goalie import GoalieDecisionMaker
from strategy.decision.params import DecisionParams

__all__ = ["DecisionParams", "FieldPlayerDecisionMaker", "GoalieDecisionMaker"]
