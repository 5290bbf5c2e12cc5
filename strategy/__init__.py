"""Team brains: formations, role assignment, voting, marking and the built-in teams.

Layering: ``strategy`` may import ``comms``, ``teamenv.field``, ``teamenv.errors`` and the
public API of ``teamenv`` (observation and action types), nothing else of ours; nothing in
``teamenv``, ``comms`` or ``locomotion`` may import ``strategy``.
"""
