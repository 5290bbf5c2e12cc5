"""Positioning layer: formations, role assignment, voting and marking -> where each agent stands.

Reads the belief (``strategy.perception``); never imports ``strategy.teams``.
"""

from strategy.perception.worldmodel import WorldView, world_view
from strategy.positioning.agent import PositioningAgent, PositioningDecision

__all__ = ["PositioningAgent", "PositioningDecision", "WorldView", "world_view"]
