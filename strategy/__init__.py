"""Team brains: formations, role assignment, voting, marking and the built-in teams.

Layering: ``strategy`` may import ``comms``, ``portable_math`` and the core of ``teamenv`` (its
plugin API: field, teams, team config, search space, observation and action types), never a
teamenv application (docs/architecture.md); nothing in ``teamenv``, ``comms`` or
``locomotion`` may import ``strategy``.
"""
