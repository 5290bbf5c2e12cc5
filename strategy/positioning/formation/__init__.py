"""Formations: ball position -> home positions (Delaunay + barycentric), files, agent2d import, plots.

Public API: ``Formation``, ``Role``, ``FormationError``, ``read_formation``,
``write_formation``, ``formation_from_dict``, ``formation_to_dict``, ``import_agent2d``,
``builtin_formation``, ``builtin_formation_names``, ``plot_formation``.
"""

from strategy.positioning.formation.agent2d import import_agent2d
from strategy.positioning.formation.builtin import builtin_formation, builtin_formation_names
from strategy.positioning.formation.fileformat import (
    formation_from_dict,
    formation_to_dict,
    read_formation,
    write_formation,
)
from strategy.positioning.formation.model import Formation, FormationError, Role
from strategy.positioning.formation.plot import plot_formation

__all__ = [
    "Formation", "FormationError", "Role", "builtin_formation", "builtin_formation_names",
    "formation_from_dict", "formation_to_dict", "import_agent2d", "plot_formation",
    "read_formation", "write_formation",
]
